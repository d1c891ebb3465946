"""docs/measure/judged_views.py: each of our objects in a dump of the check's frames, whole or
cut by the frame's edge and by its height, and how much of it each judge names as its class
(docs/realism-gap.md)."""

from __future__ import annotations

import numpy as np
import pytest

from phav_spec.judge_classes import JUDGE_CLASSES
from phav_spec.vocab import PIXEL_CLASSES
from tests.validators.learn.helpers import measure_script

CAR = PIXEL_CLASSES["car"].class_id
ROAD = PIXEL_CLASSES["road"].class_id


@pytest.fixture(scope="module")
def script():
    return measure_script("judged_views")


def _dump(tmp_path):
    """Two 256 × 340 frames of road: one with a whole car 30 px tall (Cityscapes names its top
    10 rows `car`, VOC all of it), one with a car 70 px tall cut by the left edge (neither
    names it) and a 5-pixel sliver (too small to be a view)."""
    city, voc = JUDGE_CLASSES["cityscapes"], JUDGE_CLASSES["pascal_voc"]
    whole = np.full((256, 340), ROAD, np.uint8)
    whole[100:130, 150:200] = CAR
    said = np.full(whole.shape, city.label_id("road"), np.int64)
    said[100:110, 150:200] = city.label_id("car")
    answers = np.where(whole == CAR, voc.label_id("car"), voc.label_id("background"))
    np.savez_compressed(tmp_path / "v000000-003.npz", ours=whole, said=said, voc=answers, where=np.array(["all"]))
    cut = np.full((256, 340), ROAD, np.uint8)
    cut[150:220, 0:60] = CAR
    cut[10, 300:305] = CAR
    none = np.zeros(cut.shape, np.int64)
    np.savez_compressed(tmp_path / "v000001-040.npz", ours=cut, said=none, voc=none, where=np.array(["all"]))


def test_each_object_is_tallied_by_its_view_and_each_judges_recall(script, tmp_path):
    _dump(tmp_path)
    views = script.tally(script.dump_files(tmp_path), "car")
    assert sorted(views) == ["cut by the edge, 64 px and up", "whole, 24–63 px"]
    whole, cut = views["whole, 24–63 px"], views["cut by the edge, 64 px and up"]
    keys = ("objects", "pixels", "named:cityscapes", "named:pascal_voc")
    assert [whole[k] for k in keys] == [1, 1500, 500, 1500]
    assert [cut[k] for k in keys] == [1, 4200, 0, 0]
    rows = script.table(views).splitlines()
    assert rows[2] == "| whole, 24–63 px | 1 | 1,500 (0.26) | 0.33 | 1.00 |"
    assert rows[3] == "| cut by the edge, 64 px and up | 1 | 4,200 (0.74) | 0.00 | 0.00 |"
    assert rows[4] == f"| all | 2 | 5,700 (1.00) | {500 / 5700:.2f} | {1500 / 5700:.2f} |"


def test_a_class_one_judge_names_has_that_judges_recall_only(script, tmp_path):
    _dump(tmp_path)  # VOC has no road; Cityscapes names every road pixel `road` (its id 0)
    views = script.tally(script.dump_files(tmp_path), "road")
    assert sorted(views) == ["cut by the edge, 64 px and up"]
    rows = script.table(views).splitlines()
    assert rows[0] == "| view | objects | pixels (share) | cityscapes recall |"
    assert rows[-1] == f"| all | 2 | {2 * 256 * 340 - 5700 - 5:,} (1.00) | 1.00 |"
