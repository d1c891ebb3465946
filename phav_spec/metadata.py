"""Per-frame metadata: the columns of ``cameras.parquet`` and ``people.parquet``, a contract.

Consumers and validators rely on these names, types and meanings (README, "Dataset
layout"). Each frame's WebDataset sample carries the same rows as JSON (``json`` member:
``{"camera": {...}, "people": [...]}``, NaN written as ``null``), so a WebDataset reader
needs no Parquet. A float is finite or NaN (unknown) in both: ``finite_row`` makes ±inf NaN.

Conventions (DESIGN.md): world metres, +Z up; the camera looks down its −Z axis, +Y up, +X
right; pixel (u, v) has its centre at (u + 0.5, v + 0.5), v downwards, so a pixel with depth
d is the camera-space point ((u + 0.5 − cx)·d/fx, −(v + 0.5 − cy)·d/fy, −d).
pyarrow is imported inside functions: reading the contract needs nothing heavy.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from phav_spec.canonical import canonical_json

if TYPE_CHECKING:
    import pyarrow as pa

__all__ = [
    "CAMERA_COLUMNS",
    "JOINT_ORDER",
    "METADATA_VERSION",
    "PEOPLE_COLUMNS",
    "ROLES",
    "MetaColumn",
    "arrow_schema",
    "finite_row",
    "frame_json",
    "frame_rows",
]

#: Version of the per-frame metadata contract (bumped when a column changes meaning).
METADATA_VERSION = 1

#: The 13 joints of the pixel-class table in ``joints3d``/``joints2d``/``visible`` order.
JOINT_ORDER: tuple[str, ...] = (
    "neck", "left_shoulder", "right_shoulder", "left_elbow", "right_elbow", "left_wrist", "right_wrist",
    "left_hip", "right_hip", "left_knee", "right_knee", "left_ankle", "right_ankle",
)  # fmt: skip

#: Who a person is in the video.
ROLES: tuple[str, ...] = ("protagonist", "supporting", "background")


@dataclass(frozen=True)
class MetaColumn:
    """A metadata column: name, Arrow type (``float64``, ``list<float64>[16]``, …) and meaning."""

    name: str
    arrow_type: str
    doc: str


#: The key every per-frame table starts with.
_FRAME_KEY: tuple[MetaColumn, ...] = (
    MetaColumn("video_id", "string", "v000123"),
    MetaColumn("frame", "int64", "frame index from 0"),
)

CAMERA_COLUMNS: tuple[MetaColumn, ...] = (
    *_FRAME_KEY,
    MetaColumn("time_s", "float64", "frame / fps"),
    MetaColumn("fx", "float64", "focal length along u, px"),
    MetaColumn("fy", "float64", "focal length along v, px"),
    MetaColumn("cx", "float64", "principal point u, px (pixel centres at u + 0.5)"),
    MetaColumn("cy", "float64", "principal point v, px (v downwards)"),
    MetaColumn("cam_to_world", "list<float64>[16]", "row-major 4×4 rigid pose; the camera looks down its −Z, +Y up"),
)

PEOPLE_COLUMNS: tuple[MetaColumn, ...] = (
    *_FRAME_KEY,
    MetaColumn("person_id", "int64", "0 protagonist, the supporting characters next (1 in two-person actions), "
               "the background actors after them"),
    MetaColumn("instance_rgb", "list<int64>[3]", "the person's colour in the instance modality"),
    MetaColumn("role", "string", "protagonist, supporting or background"),
    MetaColumn("human_model", "string", "one of the 20 human models, or 'sampled' (a person drawn from θ's people)"),
    MetaColumn("pixels", "int64", "pixels of the person in the instance modality"),
    MetaColumn("bbox2d", "list<float64>[4]", "x0, y0, x1, y1 px: pixel edges around the visible mask (NaN if none)"),
    MetaColumn("bbox3d", "list<float64>[24]", "8 world corners × xyz of the body box aligned with the pelvis "
               "heading; corner k is min/max along the box's x, y, z from bits 0, 1, 2 of k"),
    MetaColumn("joints3d", "list<float64>[39]", "13 joints × xyz, world metres, JOINT_ORDER"),
    MetaColumn("joints2d", "list<float64>[26]", "13 joints × (u, v) px, pixel centres at +0.5; NaN behind the camera"),
    MetaColumn("visible", "list<bool>[13]", "joint in the image and not hidden behind another surface"),
    MetaColumn("muscle_strength", "list<float64>[15]", "servo strength per muscle (MUSCLES order), 1 = nominal"),
    MetaColumn("muscle_limits", "list<list<float64>>", "per muscle: lower, upper (rad) of each of its joint "
               "DOFs in turn; the pelvis (free root) has none"),
    MetaColumn("pin_weight", "list<float64>[15]", "Cartesian pin weight per muscle: the pelvis carries the root "
               "pin (1 pinned, 0 released); the others are driven by joint servos only (0)"),
    MetaColumn("penetration_m", "float64", "deepest body–world penetration (NaN: kinematic background actor)"),
    MetaColumn("joint_limit_excess", "float64", "largest joint-limit violation, rad"),
)  # fmt: skip


def _arrow_type(name: str) -> pa.DataType:
    import pyarrow as pa  # phav_spec imports light (DESIGN.md): pyarrow only when a table is read or written

    if name.startswith("list<"):
        inner, _, size = name[5:].rpartition(">")
        value = _arrow_type(inner)
        return pa.list_(value, int(size[1:-1])) if size else pa.list_(value)
    return getattr(pa, "bool_" if name == "bool" else name)()


def arrow_schema(columns: Sequence[MetaColumn]) -> pa.Schema:
    """The Arrow schema of a metadata table, with the contract version in its metadata."""
    import pyarrow as pa  # phav_spec imports light (DESIGN.md): pyarrow only when a table is read or written

    return pa.schema(
        [pa.field(c.name, _arrow_type(c.arrow_type), nullable=False) for c in columns],
        metadata={"phav.metadata_version": str(METADATA_VERSION)},
    )


def _nan_to_none(value: Any) -> Any:
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, list | tuple):
        return [_nan_to_none(v) for v in value]
    return value


def finite_row(row: Mapping[str, Any]) -> dict[str, Any]:
    """A metadata row with every ±inf (a value or a list item) as NaN, unknown: the tables and
    the frames' json then hold the same values, and a table remade from the json
    (``frame_rows``) is the one written."""
    return {k: _inf_to_nan(v) if _has_inf(v) else v for k, v in row.items()}


def _has_inf(value: Any) -> bool:
    if isinstance(value, float):
        return math.isinf(value)
    return isinstance(value, list | tuple) and any(_has_inf(v) for v in value)


def _inf_to_nan(value: Any) -> Any:
    if isinstance(value, float) and math.isinf(value):
        return math.nan
    if isinstance(value, list | tuple):
        return [_inf_to_nan(v) for v in value]
    return value


def frame_json(camera: Mapping[str, Any], people: Sequence[Mapping[str, Any]]) -> bytes:
    """The ``json`` member of a frame's sample: its camera row and people rows, NaN as null."""
    data = {
        "metadata_version": METADATA_VERSION,
        "camera": {k: _nan_to_none(v) for k, v in camera.items()},
        "people": [{k: _nan_to_none(v) for k, v in row.items()} for row in people],
    }
    return canonical_json(data).encode("utf-8")


