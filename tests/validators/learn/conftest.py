"""A tiny PHAV dataset shared by the learning tests (3 phav-v1-short videos, 2 shards)."""

from __future__ import annotations

from pathlib import Path

import pytest

from tests.helpers import run_cli


@pytest.fixture(scope="session")
def phav(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("learn") / "data"
    result = run_cli("generate", "--theta", "phav-v1-short", "--videos", "3", "--seed", "5", "--out", str(out),
                     "--shard-size", "2", "--workers", "2")  # fmt: skip
    assert result.returncode == 0, result.stderr
    return out
