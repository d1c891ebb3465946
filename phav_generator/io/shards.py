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
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import BinaryIO

from phav_generator.io.png import PNG_LEVEL, encode_png
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


class HashingReader:
    """A read-only file that hashes and counts what is read through it (sequential reads,
    as tarfile's stream mode makes them)."""

    def __init__(self, raw: BinaryIO):
        self._raw = raw
        self.sha256 = hashlib.sha256()
        self.size = 0

    def read(self, n: int = -1) -> bytes:
        data = self._raw.read(n)
        self.sha256.update(data)
        self.size += len(data)
        return data


@dataclass
class ShardDigest:
    """A finished shard's sha256 and size in bytes (filled in when the writer closes)."""

    sha256: str = ""
    bytes: int = 0


def tar_member(name: str, data: bytes) -> bytes:
    """One USTAR member exactly as ``tarfile`` writes it: header, data, zeros to a block."""
    info = tarfile.TarInfo(name)
    info.size = len(data)
    info.mtime = TAR_MTIME
    info.mode = TAR_MODE
    info.uid = info.gid = 0
    info.uname = info.gname = ""
    header = info.tobuf(tarfile.USTAR_FORMAT, "utf-8", "surrogateescape")
    return header + data + tarfile.NUL * (-len(data) % tarfile.BLOCKSIZE)


def tar_end(members_bytes: int) -> bytes:
    """What ``tarfile`` appends when it closes after ``members_bytes`` of members: two zero
    blocks, then zeros to a whole record."""
    end = members_bytes + 2 * tarfile.BLOCKSIZE
    return tarfile.NUL * (2 * tarfile.BLOCKSIZE + (-end % tarfile.RECORDSIZE))


#: Bytes copied at a time when parts are joined into a shard.
_COPY_CHUNK = 1 << 20


class ShardWriter:
    """Tar members in order, written straight to a binary file (no end-of-archive blocks:
    a video's members are a *part* that ``assemble_shard`` joins with others)."""

    def __init__(self, sink: BinaryIO):
        self._sink = sink
        self._names: set[str] = set()
        self.size = 0

    def add(self, name: str, data: bytes) -> None:
        if name in self._names:
            raise ValueError(f"duplicate tar member {name!r}")
        self._names.add(name)
        member = tar_member(name, data)
        self._sink.write(member)
        self.size += len(member)

    def add_part(self, path: Path) -> None:
        """Copy a video's part (members written by another ``ShardWriter``) in, as is."""
        with open(path, "rb") as src:
            while chunk := src.read(_COPY_CHUNK):
                self._sink.write(chunk)
                self.size += len(chunk)

    def add_frame(
        self, video_id: str, frame: int, modalities: dict, frame_meta: bytes, png_level: int = PNG_LEVEL
    ) -> None:
        """One WebDataset sample ``{video_id}/{frame:05d}``: six PNGs (zlib ``png_level``) and
        the json metadata."""
        key = f"{video_id}/{frame:05d}"
        for m in MODALITIES:
            self.add(f"{key}.{m.key}", encode_png(modalities[m.name], m, png_level))
        self.add(f"{key}.json", frame_meta)


@contextmanager
def open_part(path: str | Path) -> Iterator[ShardWriter]:
    """Write one video's tar members to ``path`` atomically (a part, not a whole tar)."""
    with atomic_write(path) as tmp, open(tmp, "wb") as fh:
        yield ShardWriter(fh)


@contextmanager
def open_shard(path: str | Path) -> Iterator[tuple[ShardWriter, ShardDigest]]:
    """Write a whole tar at ``path`` atomically; the digest is filled in once the block exits."""
    digest = ShardDigest()
    with atomic_write(path) as tmp, open(tmp, "wb") as fh:
        sink = _HashingWriter(fh)
        writer = ShardWriter(sink)  # type: ignore[arg-type]
        yield writer, digest
        sink.write(tar_end(writer.size))
        digest.sha256 = sink.sha256.hexdigest()
        digest.bytes = sink.size


def assemble_shard(
    parts: Sequence[Path], path: str | Path, *, checkpoint: Callable[[int], None] | None = None
) -> ShardDigest:
    """Join video parts, in order, into the tar at ``path`` (atomically) and hash it.

    ``checkpoint(k)`` runs after the k-th part is copied (crash-injection tests use it).
    """
    with open_shard(path) as (writer, digest):
        for k, part in enumerate(parts):
            writer.add_part(part)
            if checkpoint is not None:
                checkpoint(k)
    return digest


def read_members(path: str | Path, wanted: Callable[[str], bool]) -> tuple[list[tuple[str, bytes]], ShardDigest]:
    """The (name, bytes) of a shard's members that ``wanted`` accepts, in tar order, and the
    digest of the whole file, read once (its bytes checked against a manifest's before the
    members are trusted). A damaged tar raises ``tarfile.TarError``."""
    found: list[tuple[str, bytes]] = []
    with open(path, "rb") as raw:
        reader = HashingReader(raw)
        with tarfile.open(fileobj=reader, mode="r|") as tar:  # type: ignore[call-overload]
            for info in tar:
                if info.isfile() and wanted(info.name):
                    member = tar.extractfile(info)
                    if member is not None:
                        found.append((info.name, member.read()))
        while reader.read(1 << 20):  # the end-of-archive blocks and anything after them
            pass
    return found, ShardDigest(reader.sha256.hexdigest(), reader.size)
