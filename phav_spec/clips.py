"""Clips out of a PHAV dataset's shards, by video: chosen modalities and frames, decoded
exactly, optionally resized — random access without unpacking anything.

``ClipReader(root)`` reads a dataset directory's manifest and recipes table and indexes each
shard's members once (tar headers only: where each frame's PNGs and JSON lie in the file);
``read(video_id, frames, modalities, size)`` then seeks straight to them. Frames come back as
arrays (T, H, W, C); flow as (u, v) float32 pixels of the returned size with 0 where invalid
(``valid`` says where); depth as float32 metres (inf for sky); labels are the recipe's action
index in ``phav_spec.vocab.ACTIONS``. ``tsn_frames`` picks the frames of TSN's segments.
``phav_spec.torchdata`` streams clips to a PyTorch ``DataLoader``.

OpenCV and pyarrow are imported on first use (phav_spec imports light, DESIGN.md).
"""

from __future__ import annotations

import errno
import os
import tarfile
from collections import OrderedDict
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, BinaryIO

import numpy as np

from phav_spec.encoding import MODALITIES, decode_depth, flow_pixels, modality
from phav_spec.errors import PhavUserError
from phav_spec.files import parse_json_object, tar_end_problem
from phav_spec.manifest import load_manifest
from phav_spec.vocab import ACTIONS
from phav_spec.webdataset import decode_png

if TYPE_CHECKING:
    from phav_spec.manifest import DatasetManifest

__all__ = ["CLIP_MODALITIES", "ClipReader", "check_size", "tsn_frames"]

#: What a clip can carry: the six image modalities and the frame's metadata (its people's
#: rows and its camera's, as in people.parquet and cameras.parquet).
CLIP_MODALITIES = ("rgb", "raw_rgb", "semantic", "instance", "depth", "flow", "people", "camera")
#: The largest member read (bytes): a 340×256 16-bit RGB PNG is at most ~0.6 MB; a hostile
#: shard's huge member is refused unread.
MAX_MEMBER_BYTES = 64 * 2**20
#: Label images are resized by nearest neighbour (a class colour is never averaged).
_NEAREST = ("semantic", "instance", "depth")


#: The members a frame has, in the index's column order: its six PNGs and its JSON.
MEMBER_KEYS = (*(m.key for m in MODALITIES), "json")
_COLUMN = {key: i for i, key in enumerate(MEMBER_KEYS)}
#: Shards a reader keeps open at once (the least recently read is closed first): a loader
#: worker reading PHAV's thousands of shards would otherwise run out of file handles.
MAX_OPEN_SHARDS = 32


@dataclass(frozen=True)
class _ShardIndex:
    """Where each frame's members lie in one shard: per video, (frames, members) arrays of
    byte offsets (−1: not in the shard) and sizes, in ``MEMBER_KEYS`` order: 16 bytes
    a member, where a dict of objects took ~380: PHAV's 42 M members in every loader worker."""

    offsets: dict[str, np.ndarray]
    sizes: dict[str, np.ndarray]

    def member(self, vid: str, frame: int, key: str) -> tuple[int, int] | None:
        offsets = self.offsets.get(vid)
        if offsets is None or frame >= len(offsets) or offsets[frame, _COLUMN[key]] < 0:
            return None
        return int(offsets[frame, _COLUMN[key]]), int(self.sizes[vid][frame, _COLUMN[key]])


def tsn_frames(n_frames: int, segments: int, rng: np.random.Generator | None = None) -> list[int]:
    """TSN's sampling: the clip cut into ``segments`` equal spans, one frame from each — at a
    random place in its span with ``rng`` (training), at its centre without (testing)."""
    if n_frames < 1 or segments < 1:
        raise ValueError(f"need frames and segments, got {n_frames} frames and {segments} segments")
    edges = np.linspace(0.0, n_frames, segments + 1)
    if rng is None:
        picks = (edges[:-1] + edges[1:]) / 2
    else:
        picks = edges[:-1] + rng.random(segments) * (edges[1:] - edges[:-1])
    return [min(int(p), n_frames - 1) for p in picks]


def _index_shard(path: Path) -> _ShardIndex:
    """Where every frame's members lie in the tar (its headers only). A header damaged after
    the first ends ``tarfile``'s listing silently: the end-of-archive marker must follow."""
    found: dict[str, list[tuple[int, int, int, int]]] = {}
    try:
        with tarfile.open(path, "r:") as tar:
            for info in tar:
                name = info.name
                if not info.isfile() or "/" not in name:
                    continue
                vid, rest = name.split("/", 1)
                frame, _, key = rest.partition(".")
                if frame.isdigit() and key in _COLUMN:
                    found.setdefault(vid, []).append((int(frame), _COLUMN[key], info.offset_data, info.size))
            end = tar.offset
        with open(path, "rb") as fh:
            unended = tar_end_problem(fh, end)
    except (tarfile.TarError, OSError) as e:
        raise PhavUserError(f"not a readable shard ({e}); run phav-validate", source=str(path)) from None
    if unended is not None:
        raise PhavUserError(f"a damaged tar header at byte {end}: the members after it cannot be read; run "
                            "phav-validate", source=str(path))  # fmt: skip
    offsets, sizes = {}, {}
    for vid, rows in found.items():
        table = np.array(rows, dtype=np.int64)
        frames = int(table[:, 0].max()) + 1
        offsets[vid] = np.full((frames, len(MEMBER_KEYS)), -1, dtype=np.int64)
        sizes[vid] = np.zeros((frames, len(MEMBER_KEYS)), dtype=np.int64)
        offsets[vid][table[:, 0], table[:, 1]] = table[:, 2]
        sizes[vid][table[:, 0], table[:, 1]] = table[:, 3]
    return _ShardIndex(offsets, sizes)


