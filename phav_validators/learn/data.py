"""Clips for training: PHAV's read from its shards by ``phav_spec.clips.ClipReader`` (the
reader users have, so that the check and ``phav train`` see what a user's loader sees), and
real datasets in the UCF-101 and HMDB-51 folder layouts decoded with PyAV.

A clip is held in memory at the training resolution: RGB frames (uint8) and forward flow
(float16, in pixels of the stored frame). PHAV's flow is its ground truth by default; any
clip's flow can instead be estimated with OpenCV (Farneback, or TV-L1 when
opencv-contrib is installed — the paper's protocol). Labels and split groups (the actor,
the motions) travel beside the pixels and never reach the model.
"""

from __future__ import annotations

import functools
import itertools
import multiprocessing
import re
from collections.abc import Callable, Iterable, Sequence
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import cv2
import numpy as np

from phav_spec.clips import ClipReader
from phav_spec.errors import PhavUserError
from phav_spec.manifest import DatasetManifest, load_manifest
from phav_spec.recipe_table import read_recipe_table
from phav_spec.vocab import ACTIONS

if TYPE_CHECKING:
    from phav_spec.recipe_table import RecipeTable

#: How flow is obtained: the dataset's ground truth, or estimated from the RGB frames.
FLOW_SOURCES = ("gt", "farneback", "tvl1")
#: The stored frame size (width, height) unless configured otherwise: PHAV's 340×256 / 4.
DEFAULT_SIZE = (85, 64)
VIDEO_SUFFIXES = (".avi", ".mp4", ".mkv", ".webm", ".mov")


@dataclass
class Clip:
    """One video at training resolution, with its label and the groups splits hold out."""

    key: str
    label: int
    source: str  # "virtual" (PHAV) or "real"
    rgb: np.ndarray  # (T, H, W, 3) uint8
    flow: np.ndarray  # (T, H, W, 2) float16, pixels of the stored frame; 0 where invalid
    #: The groups a split holds out, by kind: the clip's members, the one that decides its
    #: side first, e.g. {"actor": (protagonist, partner), "motion": (base, blended),
    #: "background": (models...)}. A single name may be given as a string.
    groups: dict[str, tuple[str, ...]] = field(default_factory=dict)

    def __post_init__(self) -> None:
        if self.rgb.ndim != 4 or self.rgb.shape[-1] != 3 or self.rgb.dtype != np.uint8:
            raise ValueError(f"{self.key}: rgb must be (T, H, W, 3) uint8, got {self.rgb.shape} {self.rgb.dtype}")
        if self.flow.shape[:3] != self.rgb.shape[:3] or self.flow.shape[-1] != 2:
            raise ValueError(f"{self.key}: flow {self.flow.shape} does not match rgb {self.rgb.shape}")
        if len(self.rgb) == 0:
            raise ValueError(f"{self.key}: a clip needs at least one frame")
        self.groups = {kind: (m,) if isinstance(m, str) else tuple(m) for kind, m in self.groups.items()}

    @property
    def n_frames(self) -> int:
        return len(self.rgb)

    @functools.cached_property
    def flow_median(self) -> np.ndarray:
        """(T, 2) float32: each flow frame's median vector, mostly the camera's motion
        (computed once per clip, as every snippet and crop of a frame subtracts it)."""
        flat = self.flow.reshape(len(self.flow), -1, 2).astype(np.float32)
        return np.median(flat, axis=1)


@dataclass
class ClipSet:
    """Clips of one source with the names of its classes (label i is ``classes[i]``)."""

    source: str
    classes: list[str]
    clips: list[Clip]

    def __len__(self) -> int:
        return len(self.clips)


# --- frames → stored arrays --------------------------------------------------------------------


def resize_rgb(image: np.ndarray, size: tuple[int, int]) -> np.ndarray:
    """An RGB frame at ``size`` (width, height), area-averaged."""

    return cv2.resize(image, size, interpolation=cv2.INTER_AREA)


def resize_flow(flow: np.ndarray, size: tuple[int, int]) -> np.ndarray:
    """Flow (H, W, 2) in pixels → at ``size`` (width, height), vectors scaled with the image;
    NaN (invalid) counts as no motion."""

    h, w = flow.shape[:2]
    flow = np.nan_to_num(flow.astype(np.float32), nan=0.0)
    out = cv2.resize(flow, size, interpolation=cv2.INTER_AREA)
    out[..., 0] *= size[0] / w
    out[..., 1] *= size[1] / h
    return out.astype(np.float16)


