"""docs/measure/device_parity.py, behind docs/learnability.md's "On a GPU": the same seed
and clips train to the same losses and predictions; on a machine with CUDA, the GPU
against the CPU up to the order of sums (there is none in CI: that case skips)."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import pytest

from tests.validators.learn.helpers import motion_clips

SCRIPT = Path(__file__).parents[3] / "docs" / "measure" / "device_parity.py"


@pytest.fixture(scope="module")
def script():
    spec = importlib.util.spec_from_file_location("device_parity", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def clips():
    data = motion_clips(4, 6)
    return data.clips[::2], data.clips[1::2], len(data.classes)


def test_one_device_twice_gives_identical_figures(script, clips):
    train_clips, test, n = clips
    figures = script.compare_devices(train_clips, test, n, ["cpu", "cpu"], epochs=2, widths=(8, 16), threads=1)
    assert figures["difference"] == {"loss_relative": 0.0, "probability": 0.0, "same_class": 1.0}
    cpu = figures["cpu"]
    assert len(cpu["losses"]) == len(cpu["epoch_seconds"]) == 2 and cpu["train_clips"] == len(train_clips)
    assert all(loss > 0 for loss in cpu["losses"])


def test_cuda_learns_what_the_cpu_learns(script, clips):
    torch = pytest.importorskip("torch")
    if not torch.cuda.is_available():
        pytest.skip("no CUDA device on this machine")
    train_clips, test, n = clips
    figures = script.compare_devices(train_clips, test, n, ["cpu", "cuda"], epochs=2, widths=(8, 16))
    assert figures["difference"]["loss_relative"] < 1e-3
    assert figures["difference"]["same_class"] >= 0.9
