"""`phav regenerate`: videos rebuilt from their recipes alone, in a fresh process, match
every content hash; a tampered manifest entry is named."""

from __future__ import annotations

import json
import shutil

import pytest

from phav_generator.dataset import fingerprint
from phav_spec.encoding import video_content_hash
from phav_spec.errors import PhavUserError
from phav_spec.manifest import load_manifest, motion_unpromised
from tests.helpers import invoke_cli, run_cli


def test_a_fresh_process_renders_the_same_manifest(small_dataset, tmp_path):
    """`phav regenerate DIR` in a fresh process: every hash equal, exit 0."""
    result = run_cli("regenerate", str(small_dataset), "--out", str(tmp_path / "r"))
    assert result.returncode == 0, result.stderr
    assert "3/3 videos match; files: 2/2 sha256 match (same renderer fingerprint" in result.stdout  # 2 shards


def test_other_blas_kernels_are_another_renderer_for_the_pixels(small_dataset, tmp_path):
    """OpenBLAS forced to another CPU's kernels stands in for a CPU of the same SIMD class
    with other numerics: the physics can carry their last bits into another motion, so the
    pixels are not promised; the rebuild says so, compares what differs within tolerances
    and calls nothing a mismatch on that account (exit 0)."""
    here = fingerprint._openblas_core()
    other = "Sandybridge" if here == "Haswell" else "Haswell"
    result = run_cli("regenerate", str(small_dataset), "--out", str(tmp_path / "r"), env={"OPENBLAS_CORETYPE": other})
    assert result.returncode == 0, result.stdout
    rebuilt = load_manifest(tmp_path / "r" / "manifest.json").renderer
    original = load_manifest(small_dataset / "manifest.json").renderer
    assert rebuilt is not None and original is not None and f"OpenBLAS {other}" in str(rebuilt.numeric_class)
    assert original.differences(rebuilt) == ["numeric_class"] == motion_unpromised(original.differences(rebuilt))
    assert "another renderer fingerprint (numeric_class): equal pixels not promised" in result.stdout
    assert "mismatch" not in result.stdout


def test_recipes_parquet_alone_regenerates_every_hash(small_dataset, tmp_path):
    """A recipes table with nothing beside it (no manifest to follow) rebuilds the videos the
    manifest lists, hash for hash."""
    alone = tmp_path / "alone"
    alone.mkdir()
    shutil.copy(small_dataset / "recipes.parquet", alone / "recipes.parquet")
    result = invoke_cli("regenerate", str(alone / "recipes.parquet"), "--out", str(tmp_path / "re"))
    assert result.returncode == 0, result.stderr
    again = load_manifest(tmp_path / "re" / "manifest.json")
    expected = load_manifest(small_dataset / "manifest.json")
    assert [(v.video_id, v.modality_hashes) for v in again.videos] == [
        (v.video_id, v.modality_hashes) for v in expected.videos
    ]


def test_regenerate_names_a_tampered_video(small_dataset_copy, tmp_path):
    data = json.loads((small_dataset_copy / "manifest.json").read_text())
    video = data["videos"][1]
    video["modality_hashes"]["depth"] = "0" * 64
    video["content_hash"] = video_content_hash(video["modality_hashes"])
    (small_dataset_copy / "manifest.json").write_text(json.dumps(data))
    result = invoke_cli("regenerate", str(small_dataset_copy), "--video", "v000001", "--out", str(tmp_path / "re"))
    assert result.returncode == 1
    assert "0/1 videos match" in result.stdout and "v000001: depth" in result.stdout


def test_a_table_with_a_video_twice_is_refused_not_regenerated_from_one_of_them(tmp_path):
    import pyarrow as pa
    import pyarrow.parquet as pq

    from phav_generator.regenerate import plan_regeneration

    table = tmp_path / "r.parquet"
    assert invoke_cli("sample", "--n", "3", "--out", str(table)).returncode == 0
    rows = pq.read_table(table)
    pq.write_table(pa.concat_tables([rows, rows.slice(1, 1)]), table)
    with pytest.raises(PhavUserError, match=r"video_id: video v000001 has 2 recipes in the table"):
        plan_regeneration(table)
