"""The learnability check as ``phav-validate --checks learnability`` runs it: the report's
numbers, the confusion image, the checkpoints and the HTML section."""

from __future__ import annotations

import json
from pathlib import Path

import cv2
import numpy as np
import pytest

from phav_spec.errors import PhavUserError
from phav_spec.manifest import load_manifest
from phav_validators.findings import CheckResult, Reason, Status
from phav_validators.learn.learnability import (
    LearnOptions,
    LearnResult,
    binomial_p,
    chance_level,
    could_pass,
    learnability_check,
    wilson_interval,
)
from phav_validators.options import DatasetReport
from phav_validators.report import learnability_html, report_html
from tests.helpers import invoke_cli


def test_validate_learnability_reports_accuracy_and_a_confusion_image(phav, tmp_path):
    report = tmp_path / "report.json"
    learn = tmp_path / "learn"
    result = invoke_cli("validate!", str(phav), "--checks", "learnability", "--learn-epochs", "1",
                        "--learn-rgb-epochs", "1", "--threads", "1", "--learn-dir", str(learn), "--json", str(report),
                        "--html", str(tmp_path / "r.html"))  # fmt: skip
    # three clips cannot show learning: the check runs and says so with its numbers (a warning)
    assert result.returncode == 0, result.stderr
    check = json.loads(report.read_text())["datasets"][0]["checks"][0]
    assert check["name"] == "learnability" and check["status"] == "warn"
    assert check["finding_counts"] == {"LEARNING_INCONCLUSIVE": 1}
    assert "too few or too alike test clips" in check["findings"][0]["message"]
    numbers = check["numbers"]
    assert numbers["test_clips"] + numbers["train_clips"] <= 3 and numbers["held_out"]["actor"]
    assert {"rgb_accuracy", "flow_accuracy", "fused_accuracy", "p_value", "chance"} <= set(numbers)
    lo, hi = numbers["fused_ci95"]
    assert 0 <= lo <= numbers["fused_accuracy"] <= hi <= 1
    assert numbers["epochs"] == {"flow": 1, "rgb": 1}  # the flow stream first: the RGB stream learns from it
    assert numbers["settings"]["distill"] > 0 and numbers["settings"]["precision"] in ("fp32", "bf16")
    image = cv2.imread(numbers["confusion_png"])
    assert image is not None and image.shape[0] > 35 * 14
    assert (learn / "rgb.pt").exists() and (learn / "flow.pt").exists()
    page = (tmp_path / "r.html").read_text()
    assert "Learnability: confusion" in page and "Per class" in page
    assert sum(row["clips"] for row in numbers["per_class"]) == numbers["test_clips"]
    assert (
        sum(numbers["test_clips_per_class"].values()) == numbers["test_clips"]
        and len(numbers["test_clips_per_class"]) == 35
    )
    # the split, listed for anyone to check against recipes.parquet
    assert numbers["flow"] == "gt" and check["summary"].startswith("inconclusive, ground-truth flow: fused")
    listed = numbers["split_videos"]
    assert listed["held_out"] == numbers["held_out"] and json.loads((learn / "split.json").read_text()) == listed
    assert len(listed["train_videos"]) == numbers["train_clips"] and len(listed["test_videos"]) == numbers["test_clips"]
    assert not set(listed["train_videos"]) & set(listed["test_videos"])
    assert numbers["train_clips_with_held_out_background"] == len(listed["train_videos_with_held_out_background"])


