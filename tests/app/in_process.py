"""Run ``phav`` or ``phav-validate`` inside the test process, as their console scripts do.

``run_app`` is the scripts' own entry: a PhavUserError becomes one line on stderr and exit
code 2. Running it in-process saves a Python start and the imports (torch, the motion
catalogue) of a subprocess per call; ``tests.helpers.run_cli`` keeps the subprocess for the
tests of what only a real process shows.
"""

from __future__ import annotations

import io
from contextlib import redirect_stderr, redirect_stdout
from dataclasses import dataclass

from phav_app.cli import app as phav_app
from phav_app.console import run_app
from phav_app.validate_cli import app as validate_app


@dataclass(frozen=True)
class Ran:
    """What a command left: its exit code and what it printed."""

    returncode: int
    stdout: str
    stderr: str


def run_in_process(*args: str) -> Ran:
    """``phav ARGS`` (``phav-validate ARGS`` when the first arg is 'validate!'), in this process."""
    if args[:1] == ("validate!",):
        app, prog, rest = validate_app, "phav-validate", args[1:]
    else:
        app, prog, rest = phav_app, "phav", args
    out, err = io.StringIO(), io.StringIO()
    code = 0
    with redirect_stdout(out), redirect_stderr(err):  # the rich consoles write to sys.stdout / sys.stderr
        try:
            run_app(lambda: app(list(rest), prog_name=prog))
        except SystemExit as e:  # click exits 0 after a command; run_app exits 2 on a user error
            code = e.code if isinstance(e.code, int) else int(e.code is not None)
    return Ran(code, out.getvalue(), err.getvalue())
