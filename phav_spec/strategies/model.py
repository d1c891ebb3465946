"""Hypothesis strategies for θ and recipes.

Public API (DESIGN.md row "property tests"): our suite uses these, and users property-test
their own loaders and samplers with them. ``thetas()`` draws modifications of the
``phav-v1`` preset that are valid by construction (no filtering): every rule of
``Theta._support`` is met by how the draws are arranged, not checked after the fact.
``recipes()`` builds recipes structurally, without the sampler, so a loader can be tested
on recipes the sampler would rarely or never write. Each strategy labels the hard cases it
reached with ``hypothesis.event`` so ``pytest --hypothesis-show-statistics`` shows how often
each one was exercised.
"""

from __future__ import annotations

import functools
import json
import math
import re
from collections.abc import Callable, Iterable, Sequence
from typing import Any

from hypothesis import event
from hypothesis import strategies as st

from phav_spec.motions import MOTIONS, theta_ab
from phav_spec.people import BOTTOMS, FABRICS, HAIR_STYLES, TOPS
from phav_spec.population import ADULT_AGE_YEARS, HAIR_COLOURS, MIN_AGE_YEARS, PEOPLE_PARAMETER_BOUNDS
from phav_spec.recipe import SAMPLED_PERSON, Recipe, frames_for, video_id
from phav_spec.scene import (
    ACTION_SCENES,
    CAMERA_INFO,
    CAMERA_PLACEMENT_VARIABLES,
    ENVIRONMENT_SCENES,
    HUMAN_MODELS,
    MAX_CAMERA_KICK_MPS,
    PARAMETER_BOUNDS,
    SPRING_MIN_DISTANCES_M,
    why_not_hosted,
)
from phav_spec.theta import RenderSettings, Theta, load_preset, parse_theta
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

__all__ = ["recipe_lists", "recipes", "thetas"]

# ----------------------------------------------------------------------------- θ

#: A categorical weight that may be zero, and one that may not. Bounded away from 0 and
#: from overflow so that a product θ_C·θ_AC·θ_EC of positive weights stays positive.
_WEIGHT = st.one_of(st.sampled_from((0.0, 0.0, 0.5, 1.0, 2.0, 3.0)), st.floats(0.01, 100.0))
_POSITIVE = st.one_of(st.sampled_from((0.5, 1.0, 2.0, 3.0)), st.floats(0.01, 100.0))
_PROBABILITY = st.one_of(st.sampled_from((0.0, 0.5, 1.0)), st.floats(0.0, 1.0))
_HOUR = st.one_of(st.integers(0, 23).map(float), st.floats(0.0, 24.0, exclude_max=True))

_SPRING_CAMERAS = tuple(c for c in CAMERAS.names if CAMERA_INFO[c].tracking == "springs")
_OUTDOOR_CAMERAS = tuple(c for c in CAMERAS.names if not CAMERA_INFO[c].indoor_only)
_LENGTHS = tuple(MOTIONS[m].length_s for m in MOTIONS.names)
_TWO_PEOPLE = tuple(a for a in ACTIONS.names if ACTIONS[a].n_people > 1)


@functools.cache
def _preset_json() -> str:
    return json.dumps(load_preset("phav-v1").model_dump(mode="json"))


def _preset_dict() -> dict[str, Any]:
    """A fresh copy of the phav-v1 preset as the mapping θ files hold (tables as ``{rows: …}``)."""
    return json.loads(_preset_json())


def _allowed_environments(action: str) -> tuple[str, ...]:
    """Environments that can host ``action`` (``scene.why_not_hosted``)."""
    return tuple(e for e in ENVIRONMENTS.names if why_not_hosted(action, e) is None)


def _allowed_variations(action: str) -> tuple[str, ...]:
    """Variations ``action`` can take: objects only with declared props, muscle ones with muscles."""
    scene = ACTION_SCENES[action]
    out = []
    for v in VARIATIONS.names:
        if v == "objects" and not scene.variation_objects:
            continue
        if v in ("random_perturbation", "action_blending") and not scene.complementary_muscles:
            continue
        out.append(v)
    return tuple(out)


def _subset(draw: st.DrawFn, names: Sequence[str], *, min_size: int = 1) -> tuple[str, ...]:
    """A subset of ``names`` of at least ``min_size``, in registry order."""
    chosen = draw(st.sets(st.sampled_from(tuple(names)), min_size=min_size, max_size=len(names)))
    return tuple(n for n in names if n in chosen)


def _support(draw: st.DrawFn, names: Sequence[str], *, min_size: int = 1) -> tuple[str, ...]:
    """Values with weight: often a single one (when ``min_size`` allows), else a subset."""
    if min_size <= 1 and draw(st.integers(0, 3)) == 0:
        return (draw(st.sampled_from(tuple(names))),)
    return _subset(draw, names, min_size=min_size)


def _vector(draw: st.DrawFn, support: Iterable[str]) -> dict[str, float]:
    """Positive, non-uniform weights on ``support``; every other value is left out (weight 0)."""
    return {name: draw(_POSITIVE) for name in support}


def _row(
    draw: st.DrawFn,
    names: Sequence[str],
    *,
    forbidden: Iterable[str] = (),
    force_one_of: Sequence[str] = (),
) -> dict[str, float]:
    """A table row: random weights with zeros, 0 on ``forbidden``, > 0 on one of ``force_one_of``."""
    forbidden = set(forbidden)
    row = {n: (0.0 if n in forbidden else draw(_WEIGHT)) for n in names}
    if force_one_of and all(row[n] <= 0 for n in force_one_of):
        row[draw(st.sampled_from(tuple(force_one_of)))] = draw(_POSITIVE)
    return row


