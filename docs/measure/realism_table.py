"""Markdown tables of realism figures from `phav-validate --checks realism --json` reports,
one column per report (docs/realism-gap.md): the headline figures, people per view, the
world per our class for each judge, and the street model by weather, day phase and light.

    python docs/measure/realism_table.py today=realism-today.json capsules=realism-capsules.json
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from phav_validators.realism.check import HEADLINES, MIN_VIDEOS, VIEWS


def realism_numbers(path: Path) -> dict:
    """The realism check's numbers of the first dataset of a JSON report."""
    report = json.loads(path.read_text())
    [check] = [c for c in report["datasets"][0]["checks"] if c["name"] == "realism"]
    return check["numbers"]


def cell(fig: dict | None) -> str:
    if fig is None:
        return "—"
    if fig["ci95"] is None:  # from one video
        return f"{fig['value']:.2f} (one video)"
    low, high = fig["ci95"]
    return f"{fig['value']:.2f} ({low:.2f}–{high:.2f})"


def table(title: str, rows: list[tuple[str, str]], runs: dict[str, dict]) -> list[str]:
    """A table whose rows are (label, figure key) and whose columns are the runs."""
    out = [f"| {title} | " + " | ".join(runs) + " |", "| --- |" + " ---: |" * len(runs)]
    for label, key in rows:
        figs = [run["figures"].get(key) for run in runs.values()]
        if any(f is not None for f in figs):
            out.append(f"| {label} | " + " | ".join(cell(f) for f in figs) + " |")
    return out


def _show(lines: list[str]) -> None:
    """A table, unless it has no rows (no figure of its kind in any report)."""
    if len(lines) > 2:
        print("\n".join(lines) + "\n")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("runs", nargs="+", help="name=report.json")
    args = parser.parse_args()
    runs = {name: realism_numbers(Path(path)) for name, path in (r.split("=", 1) for r in args.runs)}
    lines = ["| judged | " + " | ".join(runs) + " |", "| --- |" + " ---: |" * len(runs),
             "| frames (videos), protagonists | " + " | ".join(
                 f"{r['frames']} ({r['videos']}), {r['people']}" for r in runs.values()) + " |"]  # fmt: skip
    lines += table("headline", [(n, k) for n, k in HEADLINES.items()], runs)[2:]
    print("\n".join(lines) + "\n")
    people = [(f"{v}: found / PCK 0.2 / swapped", v) for v in ("all", *VIEWS)]
    rows = []
    for label, v in people:
        group = v if v == "all" else f"view={v}"
        rows += [(f"{label.split(':')[0]} — found", f"person_found|{group}"),
                 (f"{label.split(':')[0]} — PCK 0.2", f"person_pck_0.2|{group}"),
                 (f"{label.split(':')[0]} — left/right swapped", f"person_swap|{group}")]  # fmt: skip
    _show(table("people (view)", rows, runs))
    for judge in ("pascal_voc", "cityscapes"):
        ours = sorted({k.split("|")[2] for r in runs.values() for k in r["figures"] if k.startswith(f"iou|{judge}|")})
        rows = [(c, f"iou|{judge}|{c}|all") for c in ours]
        _show(table(f"{judge}: IoU of our class", rows, runs))
    # The street model per weather, day phase and in fair daylight, the light it was trained in.
    groups = sorted({k.split("|")[1] for r in runs.values() for k in r["figures"] if k.startswith("cityscapes_miou|")})
    rows = [(g, f"cityscapes_miou|{g}") for g in groups]
    rows += [(f"light=fair_day: IoU of {m}", f"class_iou|cityscapes|{m}|light=fair_day")
             for m in ("road", "building", "vegetation", "terrain", "car", "sky", "person")]  # fmt: skip
    _show(table("cityscapes: mIoU by conditions", rows, runs))
    # Per environment and per action (where at least MIN_VIDEOS videos were judged).
    for judge, c in (("pascal_voc", "person"), ("cityscapes", "person"), ("cityscapes", "road"),
                     ("cityscapes", "building"), ("cityscapes", "terrain")):  # fmt: skip
        envs = sorted({k.split("|")[3] for r in runs.values() for k in r["figures"]
                       if k.startswith(f"iou|{judge}|{c}|environment=")})  # fmt: skip
        rows = [(e.removeprefix("environment="), f"iou|{judge}|{c}|{e}") for e in envs]
        _show(table(f"{judge}: IoU of {c}, by environment", rows, runs))
    actions = sorted({k.split("|")[1] for r in runs.values() for k, f in r["figures"].items()
                      if k.startswith("person_pck_0.2|action=") and f["videos"] >= MIN_VIDEOS})  # fmt: skip
    rows = [(a.removeprefix("action="), f"person_pck_0.2|{a}") for a in actions]
    _show(table(f"PCK 0.2 by action (at least {MIN_VIDEOS} videos)", rows, runs))


if __name__ == "__main__":
    main()
