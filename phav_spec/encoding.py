"""Pixel encodings of PHAV's ground-truth modalities, as pure functions on numpy arrays.

The writer turns rendered float buffers into these integer arrays before PNG encoding, and
the validators and loaders turn them back; neither direction touches files (DESIGN.md rows
"depth", "flow", "content hash"). Depth follows Virtual KITTI 2 (1 code = 1 cm), flow
follows the KITTI 2015 devkit (1 code = 1/64 px, offset 2**15, B = valid).
"""

from __future__ import annotations

import hashlib
import struct
from collections.abc import Mapping
from typing import Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, Field

__all__ = [
    "DEPTH_MAX_CODE",
    "DEPTH_UNITS_PER_M",
    "FLOW_LIMIT_PX",
    "FLOW_OFFSET",
    "FLOW_SCALE",
    "MAX_PERSON_ID",
    "MODALITIES",
    "ContentHasher",
    "ModalityEncoding",
    "VideoHashes",
    "content_hash",
    "decode_depth",
    "decode_flow",
    "encode_depth",
    "encode_flow",
    "flow_pixels",
    "instance_rgb",
    "modality",
    "video_content_hash",
]

#: Depth codes per metre: one code is one centimetre along the camera axis.
DEPTH_UNITS_PER_M = 100
#: The largest depth code; it means "sky, no surface, or at least 655.35 m away".
DEPTH_MAX_CODE = 65535
#: Flow codes per pixel of displacement (KITTI 2015).
FLOW_SCALE = 64
#: Code of zero flow (KITTI 2015).
FLOW_OFFSET = 2**15
#: Flow components with ``|u| >= FLOW_LIMIT_PX`` or ``|v| >= FLOW_LIMIT_PX`` are invalid.
FLOW_LIMIT_PX = 512.0

# Largest and smallest rint(u * 64) that fit in a uint16 after adding the offset.
_FLOW_MAX_STEP = 2**16 - 1 - FLOW_OFFSET
_FLOW_MIN_STEP = -FLOW_OFFSET
_HASH_DOMAIN = b"phav-content-hash-v1"


def _require_float(name: str, array: np.ndarray) -> None:
    """Reject non-floating input: an integer array of metres or pixels is almost always a bug."""
    if array.dtype.kind != "f":
        raise ValueError(f"{name} must be a floating array (float32/float64), got {array.dtype}")


def encode_depth(depth_m: np.ndarray) -> np.ndarray:
    """Encode distance along the camera axis in metres as uint16 centimetre codes.

    ``code = clip(rint(d * 100), 1, 65535)`` computed in float64 (a float32 input times 100
    is exact in float64, so the code depends only on the stored value). ``np.rint`` rounds
    half to even. NaN and +inf mean sky / no surface and give 65535, as does anything that
    rounds to 65535 or more (d > 655.345 m: 655.345 m itself is 65534.5 cm, rounded to even
    65534; the far code is documented as ">= 655.35 m").
    Code 0 is never written: a surface closer than 5 mm gets 1.

    Args:
        depth_m: float32 or float64 array of any shape, metres, >= 0 or NaN or +inf.

    Returns:
        uint16 array of the same shape.

    Raises:
        ValueError: non-floating input, or any negative / -inf depth (a bug upstream).
    """
    depth = np.asarray(depth_m)
    _require_float("depth_m", depth)
    depth = depth.astype(np.float64, copy=False)
    negative = depth < 0  # NaN compares False; -inf is caught here
    n_negative = int(np.count_nonzero(negative))
    if n_negative:
        raise ValueError(
            f"{n_negative} pixel(s) have negative or -inf depth (min {float(np.nanmin(depth))}); "
            "depth is a distance along the camera axis and must be >= 0, NaN or +inf"
        )
    with np.errstate(invalid="ignore", over="ignore"):
        steps = np.rint(depth * DEPTH_UNITS_PER_M)
    # Clip in float before casting: numpy's float -> uint16 cast wraps instead of saturating.
    steps = np.where(np.isnan(steps), DEPTH_MAX_CODE, steps)
    steps = np.clip(steps, 1, DEPTH_MAX_CODE)
    return steps.astype(np.uint16)


