"""The learnability check as ``phav-validate --checks learnability`` runs it: the report's
numbers, the confusion image, the checkpoints and the HTML section."""

from __future__ import annotations

import json

import cv2

from tests.helpers import invoke_cli


def test_validate_learnability_reports_accuracy_and_a_confusion_image(phav, tmp_path):
    report = tmp_path / "report.json"
    learn = tmp_path / "learn"
    result = invoke_cli("validate!", str(phav), "--checks", "learnability", "--learn-epochs", "1",
                            "--threads", "1", "--learn-dir", str(learn), "--json", str(report),
                            "--html", str(tmp_path / "r.html"))  # fmt: skip
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
