"""Shard bytes: video parts joined into a shard are the tar one tarfile pass writes."""

from __future__ import annotations

import io
import tarfile

import numpy as np

from phav_generator.io.shards import TAR_MODE, TAR_MTIME, assemble_shard, open_part


def test_joined_parts_are_the_tar_tarfile_writes(tmp_path):
    """Video parts joined into a shard give the bytes one tarfile pass over the same members
    gives (header, padding, end-of-archive blocks and record padding included)."""
    rng = np.random.default_rng(1)
    members, parts = [], []
    for v in range(3):
        parts.append(tmp_path / f"v{v}.tar.part")
        with open_part(parts[-1]) as part:
            for j in range(5):  # sizes across block boundaries, empty members included
                name, data = f"v{v:06d}/{j:05d}.x", rng.bytes(int(rng.integers(0, 3000)))
                part.add(name, data)
                members.append((name, data))
    digest = assemble_shard(parts, tmp_path / "joined.tar")
    expected = io.BytesIO()
    with tarfile.open(fileobj=expected, mode="w", format=tarfile.USTAR_FORMAT) as tar:
        for name, data in members:
            info = tarfile.TarInfo(name)
            info.size, info.mtime, info.mode = len(data), TAR_MTIME, TAR_MODE
            tar.addfile(info, io.BytesIO(data))
    assert (tmp_path / "joined.tar").read_bytes() == expected.getvalue()
    assert digest.bytes == len(expected.getvalue())
