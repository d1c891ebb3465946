"""The integrity check: every shard listed and whole, every video's pixels hashing to the
manifest's content hashes; a PNG re-encoded with other settings is only a warning."""

from __future__ import annotations

import io
import os
import shutil
import tarfile

import cv2
import numpy as np

from phav_spec.manifest import dump_manifest, load_manifest
from phav_validators.checks.tarsafe import TarScan, iter_members
from phav_validators.findings import Reason, Status
from tests.validators.checks.support import assert_fails, check, png_edit, rewrite_tar, shard_of, validate


def test_png_reencoded_at_another_level_passes(data):
    shard = shard_of(data, "v000000")
    member = "v000000/00003.depth.png"

    def recompress(name: str, png: bytes) -> bytes:
        if not name.endswith(".png") or not name.startswith("v000000/0000"):
            return png
        image = cv2.imdecode(np.frombuffer(png, np.uint8), cv2.IMREAD_UNCHANGED)
        return cv2.imencode(".png", image, [cv2.IMWRITE_PNG_COMPRESSION, 9])[1].tobytes()

    before = dict(iter_members(shard, TarScan()))[member]
    rewrite_tar(shard, recompress)
    assert dict(iter_members(shard, TarScan()))[member] != before
    report = validate(data, "integrity", "encoding")
    integrity = check(report, "integrity")
    assert integrity.status == Status.WARN, [f.message for f in integrity.report.findings]
    assert [f.reason for f in integrity.report.findings] == [Reason.SHARD_BYTES_CHANGED]
    assert check(report, "encoding").status == Status.PASS


def test_flipped_depth_pixel_fails_integrity(data):
    def flip(image):
        image[100, 100] ^= 1
        return image

    rewrite_tar(shard_of(data, "v000001"), png_edit("v000001/00004.depth.png", flip))
    hits = assert_fails(validate(data, "integrity"), "integrity", Reason.HASH_MISMATCH, video="v000001")
    assert "depth" in hits[0].message


def test_dropped_frame_fails_integrity_and_encoding(data):
    rewrite_tar(shard_of(data, "v000000"), lambda n, d: None if n.startswith("v000000/00003.") else d)
    report = validate(data, "integrity", "encoding")
    assert_fails(report, "encoding", Reason.FRAME_COUNT, video="v000000")
    assert_fails(report, "integrity", Reason.HASH_MISMATCH, video="v000000")


