"""Rich rendering of validator results (histograms against θ, tests, findings)."""

from __future__ import annotations

from rich.console import Console
from rich.markup import escape
from rich.table import Table

from phav_validators.distribution import DistributionResult
from phav_validators.findings import Report


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
        worst = min(ts, key=lambda t: t.p_value)
        impossible = sum(t.impossible for t in ts if t.condition == "marginal") or sum(t.impossible for t in ts)
        bad = any(t.rejected for t in ts)
        tests.add_row(
            var, str(len(ts)), worst.condition, f"{worst.p_value:.3g}", str(impossible),
            "[red]FAIL[/]" if bad else "[green]ok[/]",
        )  # fmt: skip
    console.print(tests)
    console.print(
        f"mean duration: observed {result.mean_duration:.3f} s, exact {result.expected_mean_duration:.3f} s "
        f"over {result.n_videos} videos"
    )


def print_report(report: Report, console: Console, *, limit: int = 40) -> None:
    """Notes, then findings (the first ``limit``), or a line saying all checks passed."""
    for note in report.notes + report.overflow_notes():
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
