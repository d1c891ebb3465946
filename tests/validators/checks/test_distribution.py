"""The distribution check: a dataset's recipes against θ's exact expectations: an impossible
value is named, a skewed marginal rejected."""

from __future__ import annotations

import numpy as np
import pytest

from phav_generator.sampling import RecipeSampler
from phav_spec.recipe_table import RecipeRows, read_recipe_table, write_recipe_table
from phav_spec.theta import load_theta
from phav_validators.checks.distribution import parse_recipes_arrow
from phav_validators.findings import Reason
from tests.helpers import theta_variant
from tests.validators.checks.support import assert_fails, edit_recipes, validate


def test_night_video_in_a_phav_v1_dataset_fails_distribution(data):
    edit_recipes(data, "v000001", lambda d: d["world"].update(day_phase="night", clock_hour=23.0),
                 day_phase="night", clock_hour=23.0)  # fmt: skip
    report = validate(data, "distribution")
    hits = assert_fails(report, "distribution", Reason.IMPOSSIBLE_VALUE, video="v000001")
    assert "night" in hits[0].message and "recipes.parquet" in hits[0].file


def test_skewed_weather_fails_distribution_against_phav_v1(tmp_path):
    """500 recipes with 40 % clear weather, checked against phav-v1's uniform weather (its χ²
    is about 60 on 3 degrees of freedom: far past Holm's threshold)."""
    skewed = load_theta(str(theta_variant(tmp_path, lambda d: d.update(
        theta_w={"clear": 40, "overcast": 20, "rain": 20, "fog": 20}))))  # fmt: skip
    folder = tmp_path / "recipes"
    folder.mkdir()
    sampler = RecipeSampler(skewed)
    rows = RecipeRows().extend(sampler.sample(5, i) for i in range(500))
    write_recipe_table(rows.to_arrow(theta=skewed, dataset_seed=5), folder / "recipes.parquet")
    report = validate(folder, "distribution", theta="phav-v1")
    hits = assert_fails(report, "distribution", Reason.DISTRIBUTION_MISMATCH)
    assert any(f.message.startswith("weather") for f in hits), [f.message for f in hits]


def test_recipe_texts_that_are_not_recipes_are_left_out_and_the_rest_read_in_their_own_types():
    sampler = RecipeSampler(load_theta("phav-v1-short"))
    recipes = [sampler.sample(0, i).model_dump_json() for i in range(3)]
    texts = [None, "[1, 2]", "{not json", *recipes]
    # A number written as text is no recipe (JSON's types as written): that row is left out,
    # and it no longer drops every row with it (the rest keep their own types).
    texts[3] = texts[3].replace('"fps":30', '"fps":"30"', 1)
    assert '"fps":"30"' in texts[3]
    table = parse_recipes_arrow(texts)
    assert table.column("video_id").to_pylist() == ["v000001", "v000002"]
    assert [v["fps"] for v in table.column("video").to_pylist()] == [30, 30]


def test_recipes_parse_the_same_whatever_the_blocks_a_parser_would_cut():
    """pyarrow's JSON reader, in blocks read in parallel, typed a list of supporting people
    as null in a block without any and then failed to join the blocks (`phav stats` and the
    distribution check raised a traceback on 28 of 30 reads of this valid table)."""
    sampler = RecipeSampler(load_theta("phav-v1"))
    texts = [sampler.sample(1173, i).model_dump_json() for i in range(300)]
    tables = [parse_recipes_arrow(texts) for _ in range(3)]
    assert all(t.num_rows == 300 for t in tables) and tables[0].equals(tables[1]) and tables[0].equals(tables[2])


