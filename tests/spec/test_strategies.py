"""The public θ and recipe strategies produce what they promise (phav_spec.strategies)."""

from __future__ import annotations

import tempfile
from pathlib import Path

import numpy as np
import pytest
import yaml
from hypothesis import given, settings
from hypothesis import strategies as st

from phav_spec.motions import MOTIONS
from phav_spec.recipe import frames_for, load_recipe, parse_recipe, video_id
from phav_spec.recipe_table import (
    COLUMN_NAMES,
    RECIPE_COLUMN,
    RecipeRows,
    read_recipe_table,
    write_recipe_stream,
    write_recipe_table,
)
from phav_spec.scene import ACTION_SCENES, CAMERA_INFO, ENVIRONMENT_SCENES, HUMAN_MODELS
from phav_spec.strategies import recipe_lists, recipes, thetas
from phav_spec.theta import Theta, load_preset, parse_theta
from phav_spec.vocab import ACTIONS, CAMERAS, VARIATIONS

PHAV_V1 = load_preset("phav-v1")
#: A recipe to write many times over where which recipe does not matter.
ONE_RECIPE = Path(__file__).parent / "data" / "recipe-v2-dive_floor.json"
#: Examples of the tests whose every example is expensive: drawing a θ takes ~0.2 s, its
#: YAML round trip ~0.4 s (pure-Python YAML, as ``load_theta`` reads it), a Parquet file
#: ~0.1 s. A quarter (θ) or half (Parquet) of the profile's: ci 10 and 20, dev 50 and 100.
THETA_EXAMPLES = max(10, settings.default.max_examples // 4)
PARQUET_EXAMPLES = max(10, settings.default.max_examples // 2)


@settings(max_examples=THETA_EXAMPLES)
@given(thetas())
def test_thetas_are_valid_and_round_trip_through_yaml(theta: Theta) -> None:
    assert isinstance(theta, Theta)
    again = parse_theta(yaml.safe_load(theta.to_yaml()), source="<to_yaml>")
    assert again == theta
    assert again.hash == theta.hash
    assert again.model_dump(mode="json") == theta.model_dump(mode="json")
    # The JSON form (tables as {rows: ...}) is a θ file too.
    assert parse_theta(theta.model_dump(mode="json")).hash == theta.hash


def _assert_every_reachable_action_samplable(theta: Theta) -> None:
    """What valid-by-construction means, checked on the arrays rather than by validation."""
    arr = theta.arrays
    reach = [i for i in range(len(ACTIONS)) if arr.a[i] > 0]
    assert reach
    for i in reach:
        assert arr.p_b_given_a()[i].sum() > 0, "a reachable action lost every motion to T_min"
        for j in range(arr.e.size):
            if arr.p_e_given_a()[i, j] > 0:
                assert arr.p_c_given_ae()[i, j].sum() > 0
    for i in range(len(ACTIONS)):
        if arr.a[i] == 0 and arr.ae[i].sum() == 0:
            assert arr.av[i].sum() == 0  # zero rows come as a set for unreachable actions


def _recipe_invariants(recipe) -> None:
    assert recipe.n_frames == frames_for(recipe.duration_s, recipe.video.fps)
    assert recipe.video_id == video_id(recipe.index)
    assert recipe.n_people == 1 + len(recipe.supporting_characters) == ACTIONS[recipe.action].n_people
    ids = [recipe.protagonist.person_id]
    ids += [p.person_id for p in recipe.supporting_characters]
    ids += [p.person_id for p in recipe.background_actors]
    assert len(ids) == len(set(ids))
    springs = CAMERA_INFO[recipe.camera.kind].tracking == "springs"
    assert (recipe.camera.springs is not None) == springs
    assert (recipe.camera.impulse is not None) == springs
    env = ENVIRONMENT_SCENES[recipe.environment.name]
    assert recipe.environment.indoor == env.indoor
    assert recipe.environment.waypoint == env.protagonist_waypoints[recipe.environment.waypoint_index]
    assert not (env.indoor and recipe.background_actors)
    assert not (CAMERA_INFO[recipe.camera.kind].indoor_only and not env.indoor)
    for person in (recipe.protagonist, *recipe.supporting_characters, *recipe.background_actors):
        if person.human.model == "sampled":
            assert person.human.sampled is not None
        else:
            assert person.human.phenotype == HUMAN_MODELS[person.human.model].phenotype
    for actor in recipe.background_actors:
        assert actor.start_waypoint != actor.destination_waypoint
    for character in recipe.supporting_characters:
        assert character.placement == ACTION_SCENES[recipe.action].supporting_placement
    v = recipe.variation
    if v.kind == "muscle_weakening":
        assert len(v.strengths) == len(v.muscles)
    if v.kind in ("random_perturbation", "muscle_weakening", "action_blending"):
        assert len(v.muscles) == len(set(v.muscles)) >= 1
    assert 0.0 <= recipe.world.clock_hour < 24.0


@given(recipes())
def test_recipes_are_consistent_and_round_trip_through_json(recipe) -> None:
    _recipe_invariants(recipe)
    text = recipe.model_dump_json()
    again = parse_recipe(text)
    assert again == recipe
    assert again.model_dump_json() == text


@settings(max_examples=10)
@given(st.data())
def test_recipes_for_a_theta_carry_its_hash_and_video_format(data: st.DataObject) -> None:
    theta = data.draw(st.just(PHAV_V1) | thetas(), label="theta")
    recipe = data.draw(recipes(theta), label="recipe")
    _recipe_invariants(recipe)
    assert recipe.theta_hash == theta.hash
    assert recipe.video.model_dump() == theta.video.model_dump()
    assert recipe.render == theta.render
    assert parse_recipe(recipe.model_dump_json()) == recipe


@settings(max_examples=PARQUET_EXAMPLES)
@given(recipe_lists())
def test_recipe_lists_round_trip_through_parquet(recipe_list) -> None:
    indices = [r.index for r in recipe_list]
    assert len(set(indices)) == len(indices)
    assert len({r.video_id for r in recipe_list}) == len(recipe_list)
    rows = RecipeRows().extend(recipe_list)
    assert len(rows) == len(recipe_list)
    table = rows.to_arrow(theta=PHAV_V1, dataset_seed=7)
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "recipes.parquet"
        assert write_recipe_table(table, path) > 0
        back = read_recipe_table(path)
        for name in (*COLUMN_NAMES, RECIPE_COLUMN):
            assert back.column(name) == rows.columns[name], name
        assert list(back.recipes()) == recipe_list
    assert back.theta == PHAV_V1
    assert back.dataset_seed == 7
    assert back.table.num_rows == len(recipe_list)


def _row_groups(path: Path) -> list[int]:
    import pyarrow.parquet as pq

    meta = pq.ParquetFile(path).metadata
    return [meta.row_group(i).num_rows for i in range(meta.num_row_groups)]


@settings(max_examples=PARQUET_EXAMPLES)
@given(recipe_lists(), st.integers(min_value=1, max_value=4))
def test_recipes_written_as_drawn_read_back_as_one_table(recipe_list, batch_rows) -> None:
    """`phav sample` streams its rows a batch at a time: the same table as one write, in row
    groups of ``batch_rows`` and the rest; a table of one batch is the same bytes."""
    with tempfile.TemporaryDirectory() as tmp:
        whole, streamed = Path(tmp) / "whole.parquet", Path(tmp) / "streamed.parquet"
        write_recipe_table(RecipeRows().extend(recipe_list).to_arrow(theta=PHAV_V1, dataset_seed=7), whole)
        rows, size = write_recipe_stream(iter(recipe_list), streamed, theta=PHAV_V1, dataset_seed=7,
                                         batch_rows=batch_rows)  # fmt: skip
        assert (rows, size) == (len(recipe_list), streamed.stat().st_size)
        a, b = read_recipe_table(whole), read_recipe_table(streamed)
        assert b.table.equals(a.table) and b.table.schema.metadata == a.table.schema.metadata
        assert (b.theta, b.dataset_seed, list(b.recipes())) == (PHAV_V1, 7, recipe_list)
        if len(recipe_list) <= batch_rows:
            assert streamed.read_bytes() == whole.read_bytes()


@pytest.mark.parametrize(("n", "groups"), [(0, [0]), (2, [2]), (3, [3]), (4, [3, 1]), (6, [3, 3])])
def test_a_stream_has_full_row_groups_and_the_rest(tmp_path, n, groups) -> None:
    """Batches of 3: no empty row group after a full one, one (empty) group for no rows."""
    one = load_recipe(ONE_RECIPE)
    out = tmp_path / "recipes.parquet"
    assert write_recipe_stream([one] * n, out, batch_rows=3)[0] == n
    assert _row_groups(out) == groups


def test_a_stream_is_written_as_it_is_drawn(tmp_path) -> None:
    """Rows reach the temporary file batch by batch, before the last recipe is drawn (memory
    holds one batch however many recipes come)."""
    one = load_recipe(ONE_RECIPE)
    sizes = []

    def drawn():
        for i in range(7):
            if i in (3, 6):  # after the first and second batch of 3 have been taken
                (tmp,) = [p for p in tmp_path.iterdir() if p.suffix == ".tmp"]
                sizes.append(tmp.stat().st_size)
            yield one

    write_recipe_stream(drawn(), tmp_path / "recipes.parquet", batch_rows=3)
    assert 1_000 < sizes[0] < sizes[1]  # a batch of three recipes each time (the header alone: 4 bytes)


def test_a_stream_that_fails_midway_leaves_nothing(tmp_path) -> None:
    """An interrupted `phav sample` leaves the previous table (or none) and no temporary."""
    one = load_recipe(ONE_RECIPE)

    def failing():
        for _ in range(5):
            yield one
        raise KeyboardInterrupt

    out = tmp_path / "recipes.parquet"
    out.write_bytes(b"previous")
    with pytest.raises(KeyboardInterrupt):
        write_recipe_stream(failing(), out, batch_rows=2)
    assert out.read_bytes() == b"previous"
    assert [p.name for p in tmp_path.iterdir()] == ["recipes.parquet"]


def test_a_stream_needs_a_batch_of_at_least_one_row(tmp_path) -> None:
    with pytest.raises(ValueError, match="batch_rows"):
        write_recipe_stream([], tmp_path / "recipes.parquet", batch_rows=0)


def test_recipe_lists_reach_the_empty_list() -> None:
    """The empty dataset is an example the strategy produces, not just one it could."""
    seen: list[int] = []

    @settings(max_examples=60, database=None)
    @given(recipe_lists(max_size=3))
    def collect(recipe_list) -> None:
        seen.append(len(recipe_list))

    collect()
    assert 0 in seen and max(seen) > 0


def _theta_features(theta: Theta) -> set[str]:
    """The hard cases a θ exhibits, read off θ itself (not off the strategy's events)."""
    arr = theta.arrays
    out = set()
    reach = np.flatnonzero(arr.a > 0)
    for variable, weights in (("action", arr.a), ("weather", arr.w), ("day phase", arr.d)):
        if np.count_nonzero(weights) == 1:
            out.add(f"single {variable}")
    if np.flatnonzero(arr.c).tolist() == [CAMERAS.index("kite")]:
        out.add("only kite camera")
    if any(arr.a[i] == 0 and arr.ae[i].sum() == 0 and arr.av[i].sum() == 0 for i in range(len(ACTIONS))):
        out.add("unreachable all-zero rows")
    for table in (arr.ae, arr.av, arr.ac):
        for i in reach:
            positive = table[i][table[i] > 0]
            if positive.size < table.shape[1] and len(set(positive.tolist())) > 1:
                out.add("non-uniform row with zeros")
    for phase, spec in theta.clock_hours.items():
        if theta.theta_d[phase] <= 0:
            continue
        if spec.min == spec.max:
            out.add("clock point")
        elif spec.mode == spec.min:
            out.add("clock min == mode")
        elif spec.mode == spec.max:
            out.add("clock mode == max")
        if spec.min > spec.max:
            out.add("clock wrapped, mode before midnight" if spec.mode >= spec.min else "clock wrapped, mode after")
            if phase == "night":
                out.add("night wraps with weight")
    d = theta.durations
    if d.t_min == d.t_max:
        out.add("t_min == t_max")
    elif d.t_min == d.t_mod:
        out.add("t_min == t_mod")
    elif d.t_mod == d.t_max:
        out.add("t_mod == t_max")
    lengths = np.array([MOTIONS[m].length_s for m in MOTIONS.names])
    longest = min(lengths[arr.ab[i] > 0].max() for i in reach)
    if d.t_min >= 0.95 * longest:
        out.add("T_min close to the longest motion")
    if any(((arr.ab[i] > 0) & ~arr.motion_long_enough).any() for i in reach):
        out.add("T_min masks motions")
    return out


THETA_FEATURES = {
    "single action", "single weather", "single day phase", "only kite camera",
    "unreachable all-zero rows", "non-uniform row with zeros", "clock point", "clock min == mode",
    "clock mode == max", "clock wrapped, mode before midnight", "clock wrapped, mode after",
    "night wraps with weight", "t_min == t_max", "t_min == t_mod", "t_mod == t_max",
    "T_min close to the longest motion", "T_min masks motions",
}  # fmt: skip


def test_thetas_reach_every_hard_case_and_keep_every_reachable_action_samplable() -> None:
    """60 drawn θ show every hard case, and each keeps its reachable actions samplable (one
    test: drawing a θ is the cost, and these 60 provably include the hard cases)."""
    seen: set[str] = set()

    @settings(max_examples=60, database=None)
    @given(thetas())
    def collect(theta: Theta) -> None:
        _assert_every_reachable_action_samplable(theta)
        seen.update(_theta_features(theta))

    collect()
    assert THETA_FEATURES - seen == set()


def _recipe_features(recipe) -> set[str]:
    out = {f"variation {recipe.variation.kind}"}
    if recipe.n_frames == 1:
        out.add("one frame")
    out.add("no background actors" if not recipe.background_actors else "background actors")
    if len(recipe.background_actors) >= 2:
        out.add("several background actors")
    if recipe.supporting_characters:
        out.add("supporting character")
    out.add("spring camera" if recipe.camera.springs is not None else "non-spring camera")
    if recipe.world.clock_hour < 1e-3:
        out.add("clock near 0")
    if recipe.world.clock_hour > 24.0 - 1e-3:
        out.add("clock near 24")
    return out


def test_recipes_reach_every_hard_case() -> None:
    seen: set[str] = set()

    # Enough examples that every variation shows up: in a full two-process suite run, 60
    # examples once drew no muscle_weakening recipe.
    @settings(max_examples=150, database=None)
    @given(recipes())
    def collect(recipe) -> None:
        seen.update(_recipe_features(recipe))

    collect()
    expected = {f"variation {v}" for v in VARIATIONS.names} | {
        "one frame", "no background actors", "several background actors", "supporting character",
        "spring camera", "non-spring camera", "clock near 0", "clock near 24",
    }  # fmt: skip
    assert expected - seen == set()


def test_recipe_lists_rejects_bad_sizes() -> None:
    with pytest.raises(ValueError, match="min_size"):
        recipe_lists(min_size=3, max_size=2)
