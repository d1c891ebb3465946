"""Every θ parameter is both sampled and checked: recipes sampled from one θ are rejected
when validated against a θ that differs in that single parameter (STYLE.md: one registry
ties each θ variable to its sampler and its validator check)."""

from __future__ import annotations

import copy

import pytest

from phav_generator.sampling import RecipeSampler
from phav_spec.expectations import CONTINUOUS_PARAMETERS
from phav_spec.recipe_table import RecipeRows
from phav_spec.theta import Theta, load_theta, parse_theta
from phav_validators.checks.distribution import (
    check_continuous,
    check_distributions,
    parameter_draws,
    parse_recipes_arrow,
)
from tests.helpers import preset_dict

N = 800


def _all_cameras_theta() -> Theta:
    """phav-v1 with every camera reachable, so every camera parameter is drawn."""
    data = preset_dict()
    data["theta_c"] = {"kite": 1, "indoors": 1, "closeup": 1, "static": 1}
    data["theta_ac"] = {"default": {"kite": 1, "indoors": 1, "closeup": 1, "static": 1}}
    data["theta_ec"]["default"] = {"kite": 1, "closeup": 1, "static": 1}
    data["theta_ec"]["rows"]["house_interior"] = "uniform"
    return parse_theta(data)


@pytest.fixture(scope="module")
def sampled_people():
    """phav-people recipes: every person drawn from θ's people section (skin tone and
    undertone narrowed off their bounds, so that a point just outside still parses)."""
    data = load_theta("phav-people").model_dump(mode="json")
    data["people"]["skin_tone"] = {"kind": "uniform", "low": 0.02, "high": 0.98}
    data["people"]["skin_undertone"] = {"kind": "triangular", "min": -0.9, "max": 0.9, "mode": 0.0}
    theta = parse_theta(data)
    sampler = RecipeSampler(theta)
    rows = RecipeRows().extend(sampler.sample(11, i) for i in range(N))
    return theta, rows.columns


@pytest.fixture(scope="module")
def sampled():
    theta = _all_cameras_theta()
    sampler = RecipeSampler(theta)
    rows = RecipeRows().extend(sampler.sample(11, i) for i in range(N))
    return theta, rows.columns


def _leaves(node, path=()):
    """Paths of every continuous distribution in a θ mapping."""
    if isinstance(node, dict):
        if node.get("kind") in ("uniform", "triangular"):
            yield path
            return
        for key, value in node.items():
            yield from _leaves(value, (*path, str(key)))


def _matches(pattern: str, path: tuple[str, ...]) -> bool:
    parts = pattern.split(".")
    return len(parts) <= len(path) and all(p in ("*", q) for p, q in zip(parts, path, strict=False))


def _put(data: dict, leaf: tuple[str, ...], value) -> None:
    node = data
    for key in leaf[:-1]:
        node = node[key]
    node[leaf[-1]] = value


def _moved_out(data: dict, leaf: tuple[str, ...]) -> tuple[dict, Theta]:
    """A point just above the leaf's range (below, where above leaves the physical bounds),
    and θ with the leaf's distribution replaced by that point alone."""
    node = data
    for key in leaf:
        node = node[key]
    high, low = (node["high"], node["low"]) if node["kind"] == "uniform" else (node["max"], node["min"])
    step = 0.5 if leaf[-1].endswith("deg") else 0.01
    for point in (high + step, low - step):
        changed = copy.deepcopy(data)
        moved = {"kind": "uniform", "low": point, "high": point}
        _put(changed, leaf, moved)
        try:
            return moved, parse_theta(changed)
        except Exception:  # the point leaves the physical bounds: try the other side
            continue
    raise AssertionError(f"no point just outside {'.'.join(leaf)} parses")


def test_every_continuous_leaf_is_sampled_and_checked(sampled):
    """Each continuous θ leaf moved to a point just outside its range: the check of its
    parameter finds the draws sampled from θ outside, in the group that leaf belongs to.

    One θ with every leaf moved is checked once: ``check_continuous`` judges each (parameter,
    group) against that group's own distribution alone, and no two leaves share one (asserted),
    so what it finds for a leaf's (parameter, group) is that leaf's move. Which (parameter,
    group) a leaf is comes from θ with that leaf alone moved.
    """
    theta, columns = sampled
    verified = _every_leaf_is_checked(theta, columns)
    assert verified >= 55


