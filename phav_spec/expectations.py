"""Exact expectations: the marginal and conditional probabilities of every categorical
variable, and the distributions of the continuous ones, computed from θ alone by summing
over parents — never by sampling. Validators test observed recipes against these.

Under phav-v1 the camera marginal is far from θ_C's 1/3 each (the indoors camera lives only
in the house, the close-up only for brush hair): P(C) = Σ_a Σ_e P(a) P(e | a) P(C | a, e).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from phav_spec.distributions import Triangular
from phav_spec.motions import MOTIONS
from phav_spec.population import HAIR_COLOURS
from phav_spec.recipe import SAMPLED_PERSON
from phav_spec.scene import (
    ACTION_SCENES,
    CAMERA_INFO,
    ENVIRONMENT_SCENES,
    HUMAN_MODELS,
    SPRING_MIN_DISTANCES_M,
    WEATHER_ELEMENTS,
)
from phav_spec.theta import (
    BOTTOM_KINDS,
    FABRIC_KINDS,
    HAIR_STYLE_KINDS,
    SEXES,
    TOP_KINDS,
    Theta,
)
from phav_spec.vocab import (
    ACTIONS,
    CAMERAS,
    DAY_PHASES,
    ENVIRONMENTS,
    MUSCLES,
    OBJECTS,
    VARIATIONS,
    WEATHERS,
)


@dataclass(frozen=True)
class ExactTable:
    """P(variable | parents) from θ, over the videos where the variable applies.

    ``rows`` maps each parent combination with positive probability to a probability vector
    over ``values``; ``parent_probs`` is P(parents | the variable applies). A parent
    combination absent from ``rows`` has probability zero.
    """

    variable: str
    parents: tuple[str, ...]
    values: tuple[Any, ...]
    rows: dict[tuple[Any, ...], np.ndarray]
    parent_probs: dict[tuple[Any, ...], float]
    applies_to: str = "every video"
    multi: bool = False  # the column holds a list per video, each element one observation
    #: A video's elements are a subset (drawn without replacement) of its row's support: its
    #: counts spread less than independent draws', by (m − k)/(m − 1) for k of m.
    subset: bool = False

    def marginal(self) -> np.ndarray:
        """P(variable | applies) = Σ_parents P(parents) P(variable | parents)."""
        out = np.zeros(len(self.values))
        for key, p in self.parent_probs.items():
            out += p * self.rows[key]
        return out

    def marginal_dict(self) -> dict[Any, float]:
        """The marginal as value → probability."""
        return dict(zip(self.values, self.marginal().tolist(), strict=True))


def _normalise(w: np.ndarray) -> np.ndarray:
    total = w.sum(axis=-1, keepdims=True)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(total > 0, w / np.where(total > 0, total, 1.0), 0.0)


def _positive(names: tuple[Any, ...], p: np.ndarray) -> dict[tuple[Any, ...], float]:
    return {(n,): float(x) for n, x in zip(names, p, strict=True) if x > 0}


#: The values of the human-model columns: the 20 models of H, then ``sampled``.
PERSON_MODELS: tuple[str, ...] = (*HUMAN_MODELS.names, SAMPLED_PERSON)


@dataclass(frozen=True)
class ModelProbabilities:
    """The normalised categorical pieces of θ every expectation is built from."""

    a: np.ndarray  # P(A)
    d: np.ndarray
    w: np.ndarray
    h: np.ndarray  # P(person model) over PERSON_MODELS: θ_H, or all mass on ``sampled``
    e_a: np.ndarray  # P(E | A), rows of unreachable actions are zero
    v_a: np.ndarray
    b_a: np.ndarray
    c_ae: np.ndarray  # P(C | A, E)

    @classmethod
    def of(cls, theta: Theta) -> ModelProbabilities:
        """Normalise θ's weights and tables (unreachable rows stay zero)."""
        arr = theta.arrays
        h = np.append(arr.h, 0.0) if theta.people is None else np.append(np.zeros(len(arr.h)), 1.0)
        return cls(
            a=_normalise(arr.a), d=_normalise(arr.d), w=_normalise(arr.w), h=_normalise(h),
            e_a=_normalise(arr.p_e_given_a()), v_a=_normalise(arr.p_v_given_a()),
            b_a=_normalise(arr.p_b_given_a()), c_ae=_normalise(arr.p_c_given_ae()),
        )  # fmt: skip

    @property
    def ae(self) -> np.ndarray:
        """Joint P(A, E)."""
        return self.a[:, None] * self.e_a

    @property
    def c(self) -> np.ndarray:
        """Camera marginal P(C) = Σ_a Σ_e P(a) P(e | a) P(C | a, e)."""
        return np.einsum("ae,aec->c", self.ae, self.c_ae)

    @property
    def b(self) -> np.ndarray:
        """Base-motion marginal P(B) = Σ_a P(a) P(B | a)."""
        return self.a @ self.b_a


