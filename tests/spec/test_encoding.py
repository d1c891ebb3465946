"""Depth and flow encodings, the content hash and the modality table (phav_spec.encoding)."""

from __future__ import annotations

import hashlib
import struct

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from phav_spec.encoding import (
    DEPTH_MAX_CODE,
    FLOW_OFFSET,
    MODALITIES,
    ModalityEncoding,
    content_hash,
    decode_depth,
    decode_flow,
    encode_depth,
    encode_flow,
    flow_pixels,
    modality,
)
from phav_spec.strategies.frames import depth_codes, depth_maps_m, flow_codes, flow_fields

# ---------------------------------------------------------------------------------------------
# depth


@pytest.mark.parametrize(
    ("metres", "code64", "code32"),
    [
        (1.234, 123, 123),
        (0.004, 1, 1),  # rounds to 0 cm, and 0 is never written
        (0.005, 1, 1),  # 0.5 cm: round half to even gives 0, clipped to 1
        # float64 0.015 * 100 is exactly 1.5 (ties to even: 2); float32(0.015) is just below.
        (0.015, 2, 1),
        (0.0, 1, 1),
        (2.5, 250, 250),
        (655.34, 65534, 65534),
        (655.35, 65535, 65535),
        (700.0, 65535, 65535),
        (1e30, 65535, 65535),  # would wrap in a bare float -> uint16 cast
        (np.nan, 65535, 65535),
        (np.inf, 65535, 65535),
    ],
)
@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_depth_hand_computed_codes(metres: float, code64: int, code32: int, dtype: type) -> None:
    out = encode_depth(np.array([[metres]], dtype=dtype))
    assert out.dtype == np.uint16
    assert out.shape == (1, 1)
    assert int(out[0, 0]) == (code32 if dtype is np.float32 else code64)


@given(depth_maps_m())
def test_depth_round_trip(depth: np.ndarray) -> None:
    code = encode_depth(depth)
    assert code.dtype == np.uint16
    assert code.shape == depth.shape
    assert (code >= 1).all()  # 0 is never written

    d = depth.astype(np.float64)
    far = ~np.isfinite(d) | (np.rint(np.where(np.isfinite(d), d, 0) * 100) >= DEPTH_MAX_CODE)
    assert (code[far] == DEPTH_MAX_CODE).all()
    assert (code[~far] < DEPTH_MAX_CODE).all()

    decoded = decode_depth(code)
    assert decoded.dtype == np.float32
    assert np.isposinf(decoded[far]).all()
    near = ~far & (d < 0.005)
    assert (code[near] == 1).all()
    in_range = ~far & ~near
    # Half a centimetre of rounding, plus float32 resolution of the decoded value.
    err = np.abs(decoded[in_range].astype(np.float64) - d[in_range])
    assert (err <= 0.005 + 1e-4).all(), err.max()


@given(depth_codes())
def test_depth_codes_round_trip_exactly(code: np.ndarray) -> None:
    assert (encode_depth(decode_depth(code)) == code).all()


def test_depth_rejects_negative_with_pixel_count() -> None:
    depth = np.array([[1.0, -0.01], [-np.inf, np.nan]])
    with pytest.raises(ValueError, match=r"^2 pixel\(s\) have negative"):
        encode_depth(depth)


def test_depth_negative_zero_is_zero() -> None:
    assert encode_depth(np.array([-0.0]))[0] == 1


def test_depth_rejects_integer_input() -> None:
    with pytest.raises(ValueError, match="floating"):
        encode_depth(np.array([1, 2], dtype=np.int32))


def test_decode_depth_rejects_code_zero_and_wrong_dtype() -> None:
    with pytest.raises(ValueError, match="depth code 0 is never written"):
        decode_depth(np.array([[5, 0]], dtype=np.uint16))
    with pytest.raises(ValueError, match="uint16"):
        decode_depth(np.array([5], dtype=np.int32))