def test_many_background_actors_a_video_are_no_false_alarm(tmp_path):
    """A video's actors share its environment and their number varies: the waypoints'
    marginal is mixed by the actors each environment holds, so a θ with up to 50 actors a
    video passes on what it samples (p was 1e-6 on this table); the finding's count is of
    actors, not videos."""
    from phav_validators.checks.distribution import check_distributions

    def crowd(data):
        data["background_actors"]["count"]["max"] = 50

    theta = load_theta(theta_variant(tmp_path, crowd))
    sampler = RecipeSampler(theta)
    recipes = [sampler.sample(3, i) for i in range(1000)]
    write_recipe_table(RecipeRows().extend(recipes).to_arrow(theta=theta, dataset_seed=3), tmp_path / "r.parquet")
    rt = read_recipe_table(tmp_path / "r.parquet")
    result = check_distributions({n: rt.column(n) for n in rt.table.column_names}, theta, alpha=1e-3)
    marginal = next(t for t in result.tests if t.variable == "background_start_waypoints" and t.condition == "marginal")
    assert marginal.p_value > 1e-3 and marginal.unit == "background actors" and result.ok, marginal


def _subsets(rng, videos: int, weights=None) -> list[list[str]]:
    """Each video's varied muscles: k uniform in 1..15, drawn without replacement."""
    from phav_spec.vocab import MUSCLES

    names = list(MUSCLES.names)
    p = None if weights is None else np.asarray(weights, float) / np.sum(weights)
    return [[names[j] for j in rng.choice(15, size=int(rng.integers(1, 16)), replace=False, p=p)]
            for _ in range(videos)]  # fmt: skip


def test_muscle_subsets_are_tested_at_their_own_spread():
    """A video's varied muscles are a subset, drawn without replacement: their counts spread
    by (m − k)/(m − 1) of independent draws'. Scaled to it, the test's p-values are uniform
    on subsets drawn as θ says (they averaged 0.85–0.90: no power) and a tilted draw fails."""
    from phav_spec.expectations import ExactTable
    from phav_spec.vocab import MUSCLES
    from phav_validators.checks.distribution import check_table

    key = ("walk", "muscle_weakening")
    table = ExactTable("varied_muscles", ("action", "variation"), MUSCLES.names, {key: np.full(15, 1 / 15)},
                       {key: 1.0}, "muscles of muscle variations", multi=True, subset=True)  # fmt: skip

    def p_value(subsets) -> float:
        columns = {"varied_muscles": subsets, "action": ["walk"] * len(subsets),
                   "variation": ["muscle_weakening"] * len(subsets)}  # fmt: skip
        return check_table(table, columns)[0][1].p_value  # the row's test

    rng = np.random.default_rng(0)
    null = np.array([p_value(_subsets(rng, 300)) for _ in range(300)])
    assert 0.45 < null.mean() < 0.55 and 0.02 < (null < 0.05).mean() < 0.09, (null.mean(), (null < 0.05).mean())
    tilted = [p_value(_subsets(rng, 300, weights=np.arange(1, 16) ** 0.5)) for _ in range(20)]
    assert np.mean(np.array(tilted) < 1e-3) > 0.8, tilted


def test_two_cells_take_the_exact_binomial_p():
    """One value expected 5.7 times of 300 and seen 17, against the rest: the chi-square says
    p = 1.9e-6, under Holm's first threshold on a table of this size; the exact binomial p
    is 8e-5."""
    from scipy import stats

    from phav_validators.checks.distribution import chi_square

    _, dof, p, _ = chi_square(np.array([17, 283]), np.array([5.71 / 300, 1 - 5.71 / 300]))
    assert dof == 1 and p == pytest.approx(stats.binomtest(17, 300, 5.71 / 300).pvalue) and p > 5e-5


def test_many_small_cells_are_grouped_and_tested_not_pooled_into_one():
    """128 values at 3.1 expected each (the blend motions at a few thousand videos): joined
    in pairs, 64 groups test the row (pooled into one cell, the row had no test: every blend
    of one motion passed)."""
    from phav_validators.checks.distribution import chi_square

    probs = np.full(128, 1 / 128)
    rng = np.random.default_rng(1)
    _, dof, p, _ = chi_square(np.bincount(rng.choice(128, 400), minlength=128), probs)
    assert dof == 63 and p > 1e-3
    one_motion = np.zeros(128, dtype=np.int64)
    one_motion[5] = 400
    assert chi_square(one_motion, probs)[2] < 1e-12
