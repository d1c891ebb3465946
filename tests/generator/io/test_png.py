"""Modality arrays round-trip through PNG bytes bit-exactly; bad bytes give clear errors."""

from __future__ import annotations

import numpy as np
import pytest

from phav_generator.io.png import decode_png, encode_png
from phav_spec.encoding import MODALITIES, content_hash, modality


def _array(m, rng) -> np.ndarray:
    shape = (256, 340, 3) if m.channels == 3 else (256, 340)
    hi = 256 if m.dtype == "uint8" else 65536
    return rng.integers(0, hi, size=shape, dtype=m.dtype)


@pytest.mark.parametrize("m", MODALITIES, ids=lambda m: m.name)
def test_round_trip_is_bit_exact(m):
    a = _array(m, np.random.default_rng(1))
    data = encode_png(a, m)
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    b = decode_png(data, m)
    assert b.dtype == a.dtype and np.array_equal(a, b)
    assert content_hash({m.name: a}) == content_hash({m.name: b})


def test_channels_stay_in_rgb_order():
    flow = np.zeros((4, 5, 3), dtype=np.uint16)
    flow[..., 0], flow[..., 1], flow[..., 2] = 40000, 30000, 1
    back = decode_png(encode_png(flow, modality("flow")), modality("flow"))
    assert tuple(back[0, 0]) == (40000, 30000, 1)


def test_bad_arrays_and_bytes_give_clear_errors():
    with pytest.raises(ValueError, match="depth: expected uint16"):
        encode_png(np.zeros((4, 4), np.uint8), modality("depth"))
    with pytest.raises(ValueError, match="frame 7: not a readable PNG"):
        decode_png(b"\x89PNG\r\n\x1a\ntruncated", modality("rgb"), source="frame 7")
    with pytest.raises(ValueError, match=r"frame 8: not a readable PNG: no PNG signature"):  # OpenCV asserts on none
        decode_png(b"", modality("flow"), source="frame 8")
    eight_bit = encode_png(np.zeros((4, 4, 3), np.uint8), modality("rgb"))
    with pytest.raises(ValueError, match="flow must be uint16 with 3 channel"):
        decode_png(eight_bit, modality("flow"), source="x")


def test_the_zlib_level_changes_the_bytes_not_the_pixels():
    """θ's ``render.png_compression`` reaches ``encode_png``: another level, other bytes (a
    smooth image compresses better at 9 than stored at 0), the same decoded array."""
    m = modality("depth")
    ramp = np.tile(np.arange(340, dtype=np.uint16) * 100, (256, 1))
    stored, smallest = encode_png(ramp, m, 0), encode_png(ramp, m, 9)
    assert len(smallest) < len(stored) / 4
    assert np.array_equal(decode_png(stored, m), decode_png(smallest, m))
    with pytest.raises(ValueError, match="compression level must be 0–9, got 10"):
        encode_png(ramp, m, 10)