def _label_vector(variable: str, support: Sequence[str], names: Sequence[str]) -> None:
    if len(support) == 1:
        event(f"theta: single {variable} with weight")
    elif len(support) < len(names):
        event(f"theta: some {variable} weights zero")


@st.composite
def _actions(draw: st.DrawFn) -> tuple[dict[str, float], tuple[str, ...]]:
    """θ_A and the actions it reaches: one action, a subset, or all (uniform or not)."""
    case = draw(st.sampled_from(("single", "subset", "all", "uniform")))
    if case == "uniform":
        return {a: 1.0 for a in ACTIONS.names}, ACTIONS.names
    if case == "single":
        reach = (draw(st.sampled_from(ACTIONS.names)),)
    elif case == "subset":
        reach = _subset(draw, ACTIONS.names)
    else:
        reach = ACTIONS.names
    return _vector(draw, reach), reach


@st.composite
def _clock_hour(draw: st.DrawFn, phase: str, reachable: bool) -> dict[str, float]:
    """Tr(t | min, max, mode) on 24 h: ordinary, degenerate, or wrapping midnight."""
    cases = ["general", "min==mode", "mode==max", "point", "wrap:before", "wrap:after"]
    if phase == "night":
        cases += ["wrap:before", "wrap:after", "preset"]
    case = draw(st.sampled_from(cases))
    if case == "preset":
        out = {"min": 20.0, "max": 7.0, "mode": 0.0}
    elif case.startswith("wrap"):
        lo = draw(st.floats(0.0, 23.5))
        hi = draw(st.floats(lo, 24.0, exclude_min=True, exclude_max=True))
        if case == "wrap:before":  # mode in [min, 24): before midnight
            mode = draw(st.one_of(st.just(hi), st.floats(hi, 24.0, exclude_max=True)))
        else:  # mode in [0, max]: after midnight
            mode = draw(st.one_of(st.just(0.0), st.just(lo), st.floats(0.0, lo)))
        out = {"min": hi, "max": lo, "mode": mode}
    else:
        lo, mode, hi = sorted(draw(st.lists(_HOUR, min_size=3, max_size=3)))
        if case == "min==mode":
            mode = lo
        elif case == "mode==max":
            mode = hi
        elif case == "point":
            lo = mode = hi
        out = {"min": lo, "max": hi, "mode": mode}
    if reachable:
        lo_, hi_, mode_ = out["min"], out["max"], out["mode"]
        if lo_ > hi_:
            event(
                "clock: wrapped interval, mode before midnight"
                if mode_ >= lo_
                else "clock: wrapped interval, mode after midnight"
            )
            if phase == "night":
                event("clock: night wraps midnight with θ_D[night] > 0")
        if lo_ == hi_:
            event("clock: min == max (point)")
        elif mode_ == lo_:
            event("clock: min == mode")
        elif mode_ == hi_:
            event("clock: mode == max")
    return out


@st.composite
def _durations(draw: st.DrawFn, candidates: Sequence[float]) -> dict[str, float]:
    """T_min, T_mod, T_max with T_min no longer than ``min(candidates)``.

    ``candidates`` holds, per reachable action, the length of its longest matching motion:
    T_min above the smallest would leave that action without a motion. T_min is drawn
    freely, next to that limit, on it, or on the length of one of the catalogue's motions
    (the ``length >= T_min`` boundary, which masks every shorter motion).
    """
    longest = min(candidates)
    case = draw(st.sampled_from(("free", "near_longest", "equal_longest", "motion_length")))
    if case == "free":
        t_min = draw(st.floats(0.05, min(longest, 5.0)))
    elif case == "near_longest":
        t_min = longest * draw(st.floats(0.95, 1.0))
    elif case == "motion_length":
        t_min = draw(st.sampled_from(sorted({x for x in _LENGTHS if x <= longest})))
    else:
        t_min = longest
    shape = draw(st.sampled_from(("general", "t_min==t_mod", "t_mod==t_max", "t_min==t_max")))
    t_max = t_min if shape == "t_min==t_max" else t_min + draw(st.floats(0.01, 15.0))
    if shape == "t_min==t_mod":
        t_mod = t_min
    elif shape in ("t_mod==t_max", "t_min==t_max"):
        t_mod = t_max
    else:
        t_mod = draw(st.floats(t_min, t_max))
    if t_min >= 0.95 * longest:
        event("durations: T_min close to the longest motion of a reachable action")
    if t_min in _LENGTHS:
        event("durations: T_min equals a motion's length")
    if t_min == t_max:
        event("durations: t_min == t_max")
    elif t_min == t_mod:
        event("durations: t_min == t_mod")
    elif t_mod == t_max:
        event("durations: t_mod == t_max")
    return {"t_min": t_min, "t_max": t_max, "t_mod": t_mod}


