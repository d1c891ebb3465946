"""The dataset each check test damages: a private copy of the run's shared small dataset."""

from __future__ import annotations

from pathlib import Path

import pytest


@pytest.fixture
def data(small_dataset_copy: Path) -> Path:
    """Three phav-v1-tiny videos (shoot_bow in urban, shoot_ball in the stadium, golf in simple)
    in phav-000000.tar (v000000, v000001) and phav-000001.tar (v000002), six frames each."""
    return small_dataset_copy
