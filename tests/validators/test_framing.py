"""The protagonist's framing (phav_validators.framing): measured from people.parquet, equal to
what the instance pixels show, and printed by `phav stats` and the phav-validate reports."""

from __future__ import annotations

import math
import re

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq
import pytest
from rich.console import Console

from phav_app.console import print_framing
from phav_app.validate_cli import print_summary
from phav_spec.encoding import instance_rgb
from phav_spec.errors import PhavUserError
from phav_spec.recipe_table import read_recipe_table
from phav_validators.checks.distribution import DistributionResult, VariableSummary
from phav_validators.checks.reproduce import shard_video_frames
from phav_validators.findings import MAX_PER_REASON, CheckResult, Finding, Reason, Report
from phav_validators.framing import FRAMING_BINS, FramingGroup, FramingResult, VideoFrame, measure_framing, read_framing
from phav_validators.options import DatasetReport
from phav_validators.report import report_html
from tests.helpers import invoke_cli

NAN = float("nan")


def _people(rows: list[tuple[str, int, int, float, float]]) -> pa.Table:
    """A people table of (video, person, pixels, y0, y1) rows (x0, x1 fixed)."""
    return pa.table({
        "video_id": [r[0] for r in rows],
        "frame": list(range(len(rows))),
        "person_id": [r[1] for r in rows],
        "pixels": [r[2] for r in rows],
        "bbox2d": [[10.0, r[3], 20.0, r[4]] for r in rows],
    })  # fmt: skip


def test_heights_in_view_and_groups_from_protagonist_rows() -> None:
    rows = [
        ("v1", 0, 50, 100.0, 200.0),  # 100 px of 256
        ("v1", 1, 999, 0.0, 256.0),  # not the protagonist
        ("v1", 0, 0, NAN, NAN),  # out of view
        ("v1", 0, 10, 0.0, 256.0),  # the whole height
        ("v2", 0, 40, 10.0, 74.0),  # 64 px of 128 (a smaller frame)
        ("v3", 0, 40, 0.0, 10.0),  # no recipe: ignored
    ]
    videos = {"v1": VideoFrame("kite", 256), "v2": VideoFrame("closeup", 128)}
    result = measure_framing(_people(rows), videos)
    assert list(result.groups) == ["closeup", "kite", "all"]
    kite, closeup, both = result.groups["kite"], result.groups["closeup"], result.groups["all"]
    assert (kite.n_videos, kite.n_frames, kite.in_view_frames) == (1, 3, 2)
    assert kite.in_view_share == pytest.approx(2 / 3)
    assert sorted(kite.heights_px) == [100.0, 256.0]
    assert closeup.median == 0.5 and closeup.median_px == 64.0
    assert (both.n_videos, both.n_frames) == (2, 4)
    assert both.median == pytest.approx(np.median([100 / 256, 1.0, 0.5]))
    hist = both.histogram()
    assert len(hist) == len(FRAMING_BINS) - 1 and hist.sum() == pytest.approx(both.in_view_share)
    assert hist[3] == hist[5] == hist[9] == 0.25  # 39 %, 50 % and 100 % of the frame, of 4 frames
    data = result.to_json()
    assert data["kite"]["in_view_frames"] == 2 and data["all"]["height_quartiles_px"][1] == 100.0


def test_never_in_view_and_missing_columns() -> None:
    result = measure_framing(_people([("v1", 0, 0, NAN, NAN)]), {"v1": VideoFrame("kite", 256)})
    g = result.groups["kite"]
    assert g.in_view_share == 0.0 and math.isnan(g.median) and np.isnan(g.video_medians).all()
    assert measure_framing(_people([]), {}).groups == {}
    with pytest.raises(PhavUserError, match="bbox2d"):
        measure_framing(_people([("v1", 0, 1, 0.0, 1.0)]).drop_columns(["bbox2d"]), {})


def test_a_broken_column_is_one_error_naming_it_and_a_null_box_is_not_in_view() -> None:
    table = _people([("v1", 0, 50, 100.0, 200.0), ("v1", 0, 50, 0.0, 128.0)])
    boxes = table.column("bbox2d").to_pylist()
    for name, values, kind, message in (
        ("person_id", ["0", "0"], pa.string(), "people.parquet: person_id: string, not numbers"),
        ("bbox2d", [[1.0, 2.0, 3.0]] * 2, pa.list_(pa.float64()), "people.parquet: bbox2d: rows of 3 values, not 4"),
        ("pixels", ["many", "few"], pa.string(), "people.parquet: pixels: string, not numbers"),
    ):
        broken = table.set_column(table.column_names.index(name), name, pa.array(values, kind))
        with pytest.raises(PhavUserError) as e:
            measure_framing(broken, {"v1": VideoFrame("kite", 256)})
        assert str(e.value) == message
    nulled = table.set_column(table.column_names.index("bbox2d"), "bbox2d", pa.array([None, boxes[1]]))
    g = measure_framing(nulled, {"v1": VideoFrame("kite", 256)}).groups["kite"]
    assert g.in_view_share == 0.5 and g.median == pytest.approx(0.5)


