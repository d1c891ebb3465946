"""docs/measure/learn_experiments.py, the experiment script behind docs/learnability.md's
tables: its cell syntax and one cell on tiny synthetic clips (the real runs take hours)."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import pytest

from tests.validators.learn.helpers import motion_clips

SCRIPT = Path(__file__).parents[3] / "docs" / "measure" / "learn_experiments.py"


@pytest.fixture(scope="module")
def script():
    spec = importlib.util.spec_from_file_location("learn_experiments", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # its dataclasses look themselves up there
    spec.loader.exec_module(module)
    return module


def test_a_cell_names_clips_size_and_any_training_setting(script):
    clips, size, overrides = script.parse_cell("clips=320,size=128x96,widths=16-32,temporal_shift=true,lr=0.1,"
                                               "focus=motion,epochs=30", (85, 64))  # fmt: skip
    assert clips == 320 and size == (128, 96)
    assert overrides == {"widths": (16, 32), "temporal_shift": True, "lr": 0.1, "focus": "motion", "epochs": 30}
    assert script.parse_cell("baseline", (85, 64)) == (None, (85, 64), {})
    with pytest.raises(SystemExit, match="colour"):
        script.parse_cell("colour=red", (85, 64))


def test_a_cell_trains_on_held_out_actors_and_reports_a_row(script):
    data = motion_clips(4, 20)
    overrides = {"epochs": 3, "widths": (8, 16), "threads": 1}
    run = script.run_cell(data, 40, overrides, 0, ["rgb", "flow"])
    assert run["train_clips"] <= 44 and run["test_clips"] > 0
    assert set(run["accuracy"]) == {"rgb", "flow", "fused", "p_fused"}
    cell = script.Cell("epochs=3", 40, (32, 24), overrides, [run, run])
    row = script.row(cell, ["rgb", "flow"])
    assert row.startswith("| epochs=3 | 2 | ") and row.count("|") == 10