def _labels(path: Path) -> dict[str, int]:
    """Each video's action index from a recipes table; an unknown action names the table."""
    from phav_spec.recipe_table import read_recipe_table

    table = read_recipe_table(path)
    actions = {name: i for i, name in enumerate(ACTIONS.names)}
    labels = {}
    for vid, action in zip(table.column("video_id"), table.column("action"), strict=True):
        if action not in actions:
            raise PhavUserError(f"video {vid}: unknown action {action!r}", source=str(path), field="action")
        labels[vid] = actions[action]
    return labels


def _resize_flow(flow: np.ndarray, valid: np.ndarray, size: tuple[int, int]) -> tuple[np.ndarray, np.ndarray]:
    """Flow (T, H, W, 2) in pixels and its validity at ``size`` (width, height): vectors
    area-averaged over the valid pixels only (an invalid pixel's zero would shrink its
    neighbours' motion) and scaled with the image, validity by nearest neighbour, the flow 0
    where it is invalid."""
    import cv2  # phav_spec imports light (DESIGN.md): OpenCV only when frames are decoded

    h, w = flow.shape[1:3]
    weight = valid.astype(np.float32)
    summed = np.stack([cv2.resize(x * m[..., None], size, interpolation=cv2.INTER_AREA)
                       for x, m in zip(flow, weight, strict=True)])  # fmt: skip
    share = np.stack([cv2.resize(m, size, interpolation=cv2.INTER_AREA) for m in weight])
    kept = np.stack([cv2.resize(v.astype(np.uint8), size, interpolation=cv2.INTER_NEAREST) for v in valid]) > 0
    out = np.where((kept & (share > 0))[..., None], summed / np.maximum(share, 1e-12)[..., None], 0.0)
    out = out.astype(np.float32)
    out[..., 0] *= size[0] / w
    out[..., 1] *= size[1] / h
    return out, kept


def check_size(size: tuple[int, int] | None) -> None:
    """A frame size is None (as rendered) or two positive whole numbers, width and height."""
    if size is None:
        return
    ok = isinstance(size, tuple | list) and len(size) == 2
    if not ok or not all(isinstance(v, int) and not isinstance(v, bool) and v > 0 for v in size):
        raise PhavUserError(f"size must be (width, height) in whole pixels above 0, got {size!r}", field="size")


