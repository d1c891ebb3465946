"""phav_spec.files: atomic writes and what a killed writer leaves."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from phav_spec.errors import PhavUserError
from phav_spec.files import atomic_write, check_output_file


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


def test_an_earlier_report_with_a_byte_order_mark_or_a_comment_first_may_be_replaced(tmp_path: Path) -> None:
    """HTML saved by an editor (a byte-order mark) or opening with a comment was refused as
    "not a HTML file"; notes, and a page of another kind behind a comment, are still refused,
    in English."""
    for name, text in (("bom.html", "\ufeff<!DOCTYPE html><html></html>"), ("c.html", "<!-- r -->\n<html></html>"),
                       ("bom.json", "\ufeff {}")):  # fmt: skip
        (tmp_path / name).write_text(text, encoding="utf-8")
        check_output_file(tmp_path / name, field="--html", kind="JSON" if name.endswith(".json") else "HTML")
    for name, text in (("notes.html", "my notes\n"), ("notes.md", "<!-- toc -->\n# My notes\n"),
                       ("fig.svg", "<!-- made by hand -->\n<svg></svg>")):  # fmt: skip
        (tmp_path / name).write_text(text, encoding="utf-8")
        with pytest.raises(PhavUserError, match=r"--html: exists and is not an HTML file, which this would replace"):
            check_output_file(tmp_path / name, field="--html", kind="HTML")
