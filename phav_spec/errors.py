"""The one exception type for user errors: bad θ files, malformed recipes, corrupt inputs."""

from __future__ import annotations

import json
import re
from typing import Any, TypeVar

from pydantic import BaseModel, ValidationError


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


_PATH_PREFIX = re.compile(r"^([A-Za-z_]\w*(?:\.\w+)*): (.*)$", re.DOTALL)


def format_validation_error(error: ValidationError) -> tuple[str, str]:
    """(field, message) of a pydantic error, in the words a user can act on.

    A misspelt key is reported before anything it causes to look missing, and a message
    that starts with a sub-path ("rows.walk: …") has that path joined onto the field.
    """
    errors = error.errors()
    first = min(errors, key=lambda e: e["type"] != "extra_forbidden")
    parts = [str(p) for p in first["loc"] if not _is_union_tag(p)]
    msg = first["msg"].removeprefix("Value error, ").removeprefix("Assertion failed, ")
    if first["type"] == "extra_forbidden":
        msg = "unknown key (misspelt?); remove it or check the spelling"
    elif first["type"] in _TYPE_ERRORS and "input" in first:
        got = first["input"]
        msg += f", got {type(got).__name__} {got!r}"
        if isinstance(got, str):
            msg += "; write numbers without quotes"
    elif first["type"] == "missing":
        msg = "missing required field"
    while (m := _PATH_PREFIX.match(msg)) is not None:
        parts.append(m.group(1))
        msg = m.group(2)
    more = len(errors) - 1
    if more:
        msg += f" (+{more} more error{'s' if more > 1 else ''})"
    return ".".join(parts), msg


#: pydantic's errors for a value of the wrong JSON type: the message names what was written.
_TYPE_ERRORS = frozenset({"int_type", "float_type", "bool_type", "string_type", "int_from_float"})


def _is_union_tag(part: object) -> bool:
    """Pydantic inserts union member tags into error locations; users never wrote them."""
    return isinstance(part, str) and (part in ("uniform", "triangular") or "[" in part or "function-" in part)


M = TypeVar("M", bound=BaseModel)


def _json_text(data: Any, source: str) -> str:
    """``data`` as JSON text; numpy scalars (a row read with Arrow or pandas) as the numbers
    they hold, anything else JSON has no type for a user error naming its type."""

    def scalar(value: Any) -> Any:
        if hasattr(value, "item") and getattr(value, "shape", None) == ():
            return value.item()
        raise TypeError(f"a value of type {type(value).__name__} has no JSON form")

    try:
        return json.dumps(data, default=scalar)
    except (TypeError, ValueError) as e:
        raise PhavUserError(str(e), source=source) from None


def validate_user_data(model: type[M], data: Any, *, source: str, strict: bool = False) -> M:
    """``model.model_validate(data)``, with a failure as a PhavUserError naming source and field.

    ``strict`` reads ``data`` as the JSON it came from, with JSON's types as written: ``"30"``
    is no integer and ``30.5`` no string (pydantic's lax mode would take both), while an
    array is still a tuple."""
    try:
        if strict:
            return model.model_validate_json(_json_text(data, source), strict=True)
        return model.model_validate(data)
    except ValidationError as e:
        field, msg = format_validation_error(e)
        raise PhavUserError(msg, source=source, field=field or None) from None
