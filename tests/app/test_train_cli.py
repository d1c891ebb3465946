"""``phav train`` as a user runs it: results, resuming, TSN / Cool-TSN / TSN-FT on a real
dataset's folder, and user errors as one line with exit code 2.

The commands run in this process (``tests.helpers.invoke_cli``); one test runs a real ``phav``
process for the one-line, exit-code-2 contract of the console script itself.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import cv2
import pytest

from phav_validators.learn.train import RECOMMENDED
from tests.helpers import invoke_cli, run_cli
from tests.validators.learn.helpers import tiny_phav, ucf101_folder

FAST = ("--epochs", "1", "--widths", "8,16", "--threads", "1")


@pytest.fixture(scope="session")
def phav(tmp_path_factory) -> Path:
    return tiny_phav(tmp_path_factory)


def test_train_on_phav_writes_results_and_resumes(phav, tmp_path):
    out = tmp_path / "run"
    args = ("train", str(phav), "--out", str(out), "--split", "random", *FAST)
    result = invoke_cli(*args)
    assert result.returncode == 0, result.stderr
    assert "test accuracy" in result.stdout and "fused" in result.stdout
    data = json.loads((out / "results.json").read_text())
    run = data["runs"][0]
    assert run["train_clips"] == 2 and run["test_clips"] == 1
    assert set(run["accuracy"]) == {"rgb", "flow", "fused"}
    config = data["config"]  # the recommended settings: RGB differences distilled from flow
    assert config["rgb_frames"] == RECOMMENDED.rgb_frames and config["rgb_diff"]
    assert config["distill"] == RECOMMENDED.distill > 0 and config["diff_gain"] == RECOMMENDED.diff_gain
    assert config["precision"] in ("fp32", "bf16") and config["stem_pool"]  # pooled on a CPU
    assert (out / "split1-rgb.pt").exists() and (out / "split1-flow.pt").exists()
    assert cv2.imread(str(out / "split1-confusion.png")) is not None
    again = invoke_cli(*args)  # every checkpoint is finished: nothing retrained, same numbers
    assert again.returncode == 0, again.stderr
    assert json.loads((out / "results.json").read_text())["runs"] == data["runs"]


def test_held_out_actor_split_k_is_the_learnability_check_at_seed_k(phav, tmp_path):
    """Split 2 of ``--split actor`` trains as the check with ``--seed 1``: its checkpoints serve both."""
    learn, report = tmp_path / "learn", tmp_path / "check.json"
    check = invoke_cli("validate!", str(phav), "--checks", "learnability", "--learn-epochs", "1",
                       "--learn-rgb-epochs", "1", "--threads", "1", "--seed", "1", "--learn-dir", str(learn),
                       "--json", str(report))  # fmt: skip
    assert check.returncode in (0, 1), check.stderr
    out = tmp_path / "run"
    out.mkdir()
    for stream in ("flow", "rgb"):
        shutil.copy(learn / f"{stream}.pt", out / f"split2-{stream}.pt")
    stamps = {p.name: p.stat().st_mtime_ns for p in out.iterdir()}
    # a checkpoint made for other settings or clips would be refused (exit code 2)
    result = invoke_cli("train", str(phav), "--out", str(out), "--split", "actor", "--splits", "2", "--epochs", "1",
                        "--rgb-epochs", "1", "--threads", "1")  # fmt: skip
    assert result.returncode == 0, result.stderr
    assert {p.name: p.stat().st_mtime_ns for p in out.glob("split2-*.pt")} == stamps  # finished: not retrained
    numbers = json.loads(report.read_text())["datasets"][0]["checks"][0]["numbers"]
    run = json.loads((out / "results.json").read_text())["runs"][1]
    assert run["split"] == 2 and run["test_clips"] == numbers["test_clips"]
    assert run["accuracy"]["fused"] == pytest.approx(numbers["fused_accuracy"])
    assert run["accuracy"]["rgb"] == pytest.approx(numbers["rgb_accuracy"])


def test_train_with_the_settings_a_user_tunes(phav, tmp_path):
    out = tmp_path / "run"
    result = invoke_cli("train", str(phav), "--out", str(out), "--split", "random", "--segments", "4",
                        "--rgb-frames", "2", "--rgb-diff", "--crop", "0.6", "--no-scale-jitter", "--no-stem-pool",
                        "--dropout", "0.1", *FAST)  # fmt: skip
    assert result.returncode == 0, result.stderr
    data = json.loads((out / "results.json").read_text())
    config = data["config"]
    assert config["segments"] == 4 and config["rgb_frames"] == 2 and config["rgb_diff"] and config["crop"] == 0.6
    assert not config["scale_jitter"] and not config["stem_pool"] and config["dropout"] == 0.1
    assert set(data["runs"][0]["accuracy"]) == {"rgb", "flow", "fused"}


def test_distillation_trains_the_flow_stream_first_and_teaches_the_rgb_stream(phav, tmp_path):
    out = tmp_path / "run"
    result = invoke_cli("train", str(phav), "--out", str(out), "--split", "random", "--rgb-frames", "2",
                        "--distill", "5", "--scale-jitter", *FAST)  # fmt: skip
    assert result.returncode == 0, result.stderr
    data = json.loads((out / "results.json").read_text())
    assert data["config"]["distill"] == 5.0 and set(data["runs"][0]["accuracy"]) == {"rgb", "flow", "fused"}
    assert data["config"]["scale_jitter"]
    # The RGB checkpoint was written after the flow one: the teacher trained first.
    assert (out / "split1-flow.pt").stat().st_mtime_ns <= (out / "split1-rgb.pt").stat().st_mtime_ns


def test_tsns_single_rgb_frame_alone_needs_no_other_option(phav, tmp_path):
    out = tmp_path / "run"
    result = invoke_cli("train", str(phav), "--out", str(out), "--streams", "rgb", "--rgb-frames", "1",
                        "--precision", "fp32", *FAST)  # fmt: skip
    assert result.returncode == 0, result.stderr
    config = json.loads((out / "results.json").read_text())["config"]
    assert config["rgb_frames"] == 1 and not config["rgb_diff"] and config["distill"] == 0  # no flow to learn from
    assert config["diff_gain"] == 1.0  # no differences to amplify: the settings do not claim a gain
    assert config["precision"] == "fp32"


def test_cool_tsn_and_fine_tuning_on_a_ucf101_folder(phav, tmp_path):
    ucf = ucf101_folder(tmp_path / "ucf", groups=2, clips=1)
    synthetic = tmp_path / "synthetic"
    assert invoke_cli("train", str(phav), "--out", str(synthetic), "--streams", "flow", *FAST).returncode == 0
    for mode, extra in (("tsn", ()), ("cool", ("--mix", "1:2")), ("ft", ("--init", str(synthetic)))):
        out = tmp_path / mode
        result = invoke_cli("train", str(phav), "--real", f"ucf101={ucf}", "--mode", mode, "--streams", "flow",
                                "--real-fraction", "0.5,1", "--out", str(out), *FAST, *extra)  # fmt: skip
        assert result.returncode == 0, (mode, result.stderr)
        runs = json.loads((out / "results.json").read_text())["runs"]
        assert [r["fraction"] for r in runs] == [0.5, 1.0]
        assert runs[0]["test_clips"] == 3
        virtual = 3 if mode == "cool" else 0
        assert [r["train_clips"] for r in runs] == [3 + virtual, 3 + virtual]  # half of 1 per class rounds up
    # TSN-FT again into its folder from another PHAV run: its weights, not the file's name,
    # decide whether the checkpoints there are resumed
    other = tmp_path / "synthetic2"
    made = invoke_cli("train", str(phav), "--out", str(other), "--streams", "flow", "--seed", "5", *FAST)
    assert made.returncode == 0, made.stderr
    result = invoke_cli("train", str(phav), "--real", f"ucf101={ucf}", "--mode", "ft", "--streams", "flow",
                        "--real-fraction", "0.5,1", "--out", str(tmp_path / "ft"), *FAST,
                        "--init", str(other))  # fmt: skip
    assert result.returncode == 2 and "made with other settings or data" in result.stderr, result.stderr


def _one_error_line(stderr: str) -> str:
    lines = [line for line in stderr.splitlines() if line.strip()]
    assert len(lines) == 1 and lines[0].startswith("error:") and "Traceback" not in stderr, stderr
    return lines[0]


@pytest.mark.parametrize(
    ("args", "field"),
    [
        pytest.param(("--size", "tiny"), "--size", id="size"),
        pytest.param(("--real", "kinetics=/x"), "--real", id="real"),
        pytest.param(("--split", "weather"), "--split", id="split"),
        pytest.param(("--real-fraction", "0"), "--real-fraction", id="real-fraction"),
        pytest.param(("--streams", "depth"), "--streams", id="streams"),
        pytest.param(("--device", "cuda:7"), "--device", id="device"),
        pytest.param(("--distill", "1", "--streams", "rgb"), "--distill", id="distill-without-flow"),
        pytest.param(("--rgb-diff", "--rgb-frames", "1"), "--rgb-diff", id="rgb-diff-single-frame"),
        pytest.param(("--precision", "fp16"), "--precision", id="precision"),
        pytest.param(("--mode", "ft", "--real", "ucf101=REAL"), "--init", id="ft-without-init"),
        pytest.param(("--mode", "ft", "--real", "ucf101=REAL", "--init", "REAL/none"), "--init", id="init-missing"),
        pytest.param(("--streams", "flow,flow"), "--streams", id="a-stream-twice"),
        pytest.param(("--diff-gain", "inf"), "--diff-gain", id="diff-gain-inf"),
        # read after the options are checked: the official split files are missing
        pytest.param(("--real", "ucf101=REAL"), "ucfTrainTestlist", id="no-split-files"),
    ],
)
def test_train_user_errors_are_one_line(phav, tmp_path, args, field):
    args = tuple(a.replace("REAL", str(tmp_path)) for a in args)
    result = invoke_cli("train", str(phav), "--out", str(tmp_path / "x"), *FAST, *args)
    assert result.returncode == 2, (args, result.stdout, result.stderr)
    assert field in _one_error_line(result.stderr)


def test_a_device_torch_knows_but_training_does_not_is_one_line(tmp_path):
    """``--device mps`` names a torch device (Apple's GPU) that training neither supports nor
    tests: one line naming --device and exit code 2, before anything is read, not torch's
    traceback from deep inside training."""
    result = invoke_cli("train", str(tmp_path), "--out", str(tmp_path / "x"), "--device", "mps", *FAST)
    assert result.returncode == 2, (result.stdout, result.stderr)
    line = _one_error_line(result.stderr)
    assert "--device" in line and "mps" in line and "Traceback" not in result.stdout + result.stderr
    assert not (tmp_path / "x").exists()


def test_an_init_that_cannot_start_every_stream_is_refused_before_training(phav, tmp_path):
    """``--init`` is checked against ``--streams`` before any video is read: a checkpoint file
    starts one stream (the flow stream trained in full, then the RGB one failed on its
    shapes), and a folder must hold ``split1-STREAM.pt`` for each."""
    (tmp_path / "run").mkdir()
    (tmp_path / "run" / "split1-flow.pt").write_bytes(b"")
    for init, words in ((tmp_path / "run" / "split1-flow.pt", "a checkpoint starts one stream"),
                        (tmp_path / "run", "no split1-rgb.pt to start from")):  # fmt: skip
        result = invoke_cli("train", str(phav), "--out", str(tmp_path / "x"), *FAST, "--mode", "ft",
                            "--real", f"ucf101={tmp_path}", "--init", str(init))  # fmt: skip
        assert result.returncode == 2, (result.stdout, result.stderr)
        line = _one_error_line(result.stderr)
        assert "--init" in line and words in line, line
        assert not (tmp_path / "x").exists()


def test_cool_tsn_without_a_phav_dataset_is_a_user_error(tmp_path):
    result = invoke_cli("train", "--real", f"ucf101={tmp_path}", "--mode", "cool", *FAST)
    assert result.returncode == 2 and "PHAV dataset" in _one_error_line(result.stderr)


def test_the_phav_script_turns_a_user_error_into_one_line_and_exit_code_2(tmp_path):
    """The console script itself, in its own process: no traceback, one line, exit code 2."""
    result = run_cli("train", str(tmp_path), "--out", str(tmp_path / "x"), "--size", "tiny")
    assert result.returncode == 2, (result.stdout, result.stderr)
    assert "--size" in _one_error_line(result.stderr)