def test_a_budget_that_stops_training_is_inconclusive_not_a_failure(phav, tmp_path):
    report = tmp_path / "report.json"
    result = invoke_cli("validate!", str(phav), "--checks", "learnability", "--learn-epochs", "3",
                        "--learn-rgb-epochs", "1", "--learn-minutes", "0.00001", "--learn-flow", "farneback",
                        "--threads", "1", "--json", str(report))  # fmt: skip
    assert result.returncode == 0, result.stderr  # warn: phav-validate exits 0
    check = json.loads(report.read_text())["datasets"][0]["checks"][0]
    assert check["status"] == "warn" and check["finding_counts"] == {"LEARNING_INCONCLUSIVE": 1}
    assert check["summary"].startswith("inconclusive, Farneback flow estimated from the frames: fused")
    # Three clips could not decide even trained in full: that, not the budget, is the finding
    # (the budget's own finding on a test set that could decide: _verdict below).
    finding = check["findings"][0]
    assert finding["severity"] == "warn" and "too few or too alike test clips" in finding["message"]
    assert check["numbers"]["stopped_by_budget"]
    assert check["numbers"]["epochs"]["flow"] == 1 and check["numbers"]["schedule_epochs"]["flow"] == 3


def _verdict(correct: int, *, stopped: bool) -> CheckResult:
    """The check's verdict on 40 test clips of 4 classes, ``correct`` of them right."""
    classes = ["a", "b", "c", "d"]
    labels = np.arange(40) % 4
    answers = np.where(np.arange(40) < correct, labels, (labels + 1) % 4)
    probs = np.eye(4)[answers]
    chance = chance_level(labels, answers, 4)
    p = binomial_p(correct, 40, chance)
    result = LearnResult(classes, labels, {"flow": probs}, probs, chance, p, 100, 1.0, stopped,
                         keys=[f"v{i:06d}" for i in range(40)], epochs={"flow": 2 if stopped else 8},
                         schedule={"flow": 8}, epoch_seconds={"flow": 30.0})  # fmt: skip
    return learnability_check(result, LearnOptions(budget_minutes=1.0), Path("set"))


def test_the_verdict_depends_on_the_data_not_on_a_budget_that_stopped_training():
    assert _verdict(10, stopped=False).status == Status.FAIL  # chance: the whole schedule ran
    stopped = _verdict(10, stopped=True)
    assert stopped.status == Status.WARN and stopped.report.counts == {Reason.LEARNING_INCONCLUSIVE: 1}
    assert "rerun with --learn-minutes 5" in stopped.report.findings[0].message  # 8 × 30 s and a tenth
    assert stopped.report.findings[0].numbers["minutes_needed"] >= 4
    early_pass = _verdict(30, stopped=True)  # a partial result that passes already passes
    assert early_pass.status == Status.PASS and "already passes" in early_pass.report.notes[0]
    assert _verdict(30, stopped=False).status == Status.PASS


def test_a_test_set_that_could_not_pass_even_answered_right_is_inconclusive_not_a_failure():
    """Two test clips, or four of four classes: even all right, p stays over 10⁻³. That says
    nothing about the data, so the verdict is a warning naming why, not NOT_LEARNABLE."""
    for labels in ([0, 0], [0, 1, 2, 3]):
        assert not could_pass(np.array(labels), 4, 1e-3, 2.0)[0]
        answers = (np.array(labels) + 1) % 4  # all wrong
        result = _result(labels, answers, [f"v{i:06d}" for i in range(len(labels))], ["a", "b", "c", "d"])
        verdict = learnability_check(result, LearnOptions(), Path("set"))
        assert verdict.status == Status.WARN and verdict.report.counts == {Reason.LEARNING_INCONCLUSIVE: 1}
        assert "too few or too alike test clips" in verdict.report.findings[0].message
    assert could_pass(np.arange(40) % 4, 4, 1e-3, 2.0)[0]  # 40 clips of 4 classes can decide
    # 180 clips of one class and 20 of another, of 35: every answer right is only 1.2× chance,
    # but the 20 rare ones right and nothing answered the common class is 6.6× chance.
    assert could_pass(np.repeat([0, 1], [180, 20]), 35, 1e-3, 2.0)[0]


