"""docs/measure/learn_experiments.py, the experiment script behind
docs/experiments/learnability.md's tables: its cell syntax and one cell on tiny synthetic
clips (the real runs take hours)."""

from __future__ import annotations

import sys

import numpy as np
import pytest

from tests.helpers import SMALL_SEED, SMALL_SHARD_SIZE, SMALL_VIDEOS, run_cli, theta_variant, tiny
from tests.validators.learn.helpers import measure_script, motion_clips


@pytest.fixture(scope="module")
def script():
    return measure_script("learn_experiments")


def test_a_cell_names_clips_size_and_any_training_setting(script):
    clips, size, overrides = script.parse_cell("clips=320,size=128x96,widths=16-32,stem_pool=true,lr=0.1,"
                                               "precision=bf16,epochs=30", (85, 64))  # fmt: skip
    assert clips == 320 and size == (128, 96)
    assert overrides == {"widths": (16, 32), "stem_pool": True, "lr": 0.1, "precision": "bf16", "epochs": 30}
    assert script.parse_cell("baseline", (85, 64)) == (None, (85, 64), {})
    with pytest.raises(SystemExit, match="colour"):
        script.parse_cell("colour=red", (85, 64))


def test_a_cell_that_cannot_train_its_streams_is_refused_before_anything_is_read(script, tmp_path, monkeypatch):
    # distillation needs the RGB stream: a flow-only grid says so at once, naming the cell,
    # not after the cells before it have trained for an hour
    script.check_cells([("epochs=3", {"epochs": 3})], ["flow"])
    with pytest.raises(SystemExit, match=r"--cell epochs=3,distill=20 with --streams flow: --distill"):
        script.check_cells([("epochs=3", {"epochs": 3}), ("epochs=3,distill=20", {"epochs": 3, "distill": 20.0})],
                           ["flow"])  # fmt: skip
    missing = tmp_path / "no-such-dataset"
    argv = ["learn_experiments.py", str(missing), "--streams", "flow", "--cell", "epochs=3", "--cell", "distill=20"]
    monkeypatch.setattr(sys, "argv", argv)
    with pytest.raises(SystemExit, match="--cell distill=20"):
        script.main()
    assert not missing.exists() and not list(tmp_path.iterdir())


def test_a_cell_trains_on_held_out_actors_and_reports_a_row(script, tmp_path):
    data = motion_clips(4, 20)
    overrides = {"epochs": 3, "widths": (8, 16), "threads": 1}
    run = script.run_cell(data, 40, overrides, 0, ["rgb", "flow"], tmp_path)
    assert run["train_clips"] <= 44 and run["test_clips"] > 0
    assert set(run["accuracy"]) == {"rgb", "flow", "fused", "p_fused"}
    cell = script.Cell("epochs=3", 40, (32, 24), overrides, [run, run])
    row = script.row(cell, ["rgb", "flow"])
    assert row.startswith("| epochs=3 | 2 | ") and row.count("|") == 10
    # each test clip's probabilities per stream are kept, for fusion studies afterwards
    assert len(run["test_labels"]) == run["test_clips"] == len(run["test_scores"]["flow"])
    assert abs(sum(run["test_scores"]["rgb"][0]) - 1.0) < 1e-3
    # ... with their keys, so a pooled run can be scored on one dataset's clips
    assert len(run["test_keys"]) == run["test_clips"]
    assert script.accuracy_on(run, ["rgb", "flow"], "") == pytest.approx(
        {s: run["accuracy"][s] for s in ("rgb", "flow", "fused")}
    )
    first = run["test_keys"][0]
    one = script.accuracy_on(run, ["rgb", "flow"], first)
    assert one["flow"] == float(np.argmax(run["test_scores"]["flow"][0]) == run["test_labels"][0])
    assert script.row(cell, ["rgb", "flow"], first).startswith(f"| epochs=3 | 2 | {run['train_clips']} / 1 |")
    with pytest.raises(SystemExit, match="no test clip"):
        script.accuracy_on(run, ["rgb", "flow"], "elsewhere/")
    # the trained streams are kept, named by their settings, and a rerun reuses them
    kept = sorted(p.name.split("-")[0] for p in tmp_path.glob("*.pt"))
    assert kept == ["flow", "rgb"]
    again = script.run_cell(data, 40, overrides, 0, ["rgb", "flow"], tmp_path)
    assert again["test_scores"] == run["test_scores"] and again["minutes"] == run["minutes"]
    other = script.kept_stream(tmp_path, script.TrainConfig(stream="flow", epochs=4), [])
    assert other.name not in {p.name for p in tmp_path.glob("*.pt")}
    # the same settings on other inputs (stored size, flow source) are kept apart
    flow = script.TrainConfig(stream="flow", **overrides)
    assert script.kept_stream(tmp_path, flow, []) != script.kept_stream(
        tmp_path, flow, [], script.inputs_name((85, 64), "farneback")
    )


