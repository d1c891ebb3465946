"""The filesystem edge of phav_spec: reading user files with one-line errors, and atomic writes."""

from __future__ import annotations

import contextlib
import errno
import hashlib
import json
import os
import re
import secrets
import stat
import tempfile
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import TYPE_CHECKING, Any, BinaryIO

from phav_spec.errors import PhavUserError

if TYPE_CHECKING:
    import pyarrow as pa


def read_text(path: str | os.PathLike[str], *, hint: str = "check the path") -> str:
    """A UTF-8 text file's contents (a pipe's too: ``<(…)``, ``/dev/stdin``); a missing or
    unreadable file, or a device or socket (``/dev/zero`` never ends), is a PhavUserError."""
    p = Path(path)
    try:
        if p.exists() and not (p.is_file() or p.is_dir() or stat.S_ISFIFO(p.stat().st_mode)):
            raise PhavUserError("not a file or a pipe (a device or a socket)", source=str(path))
        return p.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise PhavUserError(f"no such file; {hint}", source=str(path)) from None
    except UnicodeDecodeError:
        raise PhavUserError(f"not UTF-8 text{_what_binary(p)}", source=str(path)) from None
    except OSError as e:
        raise PhavUserError(f"cannot read: {e.strerror}", source=str(path)) from None


#: What a binary file phav writes starts with, and what it is (for a text file's error).
_MAGIC = ((0, b"PAR1", "a Parquet table"), (0, b"\x89PNG", "a PNG image"), (257, b"ustar", "a tar shard"),
          (0, b"PK\x03\x04", "a zip archive"))  # fmt: skip


def _what_binary(path: Path) -> str:
    """``": it is a Parquet table"`` and the like, where the file's first bytes say what it is."""
    try:
        with open(path, "rb") as fh:
            head = fh.read(262)
    except OSError:
        return ""
    return next((f": it is {what}" for at, magic, what in _MAGIC if head[at : at + len(magic)] == magic), "")


def tar_end_problem(raw: BinaryIO, offset: int) -> str | None:
    """None when a zero block (tar's end-of-archive marker) follows the last member at
    ``offset``; otherwise why not. A tar cut at a member boundary, or a header damaged after
    the first, reads like a shorter complete tar to ``tarfile``: only the marker tells."""
    position = raw.tell()
    raw.seek(offset)
    block = raw.read(512)  # tarfile.BLOCKSIZE
    raw.seek(position)
    if len(block) < 512 or block.count(0) != 512:
        return f"no end-of-archive marker after the last member (at byte {offset})"
    return None


def read_parquet(path: str | os.PathLike[str], columns: list[str] | None = None) -> pa.Table:
    """One Parquet file (``columns`` of it, or all) as a table, its schema metadata kept. Read
    through ``ParquetFile``: ``pq.read_table`` goes through ``pyarrow.dataset``, whose import
    costs a short command about 0.4 s. pyarrow's own errors pass through."""
    import pyarrow.parquet as pq  # phav_spec imports light (DESIGN.md): pyarrow only when a table is read or written

    with pq.ParquetFile(path) as f:
        return f.read(columns=columns)


class _DuplicateKey(ValueError):
    pass


def _no_duplicate_keys(pairs: list[tuple[str, Any]]) -> dict[str, Any]:
    """A JSON object's members, refusing a key written twice (the last would silently win)."""
    out: dict[str, Any] = {}
    for key, value in pairs:
        if key in out:
            raise _DuplicateKey(key)
        out[key] = value
    return out


def parse_json_object(text: str | bytes, *, source: str) -> dict[str, Any]:
    """A JSON object from text; anything else is a PhavUserError naming the line, and a key
    written twice one naming the key."""
    if not isinstance(text, str | bytes | bytearray):  # a table's empty cell, read as None
        raise PhavUserError(f"expected a JSON object, got {'nothing' if text is None else type(text).__name__}",
                            source=source)  # fmt: skip
    try:
        data = json.loads(text, object_pairs_hook=_no_duplicate_keys)
    except json.JSONDecodeError as e:
        raise PhavUserError(f"invalid JSON at line {e.lineno} column {e.colno}: {e.msg}", source=source) from None
    except RecursionError:
        raise PhavUserError("invalid JSON: nested too deeply", source=source) from None
    except _DuplicateKey as e:
        raise PhavUserError("key written twice", source=source, field=str(e)) from None
    except ValueError as e:  # Python's limit on an integer's digits
        raise PhavUserError(f"invalid JSON: {str(e).splitlines()[0]}", source=source) from None
    if not isinstance(data, dict):
        raise PhavUserError(f"expected a JSON object, got {type(data).__name__}", source=source)
    return data


def nested(a: str | os.PathLike[str], b: str | os.PathLike[str]) -> bool:
    """True when two paths are one directory or one holds the other (symbolic links resolved):
    writing into one would then write into, or over, the other."""
    x, y = Path(a).resolve(), Path(b).resolve()
    return x == y or x in y.parents or y in x.parents


