"""Small shared test helpers: θ variants written to files, and running the CLIs."""

from __future__ import annotations

import copy
import subprocess
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

import yaml

from phav_spec.theta import PRESETS_DIR

PRESET_PATH = PRESETS_DIR / "phav-v1.yaml"


def preset_dict() -> dict[str, Any]:
    """The phav-v1 preset as its YAML file spells it (not normalised)."""
    return yaml.safe_load(PRESET_PATH.read_text(encoding="utf-8"))


def theta_variant(tmp_path: Path, edit: Callable[[dict[str, Any]], None], name: str = "theta.yaml") -> Path:
    """Write phav-v1 with ``edit`` applied to a copy of its mapping; return the file."""
    data = copy.deepcopy(preset_dict())
    edit(data)
    path = tmp_path / name
    path.write_text(yaml.safe_dump(data, sort_keys=False), encoding="utf-8")
    return path


def run_cli(*args: str, cwd: Path | None = None) -> subprocess.CompletedProcess[str]:
    """Run ``phav`` (or ``phav-validate`` when the first arg is 'validate!') as a user would."""
    if args and args[0] == "validate!":
        module, rest = "phav_app.validate_cli", args[1:]
    else:
        module, rest = "phav_app.cli", args
    return subprocess.run(
        [sys.executable, "-m", module, *rest],
        capture_output=True,
        text=True,
        cwd=cwd,
        env={"COLUMNS": "200", "PATH": ""},
    )


def file_bytes(folder: Path) -> dict[str, bytes]:
    """Every file directly in ``folder``, by name: two datasets compare byte for byte."""
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir()) if p.is_file()}
