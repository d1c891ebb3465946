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


def test_bench_reports_speed_against_error():
    result = run_cli("bench", "--n", "400")
    assert result.returncode == 0, result.stderr
    out = result.stdout
    assert "recipes/s" in out and "Parquet bytes" in out and "max |Δp| camera" in out
    assert "400" in out and "100" in out
