"""Read a shard's members in place, safely: nothing is extracted, nothing hostile is read.

A released tar is untrusted input. Members are streamed from the file (no extraction, so
nothing can be written anywhere); a member whose name is absolute or climbs with ``..``,
that is a link, device, FIFO or directory, or that is larger than any frame can be
(``MAX_MEMBER_BYTES``: a decompression bomb starts as a huge member) is refused unread and
reported. A tar that ends mid-member is reported as truncated with how far reading got.
The file's sha256 and size are computed on the same pass.
"""

from __future__ import annotations

import tarfile
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from pathlib import Path, PurePosixPath

from phav_generator.io.shards import HashingReader
from phav_spec.files import tar_end_problem

#: The largest member read (bytes). A 340×256 16-bit RGB PNG is at most ~0.6 MB even stored
#: uncompressed; frames up to 4K in 16-bit RGB (≈ 50 MB raw) still fit.
MAX_MEMBER_BYTES = 64 * 2**20


@dataclass
class Refusal:
    """A member that was not read, and why (``unsafe`` or ``oversized``)."""

    name: str
    kind: str
    why: str


@dataclass
class TarScan:
    """What one pass over a tar found besides its members: refusals, truncation, digest."""

    refused: list[Refusal] = field(default_factory=list)
    truncated: str | None = None  # why reading stopped early, None when the tar ended cleanly
    sha256: str = ""
    bytes: int = 0


def unsafe_reason(info: tarfile.TarInfo) -> str | None:
    """Why a member must not be read (None when it is a plain file with a relative name)."""
    name = info.name
    if name.startswith(("/", "\\")) or (len(name) > 1 and name[1] == ":"):
        return "absolute path"
    if ".." in PurePosixPath(name.replace("\\", "/")).parts:
        return "path climbs out with '..'"
    if info.issym() or info.islnk():
        return f"link to {info.linkname!r}"
    if info.ischr() or info.isblk():
        return "device file"
    if info.isfifo():
        return "FIFO"
    if info.isdir():
        return "directory"
    if not info.isfile():
        return f"not a regular file (type {info.type!r})"
    return None


def iter_members(
    path: str | Path, scan: TarScan, only: Callable[[str], bool] | None = None
) -> Iterator[tuple[str, bytes]]:
    """Yield (name, bytes) of every safe regular member, in tar order; ``scan`` collects
    refusals, truncation and the file's digest (complete once the iterator is exhausted).

    With ``only``, just the members it accepts are read and the rest are seeked over; no
    digest is formed and damage ends the iteration silently (another pass reports it)."""
    if not Path(path).is_file():  # a folder, a pipe (opening it waits for a writer), a device
        scan.truncated = "cannot be read (not a regular file)"
        return
    if only is not None:
        yield from _iter_some(path, only)
        return
    try:
        raw = open(path, "rb")  # closed by the with below, after the digest's last read
    except OSError as e:  # a file it may not read: damage, said with the shard's name
        scan.truncated = f"cannot be read ({e.strerror or e})"
        return
    with raw:
        reader = HashingReader(raw)
        try:
            # Stream mode ("r|"): sequential reads only, so the digest covers every byte.
            with tarfile.open(fileobj=reader, mode="r|") as tar:  # type: ignore[call-overload]
                for info in tar:
                    why = unsafe_reason(info)
                    if why is not None:
                        scan.refused.append(Refusal(info.name, "unsafe", why))
                        continue
                    if info.size > MAX_MEMBER_BYTES:
                        scan.refused.append(
                            Refusal(info.name, "oversized", f"{info.size} bytes > {MAX_MEMBER_BYTES} allowed")
                        )
                        continue
                    member = tar.extractfile(info)
                    if member is None:  # pragma: no cover - regular files always have data
                        continue
                    data = member.read()
                    if len(data) != info.size:
                        raise tarfile.ReadError(f"member {info.name!r} ends after {len(data)} of {info.size} bytes")
                    yield info.name, data
                end = tar.offset
            raw_end = tar_end_problem(raw, end)
            if raw_end is not None:
                scan.truncated = raw_end
        except (tarfile.TarError, EOFError, OSError) as e:
            scan.truncated = f"{e or type(e).__name__} (after {reader.size} bytes)"
        # Whatever follows the end-of-archive blocks still belongs to the file's digest.
        while reader.read(1 << 20):
            pass
        scan.sha256 = reader.sha256.hexdigest()
        scan.bytes = reader.size


def _iter_some(path: str | Path, only: Callable[[str], bool]) -> Iterator[tuple[str, bytes]]:
    """The safe regular members ``only`` accepts, read by seeking (random-access tar mode)."""
    try:
        with tarfile.open(path, mode="r:") as tar:
            for info in tar:
                if not only(info.name) or unsafe_reason(info) is not None or info.size > MAX_MEMBER_BYTES:
                    continue
                member = tar.extractfile(info)
                data = member.read() if member is not None else b""
                if len(data) != info.size:
                    return
                yield info.name, data
    except (tarfile.TarError, EOFError, OSError):
        return
