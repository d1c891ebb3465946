"""Hypothesis profiles: `ci` (default, bounded and deterministic) and `dev` (more examples);
the one small rendered dataset the whole run shares, and the one Ray its Ray tests share."""

from __future__ import annotations

import contextlib
import hashlib
import os
import shutil
import sys
from collections.abc import Iterator
from pathlib import Path
from unittest import mock

import pytest

#: Environment variables that pick the numeric kernels a process runs: OpenBLAS's CPU type,
#: numpy's SIMD targets, torch's and MKL's code paths, llvmpipe's. The tests compare what this
#: process computes with what CLI runs in a bare environment compute, so every process of a
#: run must run the same kernels: this one drops them too (some hosts set OPENBLAS_CORETYPE
#: for every process), before numpy loads OpenBLAS. A test sets one for a run it starts.
NUMERIC_ENV_PREFIXES = ("OPENBLAS_", "NPY_", "ATEN_", "MKL_", "LP_", "GALLIUM_")
_NUMERIC_SET = sorted(n for n in os.environ if n.startswith(NUMERIC_ENV_PREFIXES))
if _NUMERIC_SET and "numpy" in sys.modules:
    raise pytest.UsageError(f"{', '.join(_NUMERIC_SET)} set and numpy already loaded: unset them and run again")
for _name in _NUMERIC_SET:
    del os.environ[_name]

from hypothesis import HealthCheck, settings  # noqa: E402 (after the environment above)

from phav_spec.recipe import Recipe  # noqa: E402
from phav_spec.theta import Theta  # noqa: E402
from tests.helpers import (  # noqa: E402
    RAY_DELAY_S,
    SMALL_SEED,
    SMALL_SHARD_SIZE,
    SMALL_VIDEOS,
    run_cli,
    theta_variant,
    tiny,
    tiny_theta,
)

settings.register_profile(
    "ci",
    max_examples=40,
    deadline=None,
    derandomize=True,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)
settings.register_profile("dev", max_examples=200, deadline=None)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))


_CACHES = pytest.StashKey[Path]()


def pytest_configure(config: pytest.Config) -> None:
    """The data clients' caches in a folder of this process, set before any test imports
    them (both read it at import): nothing comes from ~/.cache, and mlcroissant, which keys
    what it unpacks by a file's contentUrl alone, never serves another run's shards — nor
    another test process's, where the suite runs in several (pytest-xdist)."""
    import tempfile

    caches = Path(tempfile.mkdtemp(prefix="phav-test-caches-"))
    config.stash[_CACHES] = caches
    os.environ["CROISSANT_CACHE"] = str(caches / "croissant")
    os.environ["HF_HOME"] = str(caches / "huggingface")


def pytest_unconfigure(config: pytest.Config) -> None:
    """The caches go with the process that made them: each run left ~16 MB in the temp dir."""
    caches = config.stash.get(_CACHES, None)
    if caches is not None:
        shutil.rmtree(caches, ignore_errors=True)


@pytest.fixture(scope="session")
def small_theta() -> Theta:
    """phav-v1-tiny: phav-v1 with clips of 0.2 s (6 frames)."""
    return tiny_theta()


@pytest.fixture(scope="session")
def small_recipes(small_theta: Theta) -> list[Recipe]:
    """The recipes of the shared small dataset, sampled again in this process."""
    from phav_generator.sampling import sample_recipes  # generator floor: only tests that render need it

    return list(sample_recipes(small_theta, n=SMALL_VIDEOS, seed=SMALL_SEED))


def _digest(root: Path) -> str:
    h = hashlib.sha256()
    for p in sorted(root.rglob("*")):
        h.update(str(p.relative_to(root)).encode())
        if p.is_file():
            h.update(p.read_bytes())
    return h.hexdigest()


@pytest.fixture(scope="session")
def small_dataset(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Path]:
    """One `phav generate` for the whole run: three phav-v1-tiny videos of seed 3 (shoot_bow in
    urban, shoot_ball in the stadium, golf in simple), two per shard, with two workers.

    Shared by every test that reads a dataset, so it must stay as generated: a test that
    changes files works on ``small_dataset_copy``. The run's end checks that nothing did."""
    root = tmp_path_factory.mktemp("small")
    out = root / "data"
    result = run_cli("generate", "--theta", str(theta_variant(root, tiny)), "--videos", str(SMALL_VIDEOS),
                     "--seed", str(SMALL_SEED), "--shard-size", str(SMALL_SHARD_SIZE), "--workers", "2",
                     "--out", str(out))  # fmt: skip
    assert result.returncode == 0, result.stderr
    assert f"wrote {SMALL_VIDEOS} videos" in result.stdout
    before = _digest(root)
    yield out
    assert _digest(root) == before, "a test changed the shared small dataset: use small_dataset_copy"


@pytest.fixture
def small_dataset_copy(small_dataset: Path, tmp_path: Path) -> Path:
    """A private copy of the shared small dataset, for a test to change."""
    dst = tmp_path / "data"
    shutil.copytree(small_dataset, dst)
    return dst


@pytest.fixture(scope="session")
def ray_with_delays() -> Iterator[None]:
    """A local Ray of two CPUs for the rest of the run (started once: it takes seconds), whose
    workers sleep up to RAY_DELAY_S before rendering each video, fixed by its id, so that later
    videos finish first. Every `--engine ray` run in this process uses it while it lives."""
    pytest.importorskip("ray")
    from phav_generator.engines import ray_session  # generator floor: only the Ray tests need it
    from phav_generator.faults import DELAY_ENV

    with contextlib.ExitStack() as stack:
        with mock.patch.dict(os.environ, {DELAY_ENV: str(RAY_DELAY_S)}):  # read by Ray's start only
            stack.enter_context(ray_session(2, None))
        yield
