"""Integrity of a recipes table: every recipe validates, stable columns agree with the
recipe JSON, ids are unique, and every recipe names the θ it was sampled from."""

from __future__ import annotations

from collections import Counter

from phav_spec.errors import PhavUserError
from phav_spec.recipe import Recipe, parse_recipe
from phav_spec.recipe_table import COLUMNS, RECIPE_COLUMN, RecipeTable
from phav_spec.theta import Theta
from phav_validators.findings import Finding, Reason, Report


def check_recipe_table(rt: RecipeTable, theta: Theta | None, report: Report) -> dict[str, Recipe]:
    """Add findings to ``report``; returns the recipes that validated, by video id.

    With ``theta`` None (videos made from recipes alone) the θ hash is not compared."""
    source = str(rt.path)
    cols = {c.name: rt.column(c.name) for c in COLUMNS}
    texts = rt.column(RECIPE_COLUMN)
    add = report.add

    for reason, name in ((Reason.DUPLICATE_VIDEO, "video_id"), (Reason.DUPLICATE_VIDEO, "index")):
        dupes = [v for v, k in Counter(cols[name]).items() if k > 1]
        if dupes:
            add(Finding(reason, f"{len(dupes)} duplicated {name} values, e.g. {dupes[0]}", file=source))
    valid: dict[str, Recipe] = {}
    for row, text in enumerate(texts):
        vid = cols["video_id"][row]
        try:
            recipe = parse_recipe(text, source=f"{source}[{vid}]")
        except PhavUserError as e:
            add(Finding(Reason.RECIPE_INVALID, str(e), file=source, video_id=vid))
            continue
        valid.setdefault(recipe.video_id, recipe)
        if theta is not None and recipe.theta_hash != theta.hash:
            add(Finding(
                Reason.THETA_MISMATCH,
                f"recipe was sampled from θ {recipe.theta_hash[:12]}…, not {theta.hash[:12]}…",
                file=source, video_id=vid,
            ))  # fmt: skip
        for c in COLUMNS:
            if c.extract(recipe) != cols[c.name][row]:
                add(Finding(
                    Reason.COLUMN_MISMATCH,
                    f"column {c.name} = {cols[c.name][row]!r} but the recipe says {c.extract(recipe)!r}",
                    file=source, video_id=vid,
                ))  # fmt: skip
    return valid
