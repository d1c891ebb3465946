"""Engines: Ray (≥ 2 workers, random per-task delays) and the local pool give the same
dataset byte for byte (issue: scale-out, crash safety)."""

from __future__ import annotations

import pytest

from phav_generator.dataset.write import chunk, write_dataset
from phav_generator.faults import DELAY_ENV, delay_for
from phav_generator.sampling import sample_recipes
from phav_spec.errors import PhavUserError
from phav_spec.theta import load_theta
from tests.helpers import file_bytes

SEED = 6


def test_ray_and_the_local_pool_give_identical_datasets(tmp_path, monkeypatch):
    pytest.importorskip("ray")
    theta = load_theta("phav-v1-short")
    shards = chunk(list(sample_recipes(theta, n=4, seed=SEED)), 3)
    local = write_dataset(shards, tmp_path / "local", name="demo", theta=theta, dataset_seed=SEED, workers=2)
    # Up to 3 s per task, fixed by the video id: later videos finish first.
    delays = [delay_for(r.video_id, 3.0) for recipes in shards for r in recipes]
    assert delays != sorted(delays)
    monkeypatch.setenv(DELAY_ENV, "3")
    ray = write_dataset(shards, tmp_path / "ray", name="demo", theta=theta, dataset_seed=SEED, workers=2,
                        engine="ray")  # fmt: skip
    assert ray.manifest == local.manifest
    assert file_bytes(tmp_path / "ray") == file_bytes(tmp_path / "local")


def test_an_unknown_engine_is_a_one_line_error(tmp_path):
    theta = load_theta("phav-v1-short")
    with pytest.raises(PhavUserError, match="unknown engine 'spark'"):
        write_dataset([], tmp_path / "x", name="demo", theta=theta, dataset_seed=0, engine="spark")


def test_generation_bench_times_each_worker_count_on_identical_bytes():
    from phav_app.bench.generator import bench_generation

    theta = load_theta("phav-v1-short")
    recipes = list(sample_recipes(theta, n=2, seed=SEED))
    runs = bench_generation(recipes, theta, seed=SEED, workers=(1, 2))
    assert [r.workers for r in runs] == [1, 2]
    assert all(r.identical and r.frames == sum(x.n_frames for x in recipes) and r.fps > 0 for r in runs)