def test_metadata_agrees_with_the_instance_pixels(small_dataset) -> None:
    """The heights and in-view frames read from people.parquet are those of the protagonist's
    colour in every decoded instance frame of the shards."""
    recipes = list(read_recipe_table(small_dataset / "recipes.parquet").recipes())
    result = read_framing(small_dataset / "people.parquet", recipes)
    colour = np.array(instance_rgb(0), dtype=np.uint8)
    heights, frames = [], 0
    for r in recipes:
        shard = next(
            p for p in sorted(small_dataset.glob("*.tar")) if any(True for _ in shard_video_frames(p, r.video_id))
        )
        for _, arrays in shard_video_frames(shard, r.video_id):
            frames += 1
            rows = np.flatnonzero((arrays["instance"] == colour).all(axis=-1).any(axis=1))
            if rows.size:
                heights.append((rows[-1] + 1 - rows[0]) / r.video.height)
    g = result.groups["all"]
    assert g.n_frames == frames == sum(r.n_frames for r in recipes)
    assert heights and sorted(g.heights) == pytest.approx(sorted(heights))
    assert set(result.groups) == {r.camera.kind for r in recipes} | {"all"}


def test_stats_prints_the_framing_of_a_dataset(small_dataset, tmp_path) -> None:
    result = invoke_cli("stats", str(small_dataset))
    assert result.returncode in (0, 1), result.stderr  # 1: 3 videos may fail a distribution test
    assert "protagonist framing" in result.stdout and "protagonist height histogram" in result.stdout
    assert "90%–100%" in result.stdout
    sampled = tmp_path / "recipes.parquet"
    sampled.write_bytes((small_dataset / "recipes.parquet").read_bytes())
    alone = invoke_cli("stats", str(sampled))
    assert "no people.parquet beside the table" in alone.stdout
    broken = tmp_path / "people.parquet"
    pq.write_table(pq.read_table(small_dataset / "people.parquet").drop_columns(["bbox2d"]), broken)
    old = invoke_cli("stats", str(sampled))  # the recipes' statistics still print
    assert old.returncode in (0, 1) and "goodness of fit" in old.stdout, old.stderr
    assert "protagonist framing not measured" in old.stdout and "bbox2d" in old.stdout


def test_html_and_json_reports_show_the_framing() -> None:
    rows = [("v1", 0, 50, 100.0, 200.0), ("v1", 0, 0, NAN, NAN)]
    framing = measure_framing(_people(rows), {"v1": VideoFrame("kite", 256)})
    report = DatasetReport("data", [CheckResult.skipped("integrity", "test")], n_videos=1, n_frames=2,
                           framing=framing)  # fmt: skip
    page = report_html([report])
    assert "Protagonist framing" in page and "protagonist height, kite" in page and "50.0%" in page
    assert report.to_json()["protagonist_framing"]["kite"]["in_view_share"] == 0.5
    assert DatasetReport("data", []).to_json()["protagonist_framing"] is None


def test_the_html_report_shows_each_checks_notes() -> None:
    """A note (e.g. the learnability budget's) reaches the HTML page as well as the console and JSON."""
    check = CheckResult.skipped("learnability", "test")
    check.report.notes.append("training stopped at the 15-minute budget (flow 83 of 120 epochs) & more")
    page = report_html([DatasetReport("data", [check], n_videos=1, n_frames=2)])
    assert "note: training stopped at the 15-minute budget (flow 83 of 120 epochs) &amp; more" in page


def test_the_html_report_lists_every_checks_findings_and_no_raw_nan(capsys) -> None:
    """Findings past 200 over all checks were left off without a word (a later check's all
    of them): the page lists what the JSON lists, and notes the rest as the console does. A
    camera that never sees the protagonist printed ``nan%``; a histogram of nothing observed
    said ``n = 1`` (and the console ``nan%``, in the framing table and phav-validate's line);
    a table of recipes "3 videos, 0 frames"; a flagged video whose frame could not be read
    was left out of the page (the JSON lists it)."""
    checks = []
    for name in ("integrity", "schema", "encoding", "failures", "consistency"):
        report = Report()
        for i in range(60):
            report.add(Finding(Reason.MISSING_FILE, f"m{i}", file=f"{name}.tar", video_id=f"v{i:06d}"))
        checks.append(CheckResult.from_report(name, report, f"summary of {name}", {}))
    never = FramingGroup("static", 1, 30, np.zeros(0), np.zeros(0), np.array([NAN]))
    nothing = VariableSummary("weather", ("clear", "rain"), np.array([0, 0]), np.array([0.5, 0.5]), "all videos")
    dist = DistributionResult([], [nothing], Report(), 0, NAN, 3.0)
    page = report_html([DatasetReport("data", checks, n_videos=1, n_frames=30,
                                      framing=FramingResult({"static": never}), distribution=dist)])  # fmt: skip
    rows = re.findall(r"<tr><td>(\w+)</td><td class='fail'>MISSING_FILE</td>", page)
    assert [rows.count(c.name) for c in checks] == [MAX_PER_REASON] * 5
    assert page.count(f"note: MISSING_FILE: 60 findings, first {MAX_PER_REASON} listed") == 5
    row = re.search(r"<tr><td>static</td>.*?</tr>", page).group(0)
    assert "nan" not in row and row.count("—") == 4, row
    assert "weather (all videos, n = 0)" in page
    assert "v000000 (5 fail, 0 warn): MISSING_FILE; no frame of it to show" in page  # the JSON's worst videos
    # The console's table and phav-validate's framing line, the same dash.
    console = Console(record=True, width=200)
    framing = FramingResult({"static": never, "all": never})
    print_framing(framing, console)
    print_summary(DatasetReport("data", checks[:1], n_videos=1, n_frames=30, framing=framing))
    said = console.export_text() + capsys.readouterr().out
    assert not re.search(r"\bnan\b", said.lower()) and "static median —" in said and "— │" in said
    recipes_only = report_html([DatasetReport("recipes.parquet", checks[:1], n_videos=3)])
    assert "<p>3 recipes; no θ</p>" in recipes_only  # as the console says: "3 videos, 0 frames" was said
