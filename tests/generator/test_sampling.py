"""The sampler against θ: 40,000 phav-v1 recipes match the exact expectations, a planted
bug is caught, and the first five recipes of seed 0 are pinned (golden)."""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np
import pytest
import yaml
from pydantic import ValidationError

from phav_generator.sampling import RecipeSampler
from phav_spec.expectations import exact_expectations, mean_duration
from phav_spec.motion_activity import MOVING_SPANS
from phav_spec.motions import ACTIVE_SHARE, moving_share
from phav_spec.recipe import parse_recipe
from phav_spec.recipe_table import RecipeRows, read_recipe_table
from phav_spec.seeding import part_rng, runtime_seeds, video_key
from phav_spec.theta import load_preset, load_theta, parse_theta
from phav_spec.vocab import ACTIONS, CAMERAS, ENVIRONMENTS
from phav_validators.checks.distribution import check_distributions
from phav_validators.findings import Reason
from tests.helpers import PRESET_PATH, invoke_cli

GOLDEN = Path(__file__).parents[1] / "golden" / "phav-v1-seed0-first5.json"


@pytest.fixture(
    scope="module", params=[pytest.param(4000, id="4k"), pytest.param(40000, id="40k", marks=pytest.mark.slow)]
)
def table_40k(request, tmp_path_factory):
    """`phav sample --theta recipes/phav-v1.yaml --n N --seed 0`, as a user would run it (in
    this process: a subprocess would add only its start). 40,000 is PHAV's size: the
    distribution check must not raise a false alarm on a dataset that large, where it can see
    the smallest systematic difference (slow: `make test-all`); 4,000 in the default run."""
    out = tmp_path_factory.mktemp("sample") / "recipes.parquet"
    n = str(request.param)
    result = invoke_cli("sample", "--theta", str(PRESET_PATH), "--n", n, "--seed", "0", "--out", str(out))
    assert result.returncode == 0, result.stderr
    return read_recipe_table(out)


def test_recipes_match_every_histogram_and_conditional_table(table_40k):
    theta = load_preset()
    assert table_40k.table.num_rows in (4000, 40000)
    assert table_40k.theta == theta and table_40k.dataset_seed == 0
    columns = {name: table_40k.column(name) for name in table_40k.table.column_names}
    result = check_distributions(columns, theta)
    assert result.ok, [f.message for f in result.report.findings]
    tested = {t.variable for t in result.tests}
    assert tested >= set(exact_expectations(theta)) | {"duration_s", "clock_hour"}
    conditional = [t for t in result.tests if t.condition != "marginal"]
    assert len(conditional) > (300 if table_40k.table.num_rows == 40000 else 100)  # (action), (action, env)… rows
    assert all(t.impossible == 0 for t in result.tests)


def test_no_zero_probability_value_ever_appears(table_40k):
    exact = exact_expectations(load_preset())
    for variable, table in exact.items():
        column = table_40k.column(variable)
        probs = table.marginal_dict()
        cells = [v for v in column if v is not None]
        seen = {x for xs in cells for x in xs} if table.multi else set(cells)
        assert all(probs[v] > 0 for v in seen), variable
    assert set(table_40k.column("day_phase")) == {"dawn", "day", "dusk"}  # θ_D(night) = 0
    assert "static" not in set(table_40k.column("camera"))


def test_mean_duration_is_about_five_seconds(table_40k):
    durations = np.array(table_40k.column("duration_s"))
    assert mean_duration(load_preset()) == pytest.approx(5.0, abs=0.01)  # paper: 4.99 s
    assert durations.mean() == pytest.approx(5.0, abs=0.05 if len(durations) == 40000 else 0.15)
    assert durations.min() >= 1.0 and durations.max() <= 10.0
    frames = np.array(table_40k.column("n_frames"))
    assert frames.min() >= 30 and frames.max() <= 300


def test_camera_marginal_is_far_from_theta_c():
    camera = exact_expectations(load_preset())["camera"].marginal_dict()
    assert camera["kite"] > 0.9 and camera["indoors"] < 0.07 and camera["closeup"] < 0.02
    assert camera["static"] == 0.0


class IgnoresThetaEC(RecipeSampler):
    """A planted bug: P(C | A, E) ∝ θ_C·θ_AC, forgetting θ_EC (indoors camera outdoors)."""

    def _camera_weights(self) -> np.ndarray:
        arr = self.theta.arrays
        return np.broadcast_to(arr.c[None, None, :] * arr.ac[:, None, :], (len(arr.a), len(arr.e), len(arr.c))).copy()


