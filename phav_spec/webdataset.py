"""Reading PHAV shards with the ``webdataset`` package (or any tar reader), pixels intact.

webdataset's default image decoder goes through PIL, which reads 16-bit PNGs as 8-bit and
destroys depth and flow. ``phav_decoder`` decodes every member by its extension with OpenCV
instead (``IMREAD_UNCHANGED``, RGB order), checked against the modality's encoding::

    import webdataset as wds
    from phav_spec.webdataset import phav_decoder
    for sample in wds.WebDataset("phav-000000.tar").decode(phav_decoder):
        depth_cm = sample["depth.png"]          # (256, 340) uint16
        flow = sample["flow.png"]               # (256, 340, 3) uint16, KITTI RGB order
        people = sample["json"]["people"]       # this frame's metadata rows

OpenCV (``opencv-python-headless``) is imported on first use only.
"""

from __future__ import annotations

import json
import struct
import zlib
from typing import Any

import numpy as np

from phav_spec.encoding import MODALITIES, ModalityEncoding

__all__ = ["decode_png", "phav_decoder", "png_damage"]

_BY_KEY = {m.key: m for m in MODALITIES}
_PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def png_damage(data: bytes) -> str | None:
    """What is wrong with a PNG's chunks (a truncation, a chunk whose CRC does not match),
    None where each chunk up to IEND is whole. Checked before decoding: libpng says why it
    cannot read a damaged file on the process's stderr, not to the caller."""
    if data[:8] != _PNG_SIGNATURE:
        return "no PNG signature"
    at = 8
    while at + 12 <= len(data):
        (length,) = struct.unpack_from(">I", data, at)
        kind = data[at + 4 : at + 8]
        end = at + 8 + length
        if end + 4 > len(data):
            return f"truncated in chunk {kind.decode('latin-1')!r} at byte {at}"
        if zlib.crc32(data[at + 4 : end]) != struct.unpack_from(">I", data, end)[0]:
            return f"chunk {kind.decode('latin-1')!r} at byte {at} fails its CRC"
        if kind == b"IEND":
            return None
        at = end + 4
    return "truncated: no IEND chunk"


def decode_png(data: bytes, encoding: ModalityEncoding, *, source: str = "<bytes>") -> np.ndarray:
    """PNG bytes → the modality's array (RGB order), checked against its dtype and channels.

    Raises:
        ValueError: bytes that are not a PNG OpenCV can read, or an image of another bit depth
            or channel count than the modality's (naming ``source``).
    """
    import cv2  # phav_spec imports light (DESIGN.md): OpenCV only when a 16-bit PNG is decoded

    if damage := png_damage(data):
        raise ValueError(f"{source}: not a readable PNG: {damage}")
    image = cv2.imdecode(np.frombuffer(data, dtype=np.uint8), cv2.IMREAD_UNCHANGED)
    if image is None:
        raise ValueError(f"{source}: not a readable PNG ({len(data)} bytes)")
    channels = 1 if image.ndim == 2 else image.shape[2]
    if image.dtype != np.dtype(encoding.dtype) or channels != encoding.channels:
        raise ValueError(
            f"{source}: {encoding.name} must be {encoding.dtype} with {encoding.channels} channel(s), "
            f"found {image.dtype} with {channels}"
        )
    return cv2.cvtColor(image, cv2.COLOR_BGR2RGB, dst=image) if channels == 3 else image  # in place


def phav_decoder(key: str, data: bytes) -> Any:
    """A webdataset decode handler: modality PNGs → arrays, ``json`` → dict, else None
    (so webdataset tries its other handlers). ``key`` is the member's extension."""
    ext = key.lstrip(".").lower()
    if ext in _BY_KEY:
        return decode_png(data, _BY_KEY[ext], source=ext)
    if ext == "json":
        return json.loads(data)
    return None