def estimate_flow(frames: Sequence[np.ndarray], method: str) -> list[np.ndarray]:
    """Forward flow t→t+1 (H, W, 2) estimated from full-resolution RGB frames; the last
    frame, which has no successor, repeats the previous flow (zero for a single frame)."""

    if method == "tvl1":
        if not hasattr(cv2, "optflow"):
            raise PhavUserError(
                "TV-L1 needs opencv-contrib-python-headless (cv2.optflow); install it instead of "
                "opencv-python-headless, or use --flow farneback",
                field="--flow",
            )
        tvl1 = cv2.optflow.DualTVL1OpticalFlow_create()
    elif method != "farneback":
        raise PhavUserError(f"unknown flow estimator {method!r}; choose farneback or tvl1", field="--flow")
    grey = [cv2.cvtColor(f, cv2.COLOR_RGB2GRAY) for f in frames]
    out = []
    for a, b in itertools.pairwise(grey):
        if method == "tvl1":
            out.append(tvl1.calc(a, b, None))
        else:
            out.append(cv2.calcOpticalFlowFarneback(a, b, None, 0.5, 3, 15, 3, 5, 1.2, 0))
    h, w = grey[0].shape
    out.append(out[-1] if out else np.zeros((h, w, 2), np.float32))
    return out


def make_clip(
    key: str,
    label: int,
    source: str,
    frames: Sequence[np.ndarray],
    flows: Sequence[np.ndarray] | None,
    *,
    size: tuple[int, int],
    flow: str,
    groups: dict[str, tuple[str, ...]] | None = None,
) -> Clip:
    """A clip from full-resolution RGB frames and (ground-truth) flows, or with ``flow``
    estimated when it is not ``gt`` or no flows are given."""
    if not frames:
        raise ValueError(f"{key}: no frames")
    if flow != "gt" or flows is None:
        flows = estimate_flow(frames, "farneback" if flow == "gt" else flow)
    rgb = np.stack([resize_rgb(f, size) for f in frames])
    stored = np.stack([resize_flow(f, size) for f in flows])
    return Clip(key, label, source, rgb, stored, dict(groups or {}))


# --- PHAV datasets -----------------------------------------------------------------------------


@dataclass(frozen=True)
class _ShardTask:
    root: str
    manifest: DatasetManifest
    videos: dict[str, tuple[int, dict[str, tuple[str, ...]]]]  # video id → (label, groups)
    size: tuple[int, int]
    flow: str


def _load_shard(task: _ShardTask) -> list[Clip]:
    """The clips of one shard (``phav_spec.clips.ClipReader``: members read in place). With
    ground-truth flow both streams come resized by the reader; an estimated flow is computed
    from the full-resolution frames first."""
    cv2.setNumThreads(1)
    labels = {vid: label for vid, (label, _) in task.videos.items()}
    reader = ClipReader(task.root, manifest=task.manifest, labels=labels)
    clips = []
    try:
        for vid, (label, groups) in task.videos.items():
            if task.flow == "gt":
                c = reader.read(vid, None, ("rgb", "flow"), task.size)
                clips.append(Clip(vid, label, "virtual", c["rgb"], c["flow"].astype(np.float16), groups))
            else:
                frames = list(reader.read(vid, None, ("rgb",))["rgb"])
                clips.append(make_clip(vid, label, "virtual", frames, None, size=task.size, flow=task.flow,
                                       groups=groups))  # fmt: skip
    finally:
        reader.close()
    return clips


