"""What every phav command shares: user errors as one line and exit code 2, rich consoles."""

from __future__ import annotations

import sys
from collections.abc import Callable

from rich.console import Console

from phav_spec.errors import PhavUserError

console = Console(highlight=False)
err_console = Console(stderr=True, highlight=False)

#: Exit codes: 0 fine, 1 checks found problems, 2 bad input or usage.
EXIT_FINDINGS = 1
EXIT_USER_ERROR = 2


def run_app(app: Callable[[], object]) -> None:
    """Run a Typer app; a PhavUserError becomes one line on stderr and exit code 2."""
    try:
        app()
    except PhavUserError as e:
        err_console.print(f"[bold red]error:[/] {e}", soft_wrap=True)
        sys.exit(EXIT_USER_ERROR)
    except KeyboardInterrupt:
        err_console.print("interrupted; finished files are intact (writes are atomic)")
        sys.exit(130)
