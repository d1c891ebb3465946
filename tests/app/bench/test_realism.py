"""The realism bench: seconds per judged frame and each headline figure's interval against
the number of frames judged."""

from __future__ import annotations

import pytest

from phav_app.bench.realism import bench_realism
from tests.helpers import invoke_cli

pytest.importorskip("ai_edge_litert")


def test_each_frame_count_is_one_run_whose_sample_contains_the_smaller(small_dataset):
    small, large = bench_realism(small_dataset, [3, 9], seed=2)
    assert (small.frames, large.frames) == (3, 9)
    assert small.seconds > 0 and small.seconds_per_frame == pytest.approx(small.seconds / 3)
    assert large.people >= small.people
    for p in (small, large):
        for f in p.figures.values():
            assert f.low <= f.value <= f.high


def test_bench_realism_section_prints_seconds_and_intervals(small_dataset):
    result = invoke_cli("bench", "--sections", "realism", "--realism-data", str(small_dataset),
                        "--realism-frames", "2,4")  # fmt: skip
    assert result.returncode == 0, result.stdout + result.stderr
    assert "realism (" in result.stdout and "s/frame" in result.stdout and "person_pck_0.2" in result.stdout
    bad = invoke_cli("bench", "--sections", "realism", "--realism-data", str(small_dataset), "--realism-frames", "a")
    assert bad.returncode == 2 and "--realism-frames" in bad.stderr


def test_bench_checks_every_chosen_section_s_options_before_running_any(tmp_path):
    """`--realism-frames abc`, or a --realism-data / --training-data that is no dataset, was
    found out only when its section ran, after the sections before it (hours of them);
    `--sections ' , '` ran nothing and exited 0."""
    for args, said in (
        (("--sections", "sampling,realism", "--n", "100", "--realism-frames", "abc"), "--realism-frames"),
        (("--sections", "sampling,realism", "--n", "100", "--realism-data", str(tmp_path)), "--realism-data"),
        (("--sections", "sampling,training", "--n", "100", "--training-data", str(tmp_path)), "--training-data"),
        (("--sections", " , "), "--sections: no section named"),
    ):
        result = invoke_cli("bench", *args)
        assert result.returncode == 2 and said in result.stderr and "Traceback" not in result.stderr, result.stderr
        assert "sampling" not in result.stdout, result.stdout  # nothing ran first
