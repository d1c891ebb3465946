"""PNG bytes ↔ modality arrays, through OpenCV (the only common library that writes and
reads 16-bit RGB PNGs intact; Pillow silently reads them as 8-bit).

Arrays are RGB; OpenCV wants BGR, so 3-channel images are reversed on the way in and out.
Compression level 1: PNG encoding dominates a frame's cost and level 1 is ~2× faster than
6 for a few percent more bytes. Content hashes are over decoded pixels, so the level never
changes a hash.
"""

from __future__ import annotations

import cv2
import numpy as np

from phav_spec.encoding import ModalityEncoding

#: zlib level of every PNG the generator writes.
PNG_LEVEL = 1


def encode_png(array: np.ndarray, encoding: ModalityEncoding) -> bytes:
    """One modality array (H, W) or (H, W, 3), of the encoding's dtype, as PNG bytes."""
    want = (encoding.channels,) if encoding.channels == 3 else ()
    if array.dtype != np.dtype(encoding.dtype) or array.ndim != 2 + len(want) or array.shape[2:] != want:
        raise ValueError(
            f"{encoding.name}: expected {encoding.dtype} with {encoding.channels} channel(s), "
            f"got {array.dtype} of shape {array.shape}"
        )
    image = np.ascontiguousarray(array[..., ::-1]) if encoding.channels == 3 else np.ascontiguousarray(array)
    ok, data = cv2.imencode(".png", image, [cv2.IMWRITE_PNG_COMPRESSION, PNG_LEVEL])
    if not ok:
        raise RuntimeError(f"{encoding.name}: OpenCV could not encode the PNG")
    return data.tobytes()


def decode_png(data: bytes, encoding: ModalityEncoding, *, source: str = "<bytes>") -> np.ndarray:
    """PNG bytes → the modality's array, checked against its dtype and channel count.

    Raises:
        ValueError: bytes that are not a PNG OpenCV can read, or an image of another bit depth
            or channel count than the modality's (naming ``source``).
    """
    image = cv2.imdecode(np.frombuffer(data, dtype=np.uint8), cv2.IMREAD_UNCHANGED)
    if image is None:
        raise ValueError(f"{source}: not a readable PNG ({len(data)} bytes)")
    channels = 1 if image.ndim == 2 else image.shape[2]
    if image.dtype != np.dtype(encoding.dtype) or channels != encoding.channels:
        raise ValueError(
            f"{source}: {encoding.name} must be {encoding.dtype} with {encoding.channels} channel(s), "
            f"found {image.dtype} with {channels}"
        )
    return np.ascontiguousarray(image[..., ::-1]) if channels == 3 else image