def test_decode_depth_values() -> None:
    out = decode_depth(np.array([1, 123, 65534, 65535], dtype=np.uint16))
    np.testing.assert_array_equal(out, np.array([0.01, 1.23, 655.34, np.inf], dtype=np.float32))


# ---------------------------------------------------------------------------------------------
# flow


def _flow_pixel(u: float, v: float = 0.0) -> tuple[int, int, int]:
    code = encode_flow(np.array([[u]]), np.array([[v]]))
    return tuple(int(x) for x in code[0, 0])


@pytest.mark.parametrize(
    ("u", "expected"),
    [
        (0.0, (32768, 32768, 1)),
        (1.0, (32832, 32768, 1)),
        (-1.0, (32704, 32768, 1)),
        (0.5 / 64, (32768, 32768, 1)),  # half step rounds to even: 0
        (1.5 / 64, (32770, 32768, 1)),  # half step rounds to even: 2
        (-2.5 / 64, (32766, 32768, 1)),  # half step rounds to even: -2
        (511.984375, (65535, 32768, 1)),  # largest exact value
        (511.999, (32767 + FLOW_OFFSET, 32768, 1)),  # saturates to 32767 steps
        (-511.995, (0, 32768, 1)),  # rounds to -32768 steps: code 0, still valid
        (512.0, (0, 0, 0)),
        (-512.0, (0, 0, 0)),
        (1e6, (0, 0, 0)),
        (np.nan, (0, 0, 0)),
        (np.inf, (0, 0, 0)),
        (-np.inf, (0, 0, 0)),
    ],
)
def test_flow_hand_computed_codes(u: float, expected: tuple[int, int, int]) -> None:
    assert _flow_pixel(u) == expected
    # The same rule applies to v, in the G channel.
    r, g, b = _flow_pixel(0.0, u)
    assert (g, b) == (expected[0], expected[2])
    assert r == (32768 if expected[2] else 0)


def test_flow_valid_mask_and_channel_order() -> None:
    u = np.array([[1.0, 2.0]], dtype=np.float32)
    v = np.array([[-3.0, 4.0]], dtype=np.float32)
    code = encode_flow(u, v, np.array([[True, False]]))
    assert code.dtype == np.uint16
    assert code.shape == (1, 2, 3)
    assert code[0, 0].tolist() == [32768 + 64, 32768 - 192, 1]  # RGB: R = u, G = v
    assert code[0, 1].tolist() == [0, 0, 0]


@given(flow_fields())
def test_flow_round_trip(field: tuple[np.ndarray, np.ndarray, np.ndarray | None]) -> None:
    u, v, valid = field
    code = encode_flow(u, v, valid)
    assert code.dtype == np.uint16
    assert code.shape == (*u.shape, 3)

    u64, v64 = u.astype(np.float64), v.astype(np.float64)
    with np.errstate(invalid="ignore"):
        expect_valid = np.isfinite(u64) & np.isfinite(v64) & (np.abs(u64) < 512) & (np.abs(v64) < 512)
    if valid is not None:
        expect_valid &= valid
    assert (code[~expect_valid] == 0).all()
    assert (code[..., 2] == expect_valid).all()

    flow, decoded_valid = decode_flow(code)
    assert flow.dtype == np.float32
    assert (decoded_valid == expect_valid).all()
    assert np.isnan(flow[~expect_valid]).all()
    for channel, original in ((0, u64), (1, v64)):
        x = original[expect_valid]
        y = flow[..., channel][expect_valid].astype(np.float64)
        saturated = np.rint(x * 64) >= 32768
        assert (y[saturated] == 32767 / 64).all()
        err = np.abs(y[~saturated] - x[~saturated])
        assert (err <= 1 / 128).all(), err.max()