def test_every_people_leaf_is_sampled_and_checked(sampled_people):
    """The same for θ's people section (phav-people): ages, stature, build, skin, colours."""
    theta, columns = sampled_people
    verified = _every_leaf_is_checked(theta, columns, only="people")
    assert verified == 14


def _every_leaf_is_checked(theta: Theta, columns: dict, only: str | None = None) -> int:
    """Move every continuous leaf (under ``only`` if given) out of its range; returns how many
    leaves were verified to be found outside."""
    data = theta.model_dump(mode="json")
    parsed = parse_recipes_arrow(columns["recipe"])
    leaves = [leaf for leaf in _leaves(data) if only is None or leaf[0] == only]
    assert len(leaves) > (60 if only is None else 10)
    drawn = {p.name: set(parameter_draws(parsed, p)[0].tolist()) for p in CONTINUOUS_PARAMETERS}  # groups
    every_leaf_moved = copy.deepcopy(data)
    expected: dict[tuple[str, ...], set[tuple[str, str]]] = {}  # leaf → the drawn (parameter, group) it moves
    for leaf in leaves:
        params = [p for p in CONTINUOUS_PARAMETERS if _matches(p.theta_path, leaf)]
        assert params, f"θ parameter {'.'.join(leaf)} has no validator check"
        moved, other = _moved_out(data, leaf)
        _put(every_leaf_moved, leaf, moved)
        expected[leaf] = {
            (param.name, group)
            for param in params
            for group in drawn[param.name]
            if param.distribution(theta, group) != param.distribution(other, group)
        }
    pairs = [pair for own in expected.values() for pair in own]
    assert len(pairs) == len(set(pairs)), "two θ leaves feed one (parameter, group)"
    _, outside = check_continuous(columns["recipe"], parse_theta(every_leaf_moved))
    found = {(name, group) for name, group, _ in outside}
    verified = 0
    for leaf, own in expected.items():
        if not own:
            # Only parameters θ never draws may go unverified (an element that is never on).
            assert leaf[0] == "weather_elements" and leaf[-1].endswith("_intensity"), leaf
            continue
        assert own <= found, f"{'.'.join(leaf)}: no draws found outside for {sorted(own - found)}"
        verified += 1
    return verified


def _set(path: str, value):
    def edit(d):
        *parents, last = path.split(".")
        for p in parents:
            d = d[p]
        d[last] = value

    return edit


CATEGORICAL = {
    "theta_a": (_set("theta_a", {"walk": 1, "run": 1}), "action"),
    "theta_e": (_set("theta_e", {"urban": 1, "middle": 1, "stadium": 1, "house_interior": 1}), "environment"),
    "theta_ae": (_set("theta_ae", {"default": {"urban": 1}}), "environment"),
    "theta_w": (_set("theta_w", {"clear": 1}), "weather"),
    "theta_d": (_set("theta_d", {"night": 1}), "day_phase"),
    "theta_h": (_set("theta_h", {f"model_{i:02d}": 1 for i in range(1, 11)}), "human_model"),
    "theta_v": (_set("theta_v", {"none": 1, "muscle_weakening": 1}), "variation"),
    "theta_av": (_set("theta_av", {"default": {"none": 1}}), "variation"),
    "theta_c": (_set("theta_c", {"kite": 1, "indoors": 1}), "camera"),
    "theta_ac": (_set("theta_ac", {"default": {"kite": 1, "indoors": 1}}), "camera"),
    "theta_ec": (_set("theta_ec", {"default": {"kite": 1}}), "camera"),
    "theta_ab": (_set("theta_ab.regex.walk", "^walk forward"), "base_motion"),
    "durations": (_set("durations", {"t_min": 1.0, "t_max": 10.0, "t_mod": 1.0}), "duration_s"),
    "clock_hours": (_set("clock_hours.day", {"min": 10, "max": 16, "mode": 10}), "clock_hour"),
    "weather rain": (_set("weather_elements.rain.fog.p", 0.0), "fog"),
    "weather clouds": (_set("weather_elements.clear.clouds.p_otherwise", 0.0), "clouds"),
    "weather wet ground": (_set("weather_elements.overcast.wet_ground.p_otherwise", 0.0), "wet_ground"),
    "background count": (_set("background_actors.count", {"min": 0, "max": 2}), "n_background_actors"),
    "mirror": (_set("motion.p_mirror", 0.0), "mirror"),
    "muscle count": (_set("variations.muscle_weakening.n_muscles", {"min": 1, "max": 2}), "n_varied_muscles"),
    "dead zone": (_set("cameras.kite.springs.min_distance_weights", {0: 1}), "ct_min_distance_m"),
}


