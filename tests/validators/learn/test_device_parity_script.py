"""docs/measure/device_parity.py, behind docs/experiments/learnability.md's "On a GPU": the same seed
and clips train to the same losses and predictions; on a machine with CUDA, the GPU
against the CPU up to the order of sums (there is none in CI: that case skips)."""

from __future__ import annotations

import pytest

from tests.validators.learn.helpers import measure_script, motion_clips


@pytest.fixture(scope="module")
def script():
    return measure_script("device_parity")


@pytest.fixture(scope="module")
def clips():
    data = motion_clips(4, 6)
    return data.clips[::2], data.clips[1::2], len(data.classes)


def test_one_device_twice_gives_identical_figures(script, clips):
    train_clips, test, n = clips
    figures = script.compare_devices(train_clips, test, n, ["cpu", "cpu"], epochs=2, widths=(8, 16), threads=1)
    assert figures["difference"] == {"loss_relative": 0.0, "probability": 0.0, "same_class": 1.0}
    first, second = figures["runs"]  # two runs, each kept: the second does not overwrite the first
    assert first["device"] == second["device"] == "cpu" and first["losses"] == second["losses"]
    assert len(first["losses"]) == len(first["epoch_seconds"]) == 2 and first["train_clips"] == len(train_clips)
    assert all(loss > 0 for loss in first["losses"])


def test_cuda_learns_what_the_cpu_learns(script, clips):
    torch = pytest.importorskip("torch")
    if not torch.cuda.is_available():
        pytest.skip("no CUDA device on this machine")
    train_clips, test, n = clips
    figures = script.compare_devices(train_clips, test, n, ["cpu", "cuda"], epochs=2, widths=(8, 16))
    assert figures["difference"]["loss_relative"] < 1e-3
    assert figures["difference"]["same_class"] >= 0.9