def load_phav(
    root: str | Path,
    *,
    size: tuple[int, int] = DEFAULT_SIZE,
    flow: str = "gt",
    videos: Iterable[str] | None = None,
    workers: int = 1,
    progress: Callable[[int], None] | None = None,
    manifest: DatasetManifest | None = None,
    table: RecipeTable | None = None,
) -> ClipSet:
    """A PHAV dataset directory's clips (or those in ``videos``), labelled by action.

    Shards are streamed in place, one per task, in ``workers`` processes. The label is the
    recipe's action, the groups its people and motions (``clip_groups``). A caller that has
    already read the manifest or the recipes table passes them in."""

    root = Path(root)
    if flow not in FLOW_SOURCES:
        raise PhavUserError(f"unknown flow source {flow!r}; choose from {', '.join(FLOW_SOURCES)}", field="--flow")
    if manifest is None:
        manifest_path = root / "manifest.json"
        if not manifest_path.exists():
            raise PhavUserError("not a PHAV dataset directory (no manifest.json)", source=str(root))
        manifest = load_manifest(manifest_path)
    if table is None:
        table = read_recipe_table(root / "recipes.parquet")
    actions = list(ACTIONS.names)
    info = {vid: (label, groups) for vid, label, groups in clip_groups(table)}
    chosen = None if videos is None else set(videos)
    tasks = []
    for shard in manifest.shards:
        wanted = {v: info[v] for v in shard.video_ids if v in info and (chosen is None or v in chosen)}
        if wanted:
            tasks.append(_ShardTask(str(root), manifest, wanted, size, flow))
    clips: list[Clip] = []
    if workers > 1 and len(tasks) > 1:
        mp = multiprocessing.get_context("spawn")
        with ProcessPoolExecutor(max_workers=workers, mp_context=mp) as pool:
            for part in pool.map(_load_shard, tasks):
                clips.extend(part)
                if progress is not None:
                    progress(len(part))
    else:
        for task in tasks:
            part = _load_shard(task)
            clips.extend(part)
            if progress is not None:
                progress(len(part))
    clips.sort(key=lambda c: c.key)
    return ClipSet("virtual", actions, clips)


def clip_groups(table: RecipeTable) -> list[tuple[str, int, dict[str, tuple[str, ...]]]]:
    """Each video's id, label and split groups from the recipes table: ``actor`` its
    performers (the protagonist's human model, then the supporting person's where the
    action has one), ``motion`` every motion it plays (base, then blended), ``background``
    the background people's models. A person drawn continuously (model ``sampled``) is
    nobody else: it is named by the video and its role. An action this phav's vocabulary
    does not know is a PhavUserError naming the table."""
    actions = {name: i for i, name in enumerate(ACTIONS.names)}
    columns = [table.column(name) for name in ("video_id", "action", "human_model", "supporting_human_model",
                                               "base_motion", "blend_motion", "background_human_models")]  # fmt: skip
    out = []
    for vid, action, lead, partner, base, blend, background in zip(*columns, strict=True):
        if action not in actions:
            raise PhavUserError(f"video {vid}: action {action!r} is not in this phav's vocabulary",
                                source=str(table.path), field="action")  # fmt: skip

        def person(model: str, role: str, vid: str = vid) -> str:
            return model if model != "sampled" else f"{vid}/{role}"

        actor = (person(lead, "protagonist"),) + ((person(partner, "supporting"),) if partner else ())
        motion = (base,) + ((blend,) if blend else ())
        crowd = tuple(person(m, f"background{i}") for i, m in enumerate(background or ()))
        out.append((vid, actions[action], {"actor": actor, "motion": motion, "background": crowd}))
    return out


# --- real datasets: UCF-101 and HMDB-51 layouts -----------------------------------------------


def decode_video(path: Path, max_frames: int | None = None) -> list[np.ndarray]:
    """A video file's frames as RGB arrays (PyAV; no system ffmpeg needed)."""
    try:
        import av  # optional extra phav[train]: only real video datasets need PyAV
    except ImportError:
        raise PhavUserError("reading videos needs PyAV: pip install 'phav[train]'", source=str(path)) from None
    frames: list[np.ndarray] = []
    try:
        with av.open(str(path)) as container:
            for frame in container.decode(video=0):
                frames.append(frame.to_ndarray(format="rgb24"))
                if max_frames is not None and len(frames) >= max_frames:
                    break
    except (av.error.FFmpegError, OSError) as e:  # type: ignore[attr-defined]
        raise PhavUserError(f"cannot decode video: {e}", source=str(path)) from None
    if not frames:
        raise PhavUserError("video has no frames", source=str(path))
    return frames


@dataclass(frozen=True)
class RealVideo:
    """One video of a real dataset: its file, class and group (UCF-101's gNN: one actor)."""

    path: Path
    label: int
    group: str


@dataclass
class RealSplit:
    """A real dataset's official split: its classes and train / test videos."""

    layout: str
    classes: list[str]
    train: list[RealVideo]
    test: list[RealVideo]


def _read_lines(path: Path) -> list[str]:
    if not path.exists():
        raise PhavUserError("split file missing", source=str(path))
    return [line.strip() for line in path.read_text(encoding="utf-8", errors="replace").splitlines() if line.strip()]


def _find(root: Path, names: Sequence[str], what: str) -> Path:
    for name in names:
        for base in (root, root.parent):
            if (base / name).is_dir():
                return base / name
    raise PhavUserError(f"no {what} folder ({' or '.join(names)}) in or beside the dataset", source=str(root))