@given(flow_codes())
def test_flow_codes_round_trip(code: np.ndarray) -> None:
    flow, valid = decode_flow(code)
    assert (valid == (code[..., 2] == 1)).all()
    again = encode_flow(flow[..., 0], flow[..., 1], valid)
    # A valid code 0 decodes to exactly -512 px, which the encoder calls invalid (|u| >= 512);
    # every other code survives decode -> encode unchanged.
    at_minus_512 = valid & ((code[..., 0] == 0) | (code[..., 1] == 0))
    np.testing.assert_array_equal(again[~at_minus_512], code[~at_minus_512])
    assert (again[at_minus_512] == 0).all()


def test_decode_flow_values() -> None:
    code = np.array([[[32832, 0, 1], [65535, 32768, 1], [0, 0, 0]]], dtype=np.uint16)
    flow, valid = decode_flow(code)
    assert valid.tolist() == [[True, True, False]]
    assert flow[0, 0].tolist() == [1.0, -512.0]
    assert flow[0, 1].tolist() == [511.984375, 0.0]
    assert np.isnan(flow[0, 2]).all()


def test_decode_flow_rejects_bad_input() -> None:
    good = np.zeros((2, 2, 3), dtype=np.uint16)
    bad_b = good.copy()
    bad_b[1, 1, 2] = 2
    with pytest.raises(ValueError, match="B channel must be 0 or 1"):
        decode_flow(bad_b)
    with pytest.raises(ValueError, match="uint16"):
        decode_flow(good.astype(np.uint8))
    with pytest.raises(ValueError, match=r"\(H, W, 3\)"):
        decode_flow(good[..., :2])
    with pytest.raises(ValueError, match=r"\(H, W, 3\)"):
        decode_flow(good[0])


def test_encode_flow_rejects_bad_input() -> None:
    u = np.zeros((2, 3))
    with pytest.raises(ValueError, match="one shape"):
        encode_flow(u, np.zeros((3, 2)))
    with pytest.raises(ValueError, match="floating"):
        encode_flow(u.astype(np.int16), u)
    with pytest.raises(ValueError, match="bool"):
        encode_flow(u, u, np.ones((2, 3), dtype=np.uint8))


# ---------------------------------------------------------------------------------------------
# content hash


def _reference_hash(arrays: dict[str, np.ndarray]) -> str:
    """The documented framing, spelled out independently of the implementation."""
    h = hashlib.sha256(b"phav-content-hash-v1")
    h.update(struct.pack("<Q", len(arrays)))
    for name in sorted(arrays):
        a = np.ascontiguousarray(arrays[name], dtype=arrays[name].dtype.newbyteorder("<"))
        for field in (
            name.encode(),
            a.dtype.str.encode(),
            struct.pack(f"<{a.ndim}Q", *a.shape),
            a.tobytes(),
        ):
            h.update(struct.pack("<Q", len(field)) + field)
    return h.hexdigest()


def _frame() -> dict[str, np.ndarray]:
    rng = np.random.default_rng(7)
    return {
        "rgb": rng.integers(0, 256, (4, 5, 3), dtype=np.uint8),
        "depth": rng.integers(1, 65536, (4, 5), dtype=np.uint16),
    }


def test_content_hash_matches_documented_framing() -> None:
    frame = _frame()
    assert content_hash(frame) == _reference_hash(frame)
    assert content_hash({}) == _reference_hash({})


def test_content_hash_ignores_mapping_order_and_memory_layout() -> None:
    frame = _frame()
    reordered = dict(reversed(list(frame.items())))
    assert list(reordered) != list(frame)
    assert content_hash(reordered) == content_hash(frame)
    fortran = {k: np.asfortranarray(v) for k, v in frame.items()}
    assert content_hash(fortran) == content_hash(frame)
    big_endian = {**frame, "depth": frame["depth"].astype(">u2")}
    assert content_hash(big_endian) == content_hash(frame)


def test_content_hash_changes_with_dtype_shape_name_and_one_byte() -> None:
    frame = _frame()
    base = content_hash(frame)
    assert content_hash({**frame, "depth": frame["depth"].astype(np.int32)}) != base
    assert content_hash({**frame, "depth": frame["depth"].reshape(5, 4)}) != base
    assert content_hash({**frame, "depth": frame["depth"].reshape(-1)}) != base
    assert content_hash({"rgb2": frame["rgb"], "depth": frame["depth"]}) != base
    flipped = frame["rgb"].copy()
    flipped[3, 4, 2] ^= 1
    assert content_hash({**frame, "rgb": flipped}) != base


