"""The per-frame metadata contract: a frame's json member reads back into the rows it was
written from, NaN included, and a member of another version or shape is refused."""

from __future__ import annotations

import math

import pytest

from phav_spec.canonical import canonical_json
from phav_spec.metadata import METADATA_VERSION, finite_row, frame_json, frame_rows

CAMERA = {"video_id": "v000001", "frame": 3, "time_s": 0.1, "fx": 300.0, "fy": 300.0, "cx": 170.0, "cy": 128.0,
          "cam_to_world": [1.0, 0.0, 0.0, 2.5] * 4}  # fmt: skip
PERSON = {"video_id": "v000001", "frame": 3, "person_id": 2, "instance_rgb": [1, 2, 3], "role": "background",
          "bbox2d": [math.nan] * 4, "joints2d": [10.5, math.nan] * 13, "visible": [False] * 13,
          "muscle_limits": [[-1.0, 1.0], []], "penetration_m": math.nan, "pixels": 0}  # fmt: skip


def _same(a: object, b: object) -> bool:
    """Equal, NaN equal to NaN."""
    if isinstance(a, float) and isinstance(b, float):
        return a == b or (math.isnan(a) and math.isnan(b))
    if isinstance(a, list) and isinstance(b, list):
        return len(a) == len(b) and all(_same(x, y) for x, y in zip(a, b, strict=True))
    if isinstance(a, dict) and isinstance(b, dict):
        return a.keys() == b.keys() and all(_same(a[k], b[k]) for k in a)
    return type(a) is type(b) and a == b


def test_a_frame_json_reads_back_into_its_rows_nan_included():
    camera, people = frame_rows(frame_json(CAMERA, [PERSON, PERSON]))
    assert _same(camera, CAMERA) and len(people) == 2 and all(_same(p, PERSON) for p in people)
    assert people[0]["pixels"] == 0 and isinstance(people[0]["pixels"], int)  # ints stay ints


def test_an_infinite_value_is_written_as_nan_so_the_rows_read_back_as_written():
    """±inf would come back from the json as NaN: the rows written to a table and a frame's
    json are both ``finite_row``'s, which reads back the same."""
    person = PERSON | {"penetration_m": math.inf, "joints2d": [10.5, -math.inf] * 13}
    row = finite_row(person)
    assert math.isnan(row["penetration_m"]) and row["joints2d"][:2] == [10.5, row["joints2d"][1]]
    assert math.isnan(row["joints2d"][1]) and row["instance_rgb"] is person["instance_rgb"]
    camera, people = frame_rows(frame_json(finite_row(CAMERA), [row]))
    assert _same(camera, CAMERA) and _same(people[0], row)


@pytest.mark.parametrize(
    "member",
    [
        canonical_json({"metadata_version": METADATA_VERSION + 1, "camera": {}, "people": []}).encode(),
        canonical_json({"metadata_version": METADATA_VERSION, "camera": [], "people": []}).encode(),
        canonical_json({"metadata_version": METADATA_VERSION, "camera": {}, "people": [1]}).encode(),
        canonical_json([1, 2]).encode(),
        b"{not json",
        b"\xff\xfe",
    ],
)
def test_a_member_off_the_contract_is_refused(member):
    with pytest.raises(ValueError):
        frame_rows(member)
