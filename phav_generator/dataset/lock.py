"""One run per dataset directory: an exclusive lock, and the temporaries a killed run left."""

from __future__ import annotations

import contextlib
import fcntl
import re
from collections.abc import Iterator
from pathlib import Path

from phav_spec.errors import PhavUserError

LOCK_FILE = "lock"
#: ``atomic_write``'s temporaries: ``.{name}.{16 hex}.tmp``.
_TEMPORARY = re.compile(r"\..+\.[0-9a-f]{16}\.tmp")


@contextlib.contextmanager
def exclusive(work: Path) -> Iterator[None]:
    """Hold the directory's lock: two runs writing one directory would tear each other's files."""
    with open(work / LOCK_FILE, "a+b") as fh:
        try:
            fcntl.flock(fh, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            raise PhavUserError("another run is writing to this directory", source=str(work.parent)) from None
        yield


def remove_stale_temporaries(*folders: Path) -> None:
    """Temporaries a killed run left behind (a live run holds the lock, so none is in use)."""
    for folder in folders:
        for path in folder.iterdir():
            if _TEMPORARY.fullmatch(path.name) and path.is_file():
                path.unlink()