def exact_expectations(theta: Theta) -> dict[str, ExactTable]:
    """Every checked categorical variable's exact conditional table, keyed by column name.

    In order: the roots (D, W, H, A), what the action conditions (E, V, B), the camera given
    both, the weather elements and spring dead zones, the supporting character, the objects
    variation's prop and action blending's motion, the mirror flag, the varied muscles, then
    what the environment conditions (background actors, the protagonist's waypoint), and
    with sampled people the protagonist's sex, child, hair and clothes.
    """
    p = ModelProbabilities.of(theta)
    tables = [
        *_root_tables(p),
        *_given_action_tables(p),
        _camera_table(p),
        *_weather_tables(theta, p),
        *_dead_zone_tables(theta, p),
        *_supporting_human_table(theta, p),
        *_variation_object_table(p),
        *_blend_motion_table(p),
        _mirror_table(theta),
        *_muscle_count_table(theta, p),
        *_environment_tables(theta, p),
        *_people_tables(theta, p),
    ]
    return {t.variable: t for t in tables}


def _root(variable: str, values: tuple[Any, ...], probs: np.ndarray, applies_to: str = "every video") -> ExactTable:
    """A variable without parents: one row, its probabilities."""
    return ExactTable(variable, (), values, {(): probs}, {(): 1.0}, applies_to)


def _reachable_actions(p: ModelProbabilities) -> list[int]:
    """Indices of the actions with weight in θ_A."""
    return [i for i in range(len(ACTIONS)) if p.a[i] > 0]


def _root_tables(p: ModelProbabilities) -> list[ExactTable]:
    """The day phase, weather, human model and action: drawn from θ alone."""
    return [
        _root("day_phase", DAY_PHASES.names, p.d),
        _root("weather", WEATHERS.names, p.w),
        _root("human_model", PERSON_MODELS, p.h),
        _root("action", ACTIONS.names, p.a),
    ]


def _given_action_tables(p: ModelProbabilities) -> list[ExactTable]:
    """The environment, variation and base motion, each given the action."""
    A = ACTIONS.names
    reach_a = _reachable_actions(p)
    tables = []
    for variable, values, given_a in (
        ("environment", ENVIRONMENTS.names, p.e_a),
        ("variation", VARIATIONS.names, p.v_a),
        ("base_motion", MOTIONS.names, p.b_a),
    ):
        rows = {(A[i],): given_a[i] for i in reach_a}
        tables.append(ExactTable(variable, ("action",), values, rows, _positive(A, p.a)))
    return tables


def _camera_table(p: ModelProbabilities) -> ExactTable:
    """The camera given the action and the environment."""
    A, E = ACTIONS.names, ENVIRONMENTS.names
    reach_a = _reachable_actions(p)
    ae = p.ae
    cam_rows = {(A[i], E[j]): p.c_ae[i, j] for i in reach_a for j in range(len(E)) if ae[i, j] > 0}
    cam_parents = {(A[i], E[j]): float(ae[i, j]) for i in reach_a for j in range(len(E)) if ae[i, j] > 0}
    return ExactTable("camera", ("action", "environment"), CAMERAS.names, cam_rows, cam_parents)


