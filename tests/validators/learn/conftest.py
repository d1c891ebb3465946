"""A tiny PHAV dataset shared by the learning tests (3 phav-v1-short videos, 2 shards)."""

from __future__ import annotations

from pathlib import Path

import pytest

from tests.validators.learn.helpers import tiny_phav


@pytest.fixture(scope="session")
def phav(tmp_path_factory) -> Path:
    return tiny_phav(tmp_path_factory)
