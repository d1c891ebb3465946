"""docs/measure/judged_real.py: real photographs through fog, and our dumped frames' answers
per class (docs/realism-gap.md)."""

from __future__ import annotations

import json
from collections import Counter

import numpy as np
import pytest

from phav_spec.judge_classes import JUDGE_CLASSES
from phav_spec.vocab import PIXEL_CLASSES
from tests.validators.learn.helpers import measure_script

CITY = JUDGE_CLASSES["cityscapes"]
SKY, GRASS = PIXEL_CLASSES["sky"].class_id, PIXEL_CLASSES["terrain"].class_id


@pytest.fixture(scope="module")
def script():
    return measure_script("judged_real")


def test_a_veil_mixes_each_pixel_towards_the_airlight_in_linear_light(script):
    rgb = np.array([[[0, 0, 0], [255, 255, 255], [40, 120, 200]]], np.uint8)
    assert np.array_equal(script.veiled(rgb, 1.0, 215.0), rgb)  # no fog: the photograph
    half = script.veiled(rgb, 0.5, 215.0)
    fog = (215.0 / 255.0) ** 2.2  # the renderer's display curve, undone
    assert (half[0, 0] == np.floor(255.0 * (0.5 * fog) ** (1 / 2.2) + 0.5)).all()  # black: half the fog
    towards = np.abs(half.astype(int) - 215) <= np.abs(rgb.astype(int) - 215)
    assert towards.all() and not np.array_equal(half, rgb)
    assert (np.abs(script.veiled(rgb, 1e-6, 215.0).astype(int) - 215) <= 1).all()  # nothing through: the fog


def test_veil_transmissions_parse_or_exit_in_one_line(script):
    assert script.transmissions("0.8, 0.6,0.4") == [0.8, 0.6, 0.4]
    for bad in ("0.8,x", "0", "1.5", ","):
        with pytest.raises(SystemExit, match="--veil"):
            script.transmissions(bad)


def _frame(tmp_path, name: str, groups: tuple[str, ...]) -> None:
    """12 × 16: sky over grass; the judge says sky on the sky and road on the grass."""
    ours = np.full((12, 16), GRASS, np.uint8)
    ours[:6] = SKY
    said = np.full((12, 16), CITY.label_id("road"), np.uint8)
    said[:6] = CITY.label_id("sky")
    np.savez_compressed(tmp_path / name, rgb=np.zeros((12, 16, 3), np.uint8), ours=ours, said=said,
                        where=np.array(groups))  # fmt: skip


def test_the_dump_gives_the_answers_on_each_class_interior_in_one_group(script, tmp_path):
    _frame(tmp_path, "v000000-001.npz", ("all", "weather=fog"))
    _frame(tmp_path, "v000001-001.npz", ("all", "weather=clear"))
    answers = script.judge_dump(tmp_path, "weather=fog")
    inside = script.interior(np.repeat([0, 1], 6)[:, None] * np.ones((1, 16), int), script.MARGIN_PX)
    per_half = int(inside[6:].sum())  # the grass rows at least 4 px from the sky and kept by the edge
    assert answers["terrain"] == {"weather=fog": Counter({CITY.label_id("road"): per_half})}
    assert answers["sky"] == {"weather=fog": Counter({CITY.label_id("sky"): int(inside[:6].sum())})}
    assert script.judge_dump(tmp_path, "all")["terrain"]["all"][CITY.label_id("road")] == 2 * per_half
    with pytest.raises(SystemExit, match="no judged outdoor frame of weather=rain"):
        script.judge_dump(tmp_path, "weather=rain")


def test_a_car_seen_closer_is_its_crop_scaled_up_with_its_box():
    small = measure_script("judged_real_small")
    h, w = small.H, small.W
    frame = np.zeros((h, w, 3), np.uint8)
    frame[:, w // 2 :] = 200  # the right half bright
    mask = np.zeros((h, w), bool)
    mask[h // 2 :, :] = True  # the car: the bottom half
    whole, kept = small.closer(frame, mask, small.CLOSER["whole"])
    assert np.array_equal(whole, frame) and np.array_equal(kept, mask)
    right, in_car = small.closer(frame, mask, (w // 2, h // 4, w, 3 * h // 4))  # 2×: the right half's middle
    assert right.shape == frame.shape and (right == 200).all()
    assert in_car.mean() == pytest.approx(0.5, abs=0.01) and in_car[-1].all() and not in_car[0].any()
    for x0, y0, x1, y1 in small.CLOSER.values():  # every crop has the frame's aspect
        assert (x1 - x0) * h == pytest.approx((y1 - y0) * w, rel=0.01)


def test_a_photograph_s_outline_is_cropped_and_tiled_with_it(tmp_path):
    """judged_real_small: a labelme outline becomes a mask, scaled and cropped as its
    photograph is (``right`` of the way across), and shrunk k times and tiled as the frame."""
    from PIL import Image

    small = measure_script("judged_real_small")
    h, w = small.H, small.W
    photo = tmp_path / "p.jpg"
    Image.new("RGB", (2 * w, h), (0, 0, 0)).save(photo)  # twice the frame's width
    square = [[w + 20.0, 40.0], [w + 120.0, 40.0], [w + 120.0, 140.0], [w + 20.0, 140.0]]
    shapes = [{"label": "sofa", "shape_type": "polygon", "points": square},
              {"label": "person", "shape_type": "polygon", "points": [[0, 0], [10, 0], [10, 10]]}]  # fmt: skip
    photo.with_suffix(".json").write_text(json.dumps({"shapes": shapes}), encoding="utf-8")
    outline = small.outline(photo, "sofa")
    assert outline.sum() == pytest.approx(100 * 100, rel=0.03) and not outline[:15, :15].any()
    with Image.open(photo) as image:
        frame, mask = small.cropped(image, outline, 1.0)  # the right half: the square 20 px in
    assert frame.shape == (h, w, 3) and mask.shape == (h, w)
    assert mask[90, 70] and not mask[90, 10] and small.height(mask) == pytest.approx(100, abs=2)
    quarter = small.tiled_mask(mask, 4)
    assert small.height(quarter[: h // 4]) == pytest.approx(25, abs=1)
    assert quarter.sum() == pytest.approx(mask.sum(), rel=0.1)  # 16 tiles, each a sixteenth of its area
    assert np.array_equal(small.box_mask((10, 20, 30, 60)).nonzero()[0][[0, -1]], [20, 59])


def test_a_photograph_is_read_from_the_first_folder_that_holds_it(script, tmp_path):
    first, second = tmp_path / "a", tmp_path / "b"
    (second / "frames").mkdir(parents=True)
    first.mkdir()
    (second / "frames" / "0001.bmp").write_bytes(b"x")
    assert script.found([first, second], "frames/0001.bmp") == second / "frames" / "0001.bmp"
    (first / "frames").mkdir()
    (first / "frames" / "0001.bmp").write_bytes(b"y")
    assert script.found([first, second], "frames/0001.bmp") == first / "frames" / "0001.bmp"
    assert script.found([first, second], "frames/0002.bmp") is None
    (first / "folder.bmp").mkdir()  # a folder of the name is not the photograph
    assert script.found([first], "folder.bmp") is None
