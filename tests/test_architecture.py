"""The floors hold: `lint-imports` keeps pyproject's contracts on the tree, and an import
that runs back up a floor breaks them (so the contracts are not vacuous)."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("phav_spec", "phav_generator", "phav_validators", "phav_app")
LINT = Path(sys.executable).with_name("lint-imports")


def _lint(tree: Path) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONPATH": str(tree)}
    return subprocess.run([str(LINT), "--no-cache", "--config", str(tree / "pyproject.toml")],
                          cwd=tree, env=env, capture_output=True, text=True)  # fmt: skip


@pytest.fixture(scope="module")
def tree(tmp_path_factory) -> Path:
    """A copy of the package sources and pyproject.toml, to break on purpose."""
    if not LINT.exists():
        pytest.skip("import-linter is not installed (pip install -e '.[dev]')")
    out = tmp_path_factory.mktemp("tree")
    for package in PACKAGES:
        shutil.copytree(ROOT / package, out / package, ignore=shutil.ignore_patterns("__pycache__"))
    shutil.copy(ROOT / "pyproject.toml", out / "pyproject.toml")
    return out


def test_the_contracts_hold_on_the_tree(tree):
    result = _lint(tree)
    assert result.returncode == 0, result.stdout[-3000:]
    assert "BROKEN" not in result.stdout


@pytest.mark.parametrize(
    ("module", "inverted", "contract"),
    [
        (
            "phav_generator/render/video.py",
            "from phav_validators.findings import Reason",
            "never imports the validators",
        ),
        ("phav_spec/release.py", "from phav_generator.pipeline import VideoTask", "Floors"),
        ("phav_generator/motion/rotations.py", "from phav_generator.physics import trajectory", "data-flow order"),
        ("phav_generator/io/png.py", "from phav_generator.render import camera", "never reach into"),
    ],
)
def test_an_import_that_runs_back_up_breaks_a_contract(tree, module, inverted, contract):
    path = tree / module
    original = path.read_text(encoding="utf-8")
    try:
        path.write_text(original + f"\n{inverted}  # inverted on purpose\n", encoding="utf-8")
        result = _lint(tree)
    finally:
        path.write_text(original, encoding="utf-8")
    assert result.returncode != 0
    broken = [line for line in result.stdout.splitlines() if line.rstrip().endswith("BROKEN")]
    assert any(contract in line for line in broken), result.stdout[-3000:]
