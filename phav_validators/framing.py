"""How the camera frames the protagonist, measured from ``people.parquet`` (no pixels read).

The renderer writes, per frame and person, the box of the person's visible pixels in the
instance modality (``bbox2d``) and their count (``pixels``): the protagonist (person 0) is
*in view* in a frame when it has at least one pixel there, and its *height* in that frame is
the box's height (``y1 − y0``) as a share of the frame height. Occluded or cut-off parts do
not count, so this is what a network sees, not where the body is. ``phav stats`` and the
``phav-validate`` reports show it per camera behaviour; docs/framing.md says what the kite
camera's ranges aim for.
"""

from __future__ import annotations

import itertools
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from phav_spec.errors import PhavUserError
from phav_spec.files import read_parquet
from phav_validators import tables

if TYPE_CHECKING:
    import pyarrow as pa

    from phav_spec.recipe import Recipe

__all__ = [
    "FRAMING_BINS",
    "FramingGroup",
    "FramingResult",
    "VideoFrame",
    "framing_videos",
    "measure_framing",
    "read_framing",
]

#: Histogram edges of the protagonist's height, as a share of the frame height (10 % bins).
FRAMING_BINS: tuple[float, ...] = tuple(i / 10 for i in range(11))
#: The people.parquet columns the measurement reads.
_COLUMNS = ("video_id", "person_id", "pixels", "bbox2d")


@dataclass(frozen=True)
class VideoFrame:
    """What the measurement needs to know about a video: its camera and frame height (px)."""

    camera: str
    height: int


@dataclass(frozen=True)
class FramingGroup:
    """The protagonist's framing over a group of videos (one camera behaviour, or all)."""

    name: str
    n_videos: int
    n_frames: int
    #: Box height of the protagonist's visible pixels / frame height, per frame in view.
    heights: np.ndarray
    #: Same, in pixels.
    heights_px: np.ndarray
    #: Per video: the median share over its frames in view (NaN when never in view).
    video_medians: np.ndarray

    @property
    def in_view_frames(self) -> int:
        return int(self.heights.size)

    @property
    def in_view_share(self) -> float:
        """Share of frames with at least one protagonist pixel (NaN without frames)."""
        return self.in_view_frames / self.n_frames if self.n_frames else float("nan")

    def quantiles(self, qs: tuple[float, ...] = (0.25, 0.5, 0.75), *, px: bool = False) -> tuple[float, ...]:
        """Quantiles of the height over the frames in view (share, or px), NaN when none."""
        values = self.heights_px if px else self.heights
        if values.size == 0:
            return tuple(float("nan") for _ in qs)
        return tuple(float(x) for x in np.quantile(values, qs))

    @property
    def median(self) -> float:
        return self.quantiles((0.5,))[0]

    @property
    def median_px(self) -> float:
        return self.quantiles((0.5,), px=True)[0]

    def histogram(self) -> np.ndarray:
        """Share of all frames per ``FRAMING_BINS`` bin of height; frames out of view are left
        out, so the shares sum to the in-view share."""
        counts, _ = np.histogram(np.clip(self.heights, 0.0, 1.0), bins=FRAMING_BINS)
        return counts / max(self.n_frames, 1)

    def to_json(self) -> dict[str, Any]:
        q1, q2, q3 = self.quantiles()
        p1, p2, p3 = self.quantiles(px=True)
        return {
            "videos": self.n_videos, "frames": self.n_frames, "in_view_frames": self.in_view_frames,
            "in_view_share": self.in_view_share, "height_quartiles": [q1, q2, q3],
            "height_quartiles_px": [p1, p2, p3],
            "histogram": {"edges": list(FRAMING_BINS), "shares": [float(x) for x in self.histogram()]},
        }  # fmt: skip


@dataclass(frozen=True)
class FramingResult:
    """The protagonist's framing per camera behaviour, and over all videos (``"all"``)."""

    groups: dict[str, FramingGroup]

    def to_json(self) -> dict[str, Any]:
        return {name: g.to_json() for name, g in self.groups.items()}


