"""The consistency check: flow agrees with depth and camera motion on pixels that never move."""

from __future__ import annotations

from phav_spec.vocab import PIXEL_CLASSES
from phav_validators.checks.scan import class_lut
from phav_validators.findings import Reason, Status
from tests.validators.checks.support import (
    assert_fails,
    check,
    png_edit,
    refresh_manifest,
    rewrite_tar,
    shard_of,
    validate,
)


def test_flow_that_disagrees_with_depth_fails_consistency(data):
    def shift(image):  # OpenCV order: B G R = valid, v, u; push u by 2 px where valid
        valid = image[..., 0] == 1
        image[..., 2][valid] += 128
        return image

    rewrite_tar(shard_of(data, "v000002"), png_edit("v000002/00003.flow.png", shift))
    refresh_manifest(data)  # the forger fixes the hashes too: only consistency can tell
    report = validate(data, "integrity", "consistency")
    assert check(report, "integrity").status != Status.FAIL
    hits = assert_fails(report, "consistency", Reason.FLOW_DEPTH_MISMATCH, video="v000002")
    assert "frame 00003" in hits[0].message


def test_flow_is_checked_against_depth_only_on_classes_that_never_move():
    """The consistency check's static pixels: roads and walls, not vehicles, props or doors
    (push swings a door open; its moving leaf failed v000024 of the 100-video measurement)."""
    _, person, static = class_lut()
    ids = {name: PIXEL_CLASSES[name].class_id for name in ("road", "building", "floor", "door", "car", "misc")}
    assert static[ids["road"]] and static[ids["building"]] and static[ids["floor"]]
    assert not any(static[ids[name]] for name in ("door", "car", "misc"))
    assert not static[person].any()
