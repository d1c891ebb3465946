"""The training bench: clips per second of each stream, test accuracy against training
minutes, and ``phav bench --sections training`` printing both."""

from __future__ import annotations

import functools
from dataclasses import replace
from pathlib import Path

import pytest
import torch

import phav_app.cli
from phav_app.bench.training import learning_curve, throughput
from phav_validators.learn.config import in_channels
from phav_validators.learn.model import TSN
from phav_validators.learn.splits import make_split
from phav_validators.learn.train import TrainConfig, recommended_config
from tests.helpers import invoke_cli
from tests.validators.learn.helpers import motion_clips, tiny_phav

#: The bench's code paths on a small network (the bench's own is ~840k parameters).
SMALL = TrainConfig(widths=(8, 16), mix=(("virtual", 4),), threads=1)


@pytest.fixture(scope="session")
def phav(tmp_path_factory) -> Path:
    return tiny_phav(tmp_path_factory)


@pytest.mark.parametrize("stream", ["rgb", "flow"])
def test_throughput_times_training_and_testing_and_counts_the_parameters(stream):
    config = replace(SMALL, stream=stream)
    speed = throughput(motion_clips(3, 4).clips, config, steps=2)
    assert speed.stream == stream
    assert speed.train_clips_per_s > 0 and speed.test_clips_per_s > 0
    model = TSN(in_channels(stream, config.flow_frames), {"virtual": 35}, config.arch, generator=torch.Generator())
    assert speed.parameters == sum(p.numel() for p in model.parameters())


@pytest.mark.parametrize(("kind", "name"), [("random", "random"), ("actor", "held-out actor")])
def test_learning_curve_tests_every_few_epochs_and_fuses_the_streams(kind, name):
    clips = motion_clips(3, 10)
    said: list[str] = []
    points = learning_curve(clips, kind, replace(SMALL, epochs=4, rgb_epochs=2), points=2, progress=said.append)
    # Each stream is tested twice over its own epochs; the i-th tests are fused.
    assert [p.epochs for p in points] == [{"rgb": 1, "flow": 2}, {"rgb": 2, "flow": 4}]
    assert points[0].minutes < points[1].minutes  # training time adds up; testing is not counted
    n_test = len(make_split(clips.clips, kind, seed=SMALL.seed).test)
    for p in points:
        assert p.split == name and p.test_clips == n_test
        assert set(p.accuracy) == {"rgb", "flow", "fused"} and all(0 <= a <= 1 for a in p.accuracy.values())
        assert 1 / 3 <= p.chance <= 1 and 0 <= p.p_fused <= 1
    assert [s.split(", ")[0] for s in said] == [f"{name}: rgb epoch 1/2", f"{name}: rgb epoch 2/2",
                                                 f"{name}: flow epoch 2/4", f"{name}: flow epoch 4/4"]  # fmt: skip


def test_bench_training_section_prints_speed_and_accuracy_against_minutes(phav, monkeypatch):
    # The section's code on a small network, one torch thread and the shards read in this
    # process (reading in worker processes is tested in tests/validators/learn/test_data.py).
    small = functools.partial(recommended_config, widths=(8, 16), mix=(("virtual", 4),), threads=1)
    monkeypatch.setattr(phav_app.cli, "recommended_config", small)
    monkeypatch.setattr(phav_app.cli, "default_threads", lambda: 1)
    result = invoke_cli("bench", "--sections", "training", "--training-data", str(phav), "--training-epochs", "2")
    assert result.returncode == 0, result.stderr
    out = result.stdout
    assert "training speed" in out and "training clips/s" in out
    assert "test accuracy against training minutes" in out
    assert "random" in out and "held-out actor" in out