def _none_to_nan(value: Any) -> Any:
    if value is None:
        return math.nan
    if isinstance(value, list):
        return [_none_to_nan(v) for v in value]
    return value


#: The columns whose values (or list items) are floats: where a frame's json holds null for NaN.
_FLOAT_COLUMNS = frozenset(c.name for c in (*CAMERA_COLUMNS, *PEOPLE_COLUMNS) if "float" in c.arrow_type)


def frame_rows(data: bytes) -> tuple[dict[str, Any], list[dict[str, Any]]]:
    """A frame's ``json`` member back into its camera row and people rows (``frame_json``'s
    inverse: null read as NaN in the float columns). Raises ``ValueError`` for another
    metadata version or a member that is not the contract's."""
    meta = json.loads(data)
    if not isinstance(meta, dict) or meta.get("metadata_version") != METADATA_VERSION:
        raise ValueError(f"not metadata version {METADATA_VERSION}")
    camera, people = meta.get("camera"), meta.get("people")
    if not isinstance(camera, dict) or not isinstance(people, list) or not all(isinstance(p, dict) for p in people):
        raise ValueError("no camera row or people rows")

    def row(values: dict[str, Any]) -> dict[str, Any]:
        return {k: _none_to_nan(v) if k in _FLOAT_COLUMNS else v for k, v in values.items()}

    return row(camera), [row(p) for p in people]
