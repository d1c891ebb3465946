"""docs/measure/window_coverage.py: where the crop placed on the motion lands, measured
against the body-part frames (docs/learnability.md, "Stored size and crop")."""

from __future__ import annotations

import sys

import numpy as np
import pytest

from phav_validators.learn.data import Clip
from tests.validators.learn.helpers import measure_script


@pytest.fixture(scope="module")
def script():
    return measure_script("window_coverage")


def _clip(mover: tuple[int, int], body: tuple[int, int], frames: int = 12, size=(32, 24)) -> Clip:
    """A clip whose only motion is an 8×8 patch at ``mover`` (top-left y, x) and whose only
    person is an 8×8 patch of body parts at ``body``."""
    w, h = size
    flow = np.zeros((frames, h, w, 2), np.float16)
    flow[:, mover[0] : mover[0] + 8, mover[1] : mover[1] + 8, 0] = 2.0
    parts = np.zeros((frames, h, w), np.uint8)
    parts[:, body[0] : body[0] + 8, body[1] : body[1] + 8] = 3
    return Clip("c", 0, "virtual", np.zeros((frames, h, w, 3), np.uint8), flow, {}, parts)


def test_the_window_holds_the_person_who_moves_and_misses_one_who_stands_still(script):
    # the person is what moves, in a corner: the motion window holds all of them, a centred one none
    moving, centred, default = script.body_shares(_clip(mover=(0, 0), body=(0, 0)), crop=0.5)
    assert moving == 1.0 and centred == 0.0 and 0.0 < default < 1.0
    # the person stands near the centre while a car moves in a corner: the window misses them
    moving, centred, default = script.body_shares(_clip(mover=(0, 0), body=(26, 36), size=(64, 48)), crop=0.5)
    assert moving == 0.0 and centred == 1.0 and default == 1.0
    # no person in the tested frames: nothing to measure
    empty = _clip(mover=(0, 0), body=(0, 0))
    empty.parts[:] = 0
    assert script.body_shares(empty, crop=0.5) is None


def test_the_motion_window_finds_the_mover_not_the_panning_camera(script):
    clip = _clip(mover=(0, 0), body=(0, 0), frames=8, size=(64, 48))
    clip.flow[...] = (0.8, -0.4)  # the camera pans
    clip.flow[:, 30:40, 44:52] = (2.5, -0.4)  # a mover right of centre, low
    frames = np.arange(6).reshape(3, 2)
    y0, x0 = script.motion_window(clip, frames, (16, 16))
    assert y0 <= 30 and y0 + 16 >= 40 and x0 <= 44 and x0 + 16 >= 52
    still = _clip(mover=(0, 0), body=(0, 0), frames=8, size=(64, 48))
    still.flow[...] = 0.0
    assert script.motion_window(still, frames, (16, 16)) == (16, 24)  # nothing moves: the centre


def test_an_uncompressed_npz_is_mapped_array_by_array_and_a_compressed_one_refused(script, tmp_path):
    a, b = np.arange(24, dtype=np.float16).reshape(2, 3, 4), np.arange(5, dtype=np.uint8)
    np.savez(tmp_path / "c.npz", a=a, b=b, meta="{}")
    mapped = script.memmap_npz(tmp_path / "c.npz")
    assert isinstance(mapped["a"], np.memmap) and np.array_equal(mapped["a"], a) and np.array_equal(mapped["b"], b)
    np.savez_compressed(tmp_path / "z.npz", a=a)
    with pytest.raises(SystemExit, match=r"z\.npz: a\.npy is compressed"):
        script.memmap_npz(tmp_path / "z.npz")


def test_a_missing_cache_is_one_line_naming_it(script, tmp_path, monkeypatch):
    monkeypatch.setattr(sys, "argv", ["window_coverage.py", str(tmp_path / "none.npz")])
    with pytest.raises(SystemExit, match=r"none\.npz: no such cache"):
        script.main()
