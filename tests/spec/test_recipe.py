"""Recipe schema v1: validation, migrations from older versions, refusal of newer ones."""

from __future__ import annotations

import json

import pytest

from phav_generator.sampling import RecipeSampler
from phav_spec.errors import PhavUserError
from phav_spec.recipe import (
    RECIPE_SCHEMA_VERSION,
    Recipe,
    load_recipe,
    parse_recipe,
    recipe_json_schema,
    upgrade_recipe,
)
from phav_spec.theta import load_preset
from tests.helpers import run_cli


@pytest.fixture(scope="module")
def recipe() -> Recipe:
    return RecipeSampler(load_preset()).sample(0, 3)


def test_json_round_trip_is_exact(recipe):
    assert parse_recipe(recipe.model_dump_json()) == recipe
    assert parse_recipe(recipe.model_dump_json()).model_dump_json() == recipe.model_dump_json()


def _v0_from_v1(data: dict) -> dict:
    """A synthetic schema version 0: flat clip length, camera kind at the top level."""
    old = dict(data)
    old["schema_version"] = 0
    old["clip_seconds"] = old.pop("duration_s")
    old["camera_kind"] = old["camera"]["kind"]
    old["camera"] = {k: v for k, v in old["camera"].items() if k != "kind"}
    return old


def _migrate_0_to_1(data: dict) -> dict:
    new = dict(data)
    new["duration_s"] = new.pop("clip_seconds")
    new["camera"] = {"kind": new.pop("camera_kind"), **new["camera"]}
    new["schema_version"] = 1
    return new


def test_migration_registry_upgrades_a_synthetic_older_version(recipe):
    old = _v0_from_v1(json.loads(recipe.model_dump_json()))
    with pytest.raises(PhavUserError, match="no migration from version 0"):
        upgrade_recipe(old)
    upgraded = upgrade_recipe(old, migrations={0: _migrate_0_to_1})
    assert Recipe.model_validate(upgraded) == recipe


def test_a_migration_that_forgets_the_version_is_a_bug(recipe):
    old = _v0_from_v1(json.loads(recipe.model_dump_json()))
    with pytest.raises(RuntimeError, match="did not produce version 1"):
        upgrade_recipe(old, migrations={0: lambda d: d})


def test_future_version_is_refused_with_a_clear_message(recipe, tmp_path):
    data = json.loads(recipe.model_dump_json())
    data["schema_version"] = RECIPE_SCHEMA_VERSION + 1
    path = tmp_path / "future.json"
    path.write_text(json.dumps(data), encoding="utf-8")
    with pytest.raises(PhavUserError) as info:
        load_recipe(path)
    assert str(info.value) == f"{path}: schema_version: version 2 is newer than this phav supports (1); upgrade phav"


@pytest.mark.parametrize(
    ("edit", "field", "words"),
    [
        (lambda d: d.pop("duration_s"), "duration_s", "missing required field"),
        (lambda d: d["world"].pop("clock_hour"), "world.clock_hour", "missing required field"),
        (lambda d: d.pop("schema_version"), "schema_version", "missing required field"),
        (lambda d: d.update(action="fly"), "action", "Input should be"),
        (lambda d: d.update(extra_field=1), "extra_field", "unknown key"),
        (lambda d: d.update(n_frames=d["n_frames"] + 1), "", "n_frames"),
        (lambda d: d["world"].update(clock_hour=24.0), "world.clock_hour", "less than 24"),
        (lambda d: d.update(video_id="v000003.mp4"), "video_id", "pattern"),
        (
            lambda d: d["variation"].update(kind="teleport"),
            "variation",
            "does not match any of the expected tags",
        ),
    ],
)
def test_malformed_recipes_name_the_field(recipe, edit, field, words):
    data = json.loads(recipe.model_dump_json())
    edit(data)
    with pytest.raises(PhavUserError) as info:
        parse_recipe(data, source="r.json")
    message = str(info.value)
    assert message.startswith(f"r.json: {field}" if field else "r.json: "), message
    assert words in message and "\n" not in message


def test_non_json_is_a_user_error():
    with pytest.raises(PhavUserError, match=r"r\.json: invalid JSON"):
        parse_recipe("{not json", source="r.json")
    with pytest.raises(PhavUserError, match="expected a JSON object, got list"):
        parse_recipe("[1, 2]", source="r.json")


def test_json_schema_lists_vocabularies_and_validates_structure():
    schema = recipe_json_schema()
    assert schema["properties"]["schema_version"]["const"] == 1
    text = json.dumps(schema)
    assert "walk_holding_hands" in text and "house_interior" in text and "muscle_weakening" in text
    cli = run_cli("spec", "schema")
    assert cli.returncode == 0
    assert json.loads(cli.stdout) == json.loads(json.dumps(schema))
