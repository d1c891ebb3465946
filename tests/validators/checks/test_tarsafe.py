"""Reading shards safely: members that escape the directory, links, devices and
decompression bombs are refused, and nothing is ever written."""

from __future__ import annotations

import io
import tarfile
from pathlib import Path

from phav_validators.checks.tarsafe import TarScan, iter_members
from phav_validators.findings import Reason
from tests.validators.checks.support import assert_fails, rewrite_tar, shard_of, validate


def test_evil_member_is_refused_and_nothing_is_written(data):
    shard = shard_of(data, "v000002")
    rewrite_tar(shard, lambda n, d: d, extra=[("../evil", b"gotcha"), ("/abs/evil", b"x")])
    report = validate(data, "integrity")
    hits = assert_fails(report, "integrity", Reason.UNSAFE_MEMBER, file=shard.name)
    assert any("../evil" in f.message for f in hits) and any("/abs/evil" in f.message for f in hits)
    assert not (data.parent / "evil").exists() and not Path("/abs/evil").exists()


def test_links_devices_and_bombs_are_refused(tmp_path):
    path = tmp_path / "hostile.tar"
    with tarfile.open(path, "w", format=tarfile.USTAR_FORMAT) as tar:
        link = tarfile.TarInfo("v000000/00000.rgb.png")
        link.type, link.linkname = tarfile.SYMTYPE, "/etc/passwd"
        tar.addfile(link)
        dev = tarfile.TarInfo("dev")
        dev.type = tarfile.CHRTYPE
        tar.addfile(dev)
        big = tarfile.TarInfo("v000000/00000.depth.png")
        big.size = 65 * 2**20
        tar.addfile(big, io.BytesIO(bytes(big.size)))
        ok = tarfile.TarInfo("fine.txt")
        ok.size = 2
        tar.addfile(ok, io.BytesIO(b"ok"))
    scan = TarScan()
    assert [n for n, _ in iter_members(path, scan)] == ["fine.txt"]
    assert [(r.name, r.kind) for r in scan.refused] == [
        ("v000000/00000.rgb.png", "unsafe"), ("dev", "unsafe"), ("v000000/00000.depth.png", "oversized"),
    ]  # fmt: skip
    assert scan.truncated is None and scan.bytes == path.stat().st_size
    # A secondary scan part seeks to the members it wants and still refuses the hostile ones.
    assert [n for n, _ in iter_members(path, TarScan(), only=lambda name: True)] == ["fine.txt"]
    assert [n for n, _ in iter_members(path, TarScan(), only=lambda name: name != "fine.txt")] == []