def test_content_hash_framing_is_unambiguous() -> None:
    # Same concatenated name+bytes, split differently, must not collide.
    a = {"ab": np.array([1], dtype=np.uint8)}
    b = {"a": np.array([ord("b"), 1], dtype=np.uint8)}
    assert content_hash(a) != content_hash(b)


def test_content_hash_rejects_object_arrays() -> None:
    with pytest.raises(ValueError, match="unsupported dtype"):
        content_hash({"x": np.array([object()])})


@given(depth_maps_m())
def test_content_hash_is_stable_across_copies(depth: np.ndarray) -> None:
    code = encode_depth(depth)
    assert content_hash({"depth": code}) == content_hash({"depth": code.copy()})


# ---------------------------------------------------------------------------------------------
# modality table


def test_modalities_table() -> None:
    table = {m.name: (m.key, m.dtype, m.channels) for m in MODALITIES}
    assert table == {
        "rgb": ("rgb.png", "uint8", 3),
        "raw_rgb": ("raw.png", "uint8", 3),
        "semantic": ("seg.png", "uint8", 3),
        "instance": ("inst.png", "uint8", 3),
        "depth": ("depth.png", "uint16", 1),
        "flow": ("flow.png", "uint16", 3),
    }
    assert len({m.key for m in MODALITIES}) == len(MODALITIES)
    assert modality("depth").units == "cm"
    assert "655.35" in modality("depth").description


def test_modality_lookup_error_lists_names() -> None:
    with pytest.raises(KeyError, match="raw_rgb"):
        modality("optical_flow")


def test_modality_encoding_is_strict_and_frozen() -> None:
    from pydantic import ValidationError

    with pytest.raises(ValidationError):
        ModalityEncoding(name="x", key="x.png", dtype="uint8", channels=2, description="")
    with pytest.raises(ValidationError):
        ModalityEncoding(name="x", key="x.png", dtype="uint8", channels=1, description="", k=1)
    with pytest.raises(ValidationError):
        MODALITIES[0].name = "other"  # type: ignore[misc]


@given(st.sampled_from(MODALITIES))
def test_modality_lookup_round_trips(entry: ModalityEncoding) -> None:
    assert modality(entry.name) is entry


def test_content_hasher_streams_the_content_hash():
    from phav_spec.encoding import ContentHasher

    rng = np.random.default_rng(5)
    arrays = {f"{k:05d}": rng.integers(0, 65535, size=(3, 4), dtype=np.uint16) for k in range(4)}
    hasher = ContentHasher(len(arrays))
    for name in sorted(arrays):
        hasher.add(name, arrays[name])
    assert hasher.hexdigest() == content_hash(arrays)
    out_of_order = ContentHasher(2)
    out_of_order.add("00001", arrays["00001"])
    with pytest.raises(ValueError, match="sorted-name order"):
        out_of_order.add("00000", arrays["00000"])
    short = ContentHasher(3)
    short.add("00000", arrays["00000"])
    with pytest.raises(ValueError, match="1 array"):
        short.hexdigest()


def test_flow_pixels_reads_what_decode_flow_reads_without_nan():
    rng = np.random.Generator(np.random.PCG64(0))
    u, v = rng.uniform(-600, 600, (2, 16, 24))
    code = encode_flow(u, v, rng.random((16, 24)) > 0.2)
    flow, valid = flow_pixels(code)
    expected, expected_valid = decode_flow(code)
    assert flow.dtype == np.float32 and np.array_equal(flow, np.nan_to_num(expected))
    assert np.array_equal(valid, expected_valid)
    with pytest.raises(ValueError, match="BGR"):
        flow_pixels(np.ascontiguousarray(code[..., ::-1]))
