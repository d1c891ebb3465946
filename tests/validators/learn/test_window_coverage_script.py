"""docs/measure/window_coverage.py: where the crop placed on the motion lands, measured
against the body-part frames (docs/experiments/learnability.md, "Stored size and crop")."""

from __future__ import annotations

import sys

import numpy as np
import pytest

from phav_spec.manifest import load_manifest
from phav_spec.recipe_table import read_recipe_table
from phav_spec.vocab import PIXEL_CLASSES, PixelGroup
from phav_validators.learn.data import Clip
from tests.validators.learn.helpers import measure_script


@pytest.fixture(scope="module")
def script():
    return measure_script("window_coverage")


def _clip(mover: tuple[int, int], body: tuple[int, int], frames: int = 12, size=(32, 24)) -> tuple[Clip, np.ndarray]:
    """A clip whose only motion is an 8×8 patch at ``mover`` (top-left y, x), and its body
    mask: its only person is an 8×8 patch at ``body``."""
    w, h = size
    flow = np.zeros((frames, h, w, 2), np.float16)
    flow[:, mover[0] : mover[0] + 8, mover[1] : mover[1] + 8, 0] = 2.0
    person = np.zeros((frames, h, w), bool)
    person[:, body[0] : body[0] + 8, body[1] : body[1] + 8] = True
    return Clip("c", 0, "virtual", np.zeros((frames, h, w, 3), np.uint8), flow), person


def test_the_window_holds_the_person_who_moves_and_misses_one_who_stands_still(script):
    # the person is what moves, in a corner: the motion window holds all of them, a centred one none
    moving, centred, default = script.body_shares(*_clip(mover=(0, 0), body=(0, 0)), crop=0.5)
    assert moving == 1.0 and centred == 0.0 and 0.0 < default < 1.0
    # the person stands near the centre while a car moves in a corner: the window misses them
    moving, centred, default = script.body_shares(*_clip(mover=(0, 0), body=(26, 36), size=(64, 48)), crop=0.5)
    assert moving == 0.0 and centred == 1.0 and default == 1.0
    # no person in the tested frames: nothing to measure
    clip, person = _clip(mover=(0, 0), body=(0, 0))
    assert script.body_shares(clip, np.zeros_like(person), crop=0.5) is None


def test_the_motion_window_finds_the_mover_not_the_panning_camera(script):
    clip, _ = _clip(mover=(0, 0), body=(0, 0), frames=8, size=(64, 48))
    clip.flow[...] = (0.8, -0.4)  # the camera pans
    clip.flow[:, 30:40, 44:52] = (2.5, -0.4)  # a mover right of centre, low
    frames = np.arange(6).reshape(3, 2)
    y0, x0 = script.motion_window(clip, frames, (16, 16))
    assert y0 <= 30 and y0 + 16 >= 40 and x0 <= 44 and x0 + 16 >= 52
    still, _ = _clip(mover=(0, 0), body=(0, 0), frames=8, size=(64, 48))
    still.flow[...] = 0.0
    assert script.motion_window(still, frames, (16, 16)) == (16, 24)  # nothing moves: the centre


def test_a_person_is_every_body_part_and_joint_of_either_side_and_nothing_else(script):
    names = ["left_hand", "right_wrist", "neck", "right_knee", "chest", "head", "sky", "ball"]
    image = np.array([[PIXEL_CLASSES[n].rgb for n in names] + [(0, 0, 0), (1, 2, 3)]], np.uint8)
    assert script.body_mask(image)[0].tolist() == [True] * 6 + [False] * 4
    people = [c.rgb for _, c in PIXEL_CLASSES.items() if c.group in (PixelGroup.HUMAN_PARTS, PixelGroup.HUMAN_JOINTS)]
    assert len(people) == 27 and script.body_mask(np.array([people], np.uint8)).all()


def test_the_people_are_read_from_the_semantic_frames_at_the_stored_size(script, phav):
    import cv2

    from phav_validators.checks.tarsafe import TarScan, iter_members

    shard = sorted(phav.glob("*.tar"))[0]
    name, data = next((n, d) for n, d in iter_members(shard, TarScan()) if n.endswith("00004.seg.png"))
    video = name.split("/")[0]
    seg = cv2.imdecode(np.frombuffer(data, np.uint8), cv2.IMREAD_UNCHANGED)[..., ::-1]
    small = cv2.resize(seg, (85, 64), interpolation=cv2.INTER_NEAREST)
    by_colour = {c.rgb: c.group for _, c in PIXEL_CLASSES.items()}
    person = (PixelGroup.HUMAN_PARTS, PixelGroup.HUMAN_JOINTS)
    expected = np.array([[by_colour.get(tuple(int(v) for v in px)) in person for px in row] for row in small])
    videos = sorted(v.video_id for v in load_manifest(phav / "manifest.json").videos)
    bodies = script.read_bodies(phav, videos, (85, 64))
    assert sorted(bodies) == videos and np.array_equal(bodies[video][4], expected)
    recipes = {r.video_id: r for r in read_recipe_table(phav / "recipes.parquet").recipes()}
    # every video at its length, and every protagonist shows
    assert all(b.shape == (recipes[v].n_frames, 64, 85) and b.any() for v, b in bodies.items())
    with pytest.raises(SystemExit, match=r"no manifest\.json"):
        script.read_bodies(phav / "none", videos, (85, 64))


def test_a_learn_experiments_cache_is_measured_against_its_datasets_people(script, phav, monkeypatch, capsys):
    cache = phav.parent / f"{phav.name}+1.clips-85x64-gt.npz"
    measure_script("learn_experiments").cached_clips([phav], (85, 64), "gt", workers=1)
    capsys.readouterr()  # what reading the dataset printed
    monkeypatch.setattr(sys, "argv", ["window_coverage.py", str(cache), "--crop", "0.5", "--every", "1"])
    script.main()
    out = capsys.readouterr().out.splitlines()
    assert out[0].startswith("3 clips (every 1th with a person), crop 0.5 of ")
    assert len(out) == 6 and out[3].startswith("| on the most motion (0.5) | ")


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
