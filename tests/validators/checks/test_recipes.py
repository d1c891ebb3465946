"""The schema check on a dataset's recipes and metadata tables: a recipe this phav cannot
read is named, and so is a table column off the contract."""

from __future__ import annotations

import pyarrow as pa
import pyarrow.parquet as pq

from phav_validators.findings import Reason
from tests.validators.checks.support import assert_fails, edit_recipes, validate


def test_future_schema_version_fails_schema(data):
    edit_recipes(data, "v000001", lambda d: d.update(schema_version=99))
    hits = assert_fails(validate(data, "schema"), "schema", Reason.RECIPE_INVALID, video="v000001")
    assert "newer" in hits[0].message and "schema_version" in hits[0].message


def _rewrite(path, name: str, values: list, kind: pa.DataType) -> None:
    """``path``'s column ``name`` replaced by ``values`` of ``kind`` (nullable), its metadata kept."""
    table = pq.read_table(path)
    i = table.column_names.index(name)
    table = table.set_column(i, pa.field(name, kind, nullable=True), pa.array(values, kind))
    pq.write_table(table.replace_schema_metadata(pq.read_schema(path).metadata), path)


def test_a_metadata_column_of_another_type_or_with_nulls_fails_schema(data):
    """The tables' columns are checked against the contract's types, and none may hold a
    null (a number is NaN where unknown): from the schema and the Parquet statistics."""
    people, cameras = data / "people.parquet", data / "cameras.parquet"
    roles = pq.read_table(people).column("role").to_pylist()
    _rewrite(people, "role", [None, *roles[1:]], pa.string())
    pixels = pq.read_table(people).column("pixels").to_pylist()
    _rewrite(people, "pixels", [str(p) for p in pixels], pa.string())
    boxes = pq.read_table(people).column("bbox2d").to_pylist()
    _rewrite(people, "bbox2d", [boxes[0], None, *boxes[2:]], pa.list_(pa.float64(), 4))
    frames = pq.read_table(cameras).column("frame").to_pylist()
    _rewrite(cameras, "frame", [float(f) for f in frames], pa.float64())
    hits = assert_fails(validate(data, "schema"), "schema", Reason.METADATA_INVALID)
    assert sorted((h.file, h.message) for h in hits) == [
        ("cameras.parquet", "column 'frame' is double, the contract's is int64"),
        ("people.parquet", "column 'bbox2d' holds 1 null"),
        ("people.parquet", "column 'pixels' is string, the contract's is int64"),
        ("people.parquet", "column 'role' holds 1 null"),
    ]


def test_metadata_values_the_contract_rules_out_fail_schema(data):
    people, cameras = data / "people.parquet", data / "cameras.parquet"
    table = pq.read_table(people)
    pixels, roles, vids = (table.column(c).to_pylist() for c in ("pixels", "role", "video_id"))
    _rewrite(people, "pixels", [-5, *pixels[1:]], pa.int64())
    _rewrite(people, "role", [*roles[:2], "alien", *roles[3:]], pa.string())
    _rewrite(people, "video_id", [*vids[:-1], "v999999"], pa.string())
    cams = pq.read_table(cameras)
    fx, poses = cams.column("fx").to_pylist(), cams.column("cam_to_world").to_pylist()
    _rewrite(cameras, "fx", [0.0, *fx[1:]], pa.float64())
    poses[4] = [2.0 * v for v in poses[4]]  # scaled: not a rotation, and its bottom row (0, 0, 0, 2)
    _rewrite(cameras, "cam_to_world", poses, pa.list_(pa.float64(), 16))
    hits = assert_fails(validate(data, "schema"), "schema", Reason.METADATA_INVALID)
    assert sorted((h.file, h.message) for h in hits) == [
        ("cameras.parquet", "a cam_to_world that is not a rigid pose in 1 rows (first v000000)"),
        ("cameras.parquet", "a focal length that is not positive in 1 rows (first v000000)"),
        ("people.parquet", "a negative pixel count in 1 rows (first v000000)"),
        ("people.parquet", "a role not one of protagonist, supporting, background in 1 rows (first v000000)"),
        ("people.parquet", "rows of 1 videos without a recipe (first v999999)"),
    ]


def test_without_a_readable_manifest_the_schema_check_does_not_pass(data):
    """Its videos cannot be paired with their recipes: the schema check says so, not only
    integrity."""
    (data / "manifest.json").write_text("{not json")
    hits = assert_fails(validate(data, "schema"), "schema", Reason.MANIFEST_INVALID)
    assert hits[0].message == "videos and recipes cannot be paired: the manifest is invalid"
    (data / "manifest.json").unlink()
    hits = assert_fails(validate(data, "schema", "encoding"), "schema", Reason.MISSING_FILE, file="manifest.json")
    assert hits[0].message == "videos and recipes cannot be paired: the manifest is missing"


def test_a_manifest_finding_names_the_field_and_says_no_pydantic_wrapping(data):
    """A manifest without its videos, or with a content hash that is no digest: the finding
    names the field, and its words are ours, not pydantic's "Value error, "."""
    import json

    manifest = json.loads((data / "manifest.json").read_text())
    (data / "manifest.json").write_text(json.dumps({k: v for k, v in manifest.items() if k != "videos"}))
    hits = assert_fails(validate(data, "integrity"), "integrity", Reason.MANIFEST_INVALID)
    assert hits[0].message.startswith("videos: Field required")
    manifest["videos"][0]["content_hash"] = "0" * 64
    (data / "manifest.json").write_text(json.dumps(manifest))
    hits = assert_fails(validate(data, "integrity"), "integrity", Reason.MANIFEST_INVALID)
    assert hits[0].message.startswith("videos.0: ") and "Value error" not in hits[0].message, hits[0].message


def test_a_manifest_whose_dataset_seed_is_not_the_recipes_fails_the_schema_check(data):
    import json

    manifest = json.loads((data / "manifest.json").read_text())
    manifest["dataset_seed"] += 5
    (data / "manifest.json").write_text(json.dumps(manifest))
    hits = assert_fails(validate(data, "schema"), "schema", Reason.VIDEO_RECIPE_MISMATCH)
    assert hits[0].message.startswith(f"dataset seed {manifest['dataset_seed']}, the recipes' ")


def test_a_dataset_made_from_theta_without_its_theta_file_fails_integrity(data):
    """The manifest records the θ the videos were made from; without theta.yaml the check
    read θ from the table's metadata and passed (phav release refuses such a dataset)."""
    (data / "theta.yaml").unlink()
    hits = assert_fails(validate(data, "integrity"), "integrity", Reason.MISSING_FILE)
    assert hits[0].file == "theta.yaml" and "the dataset has no theta.yaml" in hits[0].message