class WriteError(PhavUserError):
    """A write that failed (full disk, file size limit, read-only place…), said in words a
    user can act on; ``errno`` is the operating system's code."""

    def __init__(self, error: OSError, target: str, hint: str = ""):
        self.error = error
        self.errno = error.errno
        if error.errno in (errno.ENOSPC, errno.EDQUOT):
            what = "the disk is full"
        elif error.errno == errno.EFBIG:
            what = "a file size limit was reached"
        elif error.errno in (errno.EACCES, errno.EPERM, errno.EROFS):
            what = "the place is not writable"
        else:
            what = f"cannot write: {error.strerror or error}"
        super().__init__(f"{what}; {hint}" if hint else what, source=target)
        self.target, self.hint = target, hint

    def with_hint(self, hint: str) -> WriteError:
        """The same error, followed by what to do about it."""
        return WriteError(self.error, self.target, hint)

    def __reduce__(self):  # crosses process boundaries intact (pool workers)
        return (WriteError, (self.error, self.target, self.hint))


@contextlib.contextmanager
def atomic_write(path: str | os.PathLike[str], *, sweep: bool = False) -> Iterator[Path]:
    """Yield a temporary path beside ``path``; on success it is fsynced and renamed over it.

    A reader never sees a half-written file, and an interrupted write leaves the previous
    file (or none) and no temporary behind. A killed process (SIGKILL) cannot remove its
    temporary: with ``sweep``, those ``path``'s earlier writers left are removed first, when
    no write into its folder is under way (every write holds a shared lock on the folder).
    """
    target = Path(path)
    tmp = target.with_name(f".{target.name}.{secrets.token_hex(8)}.tmp")
    folder = None
    try:
        _check_writable_place(target)
        target.parent.mkdir(parents=True, exist_ok=True)
        folder = _writing_in(target, sweep)
        yield tmp
        fd = os.open(tmp, os.O_RDONLY)  # the writer must have created it: no empty files
        try:
            os.fsync(fd)
        finally:
            os.close(fd)
        os.replace(tmp, target)
    except OSError as e:
        with contextlib.suppress(OSError):  # the temporary may never have been made
            os.unlink(tmp)
        raise WriteError(e, str(target)) from None
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise
    finally:
        if folder is not None:
            os.close(folder)  # lets the folder's lock go
    _fsync_directory(target.parent)


def _writing_in(target: Path, sweep: bool) -> int | None:
    """Hold a shared lock on ``target``'s folder for a write into it (None where the folder
    cannot be locked); with ``sweep``, first remove ``atomic_write``'s temporaries of
    ``target`` if the folder can be locked alone: then no writer is alive to own them."""
    import fcntl  # POSIX only, as the rest of phav's locking

    try:
        fd = os.open(target.parent, os.O_RDONLY | os.O_DIRECTORY)
    except OSError:
        return None
    try:
        if sweep:
            with contextlib.suppress(BlockingIOError):
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
                for name in sorted(os.listdir(target.parent)):
                    if temporary_of(name) == target.name:
                        with contextlib.suppress(FileNotFoundError):
                            os.unlink(target.parent / name)
        fcntl.flock(fd, fcntl.LOCK_SH)
    except OSError:
        os.close(fd)
        return None
    return fd


#: ``atomic_write``'s temporaries: ``.{name}.{16 hex}.tmp``.
_TEMPORARY = re.compile(r"\.(.+)\.[0-9a-f]{16}\.tmp")


def temporary_of(name: str) -> str | None:
    """The file name whose ``atomic_write`` temporary ``name`` is, None if it is none."""
    match = _TEMPORARY.fullmatch(name)
    return match.group(1) if match else None


def check_output_dir(out: Path, *, field: str = "--out") -> None:
    """Refuse, before any work, an output folder that is a file or lies below one (the first
    write would fail only after the work it was to keep). A place it cannot look into is left
    to the first write to report."""
    try:
        if out.exists() and not out.is_dir():
            raise PhavUserError("exists and is not a directory", source=str(out), field=field)
        above = _file_above(out)
    except OSError:
        return
    if above is not None:
        raise PhavUserError(f"{above} is not a directory", source=str(out), field=field)


#: The files of a dataset directory (``phav generate``) or a release besides its shards.
DATASET_FILES = ("manifest.json", "release.json", "recipes.parquet", "cameras.parquet", "people.parquet", "theta.yaml")


def holds_dataset(folder: Path) -> bool:
    """Whether ``folder`` is a finished dataset or a release (its manifest or release.json)."""
    return (folder / "manifest.json").is_file() or (folder / "release.json").is_file()