def _supporting_human_table(theta: Theta, p: ModelProbabilities) -> list[ExactTable]:
    """Supporting character: H without the protagonist's, in two-people actions (H ⟂ A);
    with sampled people, a sampled person."""
    A = ACTIONS.names
    if not any(ACTIONS[A[i]].n_people > 1 for i in _reachable_actions(p)):
        return []
    h_w = np.append(theta.arrays.h, 0.0) if theta.people is None else p.h
    rows = {}
    for k, name in enumerate(PERSON_MODELS):
        if p.h[k] > 0:
            rows[(name,)] = (
                h_w / h_w.sum() if name == SAMPLED_PERSON else _normalise(np.where(np.arange(len(h_w)) == k, 0.0, h_w))
            )
    return [ExactTable(
        "supporting_human_model", ("human_model",), PERSON_MODELS, rows,
        _positive(PERSON_MODELS, p.h), "two-people actions",
    )]  # fmt: skip


def _variation_object_table(p: ModelProbabilities) -> list[ExactTable]:
    """The objects variation's prop, uniform over what the action declares."""
    A = ACTIONS.names
    v_obj = VARIATIONS.index("objects")
    a_given_obj = _normalise(p.a * p.v_a[:, v_obj])
    if not a_given_obj.sum() > 0:
        return []
    rows = {}
    for i in np.flatnonzero(a_given_obj):
        options = ACTION_SCENES[A[i]].variation_objects
        rows[(A[i],)] = np.array([1.0 / len(options) if o in options else 0.0 for o in OBJECTS.names])
    return [ExactTable(
        "variation_object", ("action",), OBJECTS.names, rows, _positive(A, a_given_obj),
        "videos with the objects variation",
    )]  # fmt: skip


def _blend_motion_table(p: ModelProbabilities) -> list[ExactTable]:
    """Action blending's second motion: uniform over every motion but the base one."""
    v_blend = VARIATIONS.index("action_blending")
    b_given_blend = _normalise((p.a * p.v_a[:, v_blend]) @ p.b_a)
    if not b_given_blend.sum() > 0:
        return []
    n = len(MOTIONS)
    blend = (1.0 - b_given_blend) / (n - 1)
    return [_root("blend_motion", MOTIONS.names, blend, "videos with action blending")]


def _mirror_table(theta: Theta) -> ExactTable:
    """Whether the base motion is mirrored: a Bernoulli of θ."""
    p_mirror = theta.motion.p_mirror
    return _root("mirror", (False, True), np.array([1.0 - p_mirror, p_mirror]))


def _environment_tables(theta: Theta, p: ModelProbabilities) -> list[ExactTable]:
    """What the environment conditions: the background actors and the protagonist's waypoint."""
    e_marg = p.a @ p.e_a
    env_parents = _positive(ENVIRONMENTS.names, e_marg)
    return [
        _background_count_table(theta, e_marg, env_parents),
        *_background_tables(theta, p, e_marg),
        _waypoint_table(e_marg, env_parents),
    ]


def _background_count_table(theta: Theta, e_marg: np.ndarray, env_parents: dict[tuple[Any, ...], float]) -> ExactTable:
    """How many background actors: uniform on θ's count where the environment has a waypoint
    graph for them, none where it has not."""
    spec = theta.background_actors
    max_n = max(spec.count.max, 0)
    rows = {}
    for j, env in enumerate(ENVIRONMENTS.names):
        if e_marg[j] <= 0:
            continue
        counts = np.zeros(max_n + 1)
        if ENVIRONMENT_SCENES[env].background_waypoints:
            counts[spec.count.min : spec.count.max + 1] = 1.0 / (spec.count.max - spec.count.min + 1)
        else:
            counts[0] = 1.0
        rows[(env,)] = counts
    return ExactTable("n_background_actors", ("environment",), tuple(range(max_n + 1)), rows, env_parents)


