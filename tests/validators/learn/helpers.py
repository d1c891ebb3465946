"""Synthetic clips whose class shows only in their motion: flow drifts in a class's direction."""

from __future__ import annotations

import math

import numpy as np

from phav_validators.learn.data import Clip, ClipSet


def motion_clips(
    n_classes: int = 6, per_class: int = 20, *, frames: int = 12, size=(32, 24), source: str = "virtual", seed: int = 0
) -> ClipSet:
    """Clips of random RGB noise; in a central patch (a mover on a still background) class
    c's flow points at angle π(c + ½)/n − π/2 (plus noise; rightwards, so that a
    horizontal flip, u → −u, never turns one class into another), each clip played by one
    of 10 actors and one of 3 motions per class."""
    rng = np.random.Generator(np.random.PCG64(seed))
    w, h = size
    clips = []
    for c in range(n_classes):
        for k in range(per_class):
            angle = math.pi * (c + 0.5) / n_classes - math.pi / 2
            flow = rng.normal(0.0, 0.3, (frames, h, w, 2))
            patch = flow[:, h // 4 : 3 * h // 4, w // 4 : 3 * w // 4]
            patch[..., 0] += 1.5 * math.cos(angle)
            patch[..., 1] += 1.5 * math.sin(angle)
            rgb = rng.integers(0, 256, (frames, h, w, 3), dtype=np.uint8)
            groups = {"actor": f"model_{k % 10:02d}", "motion": f"class{c}_motion{k % 3}"}
            clips.append(Clip(f"{source}{c:02d}{k:03d}", c, source, rgb, flow.astype(np.float16), groups))
    return ClipSet(source, [f"class{c}" for c in range(n_classes)], clips)


def write_video(path, frames: np.ndarray, fps: int = 25) -> None:
    """Frames (T, H, W, 3) uint8 → an MPEG-4 AVI (PyAV, no system ffmpeg)."""
    import av

    path.parent.mkdir(parents=True, exist_ok=True)
    with av.open(str(path), "w") as container:
        stream = container.add_stream("mpeg4", rate=fps)
        stream.width, stream.height = frames.shape[2], frames.shape[1]
        stream.pix_fmt = "yuv420p"
        for image in frames:
            for packet in stream.encode(av.VideoFrame.from_ndarray(image, format="rgb24")):
                container.mux(packet)
        for packet in stream.encode():
            container.mux(packet)


def moving_square(direction: tuple[int, int], frames: int = 10, size=(64, 48), seed: int = 0) -> np.ndarray:
    """A bright square on noise moving ``direction`` pixels per frame."""
    rng = np.random.Generator(np.random.PCG64(seed))
    w, h = size
    out = np.empty((frames, h, w, 3), np.uint8)
    background = rng.integers(0, 60, (h, w, 3), dtype=np.uint8)
    for t in range(frames):
        out[t] = background
        x = (w // 2 - 8 + direction[0] * t) % (w - 16)
        y = (h // 2 - 8 + direction[1] * t) % (h - 16)
        out[t, y : y + 16, x : x + 16] = 230
    return out


UCF_CLASSES = ("ApplyEyeMakeup", "Biking", "CliffDiving")
HMDB_CLASSES = ("brush_hair", "cartwheel", "climb")
_DIRECTIONS = ((2, 0), (0, 2), (-2, -2))


def ucf101_folder(root, groups: int = 3, clips: int = 2):
    """A tiny UCF-101: ROOT/UCF-101/<Class>/v_<Class>_gNN_cMM.avi and ROOT/ucfTrainTestlist/
    (classInd, trainlist0N, testlist0N; group 1 tested, the rest trained, as the official
    splits hold out groups)."""
    videos = root / "UCF-101"
    lists = root / "ucfTrainTestlist"
    lists.mkdir(parents=True, exist_ok=True)
    (lists / "classInd.txt").write_text("".join(f"{i + 1} {c}\n" for i, c in enumerate(UCF_CLASSES)))
    train, test = [], []
    for i, cls in enumerate(UCF_CLASSES):
        for g in range(1, groups + 1):
            for c in range(1, clips + 1):
                rel = f"{cls}/v_{cls}_g{g:02d}_c{c:02d}.avi"
                write_video(videos / rel, moving_square(_DIRECTIONS[i], seed=g * 10 + c))
                (test if g == 1 else train).append(rel)
    for k in (1, 2, 3):
        (lists / f"trainlist0{k}.txt").write_text("".join(f"{r} {UCF_CLASSES.index(r.split('/')[0]) + 1}\n"
                                                         for r in train))  # fmt: skip
        (lists / f"testlist0{k}.txt").write_text("".join(f"{r}\n" for r in test))
    return videos


def hmdb51_folder(root, clips: int = 3):
    """A tiny HMDB-51: ROOT/hmdb51/<class>/<name>.avi and ROOT/testTrainMulti_7030_splits/
    <class>_test_split<N>.txt (1 train, 2 test, 0 unused)."""
    videos = root / "hmdb51"
    lists = root / "testTrainMulti_7030_splits"
    lists.mkdir(parents=True, exist_ok=True)
    for i, cls in enumerate(HMDB_CLASSES):
        names = [f"{cls}_clip{c}_f_cm_np1_fr_med_{c}.avi" for c in range(clips + 1)]
        for c, name in enumerate(names):
            write_video(videos / cls / name, moving_square(_DIRECTIONS[i], seed=100 + c))
        marks = ["2"] + ["1"] * (clips - 1) + ["0"]
        text = "".join(f"{n} {m}\n" for n, m in zip(names, marks, strict=True))
        for k in (1, 2, 3):
            (lists / f"{cls}_test_split{k}.txt").write_text(text)
    return videos
