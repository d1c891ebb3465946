"""Property tests of θ → recipes over hypothesis-drawn θ (phav_generator.sampling).

Support, determinism, the prefix property, exact JSON/Parquet round trips, the triangular
sampler against its own CDF, and the rule that nothing calls the global random functions.
"""

# This file calls the legacy global numpy.random functions on purpose: to prove that the
# guard below catches them, and to read the global state it must leave untouched.
# ruff: noqa: NPY002

from __future__ import annotations

import contextlib
import random
import re
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import scipy.integrate
import scipy.stats
from hypothesis import event, given, settings
from hypothesis import strategies as st

import phav_generator
import phav_spec
import phav_validators
from phav_generator.sampling import RecipeSampler, sample_recipes
from phav_spec.distributions import Triangular, Uniform
from phav_spec.expectations import exact_expectations
from phav_spec.motions import MOTIONS
from phav_spec.population import age_years
from phav_spec.recipe import Recipe, frames_for, parse_recipe
from phav_spec.recipe_table import (
    COLUMN_NAMES,
    COLUMNS,
    RECIPE_COLUMN,
    RecipeRows,
    read_recipe_table,
    write_recipe_table,
)
from phav_spec.scene import ACTION_SCENES, ENVIRONMENT_SCENES
from phav_spec.strategies import thetas
from phav_spec.theta import Theta, load_preset

