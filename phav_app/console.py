"""What every phav command shares: user errors as one line and exit code 2, rich consoles,
progress bars, and validator results as rich tables (histograms against θ, tests, findings,
the protagonist's framing)."""

from __future__ import annotations

import signal
import sys
import threading
from collections.abc import Callable

import typer
from rich.console import Console
from rich.markup import escape
from rich.progress import Progress
from rich.table import Table
from rich.text import Text

from phav_spec.errors import PhavUserError
from phav_validators.checks.distribution import DistributionResult
from phav_validators.findings import Report, figure_text
from phav_validators.framing import FRAMING_BINS, FramingResult

# Piped output (CI logs, files) gets wide lines instead of rich's 80-column default, so
# tables of numbers are never cut off.
console = Console(highlight=False, width=None if sys.stdout.isatty() else 200)
err_console = Console(stderr=True, highlight=False, width=None if sys.stderr.isatty() else 200)

#: Exit codes: 0 fine, 1 checks found problems, 2 bad input or usage.
EXIT_FINDINGS = 1
EXIT_USER_ERROR = 2


class Terminated(BaseException):
    """SIGTERM, raised in the main thread so that the writes under way clean up after
    themselves as they do for Ctrl-C (an atomic write removes its temporary)."""


def _raise_terminated(signum: int, frame: object) -> None:
    raise Terminated


def run_app(app: Callable[..., object]) -> None:
    """Run a Typer app (called with ``standalone_mode=False``): a PhavUserError, or an option
    or argument Typer refuses, becomes one line on stderr and exit code 2; Ctrl-C and SIGTERM
    say what they left behind and exit 130 and 143."""
    previous = None
    if threading.current_thread() is threading.main_thread():  # Python takes signals there only
        previous = signal.signal(signal.SIGTERM, _raise_terminated)
    try:
        code = app(standalone_mode=False)
    except PhavUserError as e:
        _error_line(str(e))
        sys.exit(EXIT_USER_ERROR)
    except _CLICK_ERROR as e:  # `--videos abc`, a missing argument, an unknown option
        if type(e).__name__ != "NoArgsIsHelpError":  # a bare command group: Typer printed its help
            ctx = getattr(e, "ctx", None)
            _error_line(e.format_message() + (f" (see {ctx.command_path} --help)" if ctx is not None else ""))
        sys.exit(e.exit_code)
    except typer.Abort:
        err_console.print("aborted")
        sys.exit(1)
    except KeyboardInterrupt:
        code = _INTERRUPTED
    except Terminated:
        err_console.print("terminated; finished files are intact (writes are atomic)")
        sys.exit(_TERMINATED)
    finally:
        if previous is not None:
            signal.signal(signal.SIGTERM, previous)
    if code == _INTERRUPTED:  # Typer turns Ctrl-C inside a command into this exit code
        err_console.print("interrupted; finished files are intact (writes are atomic)")
    sys.exit(code if isinstance(code, int) else 0)


#: The exit codes of a run stopped by Ctrl-C (128 + SIGINT) and by SIGTERM (128 + SIGTERM).
_INTERRUPTED = 130
_TERMINATED = 143
#: Click's base of the errors it reports for a command line (Typer may vendor Click, so it is
#: found through the one Typer exports).
_CLICK_ERROR = next(c for c in typer.BadParameter.__mro__ if c.__name__ == "ClickException")


def _error_line(message: str) -> None:
    err_console.print(Text.assemble(("error:", "bold red"), " ", message), soft_wrap=True)


def bar_tasks(bar: Progress) -> Callable[[str, int], Callable[[int], None]]:
    """A progress factory over ``bar``: ``factory(description, total)`` adds a task and
    returns its ``advance(n)`` (the shape library code takes as ``progress``)."""

    def factory(description: str, total: int) -> Callable[[int], None]:
        task = bar.add_task(description, total=total)
        return lambda n: bar.advance(task, n)

    return factory


