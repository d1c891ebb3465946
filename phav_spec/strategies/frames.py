"""Hypothesis strategies for encoded frames: float depth and flow, and their uint16 codes.

Public API (DESIGN.md row "property tests"): our suite uses these, and users property-test
their own loaders with them. Each strategy deliberately reaches the numerical hazards of the
encodings (sky, saturation, the ±512 px flow limit, round-half-to-even) and labels every
hazard it produced with ``hypothesis.event`` so ``pytest --hypothesis-show-statistics``
shows how often each one was exercised.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from hypothesis import event
from hypothesis import strategies as st

from phav_spec.encoding import (
    DEPTH_MAX_CODE,
    DEPTH_UNITS_PER_M,
    FLOW_LIMIT_PX,
    FLOW_OFFSET,
    FLOW_SCALE,
)

__all__ = ["depth_codes", "depth_maps_m", "flow_codes", "flow_fields", "frame_shapes"]

_FLOAT_DTYPES = ("float32", "float64")

#: Depths (m) on the edges of the encoding: sky, 0 / 5 mm (round to code 0 → 1), 655.35 m.
_DEPTH_SPECIALS_M = (
    math.nan, math.inf, 0.0, 0.004, 0.005, 0.0051, 0.015, 655.34, 655.345, 655.35, 655.36,
    1e4,
)  # fmt: skip

#: Flow components (px) on the edges: ±512 (invalid), ±511.99, the saturating band
#: [511.9921875, 512), the code-0 band, half steps of 1/64 px, non-finite values.
_FLOW_SPECIALS_PX = (
    0.0, 0.5 / 64, -0.5 / 64, 1.5 / 64, -2.5 / 64, 1.0, -1.0, 511.99, -511.99,
    511.984375, -511.984375, 511.9921875, -511.9921875, 511.999, 512.0, -512.0, 513.0,
    -600.0, 1e30, math.nan, math.inf, -math.inf,
)  # fmt: skip


def frame_shapes(*, max_side: int = 8) -> st.SearchStrategy[tuple[int, int]]:
    """Image shapes (H, W) with 1 <= H, W <= ``max_side``: small keeps examples fast."""
    side = st.integers(min_value=1, max_value=max_side)
    return st.tuples(side, side)


def _as_dtype(values: Sequence[float], dtype: str) -> tuple[float, ...]:
    """Round special values to ``dtype`` so that the array holds exactly what is labelled."""
    return tuple(float(np.asarray(x, dtype=np.float64).astype(dtype)) for x in values)


def _float_array(draw: st.DrawFn, shape: tuple[int, int], dtype: str, elements: st.SearchStrategy[float]) -> np.ndarray:
    """Draw a ``shape`` array of ``dtype`` element by element (keeps shrinking per pixel)."""
    n = shape[0] * shape[1]
    values = draw(st.lists(elements, min_size=n, max_size=n))
    return np.asarray(values, dtype=np.float64).astype(dtype).reshape(shape)


@st.composite
def _depth_maps_m(draw: st.DrawFn, max_side: int, dtypes: tuple[str, ...]) -> np.ndarray:
    dtype = draw(st.sampled_from(dtypes))
    width = 32 if dtype == "float32" else 64
    shape = draw(frame_shapes(max_side=max_side))
    elements = st.one_of(
        st.floats(min_value=0.0, max_value=650.0, width=width),
        st.sampled_from(_as_dtype(_DEPTH_SPECIALS_M, dtype)),
        st.floats(min_value=655.0, max_value=1e6, width=width),
    )
    depth = _float_array(draw, shape, dtype, elements)
    _label_depth(depth)
    return depth


def _label_depth(depth: np.ndarray) -> None:
    """Record which depth hazards ``depth`` contains."""
    d = depth.astype(np.float64)
    finite = np.isfinite(d)
    steps = np.rint(np.where(finite, d, 0.0) * DEPTH_UNITS_PER_M)
    if np.isnan(d).any():
        event("depth: sky/NaN")
    if np.isposinf(d).any():
        event("depth: +inf")
    if (finite & (steps == 0)).any():
        event("depth: rounds to 0 cm -> code 1")
    if (d == np.asarray(0.005, dtype=depth.dtype)).any():
        event("depth: exactly 0.005 m")
    if (d == np.asarray(655.35, dtype=depth.dtype)).any():
        event("depth: exactly 655.35 m")
    if (finite & (d > 655.35)).any():
        event("depth: beyond 655.35 m")
    if (finite & (steps >= 1) & (steps < DEPTH_MAX_CODE)).any():
        event("depth: in range")


def depth_maps_m(*, max_side: int = 8, dtypes: Sequence[str] = _FLOAT_DTYPES) -> st.SearchStrategy[np.ndarray]:
    """Float depth maps in metres (float32 or float64, 1..8 × 1..8) that reach every hazard.

    Values are >= 0, NaN (sky) or +inf: never negative, which ``encode_depth`` rejects.
    """
    return _depth_maps_m(max_side, tuple(dtypes))


@st.composite
def _depth_codes(draw: st.DrawFn, max_side: int) -> np.ndarray:
    shape = draw(frame_shapes(max_side=max_side))
    n = shape[0] * shape[1]
    elements = st.one_of(
        st.integers(min_value=1, max_value=DEPTH_MAX_CODE),
        st.sampled_from((1, 2, DEPTH_MAX_CODE - 1, DEPTH_MAX_CODE)),
    )
    code = np.asarray(draw(st.lists(elements, min_size=n, max_size=n)), dtype=np.uint16)
    if (code == 1).any():
        event("depth code: 1 (nearest)")
    if (code == DEPTH_MAX_CODE).any():
        event("depth code: 65535 (far/sky)")
    return code.reshape(shape)


def depth_codes(*, max_side: int = 8) -> st.SearchStrategy[np.ndarray]:
    """uint16 depth codes in [1, 65535] (both ends reached), as ``encode_depth`` writes them."""
    return _depth_codes(max_side)


@st.composite
def _flow_fields(
    draw: st.DrawFn, max_side: int, dtypes: tuple[str, ...]
) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    dtype = draw(st.sampled_from(dtypes))
    width = 32 if dtype == "float32" else 64
    shape = draw(frame_shapes(max_side=max_side))
    elements = st.one_of(
        st.floats(min_value=-520.0, max_value=520.0, width=width),
        st.sampled_from(_as_dtype(_FLOW_SPECIALS_PX, dtype)),
        # Whole and half steps of 1/64 px: exact in binary, so rint's tie rule decides them.
        st.integers(min_value=-65536, max_value=65536).map(lambda k: k / (2 * FLOW_SCALE)),
    )
    u = _float_array(draw, shape, dtype, elements)
    v = _float_array(draw, shape, dtype, elements)
    n = shape[0] * shape[1]
    mask = draw(st.none() | st.lists(st.booleans(), min_size=n, max_size=n))
    valid = None if mask is None else np.asarray(mask, dtype=bool).reshape(shape)
    _label_flow(u, v, valid)
    return u, v, valid


def _label_flow(u: np.ndarray, v: np.ndarray, valid: np.ndarray | None) -> None:
    """Record which flow hazards the field contains, using the encoding's own rules."""
    u64 = u.astype(np.float64)
    v64 = v.astype(np.float64)
    finite = np.isfinite(u64) & np.isfinite(v64)
    with np.errstate(invalid="ignore"):
        inside = (np.abs(u64) < FLOW_LIMIT_PX) & (np.abs(v64) < FLOW_LIMIT_PX)
        at_limit = (np.abs(u64) == FLOW_LIMIT_PX) | (np.abs(v64) == FLOW_LIMIT_PX)
    ok = finite & inside
    if valid is None:
        event("flow: valid=None")
    else:
        if (~valid).any():
            event("flow: invalid (mask False)")
        ok &= valid
    if (~finite).any():
        event("flow: invalid NaN/inf")
    if (finite & ~inside).any():
        event("flow: invalid |u|>=512 or |v|>=512")
    if at_limit.any():
        event("flow: exactly ±512 px")
    scaled = np.concatenate([u64[ok], v64[ok]]) * FLOW_SCALE
    steps = np.rint(scaled)
    if (steps > FLOW_OFFSET - 1).any():
        event("flow: saturated to 511.984375 px")
    if (steps == -FLOW_OFFSET).any():
        event("flow: rounds to code 0 (-512 px), still valid")
    if (np.abs(scaled - np.floor(scaled) - 0.5) == 0).any():
        event("flow: half step (round half to even)")
    if ok.any():
        event("flow: valid pixel")


