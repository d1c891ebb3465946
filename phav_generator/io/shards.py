"""Reproducible WebDataset tar shards, written atomically and hashed while written.

Tar files are byte-reproducible only with fixed member metadata and order (DESIGN.md), so
every member has mtime 0, owner 0:0 with empty names, mode 0644 and the USTAR format, and
members go in the order they are added: per frame, the modalities in ``MODALITIES`` order
then the ``json`` metadata, frames in order, videos in order.
"""

from __future__ import annotations

import hashlib
import io
import tarfile
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import BinaryIO

from phav_generator.io.png import encode_png
from phav_spec.encoding import MODALITIES
from phav_spec.files import atomic_write

#: Member metadata every shard uses (reproducible tars).
TAR_MTIME = 0
TAR_MODE = 0o644


class _HashingWriter(io.RawIOBase):
    """A write-only file that hashes and counts what passes through to ``target``."""

    def __init__(self, target: BinaryIO):
        self.target = target
        self.sha256 = hashlib.sha256()
        self.size = 0

    def writable(self) -> bool:
        return True

    def tell(self) -> int:
        return self.size

    def write(self, data) -> int:  # type: ignore[override]
        view = memoryview(data)
        self.target.write(view)
        self.sha256.update(view)
        self.size += view.nbytes
        return view.nbytes


@dataclass
class ShardDigest:
    """A finished shard's sha256 and size in bytes (filled in when the writer closes)."""

    sha256: str = ""
    bytes: int = 0


class ShardWriter:
    """Members of one tar, in order; use through ``open_shard``."""

    def __init__(self, tar: tarfile.TarFile):
        self._tar = tar
        self._names: set[str] = set()

    def add(self, name: str, data: bytes) -> None:
        if name in self._names:
            raise ValueError(f"duplicate tar member {name!r}")
        self._names.add(name)
        info = tarfile.TarInfo(name)
        info.size = len(data)
        info.mtime = TAR_MTIME
        info.mode = TAR_MODE
        info.uid = info.gid = 0
        info.uname = info.gname = ""
        self._tar.addfile(info, io.BytesIO(data))

    def add_frame(self, video_id: str, frame: int, modalities: dict, frame_meta: bytes) -> None:
        """One WebDataset sample ``{video_id}/{frame:05d}``: six PNGs and the json metadata."""
        key = f"{video_id}/{frame:05d}"
        for m in MODALITIES:
            self.add(f"{key}.{m.key}", encode_png(modalities[m.name], m))
        self.add(f"{key}.json", frame_meta)


@contextmanager
def open_shard(path: str | Path) -> Iterator[tuple[ShardWriter, ShardDigest]]:
    """Write a tar at ``path`` atomically; the digest is filled in once the block exits."""
    digest = ShardDigest()
    with atomic_write(path) as tmp, open(tmp, "wb") as fh:
        sink = _HashingWriter(fh)
        with tarfile.open(fileobj=sink, mode="w", format=tarfile.USTAR_FORMAT) as tar:  # type: ignore[arg-type]
            yield ShardWriter(tar), digest
        digest.sha256 = sink.sha256.hexdigest()
        digest.bytes = sink.size
