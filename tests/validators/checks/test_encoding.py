"""The encoding check: every PNG in the documented format, label images holding only the
contract's colours, instance colours only where a person is."""

from __future__ import annotations

import json

import numpy as np
import pytest

from phav_validators.findings import Reason
from tests.validators.checks.support import assert_fails, check, png_edit, rewrite_tar, shard_of, validate


def test_eight_bit_depth_fails_encoding(data):
    eight_bit = png_edit("v000002/00004.depth.png", lambda a: (a // 256).astype(np.uint8))
    rewrite_tar(shard_of(data, "v000002"), eight_bit)
    hits = assert_fails(validate(data, "encoding"), "encoding", Reason.PNG_FORMAT, video="v000002")
    assert "8-bit" in hits[0].message and "00004.depth.png" in hits[0].message


@pytest.mark.parametrize(
    ("damage", "said"),
    [
        (lambda png: png[:60] + bytes([png[60] ^ 0xFF]) + png[61:], "fails its CRC"),  # a bit flipped in IDAT
        (lambda png: png[: len(png) // 2], "truncated in chunk 'IDAT'"),
    ],
)
def test_a_damaged_png_fails_encoding_by_its_reason_and_libpng_says_nothing(data, capfd, damage, said):
    """A flipped byte or a cut PNG is reported with what is wrong; libpng and OpenCV, which
    would write their own lines to the process's stderr, never see it."""

    def edit(name: str, raw: bytes) -> bytes:
        return damage(raw) if name == "v000001/00003.flow.png" else raw

    rewrite_tar(shard_of(data, "v000001"), edit)
    capfd.readouterr()
    hits = assert_fails(validate(data, "encoding"), "encoding", Reason.PNG_FORMAT, video="v000001")
    assert "00003.flow.png cannot be decoded: " in hits[0].message and said in hits[0].message
    assert capfd.readouterr().err == ""


def test_foreign_segmentation_colour_fails_encoding(data):
    def paint(image):
        image[10:12, 20:22] = (3, 2, 1)  # BGR of (1, 2, 3)
        return image

    rewrite_tar(shard_of(data, "v000000"), png_edit("v000000/00002.seg.png", paint))
    hits = assert_fails(validate(data, "encoding"), "encoding", Reason.FOREIGN_COLOUR, video="v000000")
    assert "(1, 2, 3)" in hits[0].message and "4 semantic pixels" in hits[0].message


def test_instance_colour_without_a_person_fails_encoding(data):
    def paint(image):
        image[0:3, 0:3] = (7, 7, 7)
        return image

    rewrite_tar(shard_of(data, "v000002"), png_edit("v000002/00001.inst.png", paint))
    assert_fails(validate(data, "encoding"), "encoding", Reason.INSTANCE_MISMATCH, video="v000002")


@pytest.mark.parametrize(
    ("field", "change"),
    [
        ("camera.cam_to_world", lambda m: m["camera"].update(cam_to_world=[1.0, 0.0])),
        ("camera.fx", lambda m: m["camera"].update(fx="wide")),
        ("camera.cam_to_world", lambda m: m["camera"].pop("cam_to_world")),
        ("people", lambda m: m.update(people=None)),
        ("people[0].joints3d", lambda m: m["people"][0].pop("joints3d")),
        ("people[0].joints2d", lambda m: m["people"][0].update(joints2d="x")),
        ("people[0].visible", lambda m: m["people"][0].update(visible=[True] * 4)),
        ("people[0].person_id or pixels", lambda m: m["people"][0].update(person_id=256)),  # no instance colour
        ("people[0].person_id or pixels", lambda m: m["people"][0].update(person_id=True)),
    ],
)
def test_a_frame_json_off_the_contract_is_reported_by_its_field_not_crashed_on(data, field, change):
    def edit(name: str, raw: bytes) -> bytes:
        if name != "v000001/00002.json":
            return raw
        meta = json.loads(raw)
        change(meta)
        return json.dumps(meta).encode()

    rewrite_tar(shard_of(data, "v000001"), edit)
    report = validate(data, "encoding", "consistency")
    hits = assert_fails(report, "encoding", Reason.METADATA_INVALID, video="v000001")
    assert hits[0].message == f"v000001/00002.json: {field} is not the frame metadata contract's"
    # Its people unknown, the frame's instance colours are not judged against them.
    assert [f.reason for f in check(report, "encoding").report.findings] == [Reason.METADATA_INVALID]


def test_a_frame_json_nested_too_deep_for_python_is_reported_not_crashed_on(data):
    deep = b"[" * 100_000 + b"]" * 100_000
    rewrite_tar(shard_of(data, "v000001"), lambda name, raw: deep if name == "v000001/00002.json" else raw)
    hits = assert_fails(validate(data, "encoding"), "encoding", Reason.METADATA_INVALID, video="v000001")
    assert hits[0].message == "v000001/00002.json is not the frame metadata contract"


@pytest.mark.parametrize("version", [99, True, "1"])
def test_a_frame_json_of_a_version_this_phav_does_not_read_is_named(data, version):
    def edit(name: str, raw: bytes) -> bytes:
        if name != "v000001/00002.json":
            return raw
        meta = json.loads(raw)
        meta["metadata_version"] = version
        return json.dumps(meta).encode()

    rewrite_tar(shard_of(data, "v000001"), edit)
    hits = assert_fails(validate(data, "encoding"), "encoding", Reason.VERSION_UNKNOWN, video="v000001")
    assert hits[0].message.startswith(f"v000001/00002.json has metadata version {version!r}")
