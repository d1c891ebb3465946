"""The dataset manifest model and its JSON file (phav_spec.manifest)."""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from pydantic import ValidationError

from phav_spec.encoding import MODALITIES
from phav_spec.errors import PhavUserError
from phav_spec.manifest import (
    MANIFEST_VERSION,
    DatasetManifest,
    RendererFingerprint,
    ShardEntry,
    VideoEntry,
    dump_manifest,
    load_manifest,
    motion_unpromised,
    renderer_differences,
)

HEX_A = "a" * 64
HEX_B = "0123456789abcdef" * 4


def _fingerprint(**changes: Any) -> RendererFingerprint:
    fields: dict[str, Any] = {
        "gl_vendor": "Mesa",
        "gl_renderer": "llvmpipe (LLVM 15.0.6, 256 bits)",
        "gl_version": "3.3 (Core Profile) Mesa 22.3.6",
        "cpu_model": "Example CPU",
        "cpu_flags": "sse4_2 avx avx2 fma",
        "versions": {"phav": "0.1.0", "numpy": "2.4.6", "mujoco": "4.0", "moderngl": "5.12"},
    }
    fields.update(changes)
    return RendererFingerprint(**fields)


def _manifest_data() -> dict[str, Any]:
    """A valid manifest with two shards and three videos, as plain JSON data."""
    return {
        "manifest_version": MANIFEST_VERSION,
        "name": "phav_demo",
        "phav_version": "0.1.0",
        "theta_hash": HEX_A,
        "dataset_seed": 0,
        "recipe_schema_version": 1,
        "modalities": [m.model_dump() for m in MODALITIES],
        "renderer": _fingerprint().model_dump(),
        "shards": [
            {"name": "phav_demo-000000.tar", "sha256": HEX_B, "bytes": 1024,
             "video_ids": ["v000000", "v000001"]},
            {"name": "phav_demo-000001.tar", "sha256": HEX_A, "bytes": 0,
             "video_ids": ["v000002"]},
        ],
        "videos": [
            {"video_id": "v000000", "shard": "phav_demo-000000.tar", "n_frames": 30,
             "content_hash": HEX_A},
            {"video_id": "v000001", "shard": "phav_demo-000000.tar", "n_frames": 1,
             "content_hash": HEX_B},
            {"video_id": "v000002", "shard": "phav_demo-000001.tar", "n_frames": 300,
             "content_hash": HEX_A},
        ],
    }  # fmt: skip


def _write(tmp_path: Path, data: Any) -> Path:
    path = tmp_path / "manifest.json"
    path.write_text(json.dumps(data), encoding="utf-8")
    return path


def _load_error(tmp_path: Path, data: Any) -> PhavUserError:
    path = _write(tmp_path, data)
    with pytest.raises(PhavUserError) as info:
        load_manifest(path)
    error = info.value
    assert str(path) in str(error)
    assert error.source == str(path)
    assert "\n" not in str(error)
    return error


def test_round_trip_through_dump_and_load(tmp_path: Path) -> None:
    manifest = DatasetManifest.model_validate(_manifest_data())
    path = tmp_path / "manifest.json"
    dump_manifest(manifest, path)
    loaded = load_manifest(path)
    assert loaded == manifest
    assert loaded.videos[2].n_frames == 300
    assert loaded.modalities == list(MODALITIES)
    # Canonical: writing the loaded manifest again gives the same bytes.
    first = path.read_bytes()
    dump_manifest(loaded, path)
    assert path.read_bytes() == first
    assert json.loads(first) == manifest.model_dump(mode="json")
    assert first.endswith(b"\n")


def test_dump_is_atomic_and_leaves_no_temp_files(tmp_path: Path) -> None:
    path = tmp_path / "manifest.json"
    path.write_text("old", encoding="utf-8")
    dump_manifest(DatasetManifest.model_validate(_manifest_data()), path)
    assert sorted(os.listdir(tmp_path)) == ["manifest.json"]
    assert load_manifest(path).name == "phav_demo"