def test_truncated_tar_fails_integrity(data):
    shard = shard_of(data, "v000000")
    shard.write_bytes(shard.read_bytes()[: shard.stat().st_size // 2 + 777])
    report = validate(data, "integrity", "encoding")
    assert_fails(report, "integrity", Reason.TRUNCATED_SHARD, file=shard.name)
    assert_fails(report, "encoding", Reason.FRAME_COUNT, video="v000001")


def test_unlisted_and_missing_shards(data):
    shutil.copy(shard_of(data, "v000000"), data / "phav-000099.tar")
    shard_of(data, "v000002").unlink()
    report = validate(data, "integrity")
    assert_fails(report, "integrity", Reason.UNLISTED_FILE, file="phav-000099.tar")
    assert_fails(report, "integrity", Reason.MISSING_FILE, file="phav-000001.tar")


def test_a_shard_that_cannot_be_read_is_damage_named_by_its_file(data):
    shard = shard_of(data, "v000002")
    shard.unlink()
    shard.mkdir()  # the tar's name, a folder's body
    hits = assert_fails(validate(data, "integrity"), "integrity", Reason.TRUNCATED_SHARD, file=shard.name)
    assert hits[0].message == "the tar is truncated or damaged: cannot be read (not a regular file)"
    shard.rmdir()
    os.mkfifo(shard)  # a pipe: opening it would wait for a writer for ever
    hits = assert_fails(validate(data, "integrity"), "integrity", Reason.TRUNCATED_SHARD, file=shard.name)
    assert hits[0].message == "the tar is truncated or damaged: cannot be read (not a regular file)"


def test_frames_out_of_order_in_a_shard_are_named_as_such(data):
    """Each sample's members together, but frame 00001's sample before frame 00000's: the
    content hash, formed in frame order, cannot be recomputed, and the finding says why."""
    shard = shard_of(data, "v000000")
    with tarfile.open(shard) as tar:
        members = [(info, tar.extractfile(info).read()) for info in tar.getmembers()]
    first = [m for m in members if m[0].name.startswith("v000000/00000.")]
    second = [m for m in members if m[0].name.startswith("v000000/00001.")]
    rest = [m for m in members if m not in first and m not in second]
    buf = io.BytesIO()
    with tarfile.open(fileobj=buf, mode="w", format=tarfile.USTAR_FORMAT) as tar:
        for info, raw in second + first + rest:
            tar.addfile(info, io.BytesIO(raw))
    shard.write_bytes(buf.getvalue())
    hits = assert_fails(validate(data, "integrity"), "integrity", Reason.HASH_MISMATCH, video="v000000")
    assert hits[0].message == "content hash cannot be recomputed: frame 00000 comes after a later frame in the shard"


def test_every_member_is_looked_at_whichever_part_of_its_shard_decodes_it(data):
    """A shard's videos are decoded in parts (v000000's and v000001's here, one process): a
    stray member of the second part's video, and a sample of it split by another video's
    whole sample, are named all the same (and that video, split by it)."""
    shard = shard_of(data, "v000001")
    with tarfile.open(shard) as tar:
        members = [(info, tar.extractfile(info).read()) for info in tar.getmembers()]
    moved = [m for m in members if m[0].name.startswith("v000000/00005.")]  # v000000's last frame, whole
    rest = [m for m in members if m not in moved]
    at = next(i for i, m in enumerate(rest) if m[0].name == "v000001/00003.rgb.png") + 1
    buf = io.BytesIO()
    with tarfile.open(fileobj=buf, mode="w", format=tarfile.USTAR_FORMAT) as tar:
        for info, raw in rest[:at] + moved + rest[at:]:
            tar.addfile(info, io.BytesIO(raw))
    shard.write_bytes(buf.getvalue())
    rewrite_tar(shard, lambda name, raw: raw, extra=[("v000001/00000.extra", b"x"), ("v000001/xx.rgb.png", b"y")])
    hits = assert_fails(validate(data, "integrity"), "integrity", Reason.UNLISTED_MEMBER, video="v000001")
    assert sorted(f.message for f in hits) == [
        "member 'v000000/00005.rgb.png': the frames of v000000 are not contiguous in the tar",
        "member 'v000001/00000.extra' belongs to no listed video frame",
        "member 'v000001/00003.raw.png': sample v000001/00003 appears twice or its members are not contiguous",
        "member 'v000001/xx.rgb.png' belongs to no listed video frame",
    ]


def test_a_manifest_listing_a_shards_videos_in_another_order_fails(data):
    """The shard's bytes and every content hash as written, its two videos listed the other
    way round: the manifest is not the shard's, and the finding says where they part."""
    m = load_manifest(data / "manifest.json")
    assert m.shards[0].video_ids == ["v000000", "v000001"]
    m.shards[0].video_ids.reverse()
    dump_manifest(m, data / "manifest.json")
    hits = assert_fails(validate(data, "integrity"), "integrity", Reason.MANIFEST_INVALID, file="phav-000000.tar")
    assert [f.message for f in hits] == ["the tar holds v000000 where the manifest lists v000001 (video 1 of the "
                                         "shard): the manifest's order is not the shard's"]  # fmt: skip


def test_a_video_whose_frames_are_split_by_anothers_is_named(data):
    """v000001's first frame moved ahead of v000000's: each sample whole and each video's
    frames in order, but v000001 is split in two."""
    shard = shard_of(data, "v000001")
    with tarfile.open(shard) as tar:
        members = [(info, tar.extractfile(info).read()) for info in tar.getmembers()]
    moved = [m for m in members if m[0].name.startswith("v000001/00000.")]
    rest = [m for m in members if m not in moved]
    buf = io.BytesIO()
    with tarfile.open(fileobj=buf, mode="w", format=tarfile.USTAR_FORMAT) as tar:
        for info, raw in moved + rest:
            tar.addfile(info, io.BytesIO(raw))
    shard.write_bytes(buf.getvalue())
    hits = assert_fails(validate(data, "integrity"), "integrity", Reason.UNLISTED_MEMBER, video="v000001")
    assert [f.message for f in hits] == ["member 'v000001/00001.rgb.png': the frames of v000001 are not "
                                         "contiguous in the tar"]  # fmt: skip
    assert_fails(validate(data, "integrity"), "integrity", Reason.MANIFEST_INVALID, file=shard.name)
