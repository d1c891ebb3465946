"""PNG bytes ↔ modality arrays, through OpenCV (the only common library that writes and
reads 16-bit RGB PNGs intact; Pillow silently reads them as 8-bit).

Arrays are RGB; OpenCV wants BGR, so 3-channel images are reversed on the way in and out.
Compression level 1 with the SUB row filter: PNG encoding dominates a frame's cost, and
libpng's adaptive filter choice (trying every filter on every row) costs twice the
compression itself. Measured on rendered frames, SUB alone is 2.2× faster than adaptive
filtering at level 1 and no larger; the RLE zlib strategy makes the 8-bit and depth images
a further 20–60 % smaller at the same speed, but not the flow image. Content hashes are
over decoded pixels, so these choices never change a hash.
"""

from __future__ import annotations

import cv2
import numpy as np

from phav_spec.encoding import ModalityEncoding
from phav_spec.webdataset import decode_png

__all__ = ["PNG_LEVEL", "decode_png", "encode_png"]

#: zlib level of the generator's PNGs unless θ's ``render.png_compression`` says otherwise.
PNG_LEVEL = 1
#: Modalities written with zlib's default strategy rather than RLE (see the module doc).
_DEFAULT_STRATEGY = frozenset({"flow"})


def _params(name: str, level: int) -> list[int]:
    strategy = cv2.IMWRITE_PNG_STRATEGY_DEFAULT if name in _DEFAULT_STRATEGY else cv2.IMWRITE_PNG_STRATEGY_RLE
    return [cv2.IMWRITE_PNG_COMPRESSION, level, cv2.IMWRITE_PNG_FILTER, cv2.IMWRITE_PNG_FILTER_SUB,
            cv2.IMWRITE_PNG_STRATEGY, strategy]  # fmt: skip


def encode_png(array: np.ndarray, encoding: ModalityEncoding, level: int = PNG_LEVEL) -> bytes:
    """One modality array (H, W) or (H, W, 3), of the encoding's dtype, as PNG bytes at zlib
    ``level`` (0–9: the bytes change, the decoded pixels and so the content hash do not)."""
    if not 0 <= level <= 9:
        raise ValueError(f"PNG compression level must be 0–9, got {level}")
    want = (encoding.channels,) if encoding.channels == 3 else ()
    if array.dtype != np.dtype(encoding.dtype) or array.ndim != 2 + len(want) or array.shape[2:] != want:
        raise ValueError(
            f"{encoding.name}: expected {encoding.dtype} with {encoding.channels} channel(s), "
            f"got {array.dtype} of shape {array.shape}"
        )
    # cvtColor swaps the channels into a new array 40× faster than numpy's reversed copy
    image = cv2.cvtColor(array, cv2.COLOR_RGB2BGR) if encoding.channels == 3 else np.ascontiguousarray(array)
    ok, data = cv2.imencode(".png", image, _params(encoding.name, level))
    if not ok:
        raise RuntimeError(f"{encoding.name}: OpenCV could not encode the PNG")
    return data.tobytes()
