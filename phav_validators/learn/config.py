"""The shape of a TSN stream, importable without torch (options and configs name it)."""

from __future__ import annotations

import importlib.util
from dataclasses import dataclass

from phav_spec.errors import PhavUserError

#: Input channels per stream: an RGB frame, or ``flow_frames`` stacked (u, v) flow frames.
STREAMS = ("rgb", "flow")


@dataclass(frozen=True)
class Architecture:
    """The backbone's shape: a 5×5 stride-2 stem (then a 3×3 stride-2 max-pool when
    ``stem_pool``), one stride-2 block per width after the first (two 3×3 convolutions
    each), global average pooling and dropout. TSN's 2D network: its K segments meet only in
    the consensus (temporal models fitted more and tested worse: docs/experiments/learnability.md,
    "Backbone")."""

    widths: tuple[int, ...] = (32, 64, 128, 192)
    dropout: float = 0.5
    stem_pool: bool = False

    def __post_init__(self) -> None:
        if not self.widths or min(self.widths) < 1:
            raise PhavUserError(f"must be positive, got {self.widths}", field="--widths")
        if not 0.0 <= self.dropout < 1.0:
            raise PhavUserError(f"must be in [0, 1), got {self.dropout}", field="--dropout")


def in_channels(stream: str, flow_frames: int, rgb_frames: int = 1) -> int:
    """Channels of one snippet of ``stream``: ``rgb_frames`` stacked RGB frames or
    ``flow_frames`` stacked (u, v) flow frames."""
    if stream == "rgb":
        return 3 * rgb_frames
    if stream == "flow":
        return 2 * flow_frames
    raise PhavUserError(f"unknown stream {stream!r}; expected one of {', '.join(STREAMS)}", field="--streams")


def require_torch() -> None:
    """Raise a one-line PhavUserError when torch is not installed."""

    if importlib.util.find_spec("torch") is None:
        raise PhavUserError("training needs torch: pip install torch (CPU wheel), or pip install 'phav[train]'")