def _action_rows(
    draw: st.DrawFn,
    preset_table: dict[str, Any],
    names: Sequence[str],
    support: Sequence[str],
    allowed_of: Callable[[str], Sequence[str]],
    reach: Sequence[str],
    zero_rows: bool,
) -> dict[str, Any]:
    """A per-action table (θ_AE, θ_AV): reachable rows give weight only to values the action
    allows among ``support`` (with at least one), unreachable rows are zero or the preset's.

    A disallowed value may keep weight where its marginal θ is zero: it stays unreachable.
    """
    rows = {}
    for a in ACTIONS.names:
        if a in reach:
            allowed = allowed_of(a)
            rows[a] = _row(
                draw,
                names,
                forbidden=[x for x in support if x not in allowed],
                force_one_of=[x for x in allowed if x in support],
            )
        elif zero_rows:
            rows[a] = {}
        else:
            rows[a] = preset_table["rows"][a]
    return {"rows": rows}


@st.composite
def _thetas(draw: st.DrawFn) -> Theta:
    """θ drawn part by part onto the phav-v1 preset, each part valid given those before it.

    The order of the steps is the order of the draws: changing it changes every example a
    seed gives.
    """
    data = _preset_dict()
    data["name"] = "hypothesis-theta"
    data["description"] = "drawn by phav_spec.strategies.thetas()"
    reach, zero_rows = _draw_actions(draw, data)
    _draw_human_models(draw, data, reach)
    _draw_people(draw, data)
    if draw(st.booleans()):
        data["world_variety"] = "video"
        event("theta: a look of its own per video")
    phases = _draw_weather_and_day_phases(draw, data)
    data["clock_hours"] = {d: draw(_clock_hour(d, d in phases)) for d in DAY_PHASES.names}
    _draw_base_motions(draw, data, reach)
    envs = _draw_environments(draw, data, reach, zero_rows)
    _draw_variations(draw, data, reach, zero_rows)
    _draw_cameras(draw, data, reach, envs, zero_rows)
    _draw_exposed_parameters(draw, data)
    _draw_continuous_parameters(draw, data)
    data["video"] = {
        "width": draw(st.sampled_from((340, 16, 640))),
        "height": draw(st.sampled_from((256, 16, 480))),
        "fps": draw(st.sampled_from((30, 1, 24, 60, 240))),
    }
    return parse_theta(data, source="<phav_spec.strategies.thetas>")


def _draw_actions(draw: st.DrawFn, data: dict[str, Any]) -> tuple[tuple[str, ...], bool]:
    """θ_A; returns the actions it reaches and whether unreachable actions get all-zero rows.

    Unreachable actions may keep their preset rows or get all-zero rows everywhere, which
    validation allows because nothing reaches them.
    """
    theta_a, reach = draw(_actions())
    data["theta_a"] = "uniform" if len(theta_a) == len(ACTIONS) and set(theta_a.values()) == {1.0} else theta_a
    _label_vector("action", reach, ACTIONS.names)
    unreachable = tuple(a for a in ACTIONS.names if a not in reach)
    zero_rows = bool(unreachable) and draw(st.integers(0, 2)) > 0
    if zero_rows:
        event("theta: unreachable actions with all-zero θ_AE/θ_AV/θ_AC rows")
    return reach, zero_rows


def _draw_human_models(draw: st.DrawFn, data: dict[str, Any], reach: Sequence[str]) -> None:
    """θ_H: two-people actions need a second human model with weight."""
    two_people = any(ACTIONS[a].n_people > 1 for a in reach)
    humans = _support(draw, HUMAN_MODELS.names, min_size=2 if two_people else 1)
    data["theta_h"] = _vector(draw, humans)
    _label_vector("human model", humans, HUMAN_MODELS.names)


def _draw_people(draw: st.DrawFn, data: dict[str, Any]) -> None:
    """θ's people section: none (the 20 models of H), ``mode: models`` spelt out, or people
    sampled continuously from drawn distributions (per-sex or shared weights, a sex that is
    never drawn, no children, greying as a step)."""
    case = draw(st.sampled_from(("none", "none", "models", "sampled", "sampled")))
    event(f"theta: people {case}")
    if case == "models":
        data["people"] = {"mode": "models"}
    if case != "sampled":
        return
    bounds = PEOPLE_PARAMETER_BOUNDS
    p_female = draw(_PROBABILITY)
    people: dict[str, Any] = {"mode": "sampled", "p_female": p_female, "p_child": draw(_PROBABILITY)}
    for key in ("adult_age_years", "child_age_years", "stature_z", "gender_offset", "weight", "muscle",
                "proportions", "skin_tone", "skin_undertone"):  # fmt: skip
        people[key] = _continuous(draw, *bounds[key][1:], label=f"people.{key}")
    start = draw(st.floats(0.0, 90.0))
    people["hair"] = {
        "styles": _per_sex(draw, HAIR_STYLES),
        "colours": _vector(draw, _support(draw, HAIR_COLOURS)),
        "grey": {"start_years": start, "full_years": draw(st.just(start) | st.floats(start, 90.0)),
                 "p_full": draw(_PROBABILITY)},
    }  # fmt: skip
    people["outfit"] = {
        "tops": _vector(draw, _support(draw, TOPS)),
        "bottoms": _per_sex(draw, BOTTOMS),
        "top_fabrics": _vector(draw, _support(draw, FABRICS)),
        "bottom_fabrics": _vector(draw, _support(draw, FABRICS)),
        **{key: _continuous(draw, *bounds[b][1:], label=f"people.outfit.{key}") for key, b in (
            ("saturation", "saturation"), ("value", "value"), ("shoes_saturation", "saturation"),
            ("shoes_value", "value"), ("pattern_scale", "pattern_scale"))},
    }  # fmt: skip
    if p_female in (0.0, 1.0):
        event("theta: people of one sex only")
    data["people"] = people