PHAV_V1 = load_preset("phav-v1")
SEEDS = st.integers(0, 2**64 - 1)
EXTRACT: dict[str, Callable[[Recipe], Any]] = {c.name: c.extract for c in COLUMNS}
#: Every example of the θ tests draws a θ (``thetas()``, ~0.2 s: most of their time), so they
#: take a quarter of the profile's examples (ci 10, dev 50); the support test, the one that
#: finds a θ a sampler mishandles, takes half (ci 20, dev 100) and more recipes from each.
THETA_EXAMPLES = max(10, settings.default.max_examples // 4)
SUPPORT_EXAMPLES = max(10, settings.default.max_examples // 2)


# --------------------------------------------------------------------------- support


def _in_clock_interval(theta: Theta, recipe: Recipe) -> bool:
    spec = theta.clock_hours[recipe.world.day_phase]
    hour = recipe.world.clock_hour
    if spec.min > spec.max:  # wraps midnight: [min, 24) ∪ [0, max]
        return hour >= spec.min or hour <= spec.max
    return spec.min <= hour <= spec.max


@settings(max_examples=SUPPORT_EXAMPLES)
@given(theta=thetas(), seed=SEEDS)
def test_sampled_values_have_positive_probability_under_theta(theta: Theta, seed: int) -> None:
    tables = exact_expectations(theta)
    assert set(tables) <= set(COLUMN_NAMES)
    dur = theta.durations
    for recipe in sample_recipes(theta, n=50, seed=seed):
        assert recipe.theta_hash == theta.hash
        for name, table in tables.items():
            value = EXTRACT[name](recipe)
            if value is None:  # the variable does not apply to this video
                assert table.applies_to != "every video", name
                continue
            observations = value if table.multi else [value]  # list columns: one per element
            if not observations:
                continue
            key = tuple(EXTRACT[parent](recipe) for parent in table.parents)
            assert key in table.rows, f"{name}: parents {key} have probability 0 under θ"
            for x in observations:
                assert x in table.values, f"{name}: {x!r} is not a value of the variable"
                p = table.rows[key][table.values.index(x)]
                assert p > 0, f"{name} = {x!r} given {key} has probability 0 under θ"
        length_b = MOTIONS[recipe.motion.base_motion].length_s
        assert recipe.motion.base_motion_length_s == length_b
        assert dur.t_min <= recipe.duration_s <= min(length_b, dur.t_max)
        assert recipe.n_frames == frames_for(recipe.duration_s, theta.video.fps)
        assert 0.0 <= recipe.world.clock_hour < 24.0
        assert _in_clock_interval(theta, recipe), (recipe.world.day_phase, recipe.world.clock_hour)
        _assert_parameters_in_support(theta, recipe)


def _within(dist: Uniform | Triangular, x: float) -> bool:
    lo, hi = dist.support
    return lo <= x <= hi


def _assert_parameters_in_support(theta: Theta, recipe: Recipe) -> None:
    """The continuous and structural parameters stay where θ and the scene declarations allow."""
    world, wt = recipe.world, theta.weather_elements[recipe.world.weather]
    assert _within(wt.sun_brightness, world.sun_brightness)
    assert _within(wt.ambient_luminosity, world.ambient_luminosity)
    for element, key in (("clouds", "cloud_intensity"), ("fog", "fog_intensity"), ("rain", "rain_intensity")):
        value = getattr(world, key)
        assert _within(getattr(wt, key), value) if getattr(world, element) else value == 0.0, key
    assert _within(theta.motion.speed, recipe.motion.speed)
    assert _within(theta.protagonist_heading_deg, recipe.protagonist.heading_deg)
    cam = theta.cameras[recipe.camera.kind]
    for name in ("fov_deg", "distance_m", "height_m", "azimuth_deg"):
        assert _within(getattr(cam, name), getattr(recipe.camera, name)), name
    env = ENVIRONMENT_SCENES[recipe.environment.name]
    count = theta.background_actors.count
    if env.background_waypoints:
        assert count.min <= len(recipe.background_actors) <= count.max
    for actor in recipe.background_actors:
        assert _within(theta.background_actors.speed_mps, actor.speed_mps)
        assert actor.start_waypoint != actor.destination_waypoint
        assert actor.human.model == "sampled" if theta.people else theta.theta_h[actor.human.model] > 0
    _assert_people_in_support(theta, recipe)
    scene = ACTION_SCENES[recipe.action]
    v = recipe.variation
    if v.kind in ("random_perturbation", "action_blending"):
        assert set(v.muscles) <= set(scene.complementary_muscles)
    if v.kind == "action_blending":
        assert v.blend_motion != recipe.motion.base_motion
    if v.kind == "objects":
        assert v.object in scene.variation_objects


def _assert_people_in_support(theta: Theta, recipe: Recipe) -> None:
    """Sampled people: every draw inside θ's support, a child only where the action allows
    one (background pedestrians always may be), the phenotype made from the draws."""
    people = theta.people
    roles = [(recipe.protagonist, True), *((s, True) for s in recipe.supporting_characters)]
    roles += [(a, False) for a in recipe.background_actors]
    for person, in_action in roles:
        human = person.human
        if people is None:
            assert human.model != "sampled" and human.sampled is None
            continue
        d = human.sampled
        assert human.model == "sampled" and d is not None
        if d.child:
            assert people.p_child > 0 and (not in_action or ACTION_SCENES[recipe.action].children)
            assert _within(people.child_age_years, d.child_age_years)
        else:
            assert _within(people.adult_age_years, d.adult_age_years)
        for name in ("stature_z", "gender_offset", "skin_tone", "skin_undertone"):
            assert _within(getattr(people, name), getattr(d, name)), name
        for name in ("weight", "muscle", "proportions"):
            assert _within(getattr(people, name), getattr(human.phenotype, name)), name
        assert d.female == (human.phenotype.gender > 0.5)
        assert people.p_sex()["female" if d.female else "male"] > 0
        assert abs(age_years(human.phenotype.age) - d.age_years) < 1e-9
        o = people.outfit
        for c in d.garment_colours:
            assert _within(o.saturation, c.saturation) and _within(o.value, c.value)
        assert _within(o.shoes_saturation, d.shoes_colour.saturation) and _within(o.shoes_value, d.shoes_colour.value)
        for garment in (human.outfit.top, human.outfit.bottom):
            assert _within(o.pattern_scale, garment.scale)
        sex = "female" if d.female else "male"
        assert people.hair.styles[sex][human.hair.style] > 0
        assert people.outfit.bottoms[sex][human.outfit.bottom.kind] > 0
        assert people.outfit.tops[human.outfit.top.kind] > 0
        assert d.hair_colour == "grey" or people.hair.colours[d.hair_colour] > 0


# --------------------------------------------------------------------------- determinism


@settings(max_examples=THETA_EXAMPLES)
@given(
    theta=thetas(),
    seed=SEEDS,
    indices=st.lists(st.integers(0, 10**6), min_size=1, max_size=8, unique=True),
)
def test_same_theta_seed_and_index_give_the_same_recipe(theta: Theta, seed: int, indices: list[int]) -> None:
    first, second = RecipeSampler(theta), RecipeSampler(theta)
    forward = [first.sample(seed, i) for i in indices]
    backward = [second.sample(seed, i) for i in reversed(indices)][::-1]
    assert forward == backward
    assert [r.model_dump_json() for r in forward] == [r.model_dump_json() for r in backward]
    # A sampler that just drew from another dataset gives the same recipe again.
    for i, expected in zip(indices, forward, strict=True):
        second.sample(seed ^ 1, i)
        assert second.sample(seed, i).model_dump_json() == expected.model_dump_json()


def _content(recipe: Recipe) -> str:
    """The recipe's JSON without what names the video: what was drawn, and the run-time seeds."""
    return recipe.model_dump_json(exclude={"dataset_seed", "index", "video_id"})


@settings(max_examples=THETA_EXAMPLES)
@given(theta=thetas(), seed=SEEDS, step=st.integers(1, 2**32))
def test_different_seeds_or_indices_give_different_recipes(theta: Theta, seed: int, step: int) -> None:
    other = (seed + step) % 2**64
    sampler = RecipeSampler(theta)
    mine = [sampler.sample(seed, i) for i in (0, 1, 2)]
    theirs = [sampler.sample(other, i) for i in (0, 1, 2)]
    for a, b in zip(mine, theirs, strict=True):
        assert _content(a) != _content(b)
        # Not only the run-time seeds: the drawn content differs too.
        assert a.model_copy(update={"seeds": b.seeds}) != b.model_copy(update={"dataset_seed": a.dataset_seed})
    # Videos of one dataset differ from each other, not only in their index.
    assert len({_content(r) for r in mine}) == len(mine)


@settings(max_examples=THETA_EXAMPLES)
@given(theta=thetas(), seed=SEEDS)
def test_a_shorter_or_shifted_run_is_a_slice_of_a_longer_one(theta: Theta, seed: int) -> None:
    full = list(sample_recipes(theta, n=12, seed=seed))
    assert [r.index for r in full] == list(range(12))
    assert list(sample_recipes(theta, n=5, seed=seed)) == full[:5]
    assert list(sample_recipes(theta, n=3, seed=seed, start=7)) == full[7:10]
    assert list(sample_recipes(theta, n=0, seed=seed)) == []


# --------------------------------------------------------------------------- round trips


@settings(max_examples=THETA_EXAMPLES)
@given(theta=thetas(), seed=SEEDS)
def test_sampled_recipes_round_trip_exactly(theta: Theta, seed: int, tmp_path_factory: pytest.TempPathFactory) -> None:
    recipes = list(sample_recipes(theta, n=10, seed=seed))
    for recipe in recipes:
        text = recipe.model_dump_json()
        again = parse_recipe(text)
        assert again == recipe
        assert again.model_dump_json() == text
    rows = RecipeRows().extend(recipes)
    path = tmp_path_factory.mktemp("recipes") / "recipes.parquet"
    write_recipe_table(rows.to_arrow(theta=theta, dataset_seed=seed), path)
    back = read_recipe_table(path)
    for name in (*COLUMN_NAMES, RECIPE_COLUMN):
        assert back.column(name) == rows.columns[name], name
    assert list(back.recipes()) == recipes
    assert back.theta == theta
    assert back.dataset_seed == seed


# --------------------------------------------------------------------------- triangular

_PERIOD = 24.0


#: Tr(a, b, c) on the line and on a 24 h clock (``clock``: period set, no wrap), and
#: wrapping midnight: support [min, 24) ∪ [0, max] with the mode before or after midnight.
TRIANGLE_CASES = ("general", "a==c", "c==b", "a==b", "clock", "wrap", "wrap:a==c", "wrap:c==b", "wrap:after")


@st.composite
def triangles(draw: st.DrawFn, case: str) -> Triangular:
    """A triangular distribution of one of the :data:`TRIANGLE_CASES`."""
    event(f"triangular: {case}")
    if not case.startswith("wrap"):
        if case == "clock":
            a = draw(st.floats(0.0, 23.0))
            b = draw(st.floats(a + 1e-3, 24.0, exclude_max=True))
        else:
            a = draw(st.floats(-1000.0, 1000.0))
            b = a + draw(st.one_of(st.sampled_from((1.0, 24.0)), st.floats(1e-3, 1000.0)))
        if case in ("a==c", "a==b"):
            c = a
        elif case == "c==b":
            c = b
        else:
            c = draw(st.floats(a, b))
        if case == "a==b":
            b = a
        return Triangular(min=a, max=b, mode=c, period=_PERIOD if case == "clock" else None)
    lo = draw(st.floats(0.0, 23.0))
    hi = draw(st.floats(lo + 1e-3, 23.999))
    if case == "wrap:a==c":
        mode = hi
    elif case == "wrap:c==b":
        mode = lo
    elif case == "wrap:after":
        mode = draw(st.floats(0.0, lo))
    else:
        mode = draw(st.floats(hi, 24.0, exclude_max=True))
    return Triangular(min=hi, max=lo, mode=mode, period=_PERIOD)


def _samples(tri: Triangular, n: int = 4000) -> np.ndarray:
    rng = np.random.Generator(np.random.PCG64(20240601))
    return np.array([tri.sample(rng=rng) for _ in range(n)])


@pytest.mark.parametrize("case", TRIANGLE_CASES)
@settings(max_examples=12)
@given(data=st.data())
def test_triangular_samples_match_the_cdf(case: str, data: st.DataObject) -> None:
    tri = data.draw(triangles(case), label="tri")
    xs = _samples(tri)
    a, b = tri.min, tri.max
    if tri.wraps:
        assert np.all((xs >= 0.0) & (xs < tri.period))
        assert np.all((xs >= a) | (xs <= b)), xs[(xs < a) & (xs > b)]
    else:
        assert np.all((xs >= a) & (xs <= b)), (xs.min(), xs.max())
    if a == b:
        assert np.all(xs == a)
        return
    result = scipy.stats.kstest(xs, tri.cdf)
    assert result.pvalue > 1e-6, result


@pytest.mark.parametrize("case", TRIANGLE_CASES)
@settings(max_examples=12)
@given(data=st.data())
def test_triangular_cdf_is_monotone_and_pdf_integrates_to_one(case: str, data: st.DataObject) -> None:
    tri = data.draw(triangles(case), label="tri")
    a, b = tri.min, tri.max
    if tri.wraps:
        grid = np.unique(np.concatenate([np.linspace(0.0, tri.period, 4001)[:-1], [a, b, tri.mode]]))
        below, above = -1.0, tri.period + 1.0
    else:
        grid = np.unique(np.concatenate([np.linspace(a - 1.0, b + 1.0, 4001), [a, b, tri.mode]]))
        below, above = a - 1.0, b + 1.0
    cdf = tri.cdf(grid)
    assert np.all((cdf >= 0.0) & (cdf <= 1.0))
    assert np.all(np.diff(cdf) >= -1e-12)
    assert tri.cdf(below) == 0.0 and tri.cdf(above) == 1.0
    if a == b:  # a point mass: a step at a, no density to integrate
        assert tri.cdf(np.nextafter(a, -np.inf)) == 0.0 and tri.cdf(a) == 1.0
        return
    if tri.wraps:
        gap = 0.5 * (a + b)  # inside (max, min), where the clock never stops
        assert tri.pdf(gap) == 0.0
        assert tri.cdf(gap) == pytest.approx(float(tri.cdf(b)), abs=1e-12)
        left = np.linspace(a, tri.period, 20001)
        right = np.linspace(0.0, b, 20001)
        total = scipy.integrate.trapezoid(tri.pdf(left), left) + scipy.integrate.trapezoid(tri.pdf(right), right)
    else:
        assert tri.cdf(a) == 0.0 and tri.cdf(b) == 1.0
        assert tri.pdf(below) == 0.0 and tri.pdf(above) == 0.0
        x = np.linspace(a, b, 20001)
        pdf = tri.pdf(x)
        total = scipy.integrate.trapezoid(pdf, x)
        running = scipy.integrate.cumulative_trapezoid(pdf, x, initial=0.0)
        assert np.max(np.abs(running - tri.cdf(x))) < 1e-3
    assert total == pytest.approx(1.0, abs=1e-3)


# --------------------------------------------------------------------------- no global randomness

#: Constructors that take an explicit seed or bit generator: usable, but never unseeded.
_SEEDED_CLASSES = ("SeedSequence", "PCG64", "PCG64DXSM", "Philox", "SFC64", "MT19937", "RandomState")
#: Explicit-state types with nothing global behind them.
_EXPLICIT = ("Generator", "BitGenerator")


class GlobalRandomnessUsed(AssertionError):
    pass


def _forbidden(name: str) -> Callable[..., Any]:
    def call(*args: Any, **kwargs: Any) -> Any:
        raise GlobalRandomnessUsed(f"{name} called: draw from an explicit np.random.Generator instead")

    return call


def _seeded_only(cls: type, name: str) -> type:
    """A subclass of ``cls`` that refuses to seed itself from the OS (no argument or None)."""

    def __init__(self: Any, seed: Any = None, *args: Any, **kwargs: Any) -> None:
        if seed is None:
            raise GlobalRandomnessUsed(f"{name}() without a seed draws OS entropy")
        cls.__init__(self, seed, *args, **kwargs)

    return type(cls.__name__, (cls,), {"__init__": __init__})


def _default_rng(seed: Any = None) -> np.random.Generator:
    if seed is None:
        raise GlobalRandomnessUsed("numpy.random.default_rng() without a seed draws OS entropy")
    return _REAL_DEFAULT_RNG(seed)


_REAL_DEFAULT_RNG = np.random.default_rng


@contextlib.contextmanager
def forbid_global_randomness() -> Iterator[None]:
    """Every public numpy.random and random function raises; seeded constructors still work."""
    np_state, py_state = np.random.get_state(), random.getstate()
    patch = pytest.MonkeyPatch()
    try:
        for name in np.random.__all__:
            obj = getattr(np.random, name)
            if name in _EXPLICIT or not callable(obj):
                continue
            if name in _SEEDED_CLASSES:
                patch.setattr(np.random, name, _seeded_only(obj, f"numpy.random.{name}"))
            elif name == "default_rng":
                patch.setattr(np.random, name, _default_rng)
            else:
                patch.setattr(np.random, name, _forbidden(f"numpy.random.{name}"))
        for name in random.__all__:
            obj = getattr(random, name)
            if name == "Random":
                patch.setattr(random, name, _seeded_only(obj, "random.Random"))
            elif callable(obj):
                patch.setattr(random, name, _forbidden(f"random.{name}"))
        yield
    finally:
        patch.undo()
    after = np.random.get_state()
    assert after[0] == np_state[0] and np.array_equal(after[1], np_state[1]) and after[2:] == np_state[2:]
    assert random.getstate() == py_state


def test_the_guard_catches_global_calls() -> None:
    """The guard itself works: each kind of global call fails inside it, seeded ones pass."""
    with forbid_global_randomness():
        for call in (
            lambda: np.random.random(),
            lambda: np.random.rand(2),
            lambda: np.random.randn(2),
            lambda: np.random.randint(3),
            lambda: np.random.choice(3),
            lambda: np.random.uniform(),
            lambda: np.random.normal(),
            lambda: np.random.seed(0),
            lambda: np.random.shuffle([1, 2]),
            lambda: np.random.permutation(3),
            lambda: np.random.default_rng(),
            lambda: np.random.default_rng(None),
            lambda: np.random.PCG64(),
            lambda: np.random.SeedSequence(),
            lambda: random.random(),
            lambda: random.randint(0, 3),
            lambda: random.choice([1, 2]),
            lambda: random.uniform(0, 1),
            lambda: random.shuffle([1, 2]),
            lambda: random.seed(0),
            lambda: random.getrandbits(8),
            lambda: random.sample([1, 2], 1),
            lambda: random.Random(),
        ):
            with pytest.raises(GlobalRandomnessUsed):
                call()
        assert 0.0 <= np.random.default_rng(1).random() < 1.0
        rng = np.random.Generator(np.random.PCG64(np.random.SeedSequence(3)))
        assert 0.0 <= rng.random() < 1.0
        assert 0.0 <= random.Random(4).random() < 1.0


def test_sampling_phav_v1_touches_no_global_random_state() -> None:
    expected = [r.model_dump_json() for r in sample_recipes(PHAV_V1, n=25, seed=11)]
    with forbid_global_randomness():
        got = [r.model_dump_json() for r in sample_recipes(PHAV_V1, n=25, seed=11)]
    assert got == expected


@settings(max_examples=8)
@given(theta=thetas(), seed=SEEDS)
def test_sampling_a_drawn_theta_touches_no_global_random_state(theta: Theta, seed: int) -> None:
    expected = [r.model_dump_json() for r in sample_recipes(theta, n=10, seed=seed)]
    with forbid_global_randomness():
        sampler = RecipeSampler(theta)
        got = [sampler.sample(seed, i).model_dump_json() for i in range(10)]
    assert got == expected


_PACKAGES = [Path(m.__file__).parent for m in (phav_spec, phav_generator, phav_validators)]
_ALLOWED_NP_RANDOM = {"SeedSequence", "Generator", "PCG64"}
_NP_RANDOM_CALL = re.compile(r"\b(?:np|numpy)\.random\.([A-Za-z_]\w*)\s*\(")
_FROM_NP_RANDOM = re.compile(r"^\s*from\s+numpy\.random\s+import\s+\(?([^)\n]*)", re.MULTILINE)
_IMPORT_NP_RANDOM = re.compile(r"^\s*import\s+numpy\.random\b", re.MULTILINE)
_STDLIB_RANDOM = re.compile(r"^\s*(?:import\s+random\b|from\s+random\s+import\b)", re.MULTILINE)
_UNSEEDED_RNG = re.compile(r"\bdefault_rng\(\s*(?:None\s*)?\)")


def test_package_sources_call_no_global_random_function() -> None:
    sources = sorted(p for package in _PACKAGES for p in package.rglob("*.py"))
    assert len(sources) > 10
    offences = []
    for path in sources:
        text = path.read_text(encoding="utf-8")
        for m in _NP_RANDOM_CALL.finditer(text):
            if m.group(1) not in _ALLOWED_NP_RANDOM:
                offences.append(f"{path}: np.random.{m.group(1)}(")
        for m in _FROM_NP_RANDOM.finditer(text):
            names = {n.strip().split(" as ")[0] for n in m.group(1).split(",") if n.strip()}
            offences += [f"{path}: from numpy.random import {n}" for n in names - _ALLOWED_NP_RANDOM]
        if _IMPORT_NP_RANDOM.search(text):
            offences.append(f"{path}: import numpy.random (aliases escape this check)")
        if _STDLIB_RANDOM.search(text):
            offences.append(f"{path}: imports the stdlib random module")
        if _UNSEEDED_RNG.search(text):
            offences.append(f"{path}: default_rng() without a seed")
    assert offences == []


def test_the_source_check_recognises_offences() -> None:
    """The patterns above match the calls they are meant to catch and not the legitimate ones."""
    bad = "x = np.random.rand(3)\ny = numpy.random.choice([1])\nimport random\nrng = np.random.default_rng()\n"
    assert {m.group(1) for m in _NP_RANDOM_CALL.finditer(bad)} == {"rand", "choice", "default_rng"}
    assert _STDLIB_RANDOM.search(bad) and _UNSEEDED_RNG.search(bad)
    good = "g = np.random.Generator(np.random.PCG64(0))\nss = np.random.SeedSequence(1)\nrng: np.random.Generator\n"
    assert {m.group(1) for m in _NP_RANDOM_CALL.finditer(good)} <= _ALLOWED_NP_RANDOM
    assert not _STDLIB_RANDOM.search("from phav_spec import random_things\n")


def test_triangular_inverse_cdf_stays_inside_its_support_at_the_extremes():
    """u within an ulp of 0 or 1 must not round a draw out of [a, b] (found by review)."""
    import math

    from phav_spec.distributions import triangular_inverse_cdf

    top = math.nextafter(1.0, 0.0)
    for a, b, c in [
        (-0.1, 0.2, 0.2),
        (0.1, 0.7, 0.1),
        (1.0, 10.0, 4.84),
        (20.0, 31.0, 24.0),
        (0.3, 0.3000000000000001, 0.3),
    ]:
        for u in (0.0, 5e-324, top):
            x = triangular_inverse_cdf(a, b, c, u)
            assert a <= x <= b, (a, b, c, u, x)
