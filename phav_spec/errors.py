"""The one exception type for user errors: bad θ files, malformed recipes, corrupt inputs."""

from __future__ import annotations


class PhavUserError(Exception):
    """A problem with the user's input, reported as one line naming the file and field.

    The CLI prints ``str(error)`` and exits with code 2; a traceback is reserved for bugs.
    """

    def __init__(self, message: str, *, source: str | None = None, field: str | None = None):
        self.source = source
        self.field = field
        self.detail = message
        parts = [p for p in (source, field) if p]
        prefix = ": ".join(parts)
        super().__init__(f"{prefix}: {message}" if prefix else message)
