"""docs/measure/judged_ceiling.py: each Cityscapes class's IoU as judged, where its false
answers lie and the mIoU were our pixels of it all named right; and judged_frames.py
scoring the frames it dumped anew (docs/realism-gap.md)."""

from __future__ import annotations

import json
import sys

import numpy as np
import pytest

from phav_spec.judge_classes import JUDGE_CLASSES
from phav_spec.vocab import PIXEL_CLASSES
from tests.validators.learn.helpers import measure_script

CITY = JUDGE_CLASSES["cityscapes"]


@pytest.fixture(scope="module")
def script():
    return measure_script("judged_ceiling")


def _frame(script, video: str, groups: tuple[str, ...]):
    """4 × 8 pixels: our sky above our grass; the judge names the sky's right half `building`
    and the grass's two right columns `sky`."""
    ours = np.full((4, 8), PIXEL_CLASSES["terrain"].class_id, np.uint8)
    ours[:2] = PIXEL_CLASSES["sky"].class_id
    said = np.full((4, 8), CITY.label_id("terrain"), np.int64)
    said[:2, :4] = CITY.label_id("sky")
    said[:2, 4:] = CITY.label_id("building")
    said[2:, 6:] = CITY.label_id("sky")
    return script.Frame(video, ours, said, groups)


def test_each_class_is_split_into_misses_and_false_answers_and_its_ceiling(script, tmp_path):
    miou, rows = script.ceilings([_frame(script, "v000000", ("all",))])
    by = {r.name: r for r in rows}
    assert sorted(by) == ["sky", "terrain"]  # building is named but none of ours is: not present
    sky, grass = by["sky"], by["terrain"]
    # sky: 8 of its 16 pixels named sky, and 4 grass pixels named sky
    assert (sky.pixels, sky.missed, dict(sky.false_on)) == (16, 8, {"terrain": 4})
    assert sky.iou == pytest.approx(8 / 20) and sky.iou_right == pytest.approx(16 / 20)
    assert (grass.pixels, grass.missed, sum(grass.false_on.values())) == (16, 4, 0)
    assert grass.iou == pytest.approx(12 / 16) and grass.iou_right == 1.0
    assert miou == pytest.approx((0.4 + 0.75) / 2)
    assert sky.miou_right == pytest.approx((0.8 + 0.75) / 2)
    # the grass named right takes the sky's false answers away with its misses
    assert grass.miou_right == pytest.approx((8 / 16 + 1.0) / 2)


def test_a_group_counts_only_its_frames_and_the_dump_round_trips(script, tmp_path):
    fog = _frame(script, "v000001", ("all", "weather=fog"))
    clear = script.Frame("v000002", fog.ours, np.full_like(fog.said, CITY.label_id("road")), ("all", "weather=clear"))
    miou, _ = script.ceilings([fog, clear], "weather=fog")
    assert miou == pytest.approx((0.4 + 0.75) / 2)
    assert script.ceilings([fog, clear], "weather=rain") == (pytest.approx(float("nan"), nan_ok=True), [])
    for f in (fog, clear):
        np.savez_compressed(tmp_path / f"{f.video}-012.npz", ours=f.ours, said=f.said, where=np.array(f.groups))
    read = script.read_dump(tmp_path)
    assert [(f.video, f.groups) for f in read] == [(f.video, f.groups) for f in (fog, clear)]
    assert all(np.array_equal(a.said, b.said) for a, b in zip(read, (fog, clear), strict=True))
    with pytest.raises(SystemExit, match=r"no \.npz frames"):
        script.read_dump(tmp_path / "empty")


def test_false_answers_in_frames_without_the_class_count_against_it(script):
    shown = _frame(script, "v000000", ("all",))
    grass = np.full_like(shown.ours, PIXEL_CLASSES["terrain"].class_id)
    said = np.full_like(shown.said, CITY.label_id("terrain"))
    said[0, :4] = CITY.label_id("sky")  # the judge's sky on a frame of grass alone
    _, rows = script.ceilings([shown, script.Frame("v000001", grass, said, ("all",))])
    sky = {r.name: r for r in rows}["sky"]
    # pooled over the sample, as Cityscapes' own evaluation pools: the grass frame's sky counts
    assert (sky.elsewhere, dict(sky.false_on)) == (4, {"terrain": 8}) and sky.iou == pytest.approx(8 / 24)
    assert sky.iou_right == pytest.approx(16 / 24)


def test_judged_frames_scores_a_dump_anew(script, tmp_path, monkeypatch, capsys):
    frames = measure_script("judged_frames")
    shown = _frame(script, "v000003", ("all", "weather=rain"))
    voc = np.zeros_like(shown.said)  # background everywhere: VOC judges none of sky or grass
    np.savez_compressed(tmp_path / "v000003-010.npz", rgb=np.zeros((4, 8, 3), np.uint8), ours=shown.ours,
                        said=shown.said, voc=voc, where=np.array(shown.groups))  # fmt: skip
    out = tmp_path / "scores.json"
    monkeypatch.setattr(sys, "argv", ["judged_frames.py", "--rescore", str(tmp_path), "--json", str(out)])
    frames.main()
    groups = json.loads(out.read_text())["groups"]
    assert sorted(groups) == ["all", "weather=rain"]
    assert groups["all"]["miou"] == pytest.approx((0.4 + 0.75) / 2, abs=1e-3)
    assert groups["all"]["sky"] == 0.4 and groups["all"]["terrain"] == 0.75
    assert "weather=rain" in capsys.readouterr().out
