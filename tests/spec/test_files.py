"""phav_spec.files: atomic writes and what a killed writer leaves."""

from __future__ import annotations

import os
from pathlib import Path

from phav_spec.files import atomic_write


def test_atomic_write_sweeps_only_when_no_write_into_the_folder_is_under_way(tmp_path: Path) -> None:
    """``sweep`` removes the target's stale temporaries, but none while another write into the
    folder holds its lock (that temporary may be the live writer's)."""
    target = tmp_path / "t.bin"
    stale = tmp_path / f".t.bin.{'a' * 16}.tmp"
    stale.write_bytes(b"left by a killed writer")
    with atomic_write(tmp_path / "u.bin") as live:
        live.write_bytes(b"u")
        with atomic_write(target, sweep=True) as tmp:
            tmp.write_bytes(b"t")
        assert stale.exists()
    with atomic_write(target, sweep=True) as tmp:
        tmp.write_bytes(b"t2")
    assert sorted(os.listdir(tmp_path)) == ["t.bin", "u.bin"] and target.read_bytes() == b"t2"
