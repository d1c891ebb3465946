"""`phav bench --sections validation`: each check's speed, and how often `--sample` finds a
corrupted video against the exact hypergeometric probability (phav_app/bench/validation.py)."""

from __future__ import annotations

import itertools
import math

import pytest

from phav_app import cli
from phav_app.bench.validation import bench_validation, flip_depth_pixel, hypergeometric_hit
from phav_validators.findings import Reason
from tests.helpers import invoke_cli
from tests.validators.checks.support import assert_fails, shard_of, validate


def test_bench_validation_reports_speed_and_detection_against_sample(small_theta, monkeypatch):
    """The section as printed, on phav-v1-tiny clips checked in one process: the bench's θ and
    pool size change its numbers, not what the tables say about them."""

    def small_bench(theta, work, **kwargs):
        return bench_validation(small_theta, work, **{**kwargs, "workers": 1})

    monkeypatch.setattr(cli, "bench_validation", small_bench)
    result = invoke_cli("bench", "--sections", "validation", "--validation-videos", "2", "--validation-trials", "1")
    assert result.returncode == 0, result.stderr
    out = result.stdout
    rows = {
        cells[0]: cells
        for cells in ([c.strip() for c in line.strip("│ ").split("│")] for line in out.splitlines())
        if len(cells) >= 5
    }
    for check in ("integrity", "schema", "encoding", "distribution", "failures", "consistency", "reproducibility"):
        # timed (seconds print to 0.1: a fast check reads 0.0), and no false alarm on clean data
        assert float(rows[check][1]) >= 0 and float(rows[check][2].split()[0].replace(",", "")) > 0, rows[check]
        assert rows[check][5] == "0", rows[check]
    assert "all but reproducibility" in rows and "faster than generation" in out
    # One of two videos corrupted: at --sample 1 integrity always finds it, as expected.
    assert rows["1"][3].startswith("1/1") and rows["1"][4] == "100%"
    assert rows["0.1"][4] == "50%"  # one of two videos drawn


def test_hypergeometric_detection_probability_matches_enumeration():
    for n, bad, drawn in ((5, 1, 2), (6, 2, 3), (7, 3, 1), (4, 1, 4), (4, 0, 2)):
        draws = list(itertools.combinations(range(n), drawn))
        hit = sum(any(i < bad for i in d) for d in draws) / len(draws)
        assert math.isclose(hypergeometric_hit(n, bad, drawn), hit), (n, bad, drawn)


def test_bench_corruption_is_caught_by_integrity(small_dataset_copy):
    data = small_dataset_copy
    flip_depth_pixel(shard_of(data, "v000002"), "v000002/00003.depth.png")
    assert_fails(validate(data, "integrity"), "integrity", Reason.HASH_MISMATCH, video="v000002")
    with pytest.raises(ValueError, match="no member"):
        flip_depth_pixel(shard_of(data, "v000002"), "v000002/99999.depth.png")


def test_the_bench_removes_only_what_an_earlier_run_wrote(small_theta, monkeypatch, tmp_path):
    """`--out-dir D`: the validation section removed D/validation/clean and .../corrupted
    whatever they held. A folder that is no dataset is now refused, and kept."""

    def small_bench(theta, work, **kwargs):
        return bench_validation(small_theta, work, **{**kwargs, "workers": 1})

    monkeypatch.setattr(cli, "bench_validation", small_bench)
    mine = tmp_path / "validation" / "clean"
    mine.mkdir(parents=True)
    (mine / "notes.txt").write_text("mine", encoding="utf-8")
    args = ("bench", "--sections", "validation", "--validation-videos", "2", "--validation-trials", "1")
    result = invoke_cli(*args, "--out-dir", str(tmp_path))
    assert result.returncode == 2 and "--out-dir: holds something the validation bench did not write" in result.stderr
    assert (mine / "notes.txt").read_text(encoding="utf-8") == "mine"
    (mine / "notes.txt").unlink()
    (mine / "manifest.json").write_text("{}", encoding="utf-8")  # an earlier run's dataset: replaced
    assert invoke_cli(*args, "--out-dir", str(tmp_path)).returncode == 0
    assert (mine / "manifest.json").read_text(encoding="utf-8") != "{}"
