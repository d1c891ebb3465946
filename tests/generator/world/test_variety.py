"""Per-video variety (θ ``world_variety: video``): a recipe carries its look's seed, which
changes the looks and nothing else; the default keeps one look per environment and the
θ hashes and recipes it had. The asset library's fingerprint follows what it builds."""

from __future__ import annotations

import json

import numpy as np
import yaml

from phav_generator.sampling import RecipeSampler
from phav_generator.world import library
from phav_generator.world.library import collider_asset, world_library_sha256
from phav_spec.recipe import parse_recipe
from phav_spec.recipe_table import RecipeRows, read_recipe_table, write_recipe_table
from phav_spec.scene import ENVIRONMENT_SCENES
from phav_spec.theta import load_preset, parse_theta

N = 12


def _video_variety(theta):
    data = json.loads(json.dumps(theta.model_dump(mode="json")))
    return parse_theta({**data, "world_variety": "video"})


def test_the_default_leaves_theta_s_hash_and_yaml_as_they_were():
    theta = load_preset()
    assert theta.world_variety == "environment"
    assert "world_variety" not in theta.to_yaml()
    varied = _video_variety(theta)
    assert varied.hash != theta.hash
    assert parse_theta(yaml.safe_load(varied.to_yaml())) == varied


def test_video_variety_gives_each_video_its_own_look_seed_and_changes_nothing_else():
    theta = load_preset()
    fixed, varied = RecipeSampler(theta), RecipeSampler(_video_variety(theta))
    seeds = []
    for i in range(N):
        a, b = fixed.sample(7, i), varied.sample(7, i)
        assert a.environment.look_seed is None and b.environment.look_seed is not None
        assert b == varied.sample(7, i)  # the same video, the same seed
        da, db = json.loads(a.model_dump_json()), json.loads(b.model_dump_json())
        db["environment"]["look_seed"] = None
        db["theta_hash"] = da["theta_hash"]
        assert da == db  # every other draw as without variety
        seeds.append(b.environment.look_seed)
    assert len(set(seeds)) == N


def test_the_look_seed_round_trips_through_json_and_the_recipes_table(tmp_path):
    sampler = RecipeSampler(_video_variety(load_preset()))
    recipes = [sampler.sample(3, i) for i in range(4)]
    for r in recipes:
        assert parse_recipe(r.model_dump_json()) == r
    path = tmp_path / "recipes.parquet"
    write_recipe_table(RecipeRows().extend(recipes).to_arrow(), path)
    table = read_recipe_table(path)
    assert list(table.recipes()) == recipes
    assert table.column("look_seed") == [r.environment.look_seed for r in recipes]


def test_a_look_seed_changes_the_look_not_the_fit():
    env = ENVIRONMENT_SCENES["urban"]
    buildings = [i for i, c in enumerate(env.colliders) if c.pixel_class == "building"]
    for i in buildings[:3]:
        half = np.array(env.colliders[i].half_size)
        looks = {collider_asset("urban", i, 0, seed).colours.tobytes() for seed in (None, 1, 2, 3)}
        assert len(looks) >= 3  # facades differ between looks
        for seed in (1, 2):
            p = collider_asset("urban", i, 0, seed).positions
            assert (np.abs(p) <= half + 0.02).all()  # still inside its collider
    assert collider_asset("urban", buildings[0], 0, None) is collider_asset("urban", buildings[0], 0)


def test_the_library_s_fingerprint_follows_what_it_builds(monkeypatch):
    before = world_library_sha256()

    def rebuilt() -> str:
        library._collider_asset.cache_clear()
        world_library_sha256.cache_clear()
        return world_library_sha256()

    try:
        monkeypatch.setattr("phav_generator.world.materials.MARKING_WHITE", (0.8, 0.8, 0.8))
        assert rebuilt() != before  # a road marking's colour is part of the world
        monkeypatch.undo()
        assert rebuilt() == before
    finally:
        monkeypatch.undo()
        rebuilt()