def _per_sex(draw: st.DrawFn, names: Sequence[str]) -> Any:
    """Weights per sex, or one set shared by both."""
    if draw(st.booleans()):
        return _vector(draw, _support(draw, names))
    return {sex: _vector(draw, _support(draw, names)) for sex in ("female", "male")}


def _draw_weather_and_day_phases(draw: st.DrawFn, data: dict[str, Any]) -> tuple[str, ...]:
    """θ_W and θ_D; returns the day phases with weight (night among them on purpose)."""
    weathers = _support(draw, WEATHERS.names)
    data["theta_w"] = _vector(draw, weathers)
    _label_vector("weather", weathers, WEATHERS.names)
    phase_case = draw(st.sampled_from(("single", "subset", "with_night")))
    if phase_case == "single":
        phases = (draw(st.sampled_from(DAY_PHASES.names)),)
    else:
        phases = _subset(draw, DAY_PHASES.names)
        if phase_case == "with_night" and "night" not in phases:
            phases = tuple(d for d in DAY_PHASES.names if d in phases or d == "night")
    data["theta_d"] = _vector(draw, phases)
    _label_vector("day phase", phases, DAY_PHASES.names)
    return phases


def _draw_base_motions(draw: st.DrawFn, data: dict[str, Any], reach: Sequence[str]) -> None:
    """θ_AB and the clip durations that every reachable action's motions allow.

    The preset regexes; some reachable actions narrowed to one motion; unreachable ones may
    lose their regex or match nothing at all.
    """
    regex = dict(data["theta_ab"]["regex"])
    ab = theta_ab(regex)
    for a in reach:
        hits = [MOTIONS.names[j] for j in range(len(MOTIONS)) if ab[ACTIONS.index(a), j] > 0]
        if draw(st.integers(0, 9)) == 0:
            motion = draw(st.sampled_from(hits))
            regex[a] = "^" + re.escape(MOTIONS[motion].description) + "$"
            event("theta: reachable action with a single base motion")
    for a in [a for a in ACTIONS.names if a not in reach]:
        fate = draw(st.sampled_from(("keep", "drop", "match_nothing")))
        if fate == "drop":
            del regex[a]
        elif fate == "match_nothing":
            regex[a] = r"(?!)"
    data["theta_ab"] = {"regex": regex}
    ab = theta_ab(regex)
    hits = {a: [x for x, hit in zip(_LENGTHS, ab[ACTIONS.index(a)], strict=True) if hit] for a in reach}
    data["durations"] = draw(_durations([max(lengths) for lengths in hits.values()]))
    if any(x < data["durations"]["t_min"] for lengths in hits.values() for x in lengths):
        event("durations: T_min masks some motions of a reachable action")


def _draw_environments(draw: st.DrawFn, data: dict[str, Any], reach: Sequence[str], zero_rows: bool) -> set[str]:
    """θ_E and θ_AE; returns the environments with weight.

    Every reachable action needs an environment with weight that has the pixel classes it
    requires (car_hit: a road, climb_stairs: stairs).
    """
    envs = set(_support(draw, ENVIRONMENTS.names))
    for a in reach:
        allowed = _allowed_environments(a)
        if not envs.intersection(allowed):
            envs.add(draw(st.sampled_from(allowed)))
    envs_t = tuple(e for e in ENVIRONMENTS.names if e in envs)
    data["theta_e"] = _vector(draw, envs_t)
    _label_vector("environment", envs_t, ENVIRONMENTS.names)
    data["theta_ae"] = _action_rows(
        draw, data["theta_ae"], ENVIRONMENTS.names, envs_t, _allowed_environments, reach, zero_rows
    )
    return envs


def _draw_variations(draw: st.DrawFn, data: dict[str, Any], reach: Sequence[str], zero_rows: bool) -> None:
    """θ_V and θ_AV: objects only where the action declares props."""
    variations = set(_support(draw, VARIATIONS.names))
    for a in reach:
        if not variations.intersection(_allowed_variations(a)):
            variations.add("none")
    variations_t = tuple(v for v in VARIATIONS.names if v in variations)
    data["theta_v"] = _vector(draw, variations_t)
    _label_vector("variation", variations_t, VARIATIONS.names)
    data["theta_av"] = _action_rows(
        draw, data["theta_av"], VARIATIONS.names, variations_t, _allowed_variations, reach, zero_rows
    )


