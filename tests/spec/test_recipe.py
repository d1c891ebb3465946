"""Recipe schema v2: validation, migrations from older versions (v1 files still load),
refusal of newer ones."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from phav_generator.sampling import RecipeSampler
from phav_spec.errors import PhavUserError
from phav_spec.recipe import (
    RECIPE_MIGRATIONS,
    RECIPE_SCHEMA_VERSION,
    Recipe,
    load_recipe,
    parse_recipe,
    recipe_json_schema,
    upgrade_recipe,
)
from phav_spec.scene import HUMAN_MODELS
from phav_spec.theta import load_preset
from tests.helpers import run_cli

V1_RECIPES = sorted((Path(__file__).parent / "data").glob("recipe-v1-*.json"))
V2_RECIPES = sorted((Path(__file__).parent / "data").glob("recipe-v2-*.json"))


@pytest.fixture(scope="module")
def recipe() -> Recipe:
    return RecipeSampler(load_preset()).sample(0, 3)


def test_json_round_trip_is_exact(recipe):
    assert parse_recipe(recipe.model_dump_json()) == recipe
    assert parse_recipe(recipe.model_dump_json()).model_dump_json() == recipe.model_dump_json()


def _v0_from_v1(data: dict) -> dict:
    """A synthetic schema version 0 (before 1): flat clip length, camera kind at the top level."""
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
    upgraded = upgrade_recipe(old, migrations={**RECIPE_MIGRATIONS, 0: _migrate_0_to_1})
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
    v = RECIPE_SCHEMA_VERSION
    assert (
        str(info.value)
        == f"{path}: schema_version: version {v + 1} is newer than this phav supports ({v}); upgrade phav"
    )


def _indoors_with_walkers(d: dict) -> None:
    """The lake's recipe moved into the house, its background walker kept."""
    d["environment"].update(name="house_interior", indoor=True, waypoint_index=0)


def _kicked(d: dict) -> None:
    """A 0.011 kg camera kicked with 6 N·s."""
    d["camera"]["springs"]["camera_mass"] = 0.011
    d["camera"]["impulse"]["strength"] = 6.0


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
        # Values θ can never give, which the renderer or the physics cannot honour.
        (lambda d: d["video"].update(width=100000), "video.width", "less than or equal to 4096"),
        (lambda d: d["camera"].update(position=[float("inf"), 1.0, 1.0]), "camera.position.0", "finite number"),
        (lambda d: d["camera"].update(fov_deg=-10.0), "camera.fov_deg", "greater than or equal to 10"),
        (lambda d: d["world"].update(sun_brightness=-3.0), "world.sun_brightness", "greater than or equal to 0"),
        (lambda d: d["world"].update(fog_intensity=1.5), "world.fog_intensity", "less than or equal to 1"),
        (lambda d: d["motion"].update(start_s=1000.0), "motion.start_s", "past the take's end"),
        (lambda d: d.update(duration_s=1e308), "", "duration_s 1e+308 is too long to count its frames"),
        (lambda d: d.update(dataset_seed=True), "dataset_seed", "valid integer"),
        (lambda d: d["seeds"].update(physics=1.0), "seeds.physics", "valid integer"),
        (_kicked, "camera", "throws it at 545.5 m/s; at most 50"),
        # JSON's types as written: a number in quotes is a hand edit, not a number.
        (lambda d: d["video"].update(fps="30"), "video.fps", "valid integer, got str '30'; write numbers without"),
        (lambda d: d.update(duration_s="4.0"), "duration_s", "valid number"),
        (lambda d: d["camera"].update(fov_deg="60"), "camera.fov_deg", "valid number"),
        # Values θ's bounds rule out, which crashed the physics (a massless camera divides by 0).
        (lambda d: d["motion"].update(speed=1e300), "motion.speed", "less than or equal to 5"),
        (lambda d: d["camera"].update(kind="kite", springs=None), "camera", "springs: a kite camera needs springs"),
        # Values the recipe repeats or indexes, checked against what they name (each was accepted).
        (lambda d: d["background_actors"][0].update(person_id=300), "background_actors.0.person_id", "or equal to 255"),
        (lambda d: d.update(index=2**63, video_id=f"v{2**63}"), "index", "less than 9223372036854775808"),
        (lambda d: d["environment"].update(waypoint_index=2**40), "", "environment.waypoint_index: lake has"),
        (lambda d: d["background_actors"][0].update(start_waypoint=99), "", "start_waypoint: lake has"),
        (_indoors_with_walkers, "", "background_actors: house_interior has no background actors' waypoints"),
        (lambda d: d["environment"].update(indoor=True), "", "environment.indoor: lake is not indoors"),
        (
            lambda d: d["camera"].update(kind="indoors", springs=None, impulse=None),
            "",
            "camera.kind: the indoors camera films indoors only, not in lake",
        ),
        (lambda d: d.update(action="walk_holding_hands"), "", "n_people: walk_holding_hands is done by 2, not 1"),
        (lambda d: d["motion"].update(base_motion_length_s=500.0), "motion", "is 10.4 s long, not 500.0"),
        (
            lambda d: d.update(duration_s=10.5, n_frames=315),
            "",
            "duration_s: 10.5 s is longer than archery_draw_release_01 (10.4 s)",
        ),
        (lambda d: d["camera"]["springs"].update(ct_min_distance_m=True), "camera.springs", "valid integer"),
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


