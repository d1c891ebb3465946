"""A PHAV dataset's clips for a PyTorch ``DataLoader``: ``PhavClips`` streams them from the
shards, in a seeded order that is the same on every run and whatever the number of workers,
each clip exactly once per epoch, and resumable.

    from torch.utils.data import DataLoader
    from phav_spec.torchdata import PhavClips, collate

    clips = PhavClips("data", modalities=("rgb", "flow"), segments=3, size=(170, 128), batch_size=8)
    loader = DataLoader(clips, batch_size=8, num_workers=2, collate_fn=collate)
    for epoch in range(10):
        clips.set_epoch(epoch)
        for batch in loader:
            batch["rgb"], batch["flow"], batch["label"]   # (8, 3, 128, 170, 3) uint8, (8, 3, 128, 170, 2), (8,)

The order of an epoch is a permutation of the videos drawn from (seed, epoch); worker w of W
reads the batches w, w + W, … of it, so the loader's batches come in exactly that order.
Under ``torch.distributed`` (its group read when ``PhavClips`` is made and at each
``set_epoch``; or with ``rank`` and ``world_size`` given), replica r of R takes
the clips r, r + R, … of that order, padded as ``DistributedSampler`` pads it (with its
first clips again) to a multiple of R, so every replica has as many batches.
After n clips, ``state_dict(n)`` saved and later ``load_state_dict`` on a fresh
``PhavClips`` continue with clip n + 1 (the loop's ``set_epoch`` of that epoch keeps its
place). The epoch is in shared memory: persistent workers follow ``set_epoch`` too.
``videos=`` takes a split's ids, e.g. from ``phav_validators.learn.splits.dataset_split``
(held-out performers, as the learnability check splits). Needs torch (``pip install 'phav[train]'``).
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np
import torch
from torch.utils.data import IterableDataset, get_worker_info

from phav_spec.clips import CLIP_MODALITIES, ClipReader, check_size, tsn_frames
from phav_spec.errors import PhavUserError
from phav_spec.seeding import seeded_rng

__all__ = ["PhavClips", "collate"]

#: The last salt of each seeded stream: numpy's seeding pads its words with zeros, so
#: (seed, epoch) and (seed, epoch, 0), or (seed) and (seed, 0), would draw one stream.
_ORDER_STREAM, _FRAMES_STREAM = 0x0D3E, 0xF4A3


class PhavClips(IterableDataset):
    """Clips of the dataset directory ``root`` (or of its ``videos``): ``modalities`` as
    ``phav_spec.clips.ClipReader.read`` gives them, as tensors; ``segments`` frames by TSN's
    sampling (random in each span when ``train``, central otherwise), or every frame when
    None; frames at ``size`` (width, height) or 340×256. ``batch_size`` must be the
    ``DataLoader``'s: it decides which worker reads which clips."""

    def __init__(
        self,
        root: str | Path,
        *,
        modalities: Sequence[str] = ("rgb", "flow"),
        segments: int | None = 3,
        size: tuple[int, int] | None = None,
        videos: Sequence[str] | None = None,
        batch_size: int = 1,
        shuffle: bool = True,
        train: bool = True,
        seed: int = 0,
        rank: int | None = None,
        world_size: int | None = None,
    ):
        super().__init__()
        self.reader = ClipReader(root)
        known = set(self.reader.video_ids)
        chosen = sorted(known if videos is None else set(videos))
        missing = [v for v in chosen if v not in known]
        if missing:
            raise PhavUserError(f"videos not in the dataset: {missing[:5]}", source=str(root), field="videos")
        if batch_size < 1 or (segments is not None and segments < 1):
            raise PhavUserError(f"batch_size and segments must be positive, got {batch_size}, {segments}")
        check_size(size)  # now, not in a worker at the first clip
        unknown = [m for m in modalities if m not in CLIP_MODALITIES]
        if unknown:
            raise PhavUserError(f"unknown modalities {unknown}; choose from {', '.join(CLIP_MODALITIES)}",
                                field="modalities")  # fmt: skip
        self._given = (rank, world_size)
        self.videos = chosen
        self.modalities = tuple(modalities)
        self.segments, self.size, self.batch_size = segments, size, batch_size
        self.shuffle, self.train, self.seed = shuffle, train, seed
        # The epoch and the clips of it already consumed (a resumed run), in shared memory:
        # a DataLoader's persistent workers keep the copy of this object they started with,
        # and would never see set_epoch's next epoch in a plain attribute.
        # The replica (rank, world size) is there too, read from the process group in this
        # process (a spawned worker has none) now and at each set_epoch: the group may be
        # initialised after this object is made.
        self._state = torch.zeros(4, dtype=torch.int64).share_memory_()
        self._find_replica()
        self._resumed: int | None = None  # the epoch load_state_dict resumes, until it is set

    def _find_replica(self) -> None:
        self._state[2], self._state[3] = _replica(*self._given)

    @property
    def rank(self) -> int:
        """This replica's rank: as given, else the ``torch.distributed`` group's (read when
        this object is made and at each ``set_epoch``), else 0."""
        return int(self._state[2])

    @property
    def world_size(self) -> int:
        """The replicas: as given, else the ``torch.distributed`` group's, else 1."""
        return int(self._state[3])

    @property
    def epoch(self) -> int:
        return int(self._state[0])

    @property
    def _skip(self) -> int:
        return int(self._state[1])

    def __len__(self) -> int:
        """The clips this replica reads per epoch (every video's once when it is the only one)."""
        return -(-len(self.videos) // self.world_size)

    def set_epoch(self, epoch: int) -> None:
        """Start ``epoch``: its order, and its frames when training. The epoch a loaded state
        resumes keeps its consumed clips (an epoch loop calls set_epoch after load_state_dict)."""
        skip = self._skip if epoch == self._resumed else 0
        self._resumed = None
        self._state[0], self._state[1] = epoch, skip
        self._find_replica()

    def order(self, epoch: int | None = None) -> list[str]:
        """The epoch's videos in the order the loader yields them (this replica's)."""
        return [video for _, video in self._placed(epoch)]

    def _placed(self, epoch: int | None = None) -> list[tuple[int, str]]:
        """This replica's clips of the epoch: (place in the whole epoch's padded order, video)."""
        epoch = self.epoch if epoch is None else epoch
        rank, world_size = self.rank, self.world_size
        whole = list(self.videos)
        if self.shuffle:
            order = seeded_rng(self.seed, epoch, _ORDER_STREAM).permutation(len(self.videos))
            whole = [self.videos[i] for i in order]
        total = -(-len(whole) // world_size) * world_size  # more replicas than videos: round it again
        padded = (whole * -(-total // len(whole)))[:total] if whole else []
        return list(enumerate(padded))[rank::world_size]

    def state_dict(self, consumed: int) -> dict[str, int]:
        """What resumes after ``consumed`` clips of the current epoch."""
        return {"epoch": self.epoch, "consumed": self._skip + consumed}

    def load_state_dict(self, state: dict[str, int]) -> None:
        """Continue where ``state_dict`` was taken."""
        self._state[0], self._state[1] = int(state["epoch"]), int(state["consumed"])
        self._resumed = int(state["epoch"])

    def __iter__(self):
        info = get_worker_info()
        if info is None:  # in the training process itself: its group as it is now
            self._find_replica()
        worker, workers = (info.id, info.num_workers) if info is not None else (0, 1)
        placed = self._placed()
        for start in range(self._skip + worker * self.batch_size, len(placed), workers * self.batch_size):
            for position, video_id in placed[start : start + self.batch_size]:
                yield self._clip(video_id, position)

    def _clip(self, video_id: str, position: int) -> dict[str, Any]:
        n = self.reader.n_frames[video_id]
        frames = None
        if self.segments is not None:
            # Seeded by the clip's place in the epoch: the same frames whatever the workers.
            rng = seeded_rng(self.seed, self.epoch, position, _FRAMES_STREAM) if self.train else None
            frames = tsn_frames(n, self.segments, rng)
        clip = self.reader.read(video_id, frames, self.modalities, self.size)
        out: dict[str, Any] = {"video_id": video_id, "label": clip["label"], "frames": torch.tensor(clip["frames"])}
        for key, value in clip.items():
            if isinstance(value, np.ndarray):
                out[key] = torch.from_numpy(np.ascontiguousarray(value))
            elif key in ("people", "camera"):
                out[key] = value
        return out


def _replica(rank: int | None, world_size: int | None) -> tuple[int, int]:
    """(rank, world size): as given, else the initialised ``torch.distributed`` group's, else (0, 1)."""
    dist = torch.distributed
    live = dist.is_available() and dist.is_initialized()
    world_size = world_size if world_size is not None else (dist.get_world_size() if live else 1)
    rank = rank if rank is not None else (dist.get_rank() if live else 0)
    if world_size < 1 or not 0 <= rank < world_size:
        raise PhavUserError(f"rank must be in [0, world_size) and world_size positive, got {rank}, {world_size}",
                            field="rank")  # fmt: skip
    return rank, world_size


def collate(clips: list[dict[str, Any]]) -> dict[str, Any]:
    """A batch: tensors stacked, labels as a tensor, video ids and people rows as lists."""
    out: dict[str, Any] = {}
    for key in clips[0]:
        values = [c[key] for c in clips]
        if isinstance(values[0], torch.Tensor):
            out[key] = torch.stack(values)
        elif key == "label":
            out[key] = torch.tensor(values)
        else:
            out[key] = values
    return out