def _draw_cameras(draw: st.DrawFn, data: dict[str, Any], reach: Sequence[str], envs: set[str], zero_rows: bool) -> None:
    """θ_C, θ_AC, θ_EC.

    One outdoor-capable camera (the fallback) with weight everywhere guarantees a camera for
    every reachable (action, environment); the indoors camera only in indoor scenes.
    """
    cameras = _camera_support(draw)
    data["theta_c"] = _vector(draw, cameras)
    fallback = draw(st.sampled_from([c for c in cameras if c in _OUTDOOR_CAMERAS]))
    ac_rows = {}
    for a in ACTIONS.names:
        if a in reach:
            ac_rows[a] = _row(draw, CAMERAS.names, force_one_of=[fallback])
        elif zero_rows:
            ac_rows[a] = {}
        else:
            ac_rows[a] = data["theta_ac"]["rows"][a]
    data["theta_ac"] = {"rows": ac_rows}
    for rows in (data["theta_ae"]["rows"], data["theta_av"]["rows"], ac_rows):
        if any(0.0 in rows[a].values() and len({w for w in rows[a].values() if w > 0}) > 1 for a in reach):
            event("theta: reachable table row with zeros and unequal weights")
            break
    ec_rows = {}
    for e in ENVIRONMENTS.names:
        indoor = ENVIRONMENT_SCENES[e].indoor
        forbidden = () if indoor else [c for c in CAMERAS.names if CAMERA_INFO[c].indoor_only]
        if e not in envs and draw(st.booleans()):
            ec_rows[e] = {}
            event("theta: environment without weight has an all-zero θ_EC row")
        else:
            ec_rows[e] = _row(draw, CAMERAS.names, forbidden=forbidden, force_one_of=[fallback])
    data["theta_ec"] = {"rows": ec_rows}


def _camera_support(draw: st.DrawFn) -> tuple[str, ...]:
    """The cameras with weight: only the kite, or a subset with an outdoor-capable camera."""
    if draw(st.integers(0, 4)) == 0:
        event("theta: only the kite camera")
        return ("kite",)
    cameras = _subset(draw, CAMERAS.names)
    if not set(cameras).intersection(_OUTDOOR_CAMERAS):
        cameras = tuple(c for c in CAMERAS.names if c in cameras or c == "kite")
    _label_vector("camera", cameras, CAMERAS.names)
    return cameras


def _draw_exposed_parameters(draw: st.DrawFn, data: dict[str, Any]) -> None:
    """Continuous and Bernoulli parameters the recipes expose as categorical columns: weather
    elements, the background actors' count, spring dead zones, the mirror probability."""
    for w in WEATHERS.names:
        spec = data["weather_elements"][w]
        for element in ("rain", "fog"):
            spec[element] = {"p": draw(_PROBABILITY)}
        for element in ("clouds", "wet_ground"):
            spec[element] = {"p_if_parent": draw(_PROBABILITY), "p_otherwise": draw(_PROBABILITY)}
    lo = draw(st.integers(0, 3))
    data["background_actors"]["count"] = {"min": lo, "max": draw(st.integers(lo, 6))}
    for cam in _SPRING_CAMERAS:
        dead = _support(draw, [str(d) for d in SPRING_MIN_DISTANCES_M])
        data["cameras"][cam]["springs"]["min_distance_weights"] = {int(d): draw(_POSITIVE) for d in dead}
    data["motion"]["p_mirror"] = draw(_PROBABILITY)


def _draw_continuous_parameters(draw: st.DrawFn, data: dict[str, Any]) -> None:
    """Continuous parameters, uniform or triangular (degenerate ones included) inside their
    bounds, and the muscle counts of the muscle variations."""
    for path, key in _BOUNDED_PARAMETERS:
        node = data
        for part in path[:-1]:
            node = node[part]
        node[path[-1]] = _continuous(draw, *PARAMETER_BOUNDS[key][1:], label=key)
    for cam in CAMERAS.names:
        for field in ("fov_deg", "distance_m", "height_m", "azimuth_deg"):
            data["cameras"][cam][field] = _continuous(draw, *CAMERA_PLACEMENT_VARIABLES[field][1:], label=field)
    for kind in ("random_perturbation", "muscle_weakening", "action_blending"):
        lo = draw(st.integers(1, len(MUSCLES)))
        data["variations"][kind]["n_muscles"] = {"min": lo, "max": draw(st.integers(lo, len(MUSCLES)))}


#: θ leaves drawn by ``_continuous`` in ``thetas()``, with their PARAMETER_BOUNDS key.
_BOUNDED_PARAMETERS: tuple[tuple[tuple[str, ...], str], ...] = (
    (("motion", "speed"), "motion_speed"),
    (("protagonist_heading_deg",), "heading_deg"),
    (("background_actors", "speed_mps"), "background_speed_mps"),
    (("supporting_characters", "side_distance_m"), "supporting_distance_m"),
    (("supporting_characters", "facing_distance_m"), "supporting_distance_m"),
    (("variations", "random_perturbation", "period_s"), "perturbation_period_s"),
    (("variations", "muscle_weakening", "strength"), "weakening_strength"),
    (("variations", "action_blending", "weight"), "blending_weight"),
)


def _continuous(draw: st.DrawFn, lo: float, hi: float, *, label: str) -> dict[str, Any]:
    """A uniform or triangular θ distribution inside [lo, hi], degenerate cases included."""
    points = sorted(draw(st.lists(st.floats(lo, hi, allow_nan=False), min_size=3, max_size=3)))
    shape = draw(st.sampled_from(("uniform", "triangular", "point", "mode_at_min", "mode_at_max")))
    event(f"theta: {label} {shape}")
    a, c, b = points
    if shape == "uniform":
        return {"kind": "uniform", "low": a, "high": b}
    if shape == "point":
        return {"kind": "uniform", "low": c, "high": c}
    if shape == "mode_at_min":
        c = a
    elif shape == "mode_at_max":
        c = b
    return {"kind": "triangular", "min": a, "max": b, "mode": c}