def test_dump_creates_a_missing_directory(tmp_path: Path) -> None:
    dump_manifest(DatasetManifest.model_validate(_manifest_data()), tmp_path / "new" / "m.json")
    assert os.listdir(tmp_path / "new") == ["m.json"]
    assert load_manifest(tmp_path / "new" / "m.json").name == "phav_demo"


def test_an_interrupted_dump_keeps_the_old_file(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    path = tmp_path / "manifest.json"
    path.write_text("old", encoding="utf-8")

    def fail(*args: object, **kwargs: object) -> None:
        raise OSError("disk full")

    monkeypatch.setattr(os, "replace", fail)
    with pytest.raises(PhavUserError, match="cannot write: disk full"):
        dump_manifest(DatasetManifest.model_validate(_manifest_data()), path)
    assert path.read_text(encoding="utf-8") == "old"
    assert os.listdir(tmp_path) == ["manifest.json"]


def test_empty_dataset_is_valid(tmp_path: Path) -> None:
    data = {**_manifest_data(), "shards": [], "videos": [], "renderer": None}
    del data["modalities"]
    manifest = DatasetManifest.model_validate(data)
    assert manifest.modalities == list(MODALITIES)
    path = tmp_path / "manifest.json"
    dump_manifest(manifest, path)
    assert load_manifest(path) == manifest


def test_fingerprint_digest_is_canonical() -> None:
    a = _fingerprint()
    b = _fingerprint(versions=dict(reversed(list(a.versions.items()))))
    assert a.digest() == b.digest()
    assert len(a.digest()) == 64
    assert _fingerprint(gl_version="4.5 Mesa 23.0").digest() != a.digest()
    assert _fingerprint(versions={**a.versions, "numpy": "2.5.0"}).digest() != a.digest()


def test_fingerprints_compare_by_simd_class_across_versions() -> None:
    """Version 1 (model and flags) against version 2 (class): the model is not compared; the
    class of version 1's flags is; version 1 lacks the numerics, which its flags stand in
    for. numpy's and OpenBLAS's kernels count for the pixels: the physics carries their last
    bits into the motion (docs/reproducibility.md)."""
    numerics = "numpy X86_V3; OpenBLAS Haswell"
    v1 = _fingerprint(cpu_flags="fpu sse2 ssse3 avx avx2 fma")
    v2 = _fingerprint(fingerprint_version=2, cpu_flags=None, cpu_class="x86-64-avx", numeric_class=numerics,
                      cpu_model="Other CPU")  # fmt: skip
    assert v1.simd_class == "x86-64-avx" and v1.differences(v2) == ["numeric_class"] and v1.digest() != v2.digest()
    assert v1.differences(v2, "files") == ["numeric_class"] and v2.differences(v2, "files") == []
    assert v1.differences(_fingerprint(cpu_flags="fpu sse2 ssse3 avx avx2 fma", cpu_model="Other"), "files") == []
    assert v1.differences(_fingerprint(cpu_flags="fpu sse2 ssse3 avx avx2 fma avx512f")) == ["numeric_class"]
    assert renderer_differences(v1, None) is None and renderer_differences(v1, v2) == ["numeric_class"]
    no_avx = _fingerprint(cpu_flags="fpu sse2 ssse3")
    newer_numpy = v2.model_copy(update={"versions": {**v1.versions, "numpy": "9.9"}})
    other_blas = v2.model_copy(update={"numeric_class": "numpy X86_V3; OpenBLAS Zen"})
    assert v2.differences(no_avx) == ["cpu_class", "numeric_class"]
    assert v2.differences(newer_numpy) == ["versions.numpy"]
    assert v2.differences(other_blas) == v2.differences(other_blas, "files") == ["numeric_class"]
    # Which keys can move the motion: the driver's alone cannot; an unrecorded renderer may have.
    other_driver = v2.model_copy(update={"gl_renderer": "llvmpipe (LLVM 19.1.7, 256 bits)"})
    assert motion_unpromised(v2.differences(other_driver)) == []
    assert motion_unpromised(v2.differences(other_blas)) == ["numeric_class"]
    assert motion_unpromised(v2.differences(newer_numpy)) == ["versions.numpy"]
    assert motion_unpromised(renderer_differences(v2, None)) == ["renderer fingerprint (not recorded)"]
    # Version 3: the driver's settings count for the pixels (version 2's unrecorded ones as
    # none), the files' encoders for the files only.
    v3 = v2.model_copy(update={"fingerprint_version": 3, "gl_settings": "", "file_versions": {"opencv": "5.0.0"}})
    assert v2.differences(v3) == [] and v2.differences(v3, "files") == ["files.opencv"]
    tuned = v3.model_copy(update={"gl_settings": "GALLIVM_PERF=no_quad_lerp"})
    assert v3.differences(tuned) == ["gl_settings"]
    encoder = v3.model_copy(update={"file_versions": {"opencv": "4.9.0"}})
    assert v3.differences(encoder) == [] and v3.differences(encoder, "files") == ["files.opencv"]


@pytest.mark.parametrize(
    ("changes", "fragment"),
    [
        ({"fingerprint_version": 4}, "newer than this phav reads"),
        ({"fingerprint_version": 2}, "needs cpu_class"),
        ({"fingerprint_version": 2, "cpu_class": "x86-64-avx"}, "needs numeric_class"),
        ({"fingerprint_version": 3, "cpu_class": "x86-64-avx", "numeric_class": "numpy X86_V3"}, "needs gl_settings"),
        ({"cpu_flags": None}, "needs cpu_flags"),
    ],
)
def test_a_fingerprint_needs_the_fields_of_its_version(tmp_path: Path, changes: dict[str, Any], fragment: str) -> None:
    data = _manifest_data()
    data["renderer"] = {**data["renderer"], **changes}
    error = _load_error(tmp_path, data)
    assert error.field == "renderer" and fragment in str(error)


@pytest.mark.parametrize(
    ("mutate", "field", "fragment"),
    [
        (lambda d: d["videos"][1].update(video_id="v000000"), "videos.1.video_id", "duplicate"),
        (lambda d: d["videos"][2].update(video_id="v.00002"), "videos.2.video_id", "never a dot"),
        (
            lambda d: d["shards"][1].update(name="phav_demo-000000.tar"),
            "shards.1.name",
            "duplicate",
        ),
        (
            lambda d: d["videos"][2].update(shard="phav_demo-000000.tar"),
            "videos.2.shard",
            "does not list it",
        ),
        (
            lambda d: d["videos"][0].update(shard="phav_demo-000009.tar"),
            "videos.0.shard",
            "not in the shard list",
        ),
        (
            lambda d: d["shards"][1]["video_ids"].append("v000000"),
            "shards.1.video_ids.1",
            "never spans shards",
        ),
        (
            lambda d: d["shards"][1]["video_ids"].append("v000777"),
            "shards.1.video_ids.1",
            "no entry in videos",
        ),
        (lambda d: d["shards"][0].update(name="demo.tar"), "shards.0.name", "-000000.tar"),
        (lambda d: d["shards"][0].update(sha256="A" * 64), "shards.0.sha256", "lowercase hex"),
        (lambda d: d["videos"][1].update(n_frames=0), "videos.1.n_frames", "greater"),
        (lambda d: d["videos"][1].update(n_frames="3"), "videos.1.n_frames", "integer"),
        (lambda d: d.update(dataset_seed=-1), "dataset_seed", "greater"),
        (lambda d: d.pop("videos"), "videos", "add the field"),
        (lambda d: d["renderer"].update(gpu="x"), "renderer.gpu", "misspelt"),
        (lambda d: d["modalities"][0].update(channels=2), "modalities.0.channels", "1 or 3"),
        (lambda d: d.update(manifest_version=2), "manifest_version", "upgrade phav"),
    ],
)
def test_invalid_manifest_names_file_and_field(tmp_path: Path, mutate: Any, field: str, fragment: str) -> None:
    data = _manifest_data()
    mutate(data)
    error = _load_error(tmp_path, data)
    assert error.field == field
    assert f": {field}: " in str(error)
    assert fragment in str(error)


def test_newer_manifest_version_is_refused_before_other_checks(tmp_path: Path) -> None:
    error = _load_error(tmp_path, {"manifest_version": MANIFEST_VERSION + 1, "layout": "v2"})
    assert error.field == "manifest_version"
    assert "newer" in str(error)


def test_bad_json(tmp_path: Path) -> None:
    path = tmp_path / "manifest.json"
    path.write_text('{"name": "x",\n  "shards": [}', encoding="utf-8")
    with pytest.raises(PhavUserError, match="invalid JSON at line 2") as info:
        load_manifest(path)
    assert str(path) in str(info.value)


def test_missing_file_and_non_object(tmp_path: Path) -> None:
    missing = tmp_path / "nope" / "manifest.json"
    with pytest.raises(PhavUserError, match="no such file") as info:
        load_manifest(missing)
    assert str(missing) in str(info.value)
    error = _load_error(tmp_path, [1, 2])
    assert "JSON object" in str(error)


def test_model_validator_errors_carry_locations() -> None:
    data = _manifest_data()
    data["videos"][1]["video_id"] = "v000000"
    with pytest.raises(ValidationError) as info:
        DatasetManifest.model_validate(data)
    locs = [e["loc"] for e in info.value.errors()]
    assert ("videos", 1, "video_id") in locs


def test_models_are_frozen() -> None:
    manifest = DatasetManifest.model_validate(_manifest_data())
    with pytest.raises(ValidationError):
        manifest.name = "other"  # type: ignore[misc]
    with pytest.raises(ValidationError):
        manifest.videos[0].n_frames = 2  # type: ignore[misc]


@st.composite
def _consistent_manifests(draw: st.DrawFn) -> DatasetManifest:
    """Datasets of up to 12 videos split into shards of ``shard_size`` videos, as phav does."""
    n_videos = draw(st.integers(min_value=0, max_value=12))
    shard_size = draw(st.integers(min_value=1, max_value=4))
    ids = [f"v{i:06d}" for i in sorted(draw(st.sets(
        st.integers(0, 999_999), min_size=n_videos, max_size=n_videos)))]  # fmt: skip
    shards, videos = [], []
    for start in range(0, n_videos, shard_size):
        name = f"demo-{start // shard_size:06d}.tar"
        chunk = ids[start : start + shard_size]
        shards.append(ShardEntry(name=name, sha256=HEX_B, bytes=start, video_ids=chunk))
        for vid in chunk:
            n_frames = draw(st.integers(min_value=1, max_value=300))
            videos.append(VideoEntry(video_id=vid, shard=name, n_frames=n_frames, content_hash=HEX_A))
    return DatasetManifest(
        name="demo", phav_version="0.1.0", theta_hash=HEX_A, dataset_seed=draw(st.integers(0)),
        recipe_schema_version=1, shards=shards, videos=videos,
    )  # fmt: skip


@settings(max_examples=30, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(_consistent_manifests())
def test_generated_manifests_round_trip(tmp_path: Path, manifest: DatasetManifest) -> None:
    path = tmp_path / "manifest.json"
    dump_manifest(manifest, path)
    assert load_manifest(path) == manifest


def test_video_ids_past_a_million_are_a_manifests_too(tmp_path: Path) -> None:
    """A recipe's id grows a digit past v999999 (``video_id``): the manifest takes it."""
    data = _manifest_data()
    data["shards"][1]["video_ids"] = ["v1000000"]
    data["videos"][2]["video_id"] = "v1000000"
    dump_manifest(DatasetManifest.model_validate(data), tmp_path / "manifest.json")
    assert load_manifest(tmp_path / "manifest.json").videos[2].video_id == "v1000000"
