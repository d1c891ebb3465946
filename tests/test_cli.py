"""The phav command as a user meets it: help, sample, bench, errors as one line."""

from __future__ import annotations

from phav_spec.recipe_table import read_recipe_table
from tests.helpers import run_cli


def test_help_lists_the_commands():
    result = run_cli("--help")
    assert result.returncode == 0
    for command in ("sample", "stats", "theta", "spec", "bench"):
        assert command in result.stdout


def test_theta_check_prints_the_hash():
    from phav_spec.theta import load_preset

    result = run_cli("theta", "check", "phav-v1")
    assert result.returncode == 0 and load_preset().hash in result.stdout


def test_sample_is_deterministic_and_prefix_stable(tmp_path):
    a, b, c = tmp_path / "a.parquet", tmp_path / "b.parquet", tmp_path / "c.parquet"
    assert run_cli("sample", "--n", "30", "--seed", "9", "--out", str(a)).returncode == 0
    assert run_cli("sample", "--n", "30", "--seed", "9", "--out", str(b)).returncode == 0
    assert run_cli("sample", "--n", "12", "--seed", "9", "--out", str(c)).returncode == 0
    ra, rb, rc = (read_recipe_table(p).column("recipe") for p in (a, b, c))
    assert ra == rb and ra[:12] == rc
    cols = read_recipe_table(a).table.column_names
    for required in ("video_id", "action", "human_model", "environment", "weather", "day_phase", "variation",
                     "camera", "base_motion", "duration_s", "n_frames", "clock_hour", "recipe"):  # fmt: skip
        assert required in cols


def test_usage_errors_exit_2_without_traceback(tmp_path):
    for args in (
        ("sample", "--n", "-3"),
        ("sample", "--theta", "nope-v9", "--n", "2", "--out", str(tmp_path / "x.parquet")),
        ("frobnicate",),
    ):
        result = run_cli(*args)
        assert result.returncode == 2, args
        assert "Traceback" not in result.stderr + result.stdout
    assert not (tmp_path / "x.parquet").exists()


def test_bench_reports_speed_against_error(tmp_path):
    report = tmp_path / "benchmarks.md"
    result = run_cli("bench", "--n", "400", "--sections", "sampling", "--report", str(report))
    assert result.returncode == 0, result.stderr
    # The Markdown report: the machine and renderer, then the section's table as printed.
    text = report.read_text(encoding="utf-8")
    assert text.startswith("# Benchmarks\n") and "`phav bench --sections sampling`" in text
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


def test_recipe_show_and_check_round_trip(tmp_path):
    table = tmp_path / "r.parquet"
    assert run_cli("sample", "--n", "5", "--seed", "2", "--out", str(table)).returncode == 0
    shown = run_cli("recipe", "show", str(table), "--video", "v000003")
    assert shown.returncode == 0
    path = tmp_path / "v000003.json"
    path.write_text(shown.stdout, encoding="utf-8")
    checked = run_cli("recipe", "check", str(path))
    assert checked.returncode == 0 and "valid recipe v000003" in checked.stdout
    missing = run_cli("recipe", "show", str(table), "--video", "v000099")
    assert missing.returncode == 2 and "no video 'v000099'" in missing.stderr


def test_bad_recipes_on_the_command_line(tmp_path):
    import json

    table = tmp_path / "r.parquet"
    assert run_cli("sample", "--n", "1", "--out", str(table)).returncode == 0
    data = json.loads(run_cli("recipe", "show", str(table), "--video", "v000000").stdout)
    cases = {
        "missing.json": (lambda d: d["camera"].pop("fov_deg"), "camera.fov_deg: missing required field"),
        "future.json": (lambda d: d.update(schema_version=7), "schema_version: version 7 is newer"),
    }
    for name, (edit, words) in cases.items():
        broken = json.loads(json.dumps(data))
        edit(broken)
        path = tmp_path / name
        path.write_text(json.dumps(broken), encoding="utf-8")
        result = run_cli("recipe", "check", str(path))
        assert result.returncode == 2 and "Traceback" not in result.stderr
        lines = [line for line in result.stderr.splitlines() if line.strip()]
        assert len(lines) == 1 and f"{path}: {words}" in lines[0], result.stderr


def test_spec_vocab_lists_the_registries():
    result = run_cli("spec", "vocab", "pixel_class")
    assert result.returncode == 0 and "guard_rail" in result.stdout and "(64)" in result.stdout
    assert run_cli("spec", "vocab", "colours").returncode == 2


def test_bench_render_reports_stages_error_and_the_floor():
    result = run_cli("bench", "--sections", "render", "--render-videos", "2", "--render-frames", "4")
    assert result.returncode == 0, result.stderr
    out = result.stdout
    header = next(line for line in out.splitlines() if "supersample" in line)
    columns = [c.strip() for c in header.strip("┃ ").split("┃")]
    assert columns[:2] == ["supersample", "frames/s"] and "edge error vs 4× (levels)" in columns
    rows = [[c.strip() for c in line.strip("│ ").split("│")] for line in out.splitlines() if line.startswith("│")]
    assert [r[0] for r in rows[:2]] == ["1×", "2×"]
    assert all(float(r[1]) > 0 for r in rows[:2])
    assert "encode-only floor" in out and "content hashes equal the bench's 2× run" in out


def test_sheets_make_one_image_per_value_and_an_index(tmp_path):
    """Weather sheets: one JPEG per weather of one base scene, listed by the index page, and
    different from each other only where the weather shows (the labels row is shared)."""
    import numpy as np
    from PIL import Image

    from phav_spec.vocab import WEATHERS

    out = tmp_path / "sheets"
    result = run_cli("sheets", "--by", "weather", "--out", str(out))
    assert result.returncode == 0, result.stderr
    images = {w: np.asarray(Image.open(out / f"weather-{w}.jpg")) for w in WEATHERS.names}
    index = (out / "README.md").read_text()
    assert all(f"weather-{w}.jpg" in index for w in WEATHERS.names)
    shapes = {im.shape for im in images.values()}
    assert shapes == {(18 + 2 * 256, 3 * 340, 3)}
    rgb = {w: im[18 : 18 + 256].astype(float) for w, im in images.items()}  # the RGB row
    labels = {w: im[18 + 256 + 20 :, :340].astype(float) for w, im in images.items()}  # semantic tile
    assert np.abs(rgb["fog"] - rgb["clear"]).mean() > 5.0
    assert max(np.abs(labels[w] - labels["clear"]).mean() for w in WEATHERS.names) < 1.0
    bad = run_cli("sheets", "--by", "mood", "--out", str(out))
    assert bad.returncode == 2 and "mood" in bad.stderr and "Traceback" not in bad.stderr


def test_bench_validation_reports_speed_and_detection_against_sample():
    result = run_cli("bench", "--sections", "validation", "--validation-videos", "2", "--validation-trials", "1")
    assert result.returncode == 0, result.stderr
    out = result.stdout
    rows = {
        cells[0]: cells
        for cells in ([c.strip() for c in line.strip("│ ").split("│")] for line in out.splitlines())
        if len(cells) >= 5
    }
    for check in ("integrity", "schema", "encoding", "distribution", "failures", "consistency", "reproducibility"):
        assert float(rows[check][1]) > 0 and rows[check][5] == "0", rows[check]  # no false alarm on clean data
    assert "all but reproducibility" in rows and "faster than generation" in out
    # One of two videos corrupted: at --sample 1 integrity always finds it, as expected.
    assert rows["1"][3].startswith("1/1") and rows["1"][4] == "100%"
    assert rows["0.1"][4] == "50%"  # one of two videos drawn