def thetas() -> st.SearchStrategy[Theta]:
    """Valid θ: modifications of the ``phav-v1`` preset, valid by construction.

    Reaches single-value supports (one action, weather, day phase, only the kite camera),
    all-zero rows for unreachable actions, non-uniform weights with zeros, degenerate and
    midnight-wrapping clock triangles (night with weight), degenerate duration triangles,
    T_min close to the longest motion of a reachable action, and people from H or sampled
    continuously (a ``people`` section, one sex only among its cases); each is labelled
    with ``hypothesis.event``.
    """
    return _thetas()


# ----------------------------------------------------------------------------- recipes

_COORD = st.floats(-1.0e4, 1.0e4, allow_nan=False)
_ANY_FINITE = st.floats(allow_nan=False, allow_infinity=False)
_UNIT = st.floats(0.0, 1.0)
_SEED = st.integers(0, 2**32 - 1)
_HASH = st.text(alphabet="0123456789abcdef", min_size=64, max_size=64)
_ALMOST_24 = math.nextafter(24.0, 0.0)


def _vec3(coord: st.SearchStrategy[float] = _COORD) -> st.SearchStrategy[tuple[float, float, float]]:
    return st.tuples(coord, coord, coord)


_BYTE = st.integers(0, 255)
_RGB = st.tuples(_BYTE, _BYTE, _BYTE)


def _hsv() -> st.SearchStrategy[dict[str, float]]:
    return st.fixed_dictionaries(
        {"hue_deg": st.floats(0.0, 360.0, exclude_max=True), "saturation": _UNIT, "value": _UNIT}
    )


@st.composite
def _garment(draw: st.DrawFn, kinds: Sequence[str]) -> dict[str, Any]:
    return {
        "kind": draw(st.sampled_from(tuple(kinds))),
        "fabric": draw(st.sampled_from(FABRICS)),
        "rgb": draw(_RGB),
        "pattern_rgb": draw(_RGB),
        "scale": draw(st.floats(0.1, 10.0)),
    }


@st.composite
def _sampled_human(draw: st.DrawFn) -> dict[str, Any]:
    """A person as θ's people section could draw one: any phenotype, look and draws."""
    child = draw(st.booleans())
    age = draw(st.floats(MIN_AGE_YEARS, ADULT_AGE_YEARS) if child else st.floats(ADULT_AGE_YEARS, 90.0))
    event("recipe: sampled child" if child else "recipe: sampled adult")
    keys = ("gender", "age", "muscle", "weight", "height", "proportions")
    return {
        "model": SAMPLED_PERSON,
        "phenotype": {k: draw(_UNIT) for k in keys},
        "skin_rgb": draw(_RGB),
        "hair": {"style": draw(st.sampled_from(HAIR_STYLES)), "rgb": draw(_RGB)},
        "outfit": {"top": draw(_garment(TOPS)), "bottom": draw(_garment(BOTTOMS)), "shoes_rgb": draw(_RGB)},
        "sampled": {
            "female": draw(st.booleans()),
            "adult_age_years": None if child else age,
            "child_age_years": age if child else None,
            "stature_z": draw(st.floats(-3.0, 3.0)),
            "stature_m": draw(st.floats(0.5, 2.5)),
            "gender_offset": draw(st.floats(0.0, 0.45)),
            "skin_tone": draw(_UNIT),
            "skin_undertone": draw(st.floats(-1.0, 1.0)),
            "hair_colour": draw(st.sampled_from((*HAIR_COLOURS, "grey"))),
            "hair_shade": draw(_UNIT),
            "garment_colours": draw(st.lists(_hsv(), min_size=4, max_size=4)),
            "shoes_colour": draw(_hsv()),
        },
    }


def _human(draw: st.DrawFn, people: str) -> dict[str, Any]:
    """A person: one of the 20 models of H (``people`` "models"), sampled ("sampled"), or either ("any")."""
    if people == "sampled" or (people == "any" and draw(st.integers(0, 2)) == 0):
        return draw(_sampled_human())
    name = draw(st.sampled_from(HUMAN_MODELS.names))
    return HUMAN_MODELS[name].human(name)


@st.composite
def _variation(draw: st.DrawFn, action: str) -> dict[str, Any]:
    kind = draw(st.sampled_from(VARIATIONS.names))
    event(f"recipe: variation {kind}")
    scene = ACTION_SCENES[action]
    pool = scene.complementary_muscles or MUSCLES.names
    if kind == "random_perturbation":
        return {
            "kind": kind,
            "muscles": _subset(draw, pool),
            "radius_m": draw(st.floats(0.0, 1.0)),
            "period_s": draw(st.floats(0.05, 10.0)),
        }
    if kind == "muscle_weakening":
        muscles = _subset(draw, MUSCLES.names)
        strengths = draw(st.lists(_UNIT, min_size=len(muscles), max_size=len(muscles)))
        return {"kind": kind, "muscles": muscles, "strengths": tuple(strengths)}
    if kind == "action_blending":
        return {
            "kind": kind,
            "muscles": _subset(draw, pool),
            "blend_motion": draw(st.sampled_from(MOTIONS.names)),
            "blend_start_s": draw(st.floats(0.0, 60.0)),
            "weight": draw(_UNIT),
        }
    if kind == "objects":
        return {"kind": kind, "object": draw(st.sampled_from(scene.variation_objects or OBJECTS.names))}
    return {"kind": "none"}