def ucf101_split(root: str | Path, split: int = 1, splits_dir: str | Path | None = None) -> RealSplit:
    """UCF-101's official split ``split`` (1–3): ``ROOT/<Class>/v_<Class>_gNN_cMM.avi`` and
    ``ucfTrainTestlist/{classInd,trainlist0N,testlist0N}.txt`` (in or beside ROOT)."""
    root = Path(root)
    lists = Path(splits_dir) if splits_dir is not None else _find(root, ["ucfTrainTestlist"], "UCF-101 split")
    classes: list[str] = []
    for line in _read_lines(lists / "classInd.txt"):
        number, _, name = line.partition(" ")
        if not number.isdigit() or int(number) != len(classes) + 1 or not name:
            raise PhavUserError(f"expected '<n> <ClassName>' numbered from 1, got {line!r}",
                                source=str(lists / "classInd.txt"))  # fmt: skip
        classes.append(name)
    index = {name: i for i, name in enumerate(classes)}

    def videos(file: str) -> list[RealVideo]:
        out = []
        for line in _read_lines(lists / file):
            rel = line.split()[0]
            cls = rel.split("/")[0]
            if cls not in index:
                raise PhavUserError(f"class {cls!r} is not in classInd.txt", source=str(lists / file))
            m = re.search(r"_g(\d+)_c\d+", rel)
            out.append(RealVideo(root / rel, index[cls], f"g{m.group(1)}" if m else rel))
        return out

    if split not in (1, 2, 3):
        raise PhavUserError(f"UCF-101 has splits 1–3, got {split}", field="--real-split")
    return RealSplit("ucf101", classes, videos(f"trainlist0{split}.txt"), videos(f"testlist0{split}.txt"))


def hmdb51_split(root: str | Path, split: int = 1, splits_dir: str | Path | None = None) -> RealSplit:
    """HMDB-51's official split ``split`` (1–3): ``ROOT/<class>/<name>.avi`` and
    ``testTrainMulti_7030_splits/<class>_test_split<N>.txt`` with lines ``<name>.avi 0|1|2``
    (1 train, 2 test, 0 unused)."""
    root = Path(root)
    lists = Path(splits_dir) if splits_dir is not None else _find(
        root, ["testTrainMulti_7030_splits", "splits"], "HMDB-51 split")  # fmt: skip
    if split not in (1, 2, 3):
        raise PhavUserError(f"HMDB-51 has splits 1–3, got {split}", field="--real-split")
    files = sorted(lists.glob(f"*_test_split{split}.txt"))
    if not files:
        raise PhavUserError(f"no *_test_split{split}.txt files", source=str(lists))
    classes = [f.name[: -len(f"_test_split{split}.txt")] for f in files]
    train, test = [], []
    for label, (cls, file) in enumerate(zip(classes, files, strict=True)):
        for line in _read_lines(file):
            parts = line.split()
            if len(parts) != 2 or parts[1] not in ("0", "1", "2"):
                raise PhavUserError(f"expected '<video> 0|1|2', got {line!r}", source=str(file))
            video = RealVideo(root / cls / parts[0], label, Path(parts[0]).stem)
            if parts[1] == "1":
                train.append(video)
            elif parts[1] == "2":
                test.append(video)
    return RealSplit("hmdb51", classes, train, test)


def real_split(layout: str, root: str | Path, split: int = 1) -> RealSplit:
    """The official split of a real dataset in the ``ucf101`` or ``hmdb51`` layout."""
    if layout == "ucf101":
        return ucf101_split(root, split)
    if layout == "hmdb51":
        return hmdb51_split(root, split)
    raise PhavUserError(f"unknown layout {layout!r}; choose ucf101 or hmdb51", field="--real")


def load_real(
    videos: Sequence[RealVideo],
    *,
    size: tuple[int, int] = DEFAULT_SIZE,
    flow: str = "farneback",
    max_frames: int | None = None,
    progress: Callable[[int], None] | None = None,
) -> list[Clip]:
    """Decode real videos into clips; their flow is always estimated (no ground truth)."""
    method = "farneback" if flow == "gt" else flow
    clips = []
    for v in videos:
        if not v.path.exists():
            raise PhavUserError("video listed in the split file is missing", source=str(v.path))
        frames = decode_video(v.path, max_frames)
        key = f"{v.path.parent.name}/{v.path.name}"
        clips.append(make_clip(key, v.label, "real", frames, None, size=size, flow=method, groups={"actor": v.group}))
        if progress is not None:
            progress(1)
    return clips