def framing_videos(recipes: Iterable[Recipe]) -> dict[str, VideoFrame]:
    """What ``measure_framing`` needs of each recipe, by video id."""
    return {r.video_id: VideoFrame(r.camera.kind, r.video.height) for r in recipes}


def _people_arrays(people: pa.Table, source: str) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(video ids, pixels, y0, y1) of the protagonist's rows; a ``PhavUserError`` naming
    the column where one is missing or malformed (``tables``)."""
    missing = [c for c in _COLUMNS if c not in people.column_names]
    if missing:
        raise PhavUserError(
            f"people table has no {', '.join(missing)} column(s): not a phav people.parquet, or written by a "
            "phav older than the metadata contract",
            source=source,
        )
    mine = tables.numbers(people, "person_id", source, key=True) == 0
    vids = tables.keys(people, "video_id", source)[mine]
    pixels = tables.numbers(people, "pixels", source)[mine]
    boxes = tables.fixed_lists(people, "bbox2d", 4, source)[mine]
    # A frame without its pixel count or box (a null) is not counted as seen.
    pixels = np.where(np.isfinite(boxes).all(axis=1), np.nan_to_num(pixels, nan=0.0), 0.0)
    return vids, pixels, boxes[:, 1], boxes[:, 3]


def measure_framing(
    people: pa.Table, videos: Mapping[str, VideoFrame], *, source: str = "people.parquet"
) -> FramingResult:
    """The protagonist's framing in the videos of ``videos`` (rows of other videos are ignored).

    ``people`` is a people table (``phav_spec.metadata.PEOPLE_COLUMNS``; only ``video_id``,
    ``person_id``, ``pixels`` and ``bbox2d`` are read). Raises ``PhavUserError`` when a
    needed column is missing.
    """
    vids, pixels, y0, y1 = _people_arrays(people, source)
    by_group: dict[str, list[tuple[np.ndarray, np.ndarray, int]]] = {}
    order = np.argsort(vids, kind="stable") if vids.size else np.zeros(0, dtype=int)
    vids, pixels, y0, y1 = vids[order], pixels[order], y0[order], y1[order]
    starts = np.flatnonzero(np.r_[True, vids[1:] != vids[:-1]]) if vids.size else np.zeros(0, dtype=int)
    bounds = np.r_[starts, vids.size]
    for a, b in itertools.pairwise(bounds.tolist()):
        info = videos.get(str(vids[a]))
        if info is None:
            continue
        seen = pixels[a:b] > 0
        px = (y1[a:b] - y0[a:b])[seen]
        for name in (info.camera, "all"):
            by_group.setdefault(name, []).append((px / info.height, px, int(b - a)))
    groups = {}
    for name in sorted(by_group, key=lambda n: (n == "all", n)):
        parts = by_group[name]
        medians = np.array([np.median(h) if h.size else np.nan for h, _, _ in parts])
        groups[name] = FramingGroup(
            name=name,
            n_videos=len(parts),
            n_frames=sum(n for _, _, n in parts),
            heights=np.concatenate([h for h, _, _ in parts]),
            heights_px=np.concatenate([p for _, p, _ in parts]),
            video_medians=medians,
        )
    return FramingResult(groups)


def read_framing(people_path: str | Path, recipes: Iterable[Recipe]) -> FramingResult:
    """``measure_framing`` of a dataset's ``people.parquet`` (only the columns it needs are
    read). Raises ``PhavUserError`` when the file is unreadable or lacks a column."""
    import pyarrow.parquet as pq

    path = Path(people_path)
    try:
        names = pq.read_schema(path).names
        people = read_parquet(path, columns=[c for c in _COLUMNS if c in names])
    except (OSError, ValueError) as e:  # pyarrow's errors derive from these
        raise PhavUserError(f"not a readable Parquet file ({e})", source=str(path)) from e
    return measure_framing(people, framing_videos(recipes), source=str(path))
