"""``phav-validate``: is a released dataset intact and distributed as θ says?

This release checks the recipes table (every recipe valid, columns consistent, ids unique,
θ recorded) and its distributions against θ's exact expectations. Shard, encoding,
physics, regeneration and learnability checks join as the generator grows.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from phav_generator.cli_support import EXIT_FINDINGS, console, run_app
from phav_spec.errors import PhavUserError
from phav_spec.recipe_table import read_recipe_table
from phav_spec.theta import load_theta

app = typer.Typer(name="phav-validate", add_completion=False, pretty_exceptions_enable=False)


@app.command()
def validate(
    path: Annotated[Path, typer.Argument(help="A dataset directory or its recipes.parquet.")],
    theta: Annotated[
        str | None,
        typer.Option(
            "--theta",
            help="θ the data must follow (default: the dataset's theta.yaml or the table's θ).",
        ),
    ] = None,
    alpha: Annotated[float, typer.Option(help="Family-wise significance level (Holm).")] = 1e-3,
    details: Annotated[bool, typer.Option("--details", help="Print per-variable histograms.")] = False,
) -> None:
    """Validate a PHAV dataset's recipes: integrity and distributions against θ."""
    from phav_validators.distribution import check_distributions
    from phav_validators.recipes import check_recipe_table
    from phav_validators.render import print_distribution, print_report

    table_path = path / "recipes.parquet" if path.is_dir() else path
    rt = read_recipe_table(table_path)
    if theta is None and path.is_dir() and (path / "theta.yaml").exists():
        theta = str(path / "theta.yaml")
    if theta is not None:
        th = load_theta(theta)
    elif rt.theta is not None:
        th = rt.theta
    else:
        raise PhavUserError("no θ recorded; pass --theta FILE", source=str(table_path), field="phav.theta")

    result = check_distributions(
        {name: rt.column(name) for name in rt.table.column_names},
        th,
        alpha=alpha,
        source=str(table_path),
    )
    report = result.report
    valid = check_recipe_table(rt, th, report)
    if details:
        print_distribution(result, console)
    failed = sum(t.rejected for t in result.tests)
    console.print(
        f"{table_path}: {rt.table.num_rows} recipes, {valid} valid; θ {th.name} {th.hash[:12]}…; "
        f"{len(result.tests)} goodness-of-fit tests, {failed} rejected; mean duration "
        f"{result.mean_duration:.3f} s (exact {result.expected_mean_duration:.3f} s)"
    )
    print_report(report, console)
    if not report.ok:
        raise typer.Exit(EXIT_FINDINGS)


def main() -> None:
    """Entry point of the `phav-validate` console script."""
    run_app(app)


if __name__ == "__main__":
    main()