def print_distribution(result: DistributionResult, console: Console, *, max_values: int = 12) -> None:
    """Per variable: observed against expected marginal, then the tests per conditional table."""
    for s in result.summaries:
        n = int(s.observed.sum())
        table = Table(title=f"{s.variable} ({s.applies_to}, n = {n})", title_justify="left")
        for col in ("value", "observed", "expected", "obs %", "exp %"):
            table.add_column(col, justify="left" if col == "value" else "right")
        order = sorted(range(len(s.values)), key=lambda i: -s.expected[i])
        shown = [i for i in order if s.expected[i] > 0 or s.observed[i] > 0]
        for i in shown[:max_values]:
            exp = s.expected[i] * n
            style = "bold red" if s.expected[i] == 0 and s.observed[i] > 0 else None
            table.add_row(
                str(s.values[i]), f"{s.observed[i]}", f"{exp:.1f}",
                f"{100 * s.observed[i] / max(n, 1):.2f}", f"{100 * s.expected[i]:.2f}", style=style,
            )  # fmt: skip
        if len(shown) > max_values:
            table.add_row(f"… {len(shown) - max_values} more", "", "", "", "")
        console.print(table)

    tests = Table(title="goodness of fit (Holm-corrected)", title_justify="left")
    for col in ("variable", "tests", "worst condition", "worst p", "impossible", "status"):
        tests.add_column(col, justify="left" if col in ("variable", "worst condition", "status") else "right")
    by_var: dict[str, list] = {}
    for t in result.tests:
        by_var.setdefault(t.variable, []).append(t)
    for var, ts in by_var.items():
        tested = [t for t in ts if t.tested]
        worst = min(tested or ts, key=lambda t: t.p_value)
        impossible = sum(t.impossible for t in ts if t.condition == "marginal") or sum(t.impossible for t in ts)
        bad = any(t.rejected for t in ts)
        status = "[red]FAIL[/]" if bad else ("[green]ok[/]" if tested else "[yellow]too few to test[/]")
        tests.add_row(
            var, f"{len(tested)}" + (f" (+{len(ts) - len(tested)} too small)" if len(tested) < len(ts) else ""),
            worst.condition if tested else "", f"{worst.p_value:.3g}" if tested else "", str(impossible), status,
        )  # fmt: skip
    console.print(tests)
    console.print(
        f"mean duration: observed {result.mean_duration:.3f} s, exact {result.expected_mean_duration:.3f} s "
        f"over {result.n_videos} videos"
    )


def print_report(report: Report, console: Console, *, limit: int = 40) -> None:
    """Notes, then findings (the first ``limit``), or a line saying all checks passed."""
    for note in report.all_notes():
        console.print(f"[yellow]note:[/] {escape(note)}", soft_wrap=True)
    if report.ok:
        console.print("[bold green]all checks passed[/]")
        return
    console.print(f"[bold red]{len(report.findings)} finding(s)[/]")
    for f in report.findings[:limit]:
        where = " ".join(x for x in (f.file, f.video_id) if x)
        console.print(
            f"  [red]{f.reason.value}[/] {escape(where + ': ' if where else '')}{escape(f.message)}", soft_wrap=True
        )
    if len(report.findings) > limit:
        console.print(f"  … {len(report.findings) - limit} more")


def print_framing(result: FramingResult, console: Console, *, source: str = "people.parquet") -> None:
    """Per camera: frames with the protagonist in view and its height's quartiles, then the
    height histogram (share of each camera's frames per 10 % of the frame height)."""
    if not result.groups:
        console.print(f"protagonist framing: no video of {escape(source)} has a recipe")
        return
    console.print(
        f"protagonist framing ({escape(source)}): in view = any pixel in the instance modality; height = "
        "the box of those pixels / the frame height, over the frames in view",
        soft_wrap=True,
    )
    table = Table(title="protagonist framing per camera", title_justify="left")
    for col in ("camera", "videos", "frames", "in view", "Q1", "median", "Q3", "median px"):
        table.add_column(col, justify="left" if col == "camera" else "right")
    for name, g in result.groups.items():
        q1, q2, q3 = g.quantiles()
        table.add_row(
            name, str(g.n_videos), f"{g.n_frames:,}", figure_text(g.in_view_share, ".1%"), figure_text(q1, ".1%"),
            figure_text(q2, ".1%"), figure_text(q3, ".1%"), figure_text(g.median_px, ".0f"),
            style="bold" if name == "all" else None,
        )  # fmt: skip
    console.print(table)
    hist = Table(title="protagonist height histogram (share of frames)", title_justify="left")
    hist.add_column("height", justify="left")
    for name in result.groups:
        hist.add_column(name, justify="right")
    hist.add_column("", justify="left")
    shares = {name: g.histogram() for name, g in result.groups.items()}
    top = max(max(float(s.max()) for s in shares.values()), 1e-9)
    overall = shares["all"]
    for b in range(len(FRAMING_BINS) - 1):
        label = f"{FRAMING_BINS[b]:.0%}–{FRAMING_BINS[b + 1]:.0%}"
        bar = "█" * round(30 * overall[b] / top)
        hist.add_row(label, *(f"{s[b]:.1%}" for s in shares.values()), bar)
    console.print(hist)