def test_a_sampler_that_ignores_theta_ec_fails_the_checks():
    """The recipe itself refuses an indoors camera outdoors; a table whose cameras were drawn
    so (written without the recipes' checks) fails the distribution checks. 1,000 recipes are
    plenty. The bug puts an indoors camera outdoors in 44 % of recipes, 8 % of them in an
    urban row: 1,000 recipes hold none with probability 0.56^1000 < 1e-250, none in an urban
    row with 0.92^1000 < 1e-36. It moves the camera marginal from (0.932, 0.054, 0.014) to
    (0.495, 0.495, 0.010): a χ² noncentrality of 3,800 on 2 degrees of freedom, which misses
    even α/m = 1e-103 with probability below 1e-100. Holm keeps the correct sampler's
    false-alarm rate below α = 0.001 at any size."""
    theta = load_preset()
    buggy = IgnoresThetaEC(theta)
    with pytest.raises(ValidationError, match="the indoors camera films indoors only"):
        for i in range(1000):
            buggy.sample(0, i)
    # The same draw, made on the correct sampler's table: its camera weights, row by row.
    sampler = RecipeSampler(theta)
    good = RecipeRows().extend(sampler.sample(0, i) for i in range(1000))
    assert check_distributions(good.columns, theta).ok
    weights = buggy._camera_weights()
    rng = np.random.default_rng(0)
    columns = dict(good.columns)
    rows = zip(columns["action"], columns["environment"], strict=True)
    columns["camera"] = [
        CAMERAS.names[rng.choice(len(CAMERAS), p=w / w.sum())]
        for w in (weights[ACTIONS.index(a), ENVIRONMENTS.index(e)] for a, e in rows)
    ]
    result = check_distributions(columns, theta)
    assert not result.ok
    reasons = {f.reason for f in result.report.findings}
    assert Reason.IMPOSSIBLE_VALUE in reasons
    camera_failures = [t for t in result.tests if t.variable == "camera" and t.rejected]
    assert any(t.condition == "marginal" for t in camera_failures)
    assert any("environment=urban" in t.condition for t in camera_failures)


def test_golden_recipes_of_phav_v1_seed_0():
    """The first five phav-v1 recipes for seed 0. Changing them changes the dataset's
    definition: a deliberate, changelogged schema bump (regenerate with
    PHAV_UPDATE_GOLDEN=1 pytest tests/generator/test_sampling.py -k golden)."""
    sampler = RecipeSampler(load_preset())
    current = [json.loads(sampler.sample(0, i).model_dump_json()) for i in range(5)]
    if os.environ.get("PHAV_UPDATE_GOLDEN") == "1":
        GOLDEN.write_text(json.dumps(current, indent=1, sort_keys=True) + "\n", encoding="utf-8")
    stored = json.loads(GOLDEN.read_text(encoding="utf-8"))
    assert current == stored
    assert [parse_recipe(r) for r in stored] == [sampler.sample(0, i) for i in range(5)]


def test_streams_are_keyed_by_name_and_index():
    a = part_rng(0, 5, "camera").random(4)
    assert np.array_equal(a, part_rng(0, 5, "camera").random(4))
    assert not np.array_equal(a, part_rng(0, 5, "world").random(4))
    assert not np.array_equal(a, part_rng(0, 6, "camera").random(4))
    assert not np.array_equal(a, part_rng(1, 5, "camera").random(4))
    seeds = runtime_seeds(video_key(0, 5))
    assert len(set(seeds.values())) == len(seeds) and all(0 <= s < 2**32 for s in seeds.values())
    with pytest.raises(ValueError, match="non-negative"):
        video_key(-1, 0)


