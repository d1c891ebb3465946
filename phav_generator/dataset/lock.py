"""One run per dataset directory: an exclusive lock, and the temporaries a killed run left."""

from __future__ import annotations

import contextlib
import fcntl
import os
from collections.abc import Iterator
from pathlib import Path
from typing import IO

from phav_spec.errors import PhavUserError
from phav_spec.files import temporary_of

LOCK_FILE = "lock"


@contextlib.contextmanager
def exclusive(work: Path) -> Iterator[None]:
    """Hold the directory's lock: two runs writing one directory would tear each other's files.

    ``work`` is made if missing. A run that finishes moves its work folder away while it
    still holds the lock, so a lock taken on a file no longer at ``work / LOCK_FILE`` is
    that finished run's: it is let go and the lock of the folder now there taken."""
    while True:
        work.mkdir(parents=True, exist_ok=True)
        fh = open(work / LOCK_FILE, "a+b")  # held open while the lock is
        try:
            try:
                fcntl.flock(fh, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:
                raise PhavUserError("another run is writing to this directory", source=str(work.parent)) from None
            if _same_file(fh, work / LOCK_FILE):
                yield
                return
        finally:
            fh.close()


def _same_file(fh: IO[bytes], path: Path) -> bool:
    held = os.fstat(fh.fileno())
    try:
        there = path.stat()
    except FileNotFoundError:
        return False
    return (held.st_dev, held.st_ino) == (there.st_dev, there.st_ino)


def remove_stale_temporaries(*folders: Path) -> None:
    """Temporaries a killed run left behind (a live run holds the lock, so none is in use)."""
    for folder in folders:
        for path in folder.iterdir():
            if temporary_of(path.name) is not None and path.is_file():
                path.unlink()