@st.composite
def _duration(draw: st.DrawFn, fps: int, longest: float) -> float:
    """Clip length in seconds, at most ``longest`` (the take's); a share of draws is short
    enough for a single frame."""
    if draw(st.integers(0, 4)) == 0:
        duration = draw(st.floats(1e-3, min(1.49 / fps, longest)))
    else:
        duration = draw(st.floats(1e-3, min(12.0, longest)))
    if frames_for(duration, fps) == 1:
        event("recipe: n_frames == 1")
    return duration


@st.composite
def _clock_hour_value(draw: st.DrawFn) -> float:
    hour = draw(
        st.one_of(
            st.floats(0.0, 24.0, exclude_max=True),
            st.sampled_from((0.0, 5e-324, 1e-9, 23.999999, _ALMOST_24)),
            st.floats(0.0, 1e-3),
            st.floats(23.999, 24.0, exclude_max=True),
        )
    )
    if hour < 1e-3:
        event("recipe: clock_hour near 0")
    if hour > 24.0 - 1e-3:
        event("recipe: clock_hour near 24")
    return hour


@st.composite
def _camera(draw: st.DrawFn, indoor: bool, position: tuple[float, float, float]) -> dict[str, Any]:
    kind = draw(st.sampled_from(CAMERAS.names if indoor else _OUTDOOR_CAMERAS))
    springs = impulse = None
    if CAMERA_INFO[kind].tracking == "springs":
        event("recipe: spring camera")
        springs = {
            "ct_spring_strength": draw(st.floats(0.1, 1.0e5)),
            "tp_spring_strength": draw(st.floats(0.1, 1.0e5)),
            "camera_mass": draw(st.floats(0.01, 100.0)),
            "target_mass": draw(st.floats(0.01, 100.0)),
            "camera_drag": draw(st.floats(0.0, 50.0)),
            "target_drag": draw(st.floats(0.0, 50.0)),
            "ct_min_distance_m": draw(st.sampled_from(SPRING_MIN_DISTANCES_M)),
            "tp_min_distance_m": draw(st.sampled_from(SPRING_MIN_DISTANCES_M)),
        }
        impulse = {
            # at most MAX_CAMERA_KICK_MPS over the camera's mass: a recipe refuses a harder kick
            "strength": draw(st.floats(0.0, min(10.0, MAX_CAMERA_KICK_MPS * springs["camera_mass"]))),
            "azimuth_deg": draw(st.floats(-180.0, 180.0)),
            "elevation_deg": draw(st.floats(-90.0, 90.0)),
        }
    else:
        event("recipe: non-spring camera")
    x, y, z = position
    return {
        "kind": kind,
        "fov_deg": draw(st.floats(10.0, 120.0)),
        "distance_m": draw(st.floats(0.3, 60.0)),
        "height_m": draw(st.floats(-2.0, 30.0)),
        "azimuth_deg": draw(st.floats(-360.0, 360.0)),
        "position": draw(_vec3()),
        "target": (x, y, z + draw(st.floats(0.0, 2.0))),
        "springs": springs,
        "impulse": impulse,
    }


@st.composite
def _recipes(draw: st.DrawFn, theta: Theta | None, index: int | None) -> Recipe:
    """A recipe drawn field by field, not by the sampler (the draw order is what a seed gives)."""
    if index is None:
        index = draw(st.one_of(st.integers(0, 999), st.integers(0, 10**9)))
    theta_hash, video, render = _recipe_format(draw, theta)
    people = "any" if theta is None else "sampled" if theta.people is not None else "models"
    # Two-people actions are 4 of 35: draw them on purpose too, for supporting characters.
    action = draw(st.one_of(st.sampled_from(ACTIONS.names), st.sampled_from(_TWO_PEOPLE)))
    variation = draw(_variation(action))
    base = draw(st.sampled_from(MOTIONS.names))
    duration = draw(_duration(video["fps"], MOTIONS[base].length_s))
    env_name = draw(st.sampled_from(ENVIRONMENTS.names))
    env = ENVIRONMENT_SCENES[env_name]
    wp = draw(st.integers(0, len(env.protagonist_waypoints) - 1))
    position = env.protagonist_waypoints[wp]
    heading = draw(st.one_of(st.floats(0.0, 360.0), _ANY_FINITE))
    supporting = _supporting_characters(draw, action)
    n_people = 1 + len(supporting)
    background = _background_actors(draw, env_name, first_person_id=n_people)
    world = _world(draw)
    # the environment's look: as θ says (one per environment, or a video's own seed); either without θ
    looks = st.none() | _SEED if theta is None else _SEED if theta.world_variety == "video" else st.none()
    look_seed = draw(looks)
    data = {
        "video_id": video_id(index),
        "index": index,
        "dataset_seed": draw(st.integers(0, 2**63 - 1)),
        "theta_hash": theta_hash,
        "action": action,
        "n_people": n_people,
        "duration_s": duration,
        "n_frames": frames_for(duration, video["fps"]),
        "video": video,
        "motion": {
            "base_motion": base,
            "base_motion_length_s": MOTIONS[base].length_s,
            "start_s": draw(st.floats(0.0, MOTIONS[base].length_s)),
            "speed": draw(st.floats(0.1, 4.0)),
            "mirror": draw(st.booleans()),
        },
        "variation": variation,
        "protagonist": {
            "position": position,
            "heading_deg": heading,
        },
        "supporting_characters": supporting,
        "environment": {
            "name": env_name,
            "indoor": env.indoor,
            "waypoint_index": wp,
            "waypoint": position,
            "look_seed": look_seed,
        },
        "background_actors": background,
        "camera": draw(_camera(env.indoor, position)),
        "world": world,
        "render": render,
        "seeds": {name: draw(_SEED) for name in ("physics", "perturbation", "render", "background")},
    }
    # People last: a sampled person is many draws, and the structure above comes first.
    for person in (data["protagonist"], *supporting, *background):
        person["human"] = _human(draw, people)
    return Recipe.model_validate(data)


