"""Pictures of the realism check: a judged frame beside its ground truth, in the judges' colours."""

from __future__ import annotations

from typing import Any

import cv2
import numpy as np

from phav_spec.judge_classes import JudgeClasses
from phav_spec.metadata import JOINT_ORDER
from phav_spec.vocab import PIXEL_CLASSES

#: The Cityscapes benchmark's colours, by trainId.
CITYSCAPES_COLOURS = (
    (128, 64, 128), (244, 35, 232), (70, 70, 70), (102, 102, 156), (190, 153, 153), (153, 153, 153),
    (250, 170, 30), (220, 220, 0), (107, 142, 35), (152, 251, 152), (70, 130, 180), (220, 20, 60), (255, 0, 0),
    (0, 0, 142), (0, 0, 70), (0, 60, 100), (0, 80, 100), (0, 0, 230), (119, 11, 32),
)  # fmt: skip
#: Pixels a judge does not judge.
NOT_JUDGED = (48, 48, 48)


def voc_colours(n: int = 21) -> np.ndarray:
    """PASCAL VOC's colour map: the bits of a class id spread over R, G and B."""
    out = np.zeros((n, 3), np.uint8)
    for i in range(n):
        c, r, g, b = i, 0, 0, 0
        for shift in range(7, -1, -1):
            r |= (c & 1) << shift
            g |= ((c >> 1) & 1) << shift
            b |= ((c >> 2) & 1) << shift
            c >>= 3
        out[i] = r, g, b
    return out


def palette(judge: JudgeClasses) -> np.ndarray:
    """(labels + 1, 3): each judge class's colour, then NOT_JUDGED."""
    colours = voc_colours(len(judge.labels)) if judge.judge == "pascal_voc" else np.array(CITYSCAPES_COLOURS, np.uint8)
    return np.vstack([colours, np.array([NOT_JUDGED], np.uint8)])


def expected_labels(classes: np.ndarray, judge: JudgeClasses) -> np.ndarray:
    """Our class ids → the judge's label each should get (len(labels): void). Our classes a
    judge has no class for are void where its benchmark leaves them out (Cityscapes), and its
    background where an answer there counts against it (VOC)."""
    lut = np.full(256, len(judge.labels) if judge.void_unjudged else judge.label_id("background"), np.int64)
    for name, info in PIXEL_CLASSES.items():
        if name in judge.judged_as:
            lut[info.class_id] = judge.label_id(judge.judged_as[name])
    return lut[classes]


def _joints_drawn(rgb: np.ndarray, person: dict[str, Any] | None, judged: dict[str, Any] | None) -> np.ndarray:
    """The frame with the protagonist's box (white), its joints (green), the detector's person
    region (yellow) and the landmark model's joints (red)."""
    out = rgb.copy()
    if person is None or person["bbox2d"][0] is None:
        return out
    x0, y0, x1, y1 = (round(v) for v in person["bbox2d"])
    cv2.rectangle(out, (x0, y0), (x1 - 1, y1 - 1), (255, 255, 255), 1)
    joints = np.array(person["joints2d"], dtype=float).reshape(-1, 2)
    for j in range(len(JOINT_ORDER)):
        if person["visible"][j] and np.all(np.isfinite(joints[j])):
            cv2.circle(out, tuple(int(v) for v in joints[j]), 3, (0, 220, 0), -1)
    if judged is not None:
        if judged["found"] is not None:  # the detector's person region, as MediaPipe builds it
            rx0, ry0, rx1, ry1 = (round(v) for v in judged["found"].region())
            cv2.rectangle(out, (rx0, ry0), (rx1, ry1), (255, 220, 0), 1)
        for x, y in judged["landmarks"].joints.values():
            cv2.drawMarker(out, (int(x), int(y)), (255, 40, 40), cv2.MARKER_CROSS, 7, 2)
    return out


def example_sheet(example: dict[str, Any], judges: dict[str, JudgeClasses]) -> np.ndarray:
    """One row: the frame with joints (ours green, the landmark model's red), then per
    segmenter that judged it what it should answer beside what it answered."""
    tiles = [_joints_drawn(example["rgb"], example["person"], example["judged"])]
    for name, judge in judges.items():
        answer = example.get(name)
        if answer is None:
            continue
        colours = palette(judge)
        tiles += [colours[expected_labels(example["classes"], judge)], colours[answer]]
    gap = np.full((tiles[0].shape[0], 4, 3), 255, np.uint8)
    row = [tiles[0]]
    for t in tiles[1:]:
        row += [gap, t]
    return np.hstack(row)