def _waypoint_table(e_marg: np.ndarray, env_parents: dict[tuple[Any, ...], float]) -> ExactTable:
    """The protagonist's waypoint, uniform over the environment's."""
    max_wp = max(len(ENVIRONMENT_SCENES[e].protagonist_waypoints) for e in ENVIRONMENTS.names)
    rows = {}
    for j, env in enumerate(ENVIRONMENTS.names):
        if e_marg[j] <= 0:
            continue
        k = len(ENVIRONMENT_SCENES[env].protagonist_waypoints)
        rows[(env,)] = np.array([1.0 / k if i < k else 0.0 for i in range(max_wp)])
    return ExactTable("waypoint_index", ("environment",), tuple(range(max_wp)), rows, env_parents)


def _muscle_count_table(theta: Theta, p: ModelProbabilities) -> list[ExactTable]:
    """How many muscles a variation acts on, given the action and the variation kind."""
    values = tuple(range(1, len(MUSCLES) + 1))
    kinds = {
        "random_perturbation": theta.variations.random_perturbation.n_muscles,
        "muscle_weakening": theta.variations.muscle_weakening.n_muscles,
        "action_blending": theta.variations.action_blending.n_muscles,
    }
    rows, parents = {}, {}
    for i, action in enumerate(ACTIONS.names):
        scene = ACTION_SCENES[action]
        for kind, spec in kinds.items():
            joint = p.a[i] * p.v_a[i, VARIATIONS.index(kind)]
            if joint <= 0:
                continue
            available = len(MUSCLES) if kind == "muscle_weakening" else len(scene.complementary_muscles)
            hi = min(spec.max, available)
            lo = max(1, min(spec.min, hi))
            rows[(action, kind)] = np.array([1.0 / (hi - lo + 1) if lo <= k <= hi else 0.0 for k in values])
            parents[(action, kind)] = joint
    if not parents:
        return []
    total = sum(parents.values())
    counts = ExactTable(
        "n_varied_muscles", ("action", "variation"), values, rows,
        {k: v / total for k, v in parents.items()}, "videos with muscle variations",
    )  # fmt: skip
    # Which muscles: a uniform subset, so each eligible muscle is equally likely; observations
    # are weighted by the expected subset size of their (action, variation).
    which, weight = {}, {}
    for (action, kind), row in rows.items():
        eligible = MUSCLES.names if kind == "muscle_weakening" else ACTION_SCENES[action].complementary_muscles
        which[(action, kind)] = np.array([1.0 / len(eligible) if m in eligible else 0.0 for m in MUSCLES.names])
        weight[(action, kind)] = parents[(action, kind)] * float(np.dot(row, values))
    total = sum(weight.values())
    muscles = ExactTable(
        "varied_muscles", ("action", "variation"), MUSCLES.names, which,
        {k: v / total for k, v in weight.items()}, "muscles of muscle variations", multi=True, subset=True,
    )  # fmt: skip
    return [counts, muscles]