def decode_depth(code: np.ndarray) -> np.ndarray:
    """Decode uint16 centimetre codes to float32 metres; 65535 (far or sky) becomes +inf.

    Raises:
        ValueError: input that is not uint16, or any code 0 (never written by ``encode_depth``).
    """
    code = np.asarray(code)
    if code.dtype != np.uint16:
        raise ValueError(f"depth codes must be uint16, got {code.dtype}")
    n_zero = int(np.count_nonzero(code == 0))
    if n_zero:
        raise ValueError(
            f"depth code 0 is never written ({n_zero} pixel(s)); the image is not a PHAV "
            "depth map or was corrupted (0 cannot be told apart from a missing value)"
        )
    depth = code.astype(np.float64) / DEPTH_UNITS_PER_M
    depth[code == DEPTH_MAX_CODE] = np.inf
    return depth.astype(np.float32)


def encode_flow(u: np.ndarray, v: np.ndarray, valid: np.ndarray | None = None) -> np.ndarray:
    """Encode forward flow t→t+1 in pixels as a KITTI 2015 uint16 (H, W, 3) array, RGB order.

    ``R = rint(u * 64) + 2**15``, ``G = rint(v * 64) + 2**15``, ``B = 1`` for a valid pixel;
    an invalid pixel is written as (0, 0, 0). ``np.rint`` rounds half to even (1.5/64 px →
    2 steps, 0.5/64 px → 0 steps); the product is exact (64 is a power of two).
    A pixel is invalid where ``valid`` is False, where u or v is not finite, or where
    ``|u| >= 512`` or ``|v| >= 512``. Valid components in [511.9921875, 512) would round to
    code 65536 and saturate to 65535 (511.984375 px); components in (-512, -511.9921875]
    round to code 0, which is a legal KITTI value and keeps B = 1. OpenCV writers want BGR:
    reverse the last axis before ``cv2.imwrite``.

    Args:
        u: horizontal flow, float (H, W), pixels, positive to the right.
        v: vertical flow, float (H, W), pixels, positive downwards.
        valid: optional bool (H, W); False marks pixels without flow (sky, behind camera).

    Returns:
        uint16 array (H, W, 3).

    Raises:
        ValueError: non-floating u/v, non-bool ``valid``, or mismatched / non-2-D shapes.
    """
    u = np.asarray(u)
    v = np.asarray(v)
    _require_float("u", u)
    _require_float("v", v)
    if u.ndim != 2 or u.shape != v.shape:
        raise ValueError(f"u and v must be 2-D arrays of one shape, got {u.shape} and {v.shape}")
    ok = np.ones(u.shape, dtype=bool)
    if valid is not None:
        valid = np.asarray(valid)
        if valid.dtype != np.bool_ or valid.shape != u.shape:
            raise ValueError(f"valid must be a bool array of shape {u.shape}, got {valid.dtype} {valid.shape}")
        ok &= valid
    # At least float32 (a float16 code would round); scaling by 64, a power of two, is exact.
    u = u.astype(np.promote_types(u.dtype, np.float32), copy=False)
    v = v.astype(np.promote_types(v.dtype, np.float32), copy=False)
    with np.errstate(invalid="ignore"):
        ok &= (np.abs(u) < FLOW_LIMIT_PX) & (np.abs(v) < FLOW_LIMIT_PX)  # False for NaN and ±inf
    out = np.zeros((*u.shape, 3), dtype=np.uint16)
    for channel, component in ((0, u), (1, v)):
        # Whole arrays, not boolean indexing (5× faster); invalid pixels are zeroed first,
        # so no NaN or infinity reaches the cast.
        steps = np.rint(np.where(ok, component, 0.0) * FLOW_SCALE)
        # Clip before casting (casts wrap); only the +512 side can overflow for |x| < 512.
        np.clip(steps, _FLOW_MIN_STEP, _FLOW_MAX_STEP, out=steps)
        steps += FLOW_OFFSET
        steps *= ok
        out[..., channel] = steps
    out[..., 2] = ok
    return out