def test_a_recipe_mapping_may_hold_numpy_scalars_but_nothing_json_cannot_write(recipe):
    """A row read with Arrow or pandas holds numpy scalars: they are the numbers they hold."""
    data = json.loads(recipe.model_dump_json())
    data["video"]["fps"] = np.int64(data["video"]["fps"])
    data["duration_s"] = np.float64(data["duration_s"])
    assert parse_recipe(data, source="r.json") == recipe
    data["video"]["fps"] = object()
    with pytest.raises(PhavUserError, match=r"^r\.json: a value of type object has no JSON form$"):
        parse_recipe(data, source="r.json")


def test_a_key_written_twice_is_refused(recipe):
    """The last of two ``action`` keys would silently win: a hand edit that meant one of them."""
    text = recipe.model_dump_json()
    doubled = text.replace('"action":', '"action":"walk","action":', 1)
    with pytest.raises(PhavUserError, match=r"^r\.json: action: key written twice$"):
        parse_recipe(doubled, source="r.json")


def test_non_json_is_a_user_error():
    with pytest.raises(PhavUserError, match=r"r\.json: invalid JSON"):
        parse_recipe("{not json", source="r.json")
    with pytest.raises(PhavUserError, match="expected a JSON object, got list"):
        parse_recipe("[1, 2]", source="r.json")


def test_json_schema_lists_vocabularies_and_validates_structure():
    schema = recipe_json_schema()
    assert schema["properties"]["schema_version"]["const"] == RECIPE_SCHEMA_VERSION
    text = json.dumps(schema)
    assert "walk_holding_hands" in text and "house_interior" in text and "muscle_weakening" in text
    cli = run_cli("spec", "schema")
    assert cli.returncode == 0
    assert json.loads(cli.stdout) == json.loads(json.dumps(schema))


@pytest.mark.parametrize("path", V1_RECIPES, ids=lambda p: p.stem)
def test_a_version_1_recipe_upgrades_to_the_same_fixed_models(path):
    """v1 recipes (the phav-v1 golden recipes of seed 0 as released before v2) still load:
    each person becomes the v2 fixed model of the same name, everything else unchanged."""
    old = json.loads(path.read_text(encoding="utf-8"))
    assert old["schema_version"] == 1 and "height_m" in old["protagonist"]["human"]
    recipe = load_recipe(path)
    assert recipe.schema_version == RECIPE_SCHEMA_VERSION
    people = [(old["protagonist"], recipe.protagonist)]
    people += list(zip(old["supporting_characters"], recipe.supporting_characters, strict=True))
    people += list(zip(old["background_actors"], recipe.background_actors, strict=True))
    assert len(people) >= 2
    for before, after in people:
        name = before["human"]["model"]
        model = HUMAN_MODELS[name]
        assert after.human.model == name and after.human.sampled is None
        assert after.human.phenotype == model.phenotype and after.human.skin_rgb == model.skin_rgb
        assert after.human.hair == model.hair and after.human.outfit == model.outfit
        assert {k: v for k, v in before.items() if k != "human"} == {
            k: v for k, v in json.loads(after.model_dump_json()).items() if k != "human"
        }
    new = json.loads(recipe.model_dump_json())
    for key in old:
        if key not in ("schema_version", "protagonist", "supporting_characters", "background_actors", "environment"):
            assert new[key] == old[key], key
    assert new["environment"] == {**old["environment"], "look_seed": None}
    cli = run_cli("recipe", "check", str(path))
    assert cli.returncode == 0, cli.stderr


