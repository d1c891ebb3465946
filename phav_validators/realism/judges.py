"""Models trained on real photographs, run on our frames with the TensorFlow Lite runtime.

Four judges (Apache-2.0, shipped in ``models/`` with their licences): MediaPipe's BlazePose
person detector and full landmark model, DeepLabV3-MobileNetV2 on PASCAL VOC and a DeepLab
on Cityscapes. Each wrapper takes an RGB frame (H, W, 3) uint8 and returns its answer in the
frame's pixels; ``ai_edge_litert`` is imported on first use (the ``phav[realism]`` extra).
"""

from __future__ import annotations

import contextlib
import hashlib
import math
import os
import sys
from collections.abc import Iterator, Mapping
from dataclasses import dataclass
from functools import cache
from pathlib import Path
from typing import Any

import cv2
import numpy as np

from phav_spec.errors import PhavUserError
from phav_spec.judge_classes import JUDGE_CLASSES, JudgeClasses

#: The models shipped with the package.
MODELS_DIR = Path(__file__).parent / "models"


@dataclass(frozen=True)
class JudgeModel:
    """One model file: what it is, where it comes from, and the sha256 of the shipped copy."""

    name: str
    file: str
    trained_on: str
    source: str
    licence: str
    sha256: str


JUDGE_MODELS: Mapping[str, JudgeModel] = {
    m.name: m
    for m in (
        JudgeModel("pose_detector", "pose_detection.tflite", "BlazePose person detector (MediaPipe)",
                   "mediapipe 0.10.21, mediapipe/modules/pose_detection/", "LICENSE-mediapipe",
                   "9ba9dd3d42efaaba86b4ff0122b06f29c4122e756b329d89dca1e297fd8f866c"),
        JudgeModel("pose_landmarks", "pose_landmark_full.tflite", "BlazePose GHUM landmarks, full (MediaPipe)",
                   "mediapipe 0.10.21, mediapipe/modules/pose_landmark/", "LICENSE-mediapipe",
                   "e9a5c5cb17f736fafd4c2ec1da3b3d331d6edbe8a0d32395855aeb2cdfd64b9f"),
        JudgeModel("pascal_voc", "deeplabv3_mnv2_pascal_quant.tflite", "DeepLabV3-MobileNetV2, PASCAL VOC 2012",
                   "google-coral/test_data", "LICENSE-coral-test-data",
                   "350af47fd346ea6d74b58833a351f583ba860e9806ec5bd292ff8d8f1f249398"),
        JudgeModel("cityscapes", "deeplab_mobilenet_edgetpu_slim_cityscapes_quant.tflite",
                   "DeepLab MobileNet-EdgeTPU slim, Cityscapes", "google-coral/test_data",
                   "LICENSE-coral-test-data", "322fe29945cb1693f426952f2a330ab67ea5678545ddee6f2548e0cfd0ca03e5"),
    )
}  # fmt: skip