def test_the_wilson_interval_of_an_accuracy():
    assert wilson_interval(50, 100) == pytest.approx((0.4038, 0.5962), abs=1e-4)
    lo, hi = wilson_interval(0, 20)
    assert lo == pytest.approx(0.0, abs=1e-12) and hi == pytest.approx(0.1611, abs=1e-4)
    # 118 of 262 (45 %): the interval is within ±6 points, as the issue asks of a test set
    lo, hi = wilson_interval(118, 262)
    assert hi - lo < 0.12 and lo < 118 / 262 < hi
    assert wilson_interval(0, 0) == (0.0, 1.0)


def _result(labels, answers, keys, classes):
    probs = np.zeros((len(answers), len(classes)))
    probs[np.arange(len(answers)), answers] = 1.0
    return LearnResult(classes, np.array(labels), {"flow": probs}, probs, 1 / len(classes), 0.5, 10, 1.0, False,
                       keys=keys)  # fmt: skip


def test_per_class_accuracy_and_the_pairs_most_answered_for_each_other():
    classes = ["a", "b", "c", "d"]
    #        a  a  a  b  b  b  c  c  d
    labels = [0, 0, 0, 1, 1, 1, 2, 2, 3]
    answer = [0, 1, 1, 1, 0, 1, 2, 3, 3]
    result = _result(labels, answer, [f"v{i:06d}" for i in range(9)], classes)
    rows = {r["class"]: r for r in result.per_class()}
    assert rows["a"] == {"class": "a", "clips": 3, "accuracy": 1 / 3, "mistaken_for": "b", "mistakes": 2}
    assert rows["d"]["accuracy"] == 1.0 and rows["d"]["mistaken_for"] is None
    assert [r["class"] for r in result.per_class()] == ["a", "c", "b", "d"]  # worst first
    assert result.confused_pairs() == [("a", "b", 3), ("c", "d", 1)]
    assert result.example("a", "b") == "v000001" and result.example("b", "c") is None


def test_the_report_shows_a_frame_of_each_class_of_a_confused_pair(phav):
    keys = sorted(v.video_id for v in load_manifest(phav / "manifest.json").videos)
    result = _result([0, 1, 1], [1, 1, 0], keys, ["walk", "run"])
    page = "".join(learnability_html(result, phav))
    assert "walk ↔ run" in page
    assert page.count("<figure>") == 2 and f"{keys[0]}: walk, answered run" in page
    assert f"{keys[1]}: run, answered run" in page  # beside it, a clip of the other class
    # In the whole report: a shard (or several) named reads its frames from the dataset's folder.
    shards = ", ".join(str(p) for p in sorted(phav.glob("*.tar")))
    named = DatasetReport(shards, [], n_videos=3, n_frames=3, learnability=result, root=str(phav))
    assert report_html([named]).count("<figure>") == 2


@pytest.mark.parametrize("minutes", [0.0, -1.0, float("nan"), float("inf")])
def test_a_budget_that_is_no_positive_finite_number_is_refused(minutes):
    with pytest.raises(PhavUserError, match=r"--learn-minutes: must be a positive, finite number"):
        LearnOptions(budget_minutes=minutes)


def test_data_the_split_cannot_divide_skips_the_check_and_keeps_the_report(phav):
    """Three clips of three actions, one motion each: holding out motions tests none. The
    check is skipped with the reason, the other checks report; it was a user error naming
    an option phav-validate lacks, and the whole report was lost."""
    from phav_validators.options import Options
    from phav_validators.source import resolve
    from phav_validators.validate import validate_dataset

    opts = Options(checks=("schema", "learnability"), learn=LearnOptions(split="motion", epochs=1, rgb_epochs=1))
    report = validate_dataset(resolve([phav])[0], options=opts)
    checks = {c.name: c for c in report.checks}
    assert checks["schema"].status == Status.PASS
    assert checks["learnability"].status == Status.SKIP
    assert "cannot split the data: holding out motion leaves" in checks["learnability"].summary