PEOPLE_CATEGORICAL = {
    "sex": (_set("people.p_female", 0.2), "sex"),
    "children": (_set("people.p_child", 0.6), "child"),
    "hair styles": (_set("people.hair.styles", {"short": 1}), "hair_style"),
    "hair colours": (_set("people.hair.colours", {"black": 1, "red": 1}), "hair_colour"),
    "greying": (_set("people.hair.grey", {"start_years": 20.0, "full_years": 30.0, "p_full": 1.0}), "hair_colour"),
    "tops": (_set("people.outfit.tops", {"long_sleeves": 1}), "top"),
    "bottoms": (_set("people.outfit.bottoms", {"trousers": 1}), "bottom"),
    "top fabrics": (_set("people.outfit.top_fabrics", "uniform"), "top_fabric"),
    "bottom fabrics": (_set("people.outfit.bottom_fabrics", "uniform"), "bottom_fabric"),
    "people of H": (lambda d: d.pop("people"), "human_model"),
}


@pytest.mark.parametrize("case", sorted(PEOPLE_CATEGORICAL))
def test_every_categorical_people_parameter_is_checked(sampled_people, case):
    _assert_a_changed_parameter_is_caught(*sampled_people, *PEOPLE_CATEGORICAL[case])


def test_people_recipes_pass_against_their_own_theta(sampled_people):
    theta, columns = sampled_people
    result = check_distributions(columns, theta)
    assert result.ok, [f.message for f in result.report.findings][:5]
    tested = {t.variable for t in result.tests}
    assert {"sex", "child", "hair_style", "hair_colour", "top", "bottom", "protagonist.adult_age_years",
            "background.skin_tone"} <= tested  # fmt: skip


@pytest.mark.parametrize("case", sorted(CATEGORICAL))
def test_every_categorical_parameter_is_checked(sampled, case):
    _assert_a_changed_parameter_is_caught(*sampled, *CATEGORICAL[case])


def _assert_a_changed_parameter_is_caught(theta, columns, edit, variable) -> None:
    """Recipes of ``theta`` checked against ``theta`` edited by ``edit``: rejected, with a
    finding naming ``variable``."""
    data = theta.model_dump(mode="json")
    edit(data)
    other = parse_theta(data)
    result = check_distributions({k: v for k, v in columns.items() if k != "recipe"}, other)
    assert not result.ok
    assert any(variable in f.message for f in result.report.findings), [f.message for f in result.report.findings][:5]


def test_list_draws_are_grouped_by_their_recipe_even_when_counts_coincide():
    """Four strengths of one muscle-weakening recipe among four recipes: each draw belongs to
    that recipe's variation kind, not to the recipe at its list position (a false alarm
    `phav-validate` once raised on a clean four-video dataset)."""
    import json

    from phav_spec.theta import load_theta

    theta = load_theta("phav-v1")
    weakened = {"kind": "muscle_weakening", "muscles": ["chest", "left_foot", "right_hand", "neck"],
                "strengths": [0.1, 0.2, 0.3, 0.4]}  # fmt: skip
    others = [{"kind": "none"}, {"kind": "objects", "object": "cup"}, {"kind": "none"}]
    recipes = [json.dumps({"variation": v}) for v in (weakened, *others)]
    param = next(p for p in CONTINUOUS_PARAMETERS if p.value == "variation.strengths[]")
    groups, values = parameter_draws(parse_recipes_arrow(recipes), param)
    assert groups.tolist() == ["muscle_weakening"] * 4 and values.tolist() == [0.1, 0.2, 0.3, 0.4]
    _, outside = check_continuous(recipes, theta)
    assert not [o for o in outside if o[0] == param.name], outside