def _background_tables(theta: Theta, p: ModelProbabilities, e_marg: np.ndarray) -> list[ExactTable]:
    """Background actors: human models from θ_H, start and destination uniform on B_WG.

    The destination is uniform over the waypoints other than the start, hence uniform over
    the graph once the start is summed out.
    """
    spec = theta.background_actors
    mean_count = (spec.count.min + spec.count.max) / 2.0
    weights = {}
    for j, env in enumerate(ENVIRONMENTS.names):
        graph = ENVIRONMENT_SCENES[env].background_waypoints
        if e_marg[j] > 0 and graph and mean_count > 0:
            weights[(env,)] = float(e_marg[j]) * mean_count
    if not weights:
        return []
    total = sum(weights.values())
    parents = {k: v / total for k, v in weights.items()}
    size = max(len(ENVIRONMENT_SCENES[e].background_waypoints) for (e,) in parents)
    rows = {}
    for (env,) in parents:
        n = len(ENVIRONMENT_SCENES[env].background_waypoints)
        rows[(env,)] = np.array([1.0 / n if i < n else 0.0 for i in range(size)])
    applies = "background actors"
    values = tuple(range(size))
    return [
        ExactTable("background_human_models", (), PERSON_MODELS, {(): p.h}, {(): 1.0}, applies, multi=True),
        ExactTable("background_start_waypoints", ("environment",), values, rows, parents, applies, multi=True),
        ExactTable("background_destination_waypoints", ("environment",), values, rows, parents, applies, multi=True),
    ]


def _people_tables(theta: Theta, p: ModelProbabilities) -> list[ExactTable]:
    """The protagonist drawn from θ's people section: sex; child given the action (never
    where the action does not allow one); hair style and bottom given the sex; the named hair
    colour (grey with age, so a mixture over the age distribution); top and fabrics."""
    people = theta.people
    if people is None:
        return []
    applies = "sampled protagonists"
    p_sex = np.array([people.p_sex()[s] for s in SEXES.names])
    sexes = _positive(SEXES.names, p_sex)
    A = ACTIONS.names
    child_rows = {}
    for i in _reachable_actions(p):
        c = people.p_child if ACTION_SCENES[A[i]].children else 0.0
        child_rows[(A[i],)] = np.array([1.0 - c, c])

    def given_sex(weights: dict[str, dict[str, float]]) -> dict[tuple[Any, ...], np.ndarray]:
        return {(s,): _normalise(np.array(list(weights[s].values()))) for (s,) in sexes}

    def root(variable: str, values: tuple[Any, ...], weights: dict[str, float]) -> ExactTable:
        return _root(variable, values, _normalise(np.array(list(weights.values()))), applies)

    o = people.outfit
    return [
        _root("sex", SEXES.names, p_sex, applies),
        ExactTable("child", ("action",), (False, True), child_rows, _positive(A, p.a), applies),
        ExactTable("hair_style", ("sex",), HAIR_STYLE_KINDS.names, given_sex(people.hair.styles), sexes, applies),
        _root("hair_colour", (*HAIR_COLOURS, "grey"), _hair_colour(theta, p), applies),
        root("top", TOP_KINDS.names, o.tops),
        root("top_fabric", FABRIC_KINDS.names, o.top_fabrics),
        ExactTable("bottom", ("sex",), BOTTOM_KINDS.names, given_sex(o.bottoms), sexes, applies),
        root("bottom_fabric", FABRIC_KINDS.names, o.bottom_fabrics),
    ]


def _hair_colour(theta: Theta, p: ModelProbabilities) -> np.ndarray:
    """P(hair colour) of sampled protagonists: grey with probability E[P(grey | age)] over
    the age mixture (children where actions allow them), else θ's colours."""
    people = theta.people
    g = people.hair.grey
    p_child = sum(
        float(p.a[i]) * people.p_child for i in _reachable_actions(p) if ACTION_SCENES[ACTIONS.names[i]].children
    )
    grey = (1.0 - p_child) * _mean_grey(people.adult_age_years, g) + p_child * _mean_grey(people.child_age_years, g)
    colours = _normalise(np.array(list(people.hair.colours.values())))
    return np.append((1.0 - grey) * colours, grey)