def decode_flow(code: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Decode a KITTI 2015 uint16 (H, W, 3) RGB array to flow in pixels and a validity mask.

    Returns:
        ``(flow, valid)``: float32 (H, W, 2) with (u, v) in pixels and NaN where invalid;
        bool (H, W). Values of R and G at invalid pixels are ignored.

    Raises:
        ValueError: a dtype other than uint16, a shape other than (H, W, 3), or a B channel
            value other than 0 or 1 (e.g. a BGR image read without reversing the channels).
    """
    code = np.asarray(code)
    if code.dtype != np.uint16:
        raise ValueError(f"flow codes must be uint16, got {code.dtype}")
    if code.ndim != 3 or code.shape[2] != 3:
        raise ValueError(f"flow codes must have shape (H, W, 3), got {code.shape}")
    blue = code[..., 2]
    bad = blue > 1
    n_bad = int(np.count_nonzero(bad))
    if n_bad:
        raise ValueError(
            f"flow B channel must be 0 or 1, found {n_bad} pixel(s) with other values "
            f"(e.g. {int(blue[bad][0])}); was the image read in BGR order?"
        )
    valid = blue == 1
    flow = (code[..., :2].astype(np.float64) - FLOW_OFFSET) / FLOW_SCALE
    flow[~valid] = np.nan
    return flow.astype(np.float32), valid


def flow_pixels(code: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """KITTI codes (H, W, 3) uint16, RGB order → (flow, valid): (u, v) float32 pixels with 0
    where invalid, and the validity. ``decode_flow``'s values without NaN, about three times
    faster, which matters when a whole dataset is read for training.

    Raises:
        ValueError: a B channel value other than 0 or 1 (e.g. a BGR image).
    """
    valid = code[..., 2]
    if valid.max(initial=0) > 1:
        raise ValueError("flow B channel must be 0 or 1 (was it read in BGR order?)")
    flow = code[..., :2].astype(np.float32)
    flow -= FLOW_OFFSET
    flow *= valid[..., None].astype(np.float32) / FLOW_SCALE
    return flow, valid.astype(bool)


def _frame(data: bytes) -> bytes:
    """Prefix ``data`` with its length so that concatenated fields cannot be re-split."""
    return struct.pack("<Q", len(data)) + data


class ContentHasher:
    """``content_hash`` computed one array at a time, for videos too large to hold at once.

    Give the number of arrays up front and add them in sorted-name order (zero-padded frame
    numbers are); ``hexdigest`` then equals ``content_hash`` of the same mapping.
    """

    def __init__(self, count: int):
        self._digest = hashlib.sha256(_HASH_DOMAIN)
        self._digest.update(struct.pack("<Q", count))
        self._count = count
        self._added = 0
        self._last: str | None = None

    def add(self, name: str, array: np.ndarray) -> None:
        if not isinstance(name, str):
            raise ValueError(f"array names must be str, got {name!r}")
        if self._last is not None and name <= self._last:
            raise ValueError(f"arrays must come in sorted-name order: {name!r} after {self._last!r}")
        array = np.asarray(array)
        if array.dtype.kind not in "biufc":
            raise ValueError(f"array {name!r} has unsupported dtype {array.dtype}")
        array = np.ascontiguousarray(array, dtype=array.dtype.newbyteorder("<"))
        self._digest.update(_frame(name.encode("utf-8")))
        self._digest.update(_frame(array.dtype.str.encode("ascii")))
        self._digest.update(_frame(struct.pack(f"<{array.ndim}Q", *array.shape)))
        # The pixels' length prefix, then the buffer itself: no copy of a frame's bytes.
        self._digest.update(struct.pack("<Q", array.nbytes))
        self._digest.update(array)  # C-contiguous, so hashlib reads its buffer in place
        self._last = name
        self._added += 1

    def hexdigest(self) -> str:
        if self._added != self._count:
            raise ValueError(f"{self._added} array(s) added, {self._count} announced")
        return self._digest.hexdigest()


def content_hash(arrays: Mapping[str, np.ndarray]) -> str:
    """Return the sha256 hex digest of decoded pixel arrays, independent of PNG/zlib bytes.

    Arrays are taken in sorted-name order, so mapping order does not matter. Each contributes
    its name, dtype string, shape and C-order bytes, every field length-prefixed; the values
    are converted to little-endian first so that byte order in memory does not matter.

    Raises:
        ValueError: a non-str name or an array that is not bool, integer, float or complex.
    """
    for name in arrays:
        if not isinstance(name, str):
            raise ValueError(f"array names must be str, got {name!r}")
    hasher = ContentHasher(len(arrays))
    for name in sorted(arrays):
        hasher.add(name, arrays[name])
    return hasher.hexdigest()


def video_content_hash(modality_hashes: Mapping[str, str]) -> str:
    """A video's content hash: sha256 over its per-modality content hashes (sorted names).

    Every modality's hash covers all of its frames, so this one digest changes when any
    pixel of any modality does."""
    h = hashlib.sha256(_HASH_DOMAIN + b"/video")
    for name in sorted(modality_hashes):
        h.update(_frame(name.encode("utf-8")))
        h.update(_frame(modality_hashes[name].encode("ascii")))
    return h.hexdigest()


class ModalityEncoding(BaseModel):
    """How one per-frame modality is stored: WebDataset key, pixel dtype and channel count."""

    model_config = ConfigDict(extra="forbid", frozen=True, strict=True)

    name: str = Field(pattern=r"^[a-z][a-z0-9_]*$")
    key: str = Field(pattern=r"^[a-z0-9_]+(\.[a-z0-9_]+)+$")
    dtype: Literal["uint8", "uint16"]
    channels: Literal[1, 3]
    description: str
    units: str | None = None


#: The six per-frame image modalities of a PHAV sample, in the order a sample lists them.
MODALITIES: tuple[ModalityEncoding, ...] = (
    ModalityEncoding(
        name="rgb", key="rgb.png", dtype="uint8", channels=3,
        description="final RGB frame after post-processing",
    ),
    ModalityEncoding(
        name="raw_rgb", key="raw.png", dtype="uint8", channels=3,
        description="RGB frame before post-processing",
    ),
    ModalityEncoding(
        name="semantic", key="seg.png", dtype="uint8", channels=3,
        description="24-bit class colours of phav_spec.vocab.PIXEL_CLASSES, (0, 0, 0) unlabeled",
    ),
    ModalityEncoding(
        name="instance", key="inst.png", dtype="uint8", channels=3,
        description="one stable 24-bit colour per person id, black background; "
        "id-colour table in the metadata",
    ),
    ModalityEncoding(
        name="depth", key="depth.png", dtype="uint16", channels=1,
        description="cm along the camera axis, 65535 = sky or >= 655.35 m, 0 never written",
        units="cm",
    ),
    ModalityEncoding(
        name="flow", key="flow.png", dtype="uint16", channels=3,
        description="KITTI 2015 forward flow t→t+1: R, G = rint(64 px) + 2**15, B = valid; "
        "invalid = (0, 0, 0); RGB order (reverse for OpenCV)",
        units="px/64",
    ),
)  # fmt: skip

_BY_NAME = {m.name: m for m in MODALITIES}


def modality(name: str) -> ModalityEncoding:
    """Look up a modality by name; raise ``KeyError`` listing the known names."""
    try:
        return _BY_NAME[name]
    except KeyError:
        raise KeyError(f"unknown modality {name!r}; expected one of: {', '.join(_BY_NAME)}") from None


class VideoHashes:
    """One ``content_hash`` per modality over a video's frames, fed frame by frame in order
    (arrays named by zero-padded frame number), and the video's hash over those."""

    def __init__(self, n_frames: int):
        self._hashers = {m.name: ContentHasher(n_frames) for m in MODALITIES}

    def add(self, frame: int, modalities: Mapping[str, np.ndarray]) -> None:
        """Add frame ``frame``'s arrays; raises ValueError when frames come out of order."""
        for name, hasher in self._hashers.items():
            hasher.add(f"{frame:05d}", modalities[name])

    def hexdigests(self) -> dict[str, str]:
        """Per modality name, the content hash (ValueError unless every frame was added)."""
        return {name: h.hexdigest() for name, h in self._hashers.items()}

    def video_hash(self) -> str:
        """The video's content hash: one digest over the per-modality hashes."""
        return video_content_hash(self.hexdigests())


#: Person ids that have an instance colour (protagonist, supporting, background actors).
MAX_PERSON_ID = 255


def instance_rgb(person_id: int) -> tuple[int, int, int]:
    """The stable instance colour of a person id: hues a golden-ratio step apart, full
    saturation bands, never black (black is "no person") and distinct for every id up to
    ``MAX_PERSON_ID``. Integer arithmetic only, so every platform gives the same colour."""
    if isinstance(person_id, bool) or not isinstance(person_id, int) or not 0 <= person_id <= MAX_PERSON_ID:
        raise ValueError(f"person id must be an int in [0, {MAX_PERSON_ID}], got {person_id!r}")
    hue = (person_id * 40503) % 65536  # 40503 / 65536 ≈ the golden ratio's fraction
    band = person_id % 3  # three brightness bands keep near hues apart
    top, low = (255, 200, 150)[band], (40, 80, 20)[band]
    sector, rest = divmod(hue * 6, 65536)
    rise = low + (top - low) * rest // 65536
    fall = top - (top - low) * rest // 65536
    r, g, b = (
        (top, rise, low), (fall, top, low), (low, top, rise), (low, fall, top), (rise, low, top), (top, low, fall),
    )[sector]  # fmt: skip
    return int(r), int(g), int(b)