@pytest.mark.parametrize("path", V2_RECIPES, ids=lambda p: p.stem)
def test_a_version_2_recipe_upgrades_to_its_environment_s_fixed_look(path):
    """v2 recipes (phav-v1 golden recipes of seed 0 as released before v3) load with the
    environment's one fixed look (``look_seed`` None), everything else as it was."""
    old = json.loads(path.read_text(encoding="utf-8"))
    assert old["schema_version"] == 2 and "look_seed" not in old["environment"]
    new = json.loads(load_recipe(path).model_dump_json())
    assert new["schema_version"] == RECIPE_SCHEMA_VERSION
    assert new["environment"] == {**old["environment"], "look_seed": None}
    assert {k: v for k, v in new.items() if k not in ("schema_version", "environment")} == {
        k: v for k, v in old.items() if k not in ("schema_version", "environment")
    }


def test_a_version_1_person_with_an_unknown_model_is_reported_after_the_upgrade():
    old = json.loads(V1_RECIPES[0].read_text(encoding="utf-8"))
    old["protagonist"]["human"]["model"] = "model_99"
    with pytest.raises(PhavUserError) as info:
        parse_recipe(old, source="old.json")
    assert str(info.value).startswith("old.json: protagonist.human.")


def test_model_and_draws_agree(recipe):
    data = json.loads(recipe.model_dump_json())
    data["protagonist"]["human"]["model"] = "sampled"
    with pytest.raises(PhavUserError, match="sampled: set exactly when model is 'sampled'"):
        parse_recipe(data, source="r.json")


def test_a_version_1_recipes_table_reads_upgraded(tmp_path):
    """A recipes.parquet written by schema 1 (its columns, v1 JSON): read with the current
    columns, computed from the upgraded recipes."""
    import pyarrow as pa

    from phav_spec.population import estimated_stature
    from phav_spec.recipe_table import (
        COLUMN_NAMES,
        COLUMNS,
        RECIPE_COLUMN,
        RecipeRows,
        read_recipe_table,
        write_recipe_table,
    )

    texts = [p.read_text(encoding="utf-8") for p in V1_RECIPES]
    upgraded = [parse_recipe(t) for t in texts]
    old_columns = COLUMN_NAMES[: COLUMN_NAMES.index("n_varied_muscles") + 1]
    rows = RecipeRows().extend(upgraded)
    arrays = {c.name: rows.to_arrow().column(c.name) for c in COLUMNS if c.name in old_columns}
    arrays[RECIPE_COLUMN] = pa.array(texts)
    table = pa.table(arrays).replace_schema_metadata({"phav.recipe_schema_version": "1"})
    path = tmp_path / "recipes.parquet"
    write_recipe_table(table, path)
    back = read_recipe_table(path)
    assert back.schema_version == 1
    assert back.table.column_names == [*COLUMN_NAMES, RECIPE_COLUMN]
    assert list(back.recipes()) == upgraded
    assert back.column("human_model") == [r.protagonist.human.model for r in upgraded]
    assert back.column("stature_m") == [estimated_stature(r.protagonist.human.phenotype) for r in upgraded]


def test_a_kite_cameras_springs_and_impulse_are_bounded_as_thetas_are(recipe):
    """Every spring and impulse value within θ's bounds (scene.KITE_SPRING_VARIABLES,
    PARAMETER_BOUNDS): a camera of mass 0 or -5 crashed the physics."""
    data = json.loads(recipe.model_dump_json())
    if data["camera"]["springs"] is None:
        pytest.skip("the fixture's camera has no springs")
    for field, value, words in (("camera_mass", 0.0, "greater than or equal to 0.01"),
                                ("camera_mass", -5.0, "greater than or equal to 0.01"),
                                ("ct_spring_strength", 1e9, "less than or equal to 100000")):  # fmt: skip
        bad = json.loads(json.dumps(data))
        bad["camera"]["springs"][field] = value
        with pytest.raises(PhavUserError) as info:
            parse_recipe(bad, source="r.json")
        assert str(info.value).startswith(f"r.json: camera.springs.{field}") and words in str(info.value)
    static = json.loads(json.dumps(data))
    static["camera"]["kind"] = "static"
    with pytest.raises(PhavUserError, match=r"springs: a static camera takes no springs"):
        parse_recipe(static, source="r.json")


@pytest.mark.parametrize("model", [["x"], {"a": 1}])
def test_a_version_1_person_whose_model_is_not_a_name_is_one_line(model):
    """A malformed v1 person (a list or a mapping for its model) was looked up in the model
    registry and raised a TypeError traceback, which stopped `phav-validate` outright."""
    data = json.loads(V1_RECIPES[0].read_text(encoding="utf-8"))
    data["protagonist"]["human"]["model"] = model
    with pytest.raises(PhavUserError, match=r"^bad\.json: protagonist\.human\."):
        parse_recipe(json.dumps(data), source="bad.json")