def _mean_grey(age: Any, grey: Any) -> float:
    """E[P(grey | age)] for an age distribution: p_full · E[clip((age − start) / (full − start), 0, 1)],
    i.e. p_full / (full − start) · ∫ P(age > x) dx over [start, full] (a point step if equal)."""
    start, full = grey.start_years, grey.full_years
    if full <= start:
        return grey.p_full * float(1.0 - age.cdf(start))
    x = np.linspace(start, full, 20001)
    survival = 1.0 - np.asarray(age.cdf(x), dtype=float)
    integral = float(np.sum((survival[1:] + survival[:-1]) * np.diff(x)) / 2.0)
    return grey.p_full * integral / (full - start)


def _weather_tables(theta: Theta, p: ModelProbabilities) -> list[ExactTable]:
    """Weather elements: a root element given W, a dependent one given W and its parent.

    Conditioning on the parent tests the Bernoulli dependency itself (fog → clouds), not
    only its marginal, which could hide a sampler that ignores the parent.
    """
    values = (False, True)
    out = []
    for element, info in WEATHER_ELEMENTS.items():
        rows: dict[tuple[Any, ...], np.ndarray] = {}
        parents: dict[tuple[Any, ...], float] = {}
        for k, weather in enumerate(WEATHERS.names):
            if p.w[k] <= 0:
                continue
            spec = theta.weather_elements[weather]
            if info.parent is None:
                on = spec.p_on(element)
                rows[(weather,)] = np.array([1.0 - on, on])
                parents[(weather,)] = float(p.w[k])
                continue
            p_parent = spec.p_on(info.parent)
            for state, p_state in ((False, 1.0 - p_parent), (True, p_parent)):
                if p_state > 0:
                    on = spec.p_on(element, state)
                    rows[(weather, state)] = np.array([1.0 - on, on])
                    parents[(weather, state)] = float(p.w[k] * p_state)
        names = ("weather",) if info.parent is None else ("weather", info.parent)
        out.append(ExactTable(element, names, values, rows, parents))
    return out


def _dead_zone_tables(theta: Theta, p: ModelProbabilities) -> list[ExactTable]:
    """Spring dead zones given the camera, over the videos filmed by a spring camera."""
    cams = CAMERAS.names
    spring = np.array([CAMERA_INFO[c].tracking == "springs" for c in cams], dtype=float)
    p_c = _normalise(p.c * spring)
    if p_c.sum() <= 0:
        return []
    rows = {
        (c,): _normalise(np.array(theta.cameras[c].springs.dead_zone_weights()))
        for k, c in enumerate(cams)
        if p_c[k] > 0
    }
    return [
        ExactTable(name, ("camera",), SPRING_MIN_DISTANCES_M, rows, _positive(cams, p_c), "spring cameras")
        for name in ("ct_min_distance_m", "tp_min_distance_m")
    ]


# --------------------------------------------------------------------------- continuous


def _duration_components(theta: Theta, weights_b: np.ndarray) -> list[tuple[float, Triangular]]:
    """P(L) as a mixture: (P(b), Tr of L given b) for every motion b with weight."""
    out = []
    for k, name in enumerate(MOTIONS.names):
        if weights_b[k] > 0:
            a, b, c = theta.durations.clip_length(MOTIONS[name].length_s)
            out.append((float(weights_b[k]), Triangular(min=a, max=b, mode=c)))
    return out


def _mixture_cdf(components: list[tuple[float, Triangular]]) -> Callable[[np.ndarray], np.ndarray]:
    def cdf(x: np.ndarray) -> np.ndarray:
        x = np.asarray(x, dtype=float)
        return sum(w * t.cdf(x) for w, t in components)

    return cdf


def duration_cdf(theta: Theta, action: str | None = None) -> Callable[[np.ndarray], np.ndarray]:
    """CDF of the clip length L (optionally given the action): a mixture of Tr over motions."""
    p = ModelProbabilities.of(theta)
    weights = p.b if action is None else p.b_a[ACTIONS.index(action)]
    return _mixture_cdf(_duration_components(theta, weights))


