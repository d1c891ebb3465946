"""docs/measure/pixel_grain.py: how much a class varies from pixel to pixel, in our dumped
frames (docs/realism-gap.md)."""

from __future__ import annotations

import numpy as np
import pytest

from phav_spec.vocab import PIXEL_CLASSES
from tests.validators.learn.helpers import measure_script

SKY, ROAD = PIXEL_CLASSES["sky"].class_id, PIXEL_CLASSES["road"].class_id


@pytest.fixture(scope="module")
def script():
    return measure_script("pixel_grain")


def test_contrast_is_zero_on_a_flat_colour_and_grows_with_the_grain(script):
    flat = np.full((8, 8, 3), 120, np.uint8)
    assert np.allclose(script.contrast(flat), 0.0)
    checker = flat.copy()
    checker[::2, ::2] = 140  # a quarter of the pixels brighter
    c = script.contrast(checker)
    assert c[4, 4] > 0.1 and c[3, 3] > 0.0  # the bright pixel stands out, its neighbour a little
    brighter = flat.copy()
    brighter[::2, ::2] = 200
    assert script.contrast(brighter)[4, 4] > c[4, 4]


def _frame(tmp_path, name: str, road_value: np.ndarray, groups: tuple[str, ...]) -> None:
    """24 × 32: sky over road; the road's pixels ``road_value``."""
    ours = np.full((24, 32), ROAD, np.uint8)
    ours[:12] = SKY
    rgb = np.full((24, 32, 3), 200, np.uint8)
    rgb[12:] = road_value[..., None]
    np.savez_compressed(tmp_path / name, rgb=rgb, ours=ours, said=np.zeros((24, 32), np.uint8),
                        where=np.array(groups))  # fmt: skip


def test_our_classes_are_measured_inside_them_per_group(script, tmp_path, monkeypatch):
    monkeypatch.setattr(script, "MIN_PIXELS", 20)
    grainy = np.where(np.indices((12, 32)).sum(axis=0) % 2 == 0, 90, 110).astype(np.uint8)
    _frame(tmp_path, "v000000-001.npz", grainy, ("all", "weather=clear"))
    _frame(tmp_path, "v000001-001.npz", np.full((12, 32), 100, np.uint8), ("all", "weather=fog"))
    clear, fog = script.ours(tmp_path, "weather=clear"), script.ours(tmp_path, "weather=fog")
    assert clear["road"][0] > 0.1 and clear["road"][1] == 1  # a checkerboard of ±10 %, one frame
    assert fog["road"] == pytest.approx((0.0, 1)) and fog["sky"] == pytest.approx((0.0, 1))  # flat colours
    assert script.ours(tmp_path, "all")["road"][1] == 2
    assert script.ours(tmp_path, "weather=rain") == {}


def test_a_missing_photograph_exits_in_one_line(script, tmp_path):
    with pytest.raises(SystemExit, match=r"building\.jpg: not found"):
        script.real(tmp_path)
