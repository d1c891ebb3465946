"""Generation never touches the network: `phav generate` runs with every internet socket
refused (a sitecustomize that each process, workers included, loads first)."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

from tests.helpers import cli_env, theta_variant, tiny

REFUSE = """
import os, socket
_connect = socket.socket.connect


def _refuse(self, address):
    if self.family in (socket.AF_INET, socket.AF_INET6):
        with open(os.environ["PHAV_TEST_REFUSALS"], "a") as fh:
            fh.write(f"{address}\\n")
        raise OSError("network refused by the offline test")
    return _connect(self, address)


socket.socket.connect = _refuse
with open(os.environ["PHAV_TEST_LOADED"], "a") as fh:
    fh.write(f"{os.getpid()}\\n")
"""


def test_generation_runs_with_internet_sockets_refused(tmp_path: Path):
    site = tmp_path / "site"
    site.mkdir()
    (site / "sitecustomize.py").write_text(REFUSE, encoding="utf-8")
    loaded, refusals = tmp_path / "loaded", tmp_path / "refusals"
    paths = [str(site), *(p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p)]
    env = cli_env() | {"PYTHONPATH": os.pathsep.join(paths), "PHAV_TEST_LOADED": str(loaded),
                       "PHAV_TEST_REFUSALS": str(refusals)}  # fmt: skip
    result = subprocess.run(
        [sys.executable, "-m", "phav_app.cli", "generate", "--theta", str(theta_variant(tmp_path, tiny)),
         "--videos", "1", "--seed", "3", "--workers", "2", "--out", str(tmp_path / "data")],
        capture_output=True, text=True, env=env,
    )  # fmt: skip
    assert result.returncode == 0, result.stderr
    assert "wrote 1 videos" in result.stdout
    assert len(loaded.read_text().split()) >= 2, "the refusal was loaded by the main process and its workers"
    assert not refusals.exists(), refusals.read_text()