#: How a file of each kind a command writes begins (after white space, in any case for text):
#: an existing file that begins otherwise is not an earlier output but something else.
FILE_SIGNATURES: dict[str, tuple[bytes, ...]] = {
    "Parquet": (b"PAR1",),
    "PNG": (b"\x89PNG\r\n\x1a\n",),
    "GIF": (b"GIF87a", b"GIF89a"),
    "JSON": (b"{", b"["),
    "HTML": (b"<!doctype html", b"<html"),
}
#: The article each kind's name takes, where it is not "a".
_ARTICLE = {"HTML": "an"}


def _begins_as(path: Path, kind: str) -> bool:
    """Whether the file at ``path`` is empty or begins as a file of ``kind`` does."""
    with path.open("rb") as fh:
        head = fh.read(4096)
    if kind in ("JSON", "HTML"):  # text: a byte-order mark and blanks may come first
        head = head.removeprefix(b"\xef\xbb\xbf").lstrip().lower()
    while kind == "HTML" and head.startswith(b"<!--") and b"-->" in head:  # and comments, before the page
        head = head[head.index(b"-->") + 3 :].lstrip()
    return not head or head.startswith(FILE_SIGNATURES[kind])


def check_output_file(path: str | os.PathLike[str], *, field: str, kind: str | None = None) -> None:
    """Refuse, before any work, an output file that cannot be one: a directory, a device or a
    pipe, or a place below a file (its write would fail only after the work it was to keep);
    one that is a dataset's own file (its manifest, a table, a shard), which a report, a
    sheet or a recipe would replace; and, given the ``kind`` written (``FILE_SIGNATURES``),
    an existing file of another kind (notes, a script), which is not an earlier output."""
    target = Path(path)
    try:
        _check_writable_place(target)
        _check_can_create_in(target.parent)
        folder = target.parent
        dataset = holds_dataset(folder)
    except OSError as e:
        raise PhavUserError(f"cannot be written here: {e.strerror}", source=str(path), field=field) from None
    if dataset and (target.name in DATASET_FILES or target.suffix == ".tar"):
        raise PhavUserError("is a file of the dataset in that directory; write elsewhere", source=str(path),
                            field=field)  # fmt: skip
    try:
        other = kind is not None and target.is_file() and not _begins_as(target, kind)
    except OSError as e:
        raise PhavUserError(f"cannot be read to see what it holds: {e.strerror}", source=str(path),
                            field=field) from None  # fmt: skip
    if other:
        raise PhavUserError(f"exists and is not {_ARTICLE.get(kind, 'a')} {kind} file, which this would replace; "
                            "remove it or write elsewhere", source=str(path), field=field)  # fmt: skip


def _check_can_create_in(folder: Path) -> None:
    """Refuse a folder (or, where it is yet to be made, the nearest one above it) in which
    this process cannot create a file: a read-only file system, a folder not its own, a
    kernel's (/proc, /sys). Tried with a file made and removed at once: permission bits do
    not tell (root passes them)."""
    existing = next((p for p in (folder, *folder.parents) if p.exists()), None)
    if existing is None or not existing.is_dir():
        return
    try:
        fd, probe = tempfile.mkstemp(prefix=".phav-probe.", suffix=".tmp", dir=existing)
    except OSError as e:
        raise PermissionError(e.errno, f"the place is not writable ({e.strerror or e})") from None
    os.close(fd)
    os.unlink(probe)


def _file_above(path: Path) -> Path | None:
    """The nearest existing folder above ``path`` if it is not a folder (a file): nothing can
    be made below it."""
    for parent in path.parents:
        if parent.exists():
            return None if parent.is_dir() else parent
    return None


def _check_writable_place(target: Path) -> None:
    """Refuse, before anything is written, a target that is a directory or some other thing
    than a file (a device, a pipe: renaming over it would replace it), and one below a file."""
    if target.is_dir():
        raise IsADirectoryError(errno.EISDIR, "Is a directory")
    if target.exists() and not target.is_file():
        raise FileExistsError(errno.EEXIST, "Not a regular file (a device, a pipe or a socket)")
    above = _file_above(target)
    if above is not None:
        raise NotADirectoryError(errno.ENOTDIR, f"Not a directory: {above}")


def _fsync_directory(directory: Path) -> None:
    """Persist the rename itself; best effort, as some platforms cannot open directories."""
    try:
        fd = os.open(directory, os.O_RDONLY)
    except OSError:
        return
    try:
        os.fsync(fd)
    except OSError:
        pass
    finally:
        os.close(fd)


#: Bytes read at a time when hashing a file.
_HASH_CHUNK = 1 << 20


def file_sha256(path: Path, advance: Callable[[int], None] | None = None) -> str:
    """sha256 hex digest of a file, read in 1 MiB chunks (``advance`` gets each chunk's bytes)."""
    digest = hashlib.sha256()
    with open(path, "rb") as fh:
        while chunk := fh.read(_HASH_CHUNK):
            digest.update(chunk)
            if advance is not None:
                advance(len(chunk))
    return digest.hexdigest()