def mean_duration(theta: Theta) -> float:
    """E[L] in seconds: Σ_b P(b) (T_min + min(L_b, T_max) + min(T_mod, L_b)) / 3."""
    p = ModelProbabilities.of(theta)
    return float(sum(w * t.mean() for w, t in _duration_components(theta, p.b)))


def clock_hour_cdf(theta: Theta, day_phase: str | None = None) -> Callable[[np.ndarray], np.ndarray]:
    """CDF of the clock time T on [0, 24): Σ_d P(d) Tr_d, or Tr_d given the day phase."""
    p = ModelProbabilities.of(theta)
    if day_phase is not None:
        return _mixture_cdf([(1.0, theta.clock_hours[day_phase].distribution())])
    comps = [(float(p.d[k]), theta.clock_hours[d].distribution()) for k, d in enumerate(DAY_PHASES.names) if p.d[k] > 0]
    return _mixture_cdf(comps)


# ------------------------------------------------------------- continuous parameters of Θ


@dataclass(frozen=True)
class ContinuousParameter:
    """A continuous θ distribution and where its draws land in a recipe.

    ``theta_path`` names the θ leaf it covers (``*`` = every key of a mapping). ``value``
    is the recipe path of the draws (``[]`` steps into a list; a null means "not drawn"),
    ``group`` the recipe path that selects which of θ's distributions applies (the camera
    kind, the weather; None = one distribution), ``when`` an optional boolean path that must
    be true (an intensity is drawn only while its element is on), and ``distribution``
    returns θ's distribution for a group, or None where θ draws nothing there (people's
    parameters under a θ whose people are the 20 models of H).
    """

    name: str
    theta_path: str
    value: str
    group: str | None
    distribution: Callable[[Theta, str], Any]
    when: str | None = None


def _camera_dist(field: str, sub: str | None = None) -> Callable[[Theta, str], Any]:
    def dist(theta: Theta, kind: str) -> Any:
        node = theta.cameras[kind]
        return getattr(node if sub is None else getattr(node, sub), field)

    return dist


_PLACEMENT_FIELD = {"side_by_side": "side_distance_m", "behind": "behind_distance_m", "facing": "facing_distance_m"}


def _continuous_parameters() -> tuple[ContinuousParameter, ...]:
    """Every continuous θ distribution, by the part of the recipe its draws land in."""
    return (
        *_people_parameters(),
        *_camera_parameters(),
        *_weather_parameters(),
        *_variation_parameters(),
        *_sampled_people_parameters(),
    )


def _people_parameters() -> list[ContinuousParameter]:
    """The motion's speed, the protagonist's heading, background and supporting people."""
    cp = ContinuousParameter
    return [
        cp("motion.speed", "motion.speed", "motion.speed", None, lambda t, g: t.motion.speed),
        cp(
            "protagonist.heading_deg",
            "protagonist_heading_deg",
            "protagonist.heading_deg",
            None,
            lambda t, g: t.protagonist_heading_deg,
        ),
        cp(
            "background_actors.speed_mps",
            "background_actors.speed_mps",
            "background_actors[].speed_mps",
            None,
            lambda t, g: t.background_actors.speed_mps,
        ),
        cp(
            "supporting_characters.distance_m",
            "supporting_characters.*",
            "supporting_characters[].distance_m",
            "supporting_characters[].placement",
            lambda t, g: getattr(t.supporting_characters, _PLACEMENT_FIELD[g]),
        ),
    ]


def _camera_parameters() -> list[ContinuousParameter]:
    """Per camera kind: its placement, then its springs and impulse (spring cameras)."""
    cp = ContinuousParameter
    params = []
    for field in ("fov_deg", "distance_m", "height_m", "azimuth_deg"):
        params.append(
            cp(f"camera.{field}", f"cameras.*.{field}", f"camera.{field}", "camera.kind", _camera_dist(field))
        )
    for sub, fields in (
        (
            "springs",
            ("ct_spring_strength", "tp_spring_strength", "camera_mass", "target_mass", "camera_drag", "target_drag"),
        ),
        ("impulse", ("strength", "azimuth_deg", "elevation_deg")),
    ):
        for field in fields:
            name = f"camera.{sub}.{field}"
            params.append(cp(name, f"cameras.*.{sub}.{field}", name, "camera.kind", _camera_dist(field, sub)))
    return params


