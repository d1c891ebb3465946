"""People drawn from θ (phav-people): deterministic per person, children only where the
action allows one, ages, statures and skin tones distributed as θ says (and a sampler that
draws them wrongly is caught)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import stats

from phav_generator.sampling import RecipeSampler
from phav_spec.population import ADULT_AGE_YEARS, estimated_stature, reference_stature
from phav_spec.recipe_table import RecipeRows
from phav_spec.scene import ACTION_SCENES
from phav_spec.theta import load_theta, parse_theta
from phav_validators.checks.distribution import check_distributions

N = 1500


@pytest.fixture(scope="module")
def theta():
    return load_theta("phav-people")


@pytest.fixture(scope="module")
def recipes(theta):
    sampler = RecipeSampler(theta)
    return [sampler.sample(5, i) for i in range(N)]


def _people(recipe):
    yield "protagonist", recipe.protagonist.human
    for s in recipe.supporting_characters:
        yield "supporting", s.human
    for a in recipe.background_actors:
        yield "background", a.human


def test_same_seed_same_people_and_each_person_has_its_own_stream(theta):
    a, b = RecipeSampler(theta), RecipeSampler(theta)
    for i in (0, 7, 123):
        assert a.sample(3, i).model_dump_json() == b.sample(3, i).model_dump_json()
    assert a.sample(3, 0).protagonist.human != a.sample(4, 0).protagonist.human
    # More or fewer background pedestrians leave everyone else's look unchanged.
    data = theta.model_dump(mode="json")
    data["background_actors"]["count"] = {"min": 7, "max": 7}
    crowded = RecipeSampler(parse_theta(data))
    for i in range(20):
        mine, theirs = a.sample(3, i), crowded.sample(3, i)
        assert mine.protagonist.human == theirs.protagonist.human
        assert [s.human for s in mine.supporting_characters] == [s.human for s in theirs.supporting_characters]
        if mine.background_actors and theirs.background_actors:
            assert mine.background_actors[0].human == theirs.background_actors[0].human


def test_children_only_where_the_action_allows_one(recipes):
    seen = {"protagonist": 0, "background": 0}
    for r in recipes:
        for role, human in _people(r):
            assert human.model == "sampled" and human.sampled is not None
            if human.sampled.child:
                assert role == "background" or ACTION_SCENES[r.action].children, (r.video_id, r.action)
                assert human.sampled.age_years < ADULT_AGE_YEARS
                seen[role] += 1
    assert seen["protagonist"] > 50 and seen["background"] > 50


def test_sampled_people_match_theta(recipes, theta):
    """The validators' distribution check on phav-people recipes (every people variable:
    sex, child | action, hair, clothes, and per role the ages, stature z, build, skin, colours)."""
    columns = RecipeRows().extend(recipes).columns
    result = check_distributions(columns, theta)
    assert result.ok, [f.message for f in result.report.findings][:5]
    tested = {t.variable for t in result.tests}
    for role in ("protagonist", "background"):
        for name in ("adult_age_years", "child_age_years", "skin_tone", "stature_z", "weight", "outfit.saturation"):
            assert f"{role}.{name}" in tested


def test_ages_skin_tones_and_statures_against_theta(recipes, theta):
    people = [h for r in recipes for _, h in _people(r)]
    adults = np.array([h.sampled.adult_age_years for h in people if not h.sampled.child])
    children = np.array([h.sampled.child_age_years for h in people if h.sampled.child])
    tones = np.array([h.sampled.skin_tone for h in people])
    assert stats.kstest(adults, theta.people.adult_age_years.cdf).pvalue > 1e-3
    assert stats.kstest(children, theta.people.child_age_years.cdf).pvalue > 1e-3
    assert stats.kstest(tones, theta.people.skin_tone.cdf).pvalue > 1e-3
    # Statures: the body's (table) equals the target; adults about the WHO reference.
    for female in (True, False):
        group = [h for h in people if h.sampled.female == female and not h.sampled.child]
        z = np.array([(estimated_stature(h.phenotype) - reference_stature(female, h.sampled.age_years)[0])
                      / reference_stature(female, h.sampled.age_years)[1] for h in group])  # fmt: skip
        assert abs(z.mean()) < 0.1 and 0.9 < z.std() < 1.1
        heights = np.array([estimated_stature(h.phenotype) for h in group])
        assert 1.45 < heights.min() and heights.max() < 2.05
    for h in people:
        assert estimated_stature(h.phenotype) == pytest.approx(h.sampled.stature_m, abs=1e-9)


def test_a_sampler_with_the_wrong_skin_tones_is_caught(recipes, theta):
    """Recipes whose skin tones come from another θ (only the lighter half of the scale)."""
    data = theta.model_dump(mode="json")
    data["people"]["skin_tone"] = {"kind": "uniform", "low": 0.0, "high": 0.5}
    lighter = parse_theta(data)
    wrong = [RecipeSampler(lighter).sample(5, i) for i in range(300)]
    result = check_distributions(RecipeRows().extend(wrong).columns, theta)
    assert not result.ok
    assert any("skin_tone" in f.message for f in result.report.findings)
