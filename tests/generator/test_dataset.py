"""Recipes → dataset directory: layout, bit-exactness across workers and processes, resume,
and a real WebDataset client reading the shards with the documented meanings."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
import tarfile

import cv2
import numpy as np
import pyarrow.parquet as pq
import pytest

from phav_generator.dataset.write import chunk, write_dataset
from phav_generator.sampling import sample_recipes
from phav_spec.encoding import DEPTH_MAX_CODE, MODALITIES, decode_depth, decode_flow
from phav_spec.errors import PhavUserError
from phav_spec.manifest import load_manifest
from phav_spec.metadata import CAMERA_COLUMNS, PEOPLE_COLUMNS
from phav_spec.scene import ENVIRONMENT_SCENES
from phav_spec.theta import load_theta
from phav_spec.vocab import PIXEL_CLASSES
from tests.helpers import run_cli

SEED = 3


@pytest.fixture(scope="module")
def theta():
    return load_theta("phav-v1-short")


@pytest.fixture(scope="module")
def recipes(theta):
    return list(sample_recipes(theta, n=3, seed=SEED))


@pytest.fixture(scope="module")
def dataset(tmp_path_factory, theta):
    """`phav generate` of three 1–2 s videos, two per shard, with two workers."""
    out = tmp_path_factory.mktemp("ds") / "data"
    args = ("generate", "--theta", "phav-v1-short", "--videos", "3", "--seed", str(SEED), "--out", str(out),
            "--shard-size", "2", "--workers", "2", "--name", "demo")  # fmt: skip
    result = run_cli(*args)
    assert result.returncode == 0, result.stderr
    assert "wrote 3 videos" in result.stdout
    return out


def test_layout_is_designs(dataset, recipes):
    names = sorted(p.name for p in dataset.iterdir())
    assert names == ["cameras.parquet", "demo-000000.tar", "demo-000001.tar", "manifest.json", "people.parquet",
                     "recipes.parquet", "theta.yaml"]  # fmt: skip
    m = load_manifest(dataset / "manifest.json")
    assert [s.video_ids for s in m.shards] == [["v000000", "v000001"], ["v000002"]]
    assert [v.n_frames for v in m.videos] == [r.n_frames for r in recipes]
    assert m.renderer is not None and m.renderer.gl_renderer and m.theta_hash == load_theta("phav-v1-short").hash
    for shard in m.shards:
        assert (dataset / shard.name).stat().st_size == shard.bytes
    with tarfile.open(dataset / "demo-000000.tar") as tar:
        members = tar.getmembers()
    assert all(t.mtime == 0 and t.uid == 0 and t.gid == 0 and t.isfile() for t in members)
    first = [t.name for t in members[:7]]
    assert first == [f"v000000/00000.{m.key}" for m in MODALITIES] + ["v000000/00000.json"]
    assert len(members) == 7 * (recipes[0].n_frames + recipes[1].n_frames)


def test_metadata_tables_follow_the_contract(dataset, recipes):
    cams = pq.read_table(dataset / "cameras.parquet")
    people = pq.read_table(dataset / "people.parquet")
    assert cams.column_names == [c.name for c in CAMERA_COLUMNS]
    assert people.column_names == [c.name for c in PEOPLE_COLUMNS]
    assert cams.num_rows == sum(r.n_frames for r in recipes)
    roles = set(people.column("role").to_pylist())
    assert "protagonist" in roles and roles <= {"protagonist", "supporting", "background"}
    row = people.slice(0, 1).to_pylist()[0]
    assert len(row["joints3d"]) == 39 and len(row["joints2d"]) == 26 and len(row["visible"]) == 13
    assert len(row["bbox3d"]) == 24 and len(row["muscle_strength"]) == 15 and len(row["pin_weight"]) == 15
    assert row["muscle_limits"][0] == [] and len(row["muscle_limits"][1]) == 6


def test_a_webdataset_client_reads_every_sample(dataset, recipes):
    """The webdataset package iterates every sample; our decoder keeps 16-bit data."""
    wds = pytest.importorskip("webdataset")
    from phav_spec.webdataset import phav_decoder

    urls = [str(p) for p in sorted(dataset.glob("demo-*.tar"))]
    keys = []
    for sample in wds.WebDataset(urls, shardshuffle=False).decode(phav_decoder):
        keys.append(sample["__key__"])
        assert sample["depth.png"].dtype == np.uint16 and sample["depth.png"].shape == (256, 340)
        assert sample["flow.png"].dtype == np.uint16 and sample["flow.png"].shape == (256, 340, 3)
        assert sample["json"]["camera"]["frame"] == int(sample["__key__"].split("/")[1])
    expected = [f"{r.video_id}/{f:05d}" for r in recipes for f in range(r.n_frames)]
    assert keys == expected


def test_opencv_reads_depth_and_flow_with_the_documented_meaning(dataset, recipes):
    """Depth PNG read by OpenCV as uint16: ground pixels unprojected through the camera row
    land on the ground plane (within the 1 cm quantum); flow is KITTI (B = valid)."""
    recipe = recipes[0]
    ground = ENVIRONMENT_SCENES[recipe.environment.name]
    cls = PIXEL_CLASSES[ground.ground_pixel_class].rgb
    with tarfile.open(dataset / "demo-000000.tar") as tar:
        depth = cv2.imdecode(np.frombuffer(tar.extractfile("v000000/00004.depth.png").read(), np.uint8), -1)
        flow = cv2.imdecode(np.frombuffer(tar.extractfile("v000000/00004.flow.png").read(), np.uint8), -1)
        seg = cv2.imdecode(np.frombuffer(tar.extractfile("v000000/00004.seg.png").read(), np.uint8), -1)[..., ::-1]
        meta = json.loads(tar.extractfile("v000000/00004.json").read())
    assert depth.dtype == np.uint16 and flow.dtype == np.uint16 and flow.shape[2] == 3
    assert depth.min() >= 1 and depth.max() <= DEPTH_MAX_CODE
    cam = meta["camera"]
    d = decode_depth(depth)
    v, u = np.nonzero(np.all(seg == cls, axis=-1) & np.isfinite(d))
    assert len(u) > 100
    pts = np.stack([(u + 0.5 - cam["cx"]) * d[v, u] / cam["fx"], -(v + 0.5 - cam["cy"]) * d[v, u] / cam["fy"],
                    -d[v, u], np.ones(len(u))], axis=1)  # fmt: skip
    world = pts @ np.array(cam["cam_to_world"]).reshape(4, 4).T
    # The ground is drawn 1 cm below its height; depth is quantised to 1 cm along the axis.
    assert np.percentile(np.abs(world[:, 2] - (ground.ground_z - 0.01)), 95) < 0.02
    uv, valid = decode_flow(flow[..., ::-1])  # OpenCV gives BGR: B, G, R = valid, v, u
    assert np.array_equal(valid, flow[..., 0] == 1) and np.all(flow[~valid] == 0)
    assert np.array_equal(np.isfinite(uv[..., 0]), valid) and valid.mean() > 0.3
    assert np.all(np.abs(uv[valid]) < 512)


def test_workers_and_fresh_processes_give_the_same_bytes(dataset, recipes, theta, tmp_path):
    """One worker in this process against the CLI's two spawned workers: same manifest, and
    a regeneration from recipes.parquet alone in a fresh process matches every hash."""
    one = write_dataset(chunk(recipes, 2), tmp_path / "one", name="demo", theta=theta, dataset_seed=SEED, workers=1)
    two = load_manifest(dataset / "manifest.json")
    assert one.manifest == two
    alone = tmp_path / "alone"
    alone.mkdir()
    shutil.copy(dataset / "recipes.parquet", alone / "recipes.parquet")
    result = run_cli("regenerate", str(alone / "recipes.parquet"), "--out", str(tmp_path / "re"))
    assert result.returncode == 0, result.stderr
    again = load_manifest(tmp_path / "re" / "manifest.json")
    assert [(v.video_id, v.modality_hashes) for v in again.videos] == [
        (v.video_id, v.modality_hashes) for v in two.videos
    ]


def test_regenerate_names_a_tampered_video(dataset, tmp_path):
    copy = tmp_path / "copy"
    shutil.copytree(dataset, copy)
    data = json.loads((copy / "manifest.json").read_text())
    video = data["videos"][1]
    video["modality_hashes"]["depth"] = "0" * 64
    from phav_spec.encoding import video_content_hash

    video["content_hash"] = video_content_hash(video["modality_hashes"])
    (copy / "manifest.json").write_text(json.dumps(data))
    result = run_cli("regenerate", str(copy), "--video", "v000001", "--out", str(tmp_path / "re"))
    assert result.returncode == 1
    assert "0/1 videos match" in result.stdout and "v000001: depth" in result.stdout


class _Stop(Exception):
    pass


def test_an_interrupted_run_resumes_without_redoing_finished_shards(recipes, theta, tmp_path):
    out = tmp_path / "ds"
    shards = chunk(recipes, 1)
    done = []

    def stop_in_the_second_shard(videos: int, frames: int) -> None:
        done.append(videos)
        if sum(done) == 2:  # the second video is rendered, its shard's tar still open
            raise _Stop

    with pytest.raises(_Stop):
        write_dataset(shards, out, name="demo", theta=theta, dataset_seed=SEED, progress=stop_in_the_second_shard)
    assert not (out / "manifest.json").exists()
    leftovers = [p.name for p in out.iterdir() if p.name.startswith(".demo") and p.name.endswith(".tmp")]
    assert leftovers == []  # the interrupted tar left no temporary behind
    resumed = write_dataset(shards, out, name="demo", theta=theta, dataset_seed=SEED)
    assert (resumed.rendered_shards, resumed.resumed_shards) == (2, 1)
    clean = write_dataset(shards, tmp_path / "clean", name="demo", theta=theta, dataset_seed=SEED)
    assert resumed.manifest == clean.manifest
    assert not (out / ".phav-work").exists()


def test_a_directory_holding_another_run_is_refused(recipes, theta, tmp_path):
    out = tmp_path / "ds"

    def stop(videos: int, frames: int) -> None:
        raise _Stop

    with pytest.raises(_Stop):
        write_dataset(chunk(recipes[:1], 1), out, name="demo", theta=theta, dataset_seed=SEED, progress=stop)
    with pytest.raises(PhavUserError, match="dataset_seed"):
        write_dataset(chunk(recipes[:1], 1), out, name="demo", theta=theta, dataset_seed=SEED + 1)
    # Another renderer never finishes a run: its pixels would differ (the Ray engine skips the
    # driver's own GPU probe, so the journalled run is what refuses here).
    with pytest.raises(PhavUserError, match=r"\(gl differ\)"):
        write_dataset(chunk(recipes[:1], 1), out, name="demo", theta=theta, dataset_seed=SEED, engine="ray",
                      gl="egl-gpu")  # fmt: skip


def test_generate_errors_are_one_line(tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("x")
    result = run_cli("generate", "--videos", "1", "--out", str(blocker))
    assert result.returncode == 2 and "Traceback" not in result.stderr and "not a directory" in result.stderr
    result = run_cli("generate", "--videos", "1", "--out", str(tmp_path / "d"), "--name", "a.b")
    assert result.returncode == 2 and "--name" in result.stderr
    result = run_cli("regenerate", str(tmp_path / "missing"), "--out", str(tmp_path / "o"))
    assert result.returncode == 2 and "missing" in result.stderr


def test_a_fresh_process_renders_the_same_manifest(dataset, tmp_path):
    """`phav regenerate DIR` in a fresh process: every hash equal, exit 0."""
    result = subprocess.run(
        [sys.executable, "-m", "phav_app.cli", "regenerate", str(dataset), "--out", str(tmp_path / "r")],
        capture_output=True, text=True, check=False,
    )  # fmt: skip
    assert result.returncode == 0, result.stderr
    assert "3/3 videos match; files: 2/2 sha256 match (same renderer fingerprint" in result.stdout  # 2 shards


def test_preview_sheets_all_modalities_and_a_gif(dataset, recipes, tmp_path):
    from PIL import Image

    out = tmp_path / "sheet.png"
    result = run_cli("preview", str(dataset), "--video", "v000001", "--frames", "3", "--out", str(out))
    assert result.returncode == 0, result.stderr
    sheet = Image.open(out)
    assert sheet.size == (6 * 340, 18 + 3 * 256)
    gif = Image.open(out.with_suffix(".gif"))
    assert gif.n_frames == recipes[1].n_frames
    result = run_cli("preview", str(dataset), "--video", "v009999", "--out", str(out))
    assert result.returncode == 2 and "v009999" in result.stderr


def test_joined_parts_are_the_tar_tarfile_writes(tmp_path):
    """Video parts joined into a shard give the bytes one tarfile pass over the same members
    gives (header, padding, end-of-archive blocks and record padding included)."""
    import io

    from phav_generator.io.shards import TAR_MODE, TAR_MTIME, assemble_shard, open_part

    rng = np.random.default_rng(1)
    members, parts = [], []
    for v in range(3):
        parts.append(tmp_path / f"v{v}.tar.part")
        with open_part(parts[-1]) as part:
            for j in range(5):  # sizes across block boundaries, empty members included
                name, data = f"v{v:06d}/{j:05d}.x", rng.bytes(int(rng.integers(0, 3000)))
                part.add(name, data)
                members.append((name, data))
    digest = assemble_shard(parts, tmp_path / "joined.tar")
    expected = io.BytesIO()
    with tarfile.open(fileobj=expected, mode="w", format=tarfile.USTAR_FORMAT) as tar:
        for name, data in members:
            info = tarfile.TarInfo(name)
            info.size, info.mtime, info.mode = len(data), TAR_MTIME, TAR_MODE
            tar.addfile(info, io.BytesIO(data))
    assert (tmp_path / "joined.tar").read_bytes() == expected.getvalue()
    assert digest.bytes == len(expected.getvalue())
