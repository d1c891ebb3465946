"""``phav train`` and ``phav-validate --checks learnability`` as a user runs them."""

from __future__ import annotations

import json

import cv2

from tests.helpers import run_cli
from tests.validators.learn.helpers import ucf101_folder

FAST = ("--epochs", "1", "--widths", "8,16", "--threads", "1")


def test_train_on_phav_writes_results_and_resumes(phav, tmp_path):
    out = tmp_path / "run"
    args = ("train", str(phav), "--out", str(out), "--split", "random", *FAST)
    result = run_cli(*args)
    assert result.returncode == 0, result.stderr
    assert "test accuracy" in result.stdout and "fused" in result.stdout
    data = json.loads((out / "results.json").read_text())
    run = data["runs"][0]
    assert run["train_clips"] == 2 and run["test_clips"] == 1
    assert set(run["accuracy"]) == {"rgb", "flow", "fused"}
    assert (out / "split1-rgb.pt").exists() and (out / "split1-flow.pt").exists()
    assert cv2.imread(str(out / "split1-confusion.png")) is not None
    again = run_cli(*args)  # every checkpoint is finished: nothing retrained, same numbers
    assert again.returncode == 0, again.stderr
    assert json.loads((out / "results.json").read_text())["runs"] == data["runs"]


def test_cool_tsn_and_fine_tuning_on_a_ucf101_folder(phav, tmp_path):
    ucf = ucf101_folder(tmp_path / "ucf", groups=2, clips=1)
    synthetic = tmp_path / "synthetic"
    assert run_cli("train", str(phav), "--out", str(synthetic), "--streams", "flow", *FAST).returncode == 0
    for mode, extra in (("tsn", ()), ("cool", ("--mix", "1:2")), ("ft", ("--init", str(synthetic)))):
        out = tmp_path / mode
        result = run_cli("train", str(phav), "--real", f"ucf101={ucf}", "--mode", mode, "--streams", "flow",
                         "--real-fraction", "0.5,1", "--out", str(out), *FAST, *extra)  # fmt: skip
        assert result.returncode == 0, (mode, result.stderr)
        runs = json.loads((out / "results.json").read_text())["runs"]
        assert [r["fraction"] for r in runs] == [0.5, 1.0]
        assert runs[0]["test_clips"] == 3
        virtual = 3 if mode == "cool" else 0
        assert [r["train_clips"] for r in runs] == [3 + virtual, 3 + virtual]  # half of 1 per class rounds up


def test_train_user_errors_are_one_line(phav, tmp_path):
    for args, field in (
        (("--size", "tiny"), "--size"),
        (("--real", "kinetics=/x"), "--real"),
        (("--split", "weather"), "--split"),
        (("--real-fraction", "0"), "--real-fraction"),
        (("--streams", "depth"), "--streams"),
        (("--device", "cuda:7"), "--device"),
    ):
        result = run_cli("train", str(phav), "--out", str(tmp_path / "x"), *FAST, *args)
        assert result.returncode == 2, (args, result.stdout, result.stderr)
        assert field in result.stderr and "Traceback" not in result.stderr
    result = run_cli("train", str(phav), "--real", f"ucf101={tmp_path}", "--mode", "ft", *FAST)
    assert result.returncode == 2 and "--init" in result.stderr
    result = run_cli("train", "--real", f"ucf101={tmp_path}", "--mode", "cool", *FAST)
    assert result.returncode == 2 and "PHAV dataset" in result.stderr
    result = run_cli("train", str(phav), "--real", f"ucf101={tmp_path}", "--out", str(tmp_path / "x"), *FAST)
    assert result.returncode == 2 and "ucfTrainTestlist" in result.stderr


def test_validate_learnability_reports_accuracy_and_a_confusion_image(phav, tmp_path):
    report = tmp_path / "report.json"
    learn = tmp_path / "learn"
    result = run_cli("validate!", str(phav), "--checks", "learnability", "--learn-epochs", "1", "--threads", "1",
                     "--learn-dir", str(learn), "--json", str(report), "--html", str(tmp_path / "r.html"))  # fmt: skip
    # three clips cannot show learning: the check runs and fails with its numbers
    assert result.returncode == 1, result.stderr
    check = json.loads(report.read_text())["datasets"][0]["checks"][0]
    assert check["name"] == "learnability" and check["status"] == "fail"
    assert check["finding_counts"] == {"NOT_LEARNABLE": 1}
    numbers = check["numbers"]
    assert numbers["test_clips"] + numbers["train_clips"] <= 3 and numbers["held_out"]["actor"]
    assert {"rgb_accuracy", "flow_accuracy", "fused_accuracy", "p_value", "chance"} <= set(numbers)
    image = cv2.imread(numbers["confusion_png"])
    assert image is not None and image.shape[0] > 35 * 14
    assert (learn / "rgb.pt").exists() and (learn / "flow.pt").exists()
    assert "Learnability: confusion" in (tmp_path / "r.html").read_text()


def test_bench_training_section_prints_speed_and_accuracy_against_minutes(phav):
    result = run_cli("bench", "--sections", "training", "--training-data", str(phav), "--training-epochs", "2")
    assert result.returncode == 0, result.stderr
    out = result.stdout
    assert "training speed" in out and "training clips/s" in out
    assert "test accuracy against training minutes" in out
    assert "random" in out and "held-out actor" in out