def file_sha256(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def model_file(name: str, models_dir: Path | None = None) -> tuple[Path, str]:
    """The file of judge ``name`` in ``models_dir`` and its sha256 (default: the shipped
    copies, whose sha256 must match: a changed shipped file is corrupt, not another version)."""
    model = JUDGE_MODELS[name]
    path = (models_dir or MODELS_DIR) / model.file
    if not path.is_file():
        raise PhavUserError(f"missing model file {model.file} ({model.trained_on})", source=str(path.parent),
                            field="--realism-models")  # fmt: skip
    digest = file_sha256(path)
    if models_dir is None and digest != model.sha256:
        raise PhavUserError("corrupt model file (its sha256 is not the shipped one's); reinstall phav",
                            source=str(path))  # fmt: skip
    return path, digest


@contextlib.contextmanager
def _native_stderr_silenced() -> Iterator[None]:
    """File descriptor 2 points at /dev/null inside the block (native libraries write there
    directly, past ``sys.stderr``); Python's own ``sys.stderr`` is flushed first."""
    sys.stderr.flush()
    saved = os.dup(2)
    try:
        with open(os.devnull, "w") as null:
            os.dup2(null.fileno(), 2)
        yield
    finally:
        os.dup2(saved, 2)
        os.close(saved)


def _interpreter(path: Path, threads: int) -> Any:
    try:
        from ai_edge_litert.interpreter import Interpreter
    except ImportError:
        raise PhavUserError("the realism check needs ai-edge-litert: pip install 'phav[realism]'",
                            field="--checks") from None  # fmt: skip
    try:
        with _native_stderr_silenced():  # the runtime logs "INFO: Created … delegate" on fd 2
            interpreter = Interpreter(model_path=str(path), num_threads=threads)
            interpreter.allocate_tensors()
    except (ValueError, RuntimeError) as e:
        raise PhavUserError(f"not a TensorFlow Lite model ({str(e).splitlines()[0]})", source=str(path)) from None
    return interpreter


class _Model:
    """A TFLite interpreter with one input; ``_run`` returns the outputs by position."""

    #: The shape of each output the judge reads, first ones first, without the batch axis
    #: (None: any length there): another model under the file's name is refused on loading.
    OUTPUTS: tuple[tuple[int | None, ...], ...] = ()

    def __init__(self, path: Path, threads: int):
        self.path = path
        self._interp = _interpreter(path, threads)
        inputs, outputs = self._interp.get_input_details(), self._interp.get_output_details()
        shapes = [tuple(int(n) for n in d["shape"][1:]) for d in outputs]
        square = len(inputs) == 1 and len(inputs[0]["shape"]) == 4 and inputs[0]["shape"][1] == inputs[0]["shape"][2]
        fits = len(shapes) >= len(self.OUTPUTS) and all(
            len(got) == len(want) and all(w is None or g == w for g, w in zip(got, want, strict=True))
            for got, want in zip(shapes, self.OUTPUTS, strict=False)
        )
        if not (square and fits):
            given = [tuple(int(n) for n in d["shape"]) for d in inputs]
            raise PhavUserError(f"not the {type(self).__name__} model this check reads (inputs {given}, "
                                f"outputs {shapes})", source=str(path))  # fmt: skip
        self._input = inputs[0]
        self._outputs = [d["index"] for d in outputs]
        self.input_size = int(self._input["shape"][2]), int(self._input["shape"][1])

    def _run(self, tensor: np.ndarray) -> list[np.ndarray]:
        self._interp.set_tensor(self._input["index"], tensor[None].astype(self._input["dtype"], copy=False))
        self._interp.invoke()
        return [self._interp.get_tensor(i)[0] for i in self._outputs]


@dataclass(frozen=True)
class Letterbox:
    """A frame scaled to fit a square model input, padded equally on both sides."""

    scale: float
    pad: tuple[float, float]
    size: tuple[int, int]  # the scaled frame (width, height)

    @staticmethod
    def fit(frame_size: tuple[int, int], side: int, *, centred: bool) -> Letterbox:
        w, h = frame_size
        scale = side / max(w, h)
        size = round(w * scale), round(h * scale)
        pad = ((side - size[0]) / 2, (side - size[1]) / 2) if centred else (0.0, 0.0)
        return Letterbox(scale, pad, size)

    def apply(self, rgb: np.ndarray, side: int, fill: int) -> np.ndarray:
        scaled = cv2.resize(rgb, self.size, interpolation=cv2.INTER_LINEAR)
        out = np.full((side, side, 3), fill, np.uint8)
        x, y = int(self.pad[0]), int(self.pad[1])
        out[y : y + self.size[1], x : x + self.size[0]] = scaled
        return out

    def to_frame(self, xy: np.ndarray) -> np.ndarray:
        """Input pixels → frame pixels."""
        return (xy - np.array([int(self.pad[0]), int(self.pad[1])])) / self.scale


class Segmenter(_Model):
    """A DeepLab trained on real photographs: a label per frame pixel, in ``classes.labels``."""

    OUTPUTS = ((None, None),)  # a label map

    def __init__(self, path: Path, classes: JudgeClasses, threads: int = 1):
        super().__init__(path, threads)
        self.classes = classes

    def labels(self, rgb: np.ndarray) -> np.ndarray:
        """(H, W) uint8 judge class ids: the frame scaled to the input's longer side, the rest
        padded with mid-grey (the input's zero), the answer cut out and scaled back."""
        h, w = rgb.shape[:2]
        side = self.input_size[0]
        box = Letterbox.fit((w, h), side, centred=False)
        (out,) = self._run(box.apply(rgb, side, 128))
        cut = out[: box.size[1], : box.size[0]].astype(np.uint8)
        return cv2.resize(cut, (w, h), interpolation=cv2.INTER_NEAREST)


def ssd_anchor_centres(side: int = 224, strides: tuple[int, ...] = (8, 16, 32, 32, 32)) -> np.ndarray:
    """(N, 2) anchor centres in [0, 1] of MediaPipe's SSD anchors with fixed size: layers of
    equal stride share a grid; each layer puts two anchors (aspect 1 and the interpolated
    scale) on every cell, row by row."""
    centres = []
    i = 0
    while i < len(strides):
        j = i
        while j < len(strides) and strides[j] == strides[i]:
            j += 1
        n = math.ceil(side / strides[i])
        per_cell = 2 * (j - i)
        ys, xs = np.meshgrid((np.arange(n) + 0.5) / n, (np.arange(n) + 0.5) / n, indexing="ij")
        grid = np.stack([xs.ravel(), ys.ravel()], axis=1)
        centres.append(np.repeat(grid, per_cell, axis=0))
        i = j
    return np.concatenate(centres)


@dataclass(frozen=True)
class PersonDetection:
    """One BlazePose detection in frame pixels: its score and the person region that
    MediaPipe builds from it — a circle around the hip centre through the scale keypoint."""

    score: float
    hip_centre: tuple[float, float]
    radius: float

    def region(self, margin: float = 1.25) -> tuple[float, float, float, float]:
        """The square person region (x0, y0, x1, y1), upright."""
        r = self.radius * margin
        x, y = self.hip_centre
        return x - r, y - r, x + r, y + r


class PoseDetector(_Model):
    """BlazePose's person detector on the whole frame (letterboxed to 224², values in [−1, 1])."""

    OUTPUTS = ((None, 12), (None, 1))  # per anchor: its box and keypoints, its score

    def __init__(self, path: Path, threads: int = 1):
        super().__init__(path, threads)
        self.anchors = ssd_anchor_centres(self.input_size[0])

    def detections(self, rgb: np.ndarray, min_score: float = 0.5) -> list[PersonDetection]:
        """Every anchor scoring at least ``min_score``, best first (no suppression: a caller
        asks whether any of them fits a person it knows)."""
        h, w = rgb.shape[:2]
        side = self.input_size[0]
        box = Letterbox.fit((w, h), side, centred=True)
        tensor = box.apply(rgb, side, 0).astype(np.float32) / 127.5 - 1.0
        raw, logits = self._run(tensor)
        scores = 1.0 / (1.0 + np.exp(-np.clip(logits[:, 0].astype(np.float64), -100, 100)))
        order = [i for i in np.argsort(-scores, kind="stable") if scores[i] >= min_score]
        found = []
        for i in order:
            keypoints = raw[i, 4:8].reshape(2, 2) + self.anchors[i] * side  # hip centre, scale point
            hip, scale = box.to_frame(keypoints)
            found.append(PersonDetection(float(scores[i]), (float(hip[0]), float(hip[1])),
                                         float(np.linalg.norm(scale - hip))))  # fmt: skip
        return found


#: Our joints (``phav_spec.metadata.JOINT_ORDER``) → BlazePose landmark ids. BlazePose has no
#: neck: the neck is not judged (the shoulders' midpoint is not where our neck joint sits).
BLAZEPOSE_JOINTS: Mapping[str, int] = {
    "left_shoulder": 11, "right_shoulder": 12, "left_elbow": 13, "right_elbow": 14,
    "left_wrist": 15, "right_wrist": 16, "left_hip": 23, "right_hip": 24,
    "left_knee": 25, "right_knee": 26, "left_ankle": 27, "right_ankle": 28,
}  # fmt: skip


@dataclass(frozen=True)
class Crop:
    """A square, rotated crop of a frame: ``centre`` and ``side`` in frame pixels, ``angle``
    (radians) the turn that stands the person upright."""

    centre: tuple[float, float]
    side: float
    angle: float

    def matrix(self, size: int) -> np.ndarray:
        """2×3 affine map crop pixels → frame pixels."""
        s = self.side / size
        c, si = math.cos(self.angle), math.sin(self.angle)
        rot = np.array([[c, -si], [si, c]]) * s
        offset = np.array(self.centre) - rot @ np.array([size / 2, size / 2])
        return np.hstack([rot, offset[:, None]])

    def cut(self, rgb: np.ndarray, size: int) -> np.ndarray:
        m = self.matrix(size)
        # OpenCV puts pixel centres on integers, the metadata and the models at +0.5.
        m[:, 2] += m[:, :2] @ np.array([0.5, 0.5]) - 0.5
        return cv2.warpAffine(rgb, m, (size, size), flags=cv2.INTER_LINEAR | cv2.WARP_INVERSE_MAP,
                              borderMode=cv2.BORDER_CONSTANT, borderValue=(0, 0, 0))  # fmt: skip

    def to_frame(self, xy: np.ndarray, size: int) -> np.ndarray:
        m = self.matrix(size)
        return xy @ m[:, :2].T + m[:, 2]


def upright_crop(box: tuple[float, float, float, float], hips: np.ndarray, shoulders: np.ndarray,
                 margin: float = 1.25) -> Crop:  # fmt: skip
    """The square crop around a person's box, turned so that its hips-to-shoulders direction
    points up (as MediaPipe turns its crops); unturned when either midpoint is unknown."""
    x0, y0, x1, y1 = box
    side = max(x1 - x0, y1 - y0) * margin
    up = shoulders - hips
    angle = 0.0
    if np.all(np.isfinite(up)) and np.linalg.norm(up) > 0:
        angle = math.atan2(up[0], -up[1])  # zero when the shoulders are straight above the hips
    return Crop(((x0 + x1) / 2, (y0 + y1) / 2), float(side), angle)


@dataclass(frozen=True)
class Landmarks:
    """BlazePose's answer for one crop: our judged joints in frame pixels, each with its
    visibility (0–1), and the pose's presence score."""

    joints: Mapping[str, tuple[float, float]]
    visibility: Mapping[str, float]
    presence: float


def _sigmoid(x: np.ndarray) -> np.ndarray:
    return 1.0 / (1.0 + np.exp(-np.clip(x.astype(np.float64), -100, 100)))


class PoseLandmarks(_Model):
    """BlazePose GHUM's full landmark model on a person crop (256², values in [0, 1])."""

    OUTPUTS = ((195,), (1,))  # 39 landmarks × 5 values, the person's presence

    def landmarks(self, rgb: np.ndarray, crop: Crop) -> Landmarks:
        size = self.input_size[0]
        tensor = crop.cut(rgb, size).astype(np.float32) / 255.0
        raw, presence, *_ = self._run(tensor)
        points = raw.reshape(-1, 5).astype(np.float64)
        ids = list(BLAZEPOSE_JOINTS.values())
        xy = crop.to_frame(points[ids, :2], size)
        vis = _sigmoid(points[ids, 3])
        names = list(BLAZEPOSE_JOINTS)
        return Landmarks(
            {n: (float(x), float(y)) for n, (x, y) in zip(names, xy, strict=True)},
            {n: float(v) for n, v in zip(names, vis, strict=True)},
            float(presence[0]),  # already a probability
        )


@dataclass
class Judges:
    """The four judges, loaded once per process."""

    detector: PoseDetector
    landmarks: PoseLandmarks
    segmenters: dict[str, Segmenter]
    #: name → sha256 of the file that judged (the report names each model and version).
    files: dict[str, str]


@cache
def load_judges(models_dir: Path | None = None, threads: int = 1) -> Judges:
    """Every judge from ``models_dir`` (default: the shipped models)."""
    files = {name: model_file(name, models_dir) for name in JUDGE_MODELS}
    paths = {name: path for name, (path, _) in files.items()}
    return Judges(
        PoseDetector(paths["pose_detector"], threads),
        PoseLandmarks(paths["pose_landmarks"], threads),
        {name: Segmenter(paths[name], classes, threads) for name, classes in JUDGE_CLASSES.items()},
        {name: digest for name, (_, digest) in files.items()},
    )
