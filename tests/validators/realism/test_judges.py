"""The judges' decoding on rendered frames with known ground truth: the detector finds a
large person, the landmark model lands the joints on ours, the segmenters label people."""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pytest

from phav_spec.errors import PhavUserError
from phav_spec.metadata import JOINT_ORDER
from phav_validators.realism.judges import (
    JUDGE_MODELS,
    MODELS_DIR,
    Crop,
    file_sha256,
    load_judges,
    model_file,
    ssd_anchor_centres,
    upright_crop,
)
from tests.helpers import written_frames

pytest.importorskip("ai_edge_litert")

J = {name: i for i, name in enumerate(JOINT_ORDER)}


@pytest.fixture(scope="module")
def judges():
    return load_judges()


def _height(person) -> float:
    box = person["bbox2d"]
    return -1.0 if box[0] is None else box[3] - box[1]


@pytest.fixture(scope="module")
def large_people(small_dataset):
    """(RGB, protagonist row) of every frame of the shared dataset whose protagonist is over
    80 px tall (all 18 frames of its three videos), in key order."""
    frames = written_frames(small_dataset)
    found = [(frames[k]["rgb.png"], frames[k]["json"]["people"][0]) for k in sorted(frames)]
    found = [(rgb, p) for rgb, p in found if p["role"] == "protagonist" and _height(p) > 80]
    assert len(found) >= 12
    return found


@pytest.fixture(scope="module")
def large_person(large_people):
    """The frame where the protagonist is tallest."""
    return max(large_people, key=lambda f: _height(f[1]))


def test_the_shipped_models_are_the_published_files():
    for model in JUDGE_MODELS.values():
        assert file_sha256(MODELS_DIR / model.file) == model.sha256
        assert (MODELS_DIR / model.licence).is_file()


def test_anchors_are_mediapipes_grid():
    centres = ssd_anchor_centres(224)
    assert centres.shape == (28 * 28 * 2 + 14 * 14 * 2 + 7 * 7 * 6, 2)
    assert np.allclose(centres[0], [0.5 / 28, 0.5 / 28]) and np.allclose(centres[1], centres[0])
    assert np.allclose(centres[2], [1.5 / 28, 0.5 / 28])  # row by row
    assert np.allclose(centres[-1], [6.5 / 7, 6.5 / 7])


def test_a_crop_maps_back_to_the_frame_it_was_cut_from():
    crop = Crop((100.0, 80.0), 64.0, 0.7)
    frame = np.zeros((160, 200, 3), np.uint8)
    frame[70:74, 108:112] = 255  # a bright dot at (110, 72) in frame pixels
    weight = crop.cut(frame, 256)[..., 0].astype(float)
    ys, xs = np.indices(weight.shape) + 0.5  # pixel centres at +0.5, as in joints2d
    centroid = np.array([[(xs * weight).sum(), (ys * weight).sum()]]) / weight.sum()
    assert np.allclose(crop.to_frame(centroid, 256), [[110, 72]], atol=0.05)


def test_an_upright_crop_turns_a_lying_person_upright():
    box = (0.0, 0.0, 100.0, 40.0)
    assert upright_crop(box, np.array([20.0, 20.0]), np.array([20.0, 0.0])).angle == 0.0
    lying = upright_crop(box, np.array([20.0, 20.0]), np.array([80.0, 20.0]))  # shoulders to the right
    assert lying.angle == pytest.approx(np.pi / 2) and lying.side == pytest.approx(125.0)
    up = lying.to_frame(np.array([[128.0, 0.0]]), 256)[0] - lying.centre  # the crop's top, in the frame
    assert up[0] > 0 and abs(up[1]) < 1e-9


def test_the_detector_finds_a_large_person(judges, large_person):
    rgb, person = large_person
    x0, y0, x1, y1 = person["bbox2d"]
    found = [d for d in judges.detector.detections(rgb) if x0 <= d.hip_centre[0] <= x1 and y0 <= d.hip_centre[1] <= y1]
    assert found and found[0].score > 0.5
    hips = np.array(person["joints2d"]).reshape(13, 2)[[J["left_hip"], J["right_hip"]]].mean(axis=0)
    assert np.linalg.norm(np.array(found[0].hip_centre) - hips) < 0.2 * (y1 - y0)


def test_the_landmark_model_lands_the_wrists_on_the_wrists(judges, large_people):
    errors: dict[str, list[float]] = {}
    for rgb, person in large_people:
        joints = np.array(person["joints2d"]).reshape(13, 2)
        hips = joints[[J["left_hip"], J["right_hip"]]].mean(axis=0)
        shoulders = joints[[J["left_shoulder"], J["right_shoulder"]]].mean(axis=0)
        answer = judges.landmarks.landmarks(rgb, upright_crop(tuple(person["bbox2d"]), hips, shoulders))
        assert answer.presence > 0.5
        for name, xy in answer.joints.items():
            if person["visible"][J[name]]:
                errors.setdefault(name, []).append(np.linalg.norm(np.array(xy) - joints[J[name]]) / _height(person))
    wrists = errors["left_wrist"] + errors["right_wrist"]
    assert len(wrists) >= 12 and np.median(wrists) < 0.1, wrists  # in box heights
    every = np.concatenate([np.array(e) for e in errors.values()])
    assert (every < 0.2).mean() > 0.9


def test_the_voc_segmenter_labels_the_person_person(judges, large_person, small_dataset):
    rgb, person = large_person
    labels = judges.segmenters["pascal_voc"].labels(rgb)
    assert labels.shape == rgb.shape[:2]
    x0, y0, x1, y1 = (round(v) for v in person["bbox2d"])
    person_id = judges.segmenters["pascal_voc"].classes.label_id("person")
    inside = (labels[y0:y1, x0:x1] == person_id).mean()
    outside = (labels == person_id).sum() - (labels[y0:y1, x0:x1] == person_id).sum()
    assert inside > 0.2 and outside < (labels[y0:y1, x0:x1] == person_id).sum()


def test_judging_twice_gives_the_same_answer(judges, large_person):
    rgb, _ = large_person
    first = judges.segmenters["cityscapes"].labels(rgb)
    again = load_judges.__wrapped__().segmenters["cityscapes"].labels(rgb)  # a fresh interpreter
    assert np.array_equal(first, again)
    assert judges.detector.detections(rgb) == judges.detector.detections(rgb)


def test_a_missing_or_corrupt_model_is_one_clear_error(tmp_path: Path):
    with pytest.raises(PhavUserError, match=r"missing model file pose_detection\.tflite"):
        model_file("pose_detector", tmp_path)
    for model in JUDGE_MODELS.values():
        shutil.copy(MODELS_DIR / model.file, tmp_path)
    bad = tmp_path / "pose_detection.tflite"
    bad.write_bytes(bad.read_bytes()[:5000])
    with pytest.raises(PhavUserError, match="not a TensorFlow Lite model"):
        load_judges.__wrapped__(tmp_path)
