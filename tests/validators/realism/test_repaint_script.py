"""docs/measure/judged_repaint.py: dumped frames repainted and scored again as the realism
check scores them (docs/realism-gap.md)."""

from __future__ import annotations

import re

import numpy as np
import pytest

from phav_spec.judge_classes import JUDGE_CLASSES
from phav_spec.vocab import PIXEL_CLASSES
from tests.validators.learn.helpers import measure_script

CITY = JUDGE_CLASSES["cityscapes"]
SKY, GRASS = PIXEL_CLASSES["sky"].class_id, PIXEL_CLASSES["terrain"].class_id


@pytest.fixture(scope="module")
def script():
    return measure_script("judged_repaint")


def _frame(script, groups=("all",)):
    """4 × 6: a warm grey sky over green grass."""
    ours = np.full((4, 6), GRASS, np.uint8)
    ours[:2] = SKY
    rgb = np.zeros((4, 6, 3), np.uint8)
    rgb[:2] = (210, 207, 205)
    rgb[2:] = (80, 100, 60)
    return script.Painted("v000000", rgb, ours, groups)


def _labels(rgb: np.ndarray) -> np.ndarray:
    """A judge that takes blue over red for sky, green over both for terrain, else building."""
    r, g, b = (rgb[..., i].astype(int) for i in range(3))
    out = np.full(rgb.shape[:2], CITY.label_id("building"), np.int64)
    out[b > r] = CITY.label_id("sky")
    out[(g > r) & (g > b)] = CITY.label_id("terrain")
    return out


def test_repaints_change_only_what_they_name(script):
    f = _frame(script)
    assert np.array_equal(script.repaint("none")(f.rgb, f.ours), f.rgb)
    sky = script.repaint("sky-tint:0.1")(f.rgb, f.ours)
    assert np.array_equal(sky[2:], f.rgb[2:]) and (sky[:2, :, 2] > sky[:2, :, 0]).all()
    whole = script.repaint("tint:0.1")(f.rgb, f.ours)
    assert (whole[2:, :, 0] < f.rgb[2:, :, 0]).all() and (whole[2:, :, 2] > f.rgb[2:, :, 2]).all()
    grey = script.repaint("sky-grey:240")(f.rgb, f.ours)
    assert (grey[:2] == 240).all() and np.array_equal(grey[2:], f.rgb[2:])
    assert (script.repaint("sky-gain:10")(f.rgb, f.ours)[:2] == 255).all()  # clipped at white


def test_fog_repaints_change_the_grass_or_take_the_airlight_out(script):
    f = _frame(script)
    brighter = script.repaint("gain:2")(f.rgb, f.ours)
    assert (brighter > f.rgb).all() and (script.repaint("gain:100")(f.rgb, f.ours) == 255).all()
    greener = script.repaint("grass-chroma:2")(f.rgb, f.ours)
    assert np.array_equal(greener[:2], f.rgb[:2])  # the sky as it was
    g = greener[2:].astype(int)
    assert (g[..., 1] - g[..., 0] > 20).all() and (g[..., 1] - g[..., 2] > 40).all()  # farther from grey
    grey = script.repaint("grass-chroma:0")(f.rgb, f.ours)[2:]
    assert (grey.max(axis=-1).astype(int) - grey.min(axis=-1) <= 1).all()
    # a frame mixed half-and-half with its sky's colour is its own again once half of that is out
    x = script.linear(f.rgb)
    airlight = x[0, 0]
    hazed = script.display(0.5 * x + 0.5 * airlight)
    clear = script.repaint("dehaze:0.5")(hazed, f.ours)
    assert (np.abs(clear.astype(int) - f.rgb) <= 2).all()


@pytest.mark.parametrize("spec", ["tint", "tint:x", "tint:1.5", "sky-gain:0", "sky-grey:300", "blur:2", "gain:0",
                                  "grass-chroma:-1", "dehaze:1"])  # fmt: skip
def test_a_bad_repaint_is_one_line(script, spec):
    with pytest.raises(SystemExit, match=re.escape(f"repaint '{spec}'")):
        script.repaint(spec)


def test_a_repaint_is_scored_as_the_check_scores_and_by_group(script):
    frames = [_frame(script, ("all", "weather=overcast"))]
    miou, classes = script.scores(frames, script.repaint("none"), _labels, "all")
    # the warm grey sky is named building: sky IoU 0, grass 1; building is not ours, no figure
    assert classes == {"sky": 0.0, "terrain": 1.0} and miou == pytest.approx(0.5)
    miou, classes = script.scores(frames, script.repaint("sky-tint:0.1"), _labels, "weather=overcast")
    assert classes == {"sky": 1.0, "terrain": 1.0} and miou == 1.0
    miou, classes = script.scores(frames, script.repaint("none"), _labels, "weather=rain")
    assert np.isnan(miou) and classes == {}
    table = script.table([("none", 0.5, {"sky": 0.0, "terrain": 1.0}), ("sky-tint:0.1", 1.0, {"sky": 1.0})])
    assert table.splitlines()[0] == "| repaint | mIoU | sky | terrain |"
    assert table.splitlines()[-1] == "| sky-tint:0.1 | 1.000 | 1.00 |  |"


def test_the_dump_is_read_back_with_its_pixels(script, tmp_path):
    f = _frame(script, ("all", "weather=fog"))
    said = _labels(f.rgb)
    np.savez_compressed(tmp_path / "v000007-012.npz", rgb=f.rgb, ours=f.ours, where=np.array(f.groups), said=said)
    np.savez_compressed(tmp_path / "v000008-003.npz", rgb=f.rgb, ours=f.ours, where=np.array(f.groups), voc=said)
    (back,) = script.read(tmp_path)  # the room, judged by PASCAL VOC alone, is not read
    assert back.video == "v000007" and back.groups == f.groups
    assert np.array_equal(back.rgb, f.rgb) and np.array_equal(back.ours, f.ours)
    with pytest.raises(SystemExit, match=r"no \.npz frames"):
        script.read(tmp_path / "empty")