def flow_fields(
    *, max_side: int = 8, dtypes: Sequence[str] = _FLOAT_DTYPES
) -> st.SearchStrategy[tuple[np.ndarray, np.ndarray, np.ndarray | None]]:
    """Forward flow ``(u, v, valid)`` in pixels that reaches every hazard of ``encode_flow``.

    ``u`` and ``v`` share one float dtype and shape (1..8 × 1..8); ``valid`` is a bool mask of
    that shape or None. Components reach ±511.99, ±512 exactly (invalid), beyond, NaN, ±inf,
    the saturating band just below 512 and exact half steps of 1/64 px.
    """
    return _flow_fields(max_side, tuple(dtypes))


@st.composite
def _flow_codes(draw: st.DrawFn, max_side: int) -> np.ndarray:
    shape = draw(frame_shapes(max_side=max_side))
    n = shape[0] * shape[1]
    component = st.one_of(
        st.integers(min_value=0, max_value=2**16 - 1),
        st.sampled_from((0, 1, FLOW_OFFSET - 1, FLOW_OFFSET, FLOW_OFFSET + 1, 2**16 - 1)),
    )
    pixels = draw(st.lists(st.tuples(component, component, st.booleans()), min_size=n, max_size=n))
    code = np.asarray(pixels, dtype=np.uint16).reshape((*shape, 3))
    code[code[..., 2] == 0] = 0  # invalid pixels are written as (0, 0, 0)
    valid = code[..., 2] == 1
    rg = code[..., :2][valid]
    if (~valid).any():
        event("flow code: invalid pixel")
    if (rg == 0).any():
        event("flow code: R or G = 0 (-512 px), valid")
    if (rg == 2**16 - 1).any():
        event("flow code: R or G = 65535 (511.984375 px)")
    if (rg == FLOW_OFFSET).any():
        event("flow code: zero flow component")
    return code


def flow_codes(*, max_side: int = 8) -> st.SearchStrategy[np.ndarray]:
    """Valid KITTI 2015 uint16 (H, W, 3) RGB codes: B in {0, 1}, invalid pixels all zero."""
    return _flow_codes(max_side)
