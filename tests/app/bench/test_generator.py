"""`phav bench` sections on the generator: sampling, render and generation speed, each
against the error or the bytes it must keep (phav_app/bench/generator.py)."""

from __future__ import annotations

import re

from phav_app.bench.generator import bench_generation
from tests.helpers import SMALL_SEED, invoke_cli


def test_bench_reports_speed_against_error(tmp_path):
    report = tmp_path / "benchmarks.md"
    result = invoke_cli("bench", "--n", "400", "--sections", "sampling", "--report", str(report))
    assert result.returncode == 0, result.stderr
    # The Markdown report: the machine and renderer, then the section's table as printed.
    text = report.read_text(encoding="utf-8")
    assert text.startswith("# Benchmarks\n") and "`phav bench --sections sampling --n 400`" in text  # rerunnable
    fingerprint = next(line for line in text.splitlines() if line.startswith("| renderer fingerprint |"))
    assert len(fingerprint.split("`")[1]) == 64
    gl = next(line for line in text.splitlines() if line.startswith("| GL | "))
    assert gl.count(";") == 2 and len(gl) > 20  # vendor; renderer; version
    section = text.split("## sampling\n", 1)[1]
    printed = [line.rstrip() for line in result.stdout.splitlines() if line.startswith("│")]
    assert printed and all(line in section for line in printed)
    header = next(line for line in result.stdout.splitlines() if "recipes/s" in line)
    columns = [c.strip() for c in header.strip("┃ ").split("┃")]
    assert columns[:4] == ["recipes", "recipes/s", "µs/recipe", "Parquet bytes"]
    assert "max |Δp| camera" in columns and "rejected (Holm)" in columns
    rows = [
        [c.strip() for c in line.strip("│ ").split("│")] for line in result.stdout.splitlines() if line.startswith("│")
    ]
    assert [r[0] for r in rows] == ["100", "400"]
    for row in rows:
        cells = dict(zip(columns, row, strict=True))
        assert float(cells["recipes/s"].replace(",", "")) > 0
        assert int(cells["Parquet bytes"].replace(",", "")) > 1000
        assert 0 <= float(cells["max |Δp| camera"]) < 0.2
        rejected, total = cells["rejected (Holm)"].split("/")
        assert int(rejected) == 0 and int(total) > 100


def test_bench_render_reports_stages_error_and_the_floor():
    """One video of two frames is enough for every number of the table (and the hash check)."""
    result = invoke_cli("bench", "--sections", "render", "--render-videos", "1", "--render-frames", "2")
    assert result.returncode == 0, result.stderr
    out = result.stdout
    header = next(line for line in out.splitlines() if "supersample" in line)
    columns = [c.strip() for c in header.strip("┃ ").split("┃")]
    assert columns[:2] == ["supersample", "frames/s"] and "edge error vs 4× (levels)" in columns
    rows = [[c.strip() for c in line.strip("│ ").split("│")] for line in out.splitlines() if line.startswith("│")]
    assert [r[0] for r in rows[:2]] == ["1×", "2×"]
    assert all(float(r[1]) > 0 for r in rows[:2])
    assert "encode-only floor" in out and "content hashes equal the bench's 2× run" in out
    # The people's share is a difference of two timings of two frames: its sign is noise on a
    # busy machine, so only its presence and the whole frame's time are asserted.
    share = re.search(r"people \(anny bodies\), 2×: (-?[\d.]+) of ([\d.]+) ms of render \+ post per frame", out)
    assert share and float(share.group(2)) > 0, out


def test_generation_bench_times_each_worker_count_on_identical_bytes(small_recipes, small_theta):
    recipes = small_recipes[:2]
    runs = bench_generation(recipes, small_theta, seed=SMALL_SEED, workers=(1, 2))
    assert [r.workers for r in runs] == [1, 2]
    assert all(r.identical and r.frames == sum(x.n_frames for x in recipes) and r.fps > 0 for r in runs)