def test_parts_do_not_share_draws():
    """Changing how many draws one part makes leaves every other part unchanged.

    Variations (kind and muscle counts) and background actors (how many) draw a different
    number of doubles under ``other``; with one shared stream every later draw would move.
    """
    from phav_spec.theta import parse_theta

    theta = load_preset()
    data = theta.model_dump(mode="json")
    data["theta_v"] = {"muscle_weakening": 1.0}
    data["theta_av"] = {"rows": {a: {"muscle_weakening": 1.0} for a in data["theta_av"]["rows"]}}
    data["variations"]["muscle_weakening"]["n_muscles"] = {"min": 15, "max": 15}
    data["background_actors"]["count"] = {"min": 6, "max": 6}
    other = parse_theta(data)
    changed_variation = changed_background = 0
    sampler, other_sampler = RecipeSampler(theta), RecipeSampler(other)
    for i in range(60):
        a, b = sampler.sample(3, i), other_sampler.sample(3, i)
        same = ("action", "motion", "world", "environment", "protagonist", "duration_s", "camera", "seeds")
        for part in (*same, "supporting_characters"):
            assert getattr(a, part) == getattr(b, part), (i, part)
        changed_variation += a.variation != b.variation
        changed_background += a.background_actors != b.background_actors
    assert changed_variation > 30 and changed_background > 30


def test_fixed_length_clips_pass_the_duration_tests():
    """T_min = T_max = T_mod puts every clip at one length: an atom of θ's duration CDF. The
    KS tests must accept it (a continuous-CDF KS test finds D = 1 there), and still reject
    clips of another length."""
    import copy

    from phav_spec.expectations import duration_cdf
    from phav_spec.theta import parse_theta
    from phav_validators.checks.distribution import ks
    from tests.helpers import preset_dict

    data = copy.deepcopy(preset_dict())
    data["durations"] = {"t_min": 2.0, "t_max": 2.0, "t_mod": 2.0}
    theta = parse_theta(data)
    sampler = RecipeSampler(theta)
    rows = RecipeRows().extend(sampler.sample(3, i) for i in range(300)).to_arrow(theta=theta, dataset_seed=3)
    columns = {name: rows.column(name).to_pylist() for name in rows.column_names}
    result = check_distributions(columns, theta)
    durations = [t for t in result.tests if t.variable == "duration_s"]
    assert durations and all(t.statistic < 1e-9 and t.p_value > 0.999 for t in durations)
    assert not any(f.reason == Reason.DISTRIBUTION_MISMATCH for f in result.report.findings)
    wrong = ks("duration_s", "marginal", np.full(300, 2.5), duration_cdf(theta))
    assert wrong.statistic > 1 - 1e-9 and wrong.p_value < 1e-12


def test_short_clips_start_where_the_body_moves():
    """phav-v1-short (``motion.start: active``): every clip's window keeps at least 3/4 of
    the most moving time its take allows, and only the start differs from the uniform θ's
    recipe (the same draws feed every other field)."""
    short = load_theta("phav-v1-short")
    uniform = parse_theta(
        {**yaml.safe_load(short.to_yaml()), "motion": {**short.motion.model_dump(), "start": "uniform"}}
    )
    active_sampler, uniform_sampler = RecipeSampler(short), RecipeSampler(uniform)
    gained = []
    for i in range(300):
        recipe, plain = active_sampler.sample(0, i), uniform_sampler.sample(0, i)
        m = recipe.motion
        window = recipe.duration_s * m.speed
        room = max(0.0, m.base_motion_length_s - window)
        spans = MOVING_SPANS[m.base_motion]
        grid = np.arange(int(np.floor(room * 30)) + 1) / 30
        best = moving_share(spans, grid, window).max() if window > 0 else 0.0
        share = float(moving_share(spans, np.array([m.start_s]), window)[0])
        assert 0.0 <= m.start_s <= room + 1e-9 and share >= ACTIVE_SHARE * best - 1e-9, (i, m)
        gained.append(share - float(moving_share(spans, np.array([plain.motion.start_s]), window)[0]))
        assert recipe.model_dump(exclude={"motion", "theta_hash"}) == plain.model_dump(exclude={"motion", "theta_hash"})
    assert np.mean(gained) > 0.1  # uniform windows hold poses a fair share of the time


def test_a_blended_motion_is_played_within_its_length():
    """The blended motion plays at the clip's speed: its start was drawn as if it played at
    1×, so a fast clip ran past its end (and wrapped) where it need not."""
    from phav_spec.motions import MOTIONS

    sampler = RecipeSampler(load_preset("phav-v1"))
    blended = [r for r in (sampler.sample(3, i) for i in range(400))
               if r.variation.kind == "action_blending"]  # fmt: skip
    assert len(blended) >= 20
    for r in blended:
        played = r.n_frames / r.video.fps * r.motion.speed
        length = MOTIONS[r.variation.blend_motion].length_s
        frame = r.motion.speed / r.video.fps  # the clip's frames round its duration
        assert r.variation.blend_start_s + played <= max(length, played) + frame, r.video_id