def test_the_speed_script_times_a_step_under_each_arithmetic():
    module = measure_script("train_speed")
    from phav_validators.learn.config import Architecture

    for bf16, last, stem_pool in ((False, False, False), (True, True, False), (True, False, True)):
        arch = Architecture(widths=(8, 16), stem_pool=stem_pool)
        ms = module.step_ms(arch, bf16=bf16, channels_last=last, channels=10, steps=1, warm=0)
        assert 0 < ms < 60_000


def test_the_factor_presets_change_one_theta_key_each_and_are_valid(tmp_path):
    from phav_spec.theta import load_theta, parse_theta

    module = measure_script("theta_factors")
    base = module.base_preset()
    found = module.variants(base)
    assert set(found) == {"clips-0.5-1s", "clips-2-4s", "kite", "kite-far", "clear", "one-motion", "supersampling-2"}
    hashes = {load_theta("phav-v1-short").hash}
    for factor, theta in found.items():
        changed = {k for k in base if theta[k] != base[k]} - {"name", "description"}
        assert len(changed) == 1, (factor, changed)
        hashes.add(parse_theta(theta, source=factor).hash)
    assert len(hashes) == 8  # every variant is another θ
    one = parse_theta(found["one-motion"], source="one-motion")
    ab = one.arrays.ab * one.arrays.motion_long_enough
    assert (ab.sum(axis=1) == 1).all()  # one take per action, long enough for the shortest clip


def test_the_pair_sheet_stacks_each_videos_frames_over_their_flow(phav, tmp_path, monkeypatch):
    from phav_spec.manifest import load_manifest

    module = measure_script("pair_sheet")
    videos = sorted(v.video_id for v in load_manifest(phav / "manifest.json").videos)[:2]
    out = tmp_path / "pair.png"
    monkeypatch.setattr(sys, "argv", ["pair_sheet", str(phav), *videos, "--label", "a", "--frames", "3",
                                      "--out", str(out)])  # fmt: skip
    module.main()
    import cv2

    sheet = cv2.imread(str(out))
    # two videos, each 3 frames wide at half size, RGB over flow, a 4-px gap between them
    assert sheet.shape == (2 * 2 * 128 + 4, 3 * 170, 3)
    top_rgb, top_flow = sheet[20:128], sheet[128:256]
    assert top_rgb.std() > 5 and not np.array_equal(top_rgb, top_flow)


def test_supersampling_moves_the_rgb_modality_only(small_dataset, tmp_path):
    """The shared set's recipes again with one sample a pixel instead of phav-v1's two: the
    labels, depth and flow hash the same, the RGB and raw RGB (the samples' mean) do not, and
    the RGB frames differ, less once area-averaged to the check's size."""

    def one_sample(data: dict) -> None:
        tiny(data)
        data["render"] = {**data["render"], "supersampling": 1}

    theta = theta_variant(tmp_path, one_sample)
    out = tmp_path / "ss1"
    result = run_cli("generate", "--theta", str(theta), "--videos", str(SMALL_VIDEOS), "--seed", str(SMALL_SEED),
                     "--out", str(out), "--shard-size", str(SMALL_SHARD_SIZE), "--workers", "2")  # fmt: skip
    assert result.returncode == 0, result.stderr
    found = measure_script("supersampling").compare(small_dataset, out)
    assert found["videos"] == SMALL_VIDEOS and found["frames"] == SMALL_VIDEOS * 6
    assert found["equal_hashes"] == {"depth": 3, "flow": 3, "instance": 3, "raw_rgb": 0, "rgb": 0, "semantic": 3}
    rgb = found["rgb_mean_abs"]
    assert 0 < rgb["check_size"] < rgb["stored"] < 5