def _recipe_format(draw: st.DrawFn, theta: Theta | None) -> tuple[str, dict[str, Any], RenderSettings]:
    """θ's hash, video format and render settings: ``theta``'s, or drawn when there is none."""
    if theta is not None:
        return theta.hash, theta.video.model_dump(), theta.render
    theta_hash = draw(_HASH)
    video = {
        "width": draw(st.integers(16, 4096)),
        "height": draw(st.integers(16, 4096)),
        "fps": draw(st.one_of(st.sampled_from((30, 1, 24, 60)), st.integers(1, 240))),
    }
    render = RenderSettings(supersampling=draw(st.sampled_from((1, 2, 4))), png_compression=draw(st.integers(0, 9)))
    return theta_hash, video, render


def _supporting_characters(draw: st.DrawFn, action: str) -> list[dict[str, Any]]:
    """The supporting character of a two-people action (person 1), none otherwise (its
    ``human`` is drawn by the caller)."""
    placement = ACTION_SCENES[action].supporting_placement
    if placement is None:
        return []
    event("recipe: supporting character")
    return [{
        "person_id": 1,
        "placement": placement,
        "distance_m": draw(st.floats(0.0, 10.0)),
        "position": draw(_vec3()),
        "heading_deg": draw(st.floats(-360.0, 360.0)),
    }]  # fmt: skip


def _background_actors(draw: st.DrawFn, environment: str, *, first_person_id: int) -> list[dict[str, Any]]:
    """Up to four background actors walking between distinct waypoints of the environment's
    graph (their ``human`` is drawn by the caller)."""
    graph = ENVIRONMENT_SCENES[environment].background_waypoints
    background = []
    n_background = draw(st.integers(0, 4)) if graph else 0
    for k in range(n_background):
        start = draw(st.integers(0, len(graph) - 1))
        dest = draw(st.integers(0, len(graph) - 2))
        dest += dest >= start
        background.append({
            "person_id": first_person_id + k,
            "start_waypoint": start,
            "destination_waypoint": dest,
            "start": graph[start],
            "destination": graph[dest],
            "speed_mps": draw(st.floats(0.1, 3.0)),
        })  # fmt: skip
    event("recipe: no background actors" if not background else "recipe: background actors")
    if len(background) >= 2:
        event("recipe: several background actors")
    return background


def _world(draw: st.DrawFn) -> dict[str, Any]:
    """Day phase, clock, weather and its elements; an intensity is drawn only while its element is on."""
    rain, fog = draw(st.booleans()), draw(st.booleans())
    return {
        "day_phase": draw(st.sampled_from(DAY_PHASES.names)),
        "clock_hour": draw(_clock_hour_value()),
        "weather": draw(st.sampled_from(WEATHERS.names)),
        "sun_brightness": draw(st.floats(0.0, 2.0)),
        "ambient_luminosity": draw(st.floats(0.0, 2.0)),
        "rain": rain,
        "fog": fog,
        "clouds": draw(st.booleans()),
        "wet_ground": draw(st.booleans()),
        "cloud_intensity": draw(_UNIT),
        "fog_intensity": draw(_UNIT) if fog else 0.0,
        "rain_intensity": draw(_UNIT) if rain else 0.0,
    }


def recipes(theta: Theta | None = None) -> st.SearchStrategy[Recipe]:
    """Valid recipes built field by field (not by the sampler).

    Names come from the vocabularies, ``n_frames`` = ``frames_for(duration_s, fps)``,
    ``video_id`` = ``video_id(index)``, ``n_people`` counts the protagonist and the
    supporting character of a two-people action, person ids are unique and spring
    parameters appear exactly on spring cameras. People are fixed models of H or sampled
    persons (with ``theta``: the kind θ draws). With ``theta``, recipes carry its hash,
    video format and render settings. Reaches one-frame clips, every variation kind, zero
    and several background actors, supporting characters, spring and non-spring cameras
    and clock hours next to 0 h and 24 h (each labelled with ``hypothesis.event``).
    """
    return _recipes(theta, None)


@st.composite
def _recipe_lists(draw: st.DrawFn, theta: Theta | None, min_size: int, max_size: int) -> list[Recipe]:
    indices = draw(st.lists(st.integers(0, 10**7), min_size=min_size, max_size=max_size, unique=True))
    if not indices:
        event("recipe list: empty")
    return [draw(_recipes(theta, i)) for i in indices]


def recipe_lists(
    min_size: int = 0, max_size: int = 6, *, theta: Theta | None = None
) -> st.SearchStrategy[list[Recipe]]:
    """Lists of :func:`recipes` with distinct indices (hence distinct video ids), empty included."""
    if not 0 <= min_size <= max_size:
        raise ValueError(f"need 0 <= min_size <= max_size, got {min_size} and {max_size}")
    return _recipe_lists(theta, min_size, max_size)
