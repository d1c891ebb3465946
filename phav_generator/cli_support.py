"""What every phav command shares: user errors as one line and exit code 2, rich consoles."""

from __future__ import annotations

import sys
from collections.abc import Callable

from rich.console import Console
from rich.progress import Progress
from rich.text import Text

from phav_spec.errors import PhavUserError

# Piped output (CI logs, files) gets wide lines instead of rich's 80-column default, so
# tables of numbers are never cut off.
console = Console(highlight=False, width=None if sys.stdout.isatty() else 200)
err_console = Console(stderr=True, highlight=False, width=None if sys.stderr.isatty() else 200)

#: Exit codes: 0 fine, 1 checks found problems, 2 bad input or usage.
EXIT_FINDINGS = 1
EXIT_USER_ERROR = 2


def run_app(app: Callable[[], object]) -> None:
    """Run a Typer app; a PhavUserError becomes one line on stderr and exit code 2."""
    try:
        app()
    except PhavUserError as e:
        err_console.print(Text.assemble(("error:", "bold red"), " ", str(e)), soft_wrap=True)
        sys.exit(EXIT_USER_ERROR)
    except KeyboardInterrupt:
        err_console.print("interrupted; finished files are intact (writes are atomic)")
        sys.exit(130)


def bar_tasks(bar: Progress) -> Callable[[str, int], Callable[[int], None]]:
    """A progress factory over ``bar``: ``factory(description, total)`` adds a task and
    returns its ``advance(n)`` (the shape library code takes as ``progress``)."""

    def factory(description: str, total: int) -> Callable[[int], None]:
        task = bar.add_task(description, total=total)
        return lambda n: bar.advance(task, n)

    return factory
