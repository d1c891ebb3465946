"""`make install` installs exactly requirements.lock: every locked package at its version,
nothing else but phav itself, torch (pinned apart: its CPU wheel) and the installers."""

from __future__ import annotations

import re
import sysconfig
from importlib.metadata import distributions
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
#: Installed beside the lock on purpose: phav (editable), torch (the Makefile's TORCH) and
#: the tools that install (uv only after `make lock`).
BESIDE_THE_LOCK = {"phav", "torch", "pip", "uv"}


def _name(text: str) -> str:
    return re.sub(r"[-_.]+", "-", text).lower()


def _locked() -> dict[str, str]:
    pins = re.findall(
        r"^([A-Za-z0-9][A-Za-z0-9._-]*)==([^\s;\\]+)", (ROOT / "requirements.lock").read_text("utf-8"), re.M
    )
    return {_name(name): version for name, version in pins}


def _makefile_torch() -> str:
    return re.search(r"^TORCH := torch==(\S+)$", (ROOT / "Makefile").read_text("utf-8"), re.M).group(1)


def test_the_environment_is_the_lock():
    locked = _locked()
    # The environment's own packages: Ray, once imported, puts its vendored ones on sys.path.
    site = sorted({sysconfig.get_paths()["purelib"], sysconfig.get_paths()["platlib"]})
    installed = {_name(d.metadata["Name"]): d.version for d in distributions(path=site)}
    assert {"numpy", "mujoco", "moderngl", "anny", "pytest"} <= set(locked)
    wrong = {name: (installed.get(name), version) for name, version in locked.items() if installed.get(name) != version}
    assert not wrong, f"(installed, locked) differ: {wrong}; run make install"
    beside = sorted(set(installed) - set(locked) - BESIDE_THE_LOCK)
    assert not beside, f"installed but not locked: {beside}"
    assert installed["torch"].split("+")[0] == _makefile_torch()
    assert "warp-lang" not in installed and "torch" not in locked and "warp-lang" not in locked