class ClipReader:
    """Random access to a dataset directory's clips (``read``), its videos' frame counts and
    labels. Each shard is indexed when a clip of it is first read; a reader pickles without
    its open files, so that ``DataLoader`` workers each open their own."""

    def __init__(self, root: str | Path, *, manifest: DatasetManifest | None = None,
                 labels: Mapping[str, int] | None = None):  # fmt: skip
        self.root = Path(root)
        if manifest is None:
            manifest_path = self.root / "manifest.json"
            if not manifest_path.exists():
                raise PhavUserError("not a PHAV dataset directory (no manifest.json)", source=str(self.root))
            manifest = load_manifest(manifest_path)
        self.manifest = manifest
        self.labels = dict(labels) if labels is not None else _labels(self.root / "recipes.parquet")
        self.n_frames = {v.video_id: v.n_frames for v in manifest.videos}
        self._shard_of = {v.video_id: self.root / v.shard for v in manifest.videos}
        self._index: dict[Path, _ShardIndex] = {}
        self._files: OrderedDict[Path, BinaryIO] = OrderedDict()
        self._pid = os.getpid()

    def __getstate__(self) -> dict[str, Any]:
        return {**self.__dict__, "_files": OrderedDict()}

    def close(self) -> None:
        """Close the shards this reader opened (it reopens them when read again)."""
        for fh in self._files.values():
            fh.close()
        self._files = OrderedDict()

    def _open(self, shard: Path) -> BinaryIO:
        """The shard's file, kept open across reads, at most ``MAX_OPEN_SHARDS`` at once."""
        if self._pid != os.getpid():  # a forked worker: the parent's files share its offsets
            self._files, self._pid = OrderedDict(), os.getpid()
        fh = self._files.get(shard)
        if fh is not None:
            self._files.move_to_end(shard)
            return fh
        while len(self._files) >= MAX_OPEN_SHARDS:
            self._files.popitem(last=False)[1].close()
        try:
            fh = self._files[shard] = open(shard, "rb")
        except OSError as e:
            if e.errno == errno.EMFILE:
                raise PhavUserError("too many open files in this process (ulimit -n); close other readers",
                                    source=str(shard)) from None  # fmt: skip
            raise PhavUserError(f"cannot be read ({e.strerror or e})", source=str(shard)) from None
        return fh

    @property
    def video_ids(self) -> list[str]:
        """Every video with a recipe, in manifest order."""
        return [v.video_id for v in self.manifest.videos if v.video_id in self.labels]

    def _bytes(self, vid: str, frame: int, key: str) -> bytes:
        shard = self._shard_of[vid]
        if shard not in self._index:
            self._index[shard] = _index_shard(shard)
        member = self._index[shard].member(vid, frame, key)
        if member is None:
            raise PhavUserError(f"video {vid}: frames missing from the shard (frame {frame}'s {key}); run "
                                "phav-validate", source=str(shard))  # fmt: skip
        offset, size = member
        if size > MAX_MEMBER_BYTES:
            raise PhavUserError(f"{vid}/{frame:05d}.{key}: {size} bytes, larger than any frame can be",
                                source=str(shard))  # fmt: skip
        fh = self._open(shard)
        fh.seek(offset)
        data = fh.read(size)
        if len(data) != size:
            raise PhavUserError(f"{vid}/{frame:05d}.{key}: the shard ends early", source=str(shard))
        return data

    def read(
        self,
        video_id: str,
        frames: Sequence[int] | None = None,
        modalities: Sequence[str] = ("rgb", "flow"),
        size: tuple[int, int] | None = None,
    ) -> dict[str, Any]:
        """One clip: per modality an array over ``frames`` (all when None) at ``size``
        (width, height; None keeps 340×256), plus ``label``, ``video_id`` and ``frames``.

        Image modalities are (T, H, W, 3) uint8; ``depth`` (T, H, W) float32 metres (inf:
        sky); ``flow`` (T, H, W, 2) float32 pixels of the returned size, 0 where invalid,
        with ``flow_valid`` (T, H, W) bool; ``people`` a list (per frame) of the frame's
        people rows, ``camera`` of its camera row (NaN as None)."""
        import cv2  # phav_spec imports light (DESIGN.md): OpenCV only when frames are decoded

        unknown = [m for m in modalities if m not in CLIP_MODALITIES]
        if unknown:
            raise PhavUserError(f"unknown modalities {unknown}; choose from {', '.join(CLIP_MODALITIES)}",
                                field="modalities")  # fmt: skip
        if video_id not in self.labels or video_id not in self.n_frames:
            raise PhavUserError(f"no video {video_id!r} with a recipe and frames", source=str(self.root))
        order = list(range(self.n_frames[video_id])) if frames is None else [int(f) for f in frames]
        outside = [f for f in order if not 0 <= f < self.n_frames[video_id]]
        if not order or outside:
            raise PhavUserError(f"frames must be a non-empty list within 0–{self.n_frames[video_id] - 1}, got "
                                f"{outside[:3] or 'none'}", field=f"{video_id} frames")  # fmt: skip
        check_size(size)
        out: dict[str, Any] = {"video_id": video_id, "label": self.labels[video_id], "frames": order}
        metadata = [m for m in modalities if m in ("people", "camera")]
        if metadata:  # one read of each frame's JSON serves both
            rows = []
            for f in order:
                source = f"{self._shard_of[video_id]}: {video_id}/{f:05d}.json"
                row = parse_json_object(self._bytes(video_id, f, "json"), source=source)
                absent = [name for name in metadata if name not in row]
                if absent:
                    raise PhavUserError("missing from the frame's metadata", source=source, field=absent[0])
                rows.append(row)
            out |= {name: [row[name] for row in rows] for name in metadata}
        for name in modalities:
            if name in metadata:
                continue
            enc = modality(name)
            arrays = []
            for f in order:
                source = f"{self.root}: {video_id}/{f:05d}.{enc.key}"
                try:
                    arrays.append(decode_png(self._bytes(video_id, f, enc.key), enc, source=source))
                except ValueError as e:
                    raise PhavUserError(str(e)) from None
            stack = np.stack(arrays)
            try:
                if name == "flow":
                    flow, valid = flow_pixels(stack)
                    if size is not None:
                        flow, valid = _resize_flow(flow, valid, size)
                    out["flow"], out["flow_valid"] = flow, valid
                    continue
                if size is not None:
                    mode = cv2.INTER_NEAREST if name in _NEAREST else cv2.INTER_AREA
                    stack = np.stack([cv2.resize(x, size, interpolation=mode) for x in stack])
                out[name] = decode_depth(stack) if name == "depth" else stack
            except ValueError as e:
                raise PhavUserError(f"video {video_id}: {e}", source=str(self.root)) from None
        return out