def _weather_parameters() -> list[ContinuousParameter]:
    """Per weather: light levels, and each element's intensity while the element is on."""
    return [
        ContinuousParameter(
            f"world.{field}",
            f"weather_elements.*.{field}",
            f"world.{field}",
            "world.weather",
            lambda t, g, field=field: getattr(t.weather_elements[g], field),
            when=f"world.{element}" if element else None,
        )
        for field, element in (
            ("sun_brightness", None),
            ("ambient_luminosity", None),
            ("cloud_intensity", "clouds"),
            ("fog_intensity", "fog"),
            ("rain_intensity", "rain"),
        )
    ]


def _variation_parameters() -> list[ContinuousParameter]:
    """Per variation kind, the continuous parameters it draws."""
    return [
        ContinuousParameter(
            path.removesuffix("[]"),
            f"variations.{kind}.{theta_field}",
            path,
            "variation.kind",
            lambda t, g, theta_field=theta_field: getattr(getattr(t.variations, g), theta_field),
        )
        for kind, path, theta_field in (
            ("random_perturbation", "variation.radius_m", "radius_m"),
            ("random_perturbation", "variation.period_s", "period_s"),
            ("muscle_weakening", "variation.strengths[]", "strength"),
            ("action_blending", "variation.weight", "weight"),
        )
    ]


#: Where each role's people sit in a recipe.
PERSON_PATHS: dict[str, str] = {
    "protagonist": "protagonist.human",
    "supporting": "supporting_characters[].human",
    "background": "background_actors[].human",
}


def _people_dist(*fields: str) -> Callable[[Theta, str], Any]:
    def dist(theta: Theta, group: str) -> Any:
        node: Any = theta.people
        for field in fields:
            if node is None:
                return None
            node = getattr(node, field)
        return node

    return dist


def _sampled_people_parameters() -> list[ContinuousParameter]:
    """θ's people distributions, per role: the draws kept in each person's ``sampled``
    (ages, stature z, gender offset, skin, garment and shoe colours), the phenotype's weight,
    muscle and proportions, and the garments' pattern scale."""
    leaves = [
        (leaf, f"sampled.{leaf}", ("people", leaf))
        for leaf in ("adult_age_years", "child_age_years", "stature_z", "gender_offset", "skin_tone", "skin_undertone")
    ]
    leaves += [(leaf, f"phenotype.{leaf}", ("people", leaf)) for leaf in ("weight", "muscle", "proportions")]
    leaves += [
        ("outfit.saturation", "sampled.garment_colours[].saturation", ("people", "outfit", "saturation")),
        ("outfit.value", "sampled.garment_colours[].value", ("people", "outfit", "value")),
        ("outfit.shoes_saturation", "sampled.shoes_colour.saturation", ("people", "outfit", "shoes_saturation")),
        ("outfit.shoes_value", "sampled.shoes_colour.value", ("people", "outfit", "shoes_value")),
        ("outfit.top_scale", "outfit.top.scale", ("people", "outfit", "pattern_scale")),
        ("outfit.bottom_scale", "outfit.bottom.scale", ("people", "outfit", "pattern_scale")),
    ]
    return [
        ContinuousParameter(
            f"{role}.{name}", ".".join(theta_path), f"{base}.{value}", None, _people_dist(*theta_path[1:])
        )
        for role, base in PERSON_PATHS.items()
        for name, value, theta_path in leaves
    ]


#: Every continuous θ distribution the sampler draws from, with where its draws land.
CONTINUOUS_PARAMETERS: tuple[ContinuousParameter, ...] = _continuous_parameters()
