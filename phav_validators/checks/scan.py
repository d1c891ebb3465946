"""One pass over a shard: members present, pixels decoded once, and per video the content
hashes (integrity), encoding checks and cross-modal consistency numbers.

The pass is a pure function of the shard file and what the manifest and recipes expect
(``ShardJob``), so shards are scanned by a process pool in any order with the same result.
Findings are collected, never raised; a truncated or hostile tar yields what could be read.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import json
import struct
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import cv2
import numpy as np

from phav_generator.faults import crash_point
from phav_generator.render.camera import project, view
from phav_spec.encoding import (
    DEPTH_MAX_CODE,
    FLOW_OFFSET,
    FLOW_SCALE,
    MAX_PERSON_ID,
    MODALITIES,
    VideoHashes,
    instance_rgb,
)
from phav_spec.metadata import METADATA_VERSION
from phav_spec.vocab import PIXEL_CLASSES, PixelGroup
from phav_spec.webdataset import png_damage
from phav_validators.checks.tarsafe import TarScan, iter_members
from phav_validators.findings import Finding, Reason

_BY_KEY = {m.key: m for m in MODALITIES}
#: A frame's members: the six modality PNGs then its json metadata.
FRAME_KEYS: tuple[str, ...] = (*(m.key for m in MODALITIES), "json")
_PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
#: PNG (bit depth, colour type) per modality: 2 = RGB, 0 = grayscale.
_PNG_FORMAT = {m.name: (8 if m.dtype == "uint8" else 16, 2 if m.channels == 3 else 0) for m in MODALITIES}

#: Flow is compared with depth + camera motion on every ``FLOW_STRIDE``-th pixel each way.
FLOW_STRIDE = 2
#: Neighbouring depths within this fraction of each other count as one smooth surface.
SMOOTH_DEPTH = 0.02
#: Flow end-point error (px) above which a static pixel counts as disagreeing.
FLOW_BAD_PX = 1.0
#: A visible joint's pixel shows no surface nearer than this (m) in front of the joint; a
#: hidden one shows a surface no farther than ``JOINT_DEPTH_TOL_M`` behind it (depth is in cm).
JOINT_DEPTH_SLACK_M = 0.35
JOINT_DEPTH_TOL_M = 0.01
#: 2-D joints must equal the projection of the 3-D joints within this (px).
JOINT_2D_TOL_PX = 0.01

_PERSON_GROUPS = (PixelGroup.HUMAN_PARTS, PixelGroup.HUMAN_JOINTS)
#: Static scene classes: everything that never moves. Vehicles drive, ``misc`` holds props,
#: and a door swings open when push pushes it.
_MOVING = ("sky", "car", "truck", "bus", "misc", "door")
FOREIGN = 255


def _lut() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Colour code (r<<16 | g<<8 | b) → class id (255: not in the palette); person and static
    masks per class id."""
    table = np.full(1 << 24, FOREIGN, dtype=np.uint8)
    person = np.zeros(256, dtype=bool)
    static = np.zeros(256, dtype=bool)
    for name in PIXEL_CLASSES.names:
        c = PIXEL_CLASSES[name]
        r, g, b = c.rgb
        table[(r << 16) | (g << 8) | b] = c.class_id
        person[c.class_id] = c.group in _PERSON_GROUPS
        static[c.class_id] = c.group in (PixelGroup.VIRTUAL_KITTI, PixelGroup.INDOORS) and name not in _MOVING
    return table, person, static


_LUT: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None


def class_lut() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The palette lookup (16 MiB), built once per process."""
    global _LUT
    if _LUT is None:
        _LUT = _lut()
    return _LUT


def rgb_code(image: np.ndarray) -> np.ndarray:
    """(H, W, 3) uint8 RGB → (H, W) uint32 colour codes r<<16 | g<<8 | b.

    Through OpenCV: swapping R and B into a zero-alpha RGBA image lays each pixel out as a
    little-endian r<<16 | g<<8 | b word (5× faster than shifting three planes)."""

    rgba = cv2.cvtColor(np.ascontiguousarray(image), cv2.COLOR_BGR2RGBA)
    rgba[..., 3] = 0
    return rgba.view("<u4")[..., 0]


@dataclass(frozen=True)
class VideoExpect:
    """What the manifest and recipe say about one video in the shard."""

    video_id: str
    n_frames: int
    width: int
    height: int
    modality_hashes: dict[str, str] | None  # None: the manifest records none
    decode: bool = True  # False: outside --sample, only member presence is checked


@dataclass(frozen=True)
class ShardJob:
    """One shard to scan (or one part of it) and what it should hold.

    A shard may be split into parts that scan in parallel: each part decodes its own
    ``videos`` and passes over the members of ``others`` (the shard's other videos) unread;
    only the ``primary`` part reports what concerns the whole file (refused members,
    truncation, stray members, the file's digest)."""

    path: str
    videos: tuple[VideoExpect, ...]
    #: Shard sha256 and size in the manifest (None: not listed).
    sha256: str | None = None
    bytes: int | None = None
    consistency: bool = True
    others: frozenset[str] = frozenset()
    primary: bool = True
    #: The shard's videos in the order the manifest lists them (empty: no manifest lists it).
    listed_order: tuple[str, ...] = ()


@dataclass
class VideoScan:
    """What the pass measured for one video."""

    video_id: str
    frames: list[int] = field(default_factory=list)  # frames with every member present, in order
    decoded: bool = False
    modality_hashes: dict[str, str] = field(default_factory=dict)
    content_hash: str | None = None
    #: Per person id, pixels of its instance colour per frame (decoded videos only; −1 in a
    #: frame the scan could not read).
    instance_pixels: dict[int, list[int]] = field(default_factory=dict)
    #: Per frame t < n − 1 with a comparable flow: (static pixels compared, mean EPE px, bad fraction).
    flow_epe: list[tuple[int, int, float, float]] = field(default_factory=list)
    joint_2d_error_px: float = 0.0  # largest |projection(joints3d) − joints2d|
    joint_depth_outliers: int = 0  # visible joints whose depth pixel is not near the joint
    joints_checked: int = 0
    person_pixels: int = 0  # pixels of semantic person classes
    mask_disagree: int = 0  # pixels person in one of instance / semantic but not the other


@dataclass
class ShardScan:
    """A shard's scan: per video results, the tar pass, and findings by check."""

    path: str
    tar: TarScan
    videos: dict[str, VideoScan]
    findings: dict[str, list[Finding]]  # check name → findings
    frames_decoded: int = 0


def tune_allocator() -> bool:
    """Keep freed frame-sized buffers in this process's heap (glibc only; True if applied).

    Decoded images and their temporaries are 0.1–0.5 MB each: above glibc's default mmap
    threshold, so every one is a fresh mmap whose pages fault in again, which costs ~15 % of
    a scan on a VM. Raising the thresholds lets the heap reuse them. Call it in processes
    that scan (workers, the CLI); it changes memory reuse only, never results.
    """

    name = ctypes.util.find_library("c")
    try:
        libc = ctypes.CDLL(name)
        mallopt = libc.mallopt
    except (OSError, AttributeError, TypeError):  # not glibc (musl, macOS): leave it be
        return False
    m_trim_threshold, m_top_pad, m_mmap_threshold = -1, -2, -3
    return all((
        mallopt(m_mmap_threshold, 32 * 2**20),  # glibc's largest allowed value
        mallopt(m_trim_threshold, 256 * 2**20),
        mallopt(m_top_pad, 64 * 2**20),
    ))  # fmt: skip


def png_header(data: bytes) -> tuple[int, int, int, int] | None:
    """(width, height, bit depth, colour type) from a PNG's IHDR, None if not a PNG."""
    if len(data) < 33 or data[:8] != _PNG_SIGNATURE or data[12:16] != b"IHDR":
        return None
    width, height, depth, colour = struct.unpack(">IIBB", data[16:26])
    return width, height, depth, colour


def decode_image(data: bytes) -> np.ndarray | None:
    """PNG bytes → array in RGB order (None if unreadable or damaged, ``png_damage``); the
    caller checks the header first."""
    if png_damage(data):
        return None
    image = cv2.imdecode(np.frombuffer(data, dtype=np.uint8), cv2.IMREAD_UNCHANGED)
    if image is None:
        return None
    return cv2.cvtColor(image, cv2.COLOR_BGR2RGB) if image.ndim == 3 else image


def _is_number(value: Any) -> bool:
    return isinstance(value, int | float) and not isinstance(value, bool)


def _is_int(value: Any) -> bool:
    return isinstance(value, int) and not isinstance(value, bool)


def _contract_break(meta: dict[str, Any]) -> str | None:
    """The first field of a frame's metadata the scan reads that breaks the contract (the
    camera's pose and intrinsics; each person's id, pixel count, joints and visibility),
    None where none does."""
    camera, people = meta["camera"], meta["people"]
    if not isinstance(camera, dict):
        return "camera"
    pose = camera.get("cam_to_world")
    if not (isinstance(pose, list) and len(pose) == 16 and all(_is_number(v) for v in pose)):
        return "camera.cam_to_world"
    for name in ("fx", "fy", "cx", "cy"):
        if not _is_number(camera.get(name)):
            return f"camera.{name}"
    if not (isinstance(people, list) and all(isinstance(row, dict) for row in people)):
        return "people"
    for k, row in enumerate(people):
        person, pixels = row.get("person_id"), row.get("pixels")
        if not (_is_int(person) and 0 <= person <= MAX_PERSON_ID and _is_int(pixels)):
            return f"people[{k}].person_id or pixels"
        for name, width in (("joints3d", 39), ("joints2d", 26)):
            values = row.get(name)  # a null is NaN (behind the camera, unknown)
            if not (
                isinstance(values, list) and len(values) == width and all(v is None or _is_number(v) for v in values)
            ):
                return f"people[{k}].{name}"
        visible = row.get("visible")
        if not (isinstance(visible, list) and len(visible) == 13 and all(isinstance(v, bool) for v in visible)):
            return f"people[{k}].visible"
    return None


def _camera(row: dict[str, Any]) -> tuple[np.ndarray, tuple[float, float, float, float]]:
    pose = np.array(row["cam_to_world"], dtype=float).reshape(4, 4)
    return pose, (float(row["fx"]), float(row["fy"]), float(row["cx"]), float(row["cy"]))


def flow_against_depth(
    depth: np.ndarray,
    flow: np.ndarray,
    classes: np.ndarray,
    cam0: dict[str, Any],
    cam1: dict[str, Any],
    static: np.ndarray,
) -> tuple[int, float, float]:
    """Static pixels' flow against the flow that depth and the two camera poses imply.

    Returns (pixels compared, mean end-point error px, fraction with EPE > ``FLOW_BAD_PX``).
    Compared: every ``FLOW_STRIDE``-th pixel that is a static class, has a depth and a valid
    flow, and lies on a smooth surface (its right and lower neighbours within
    ``SMOOTH_DEPTH`` of its depth and of its class), so depth edges do not count.
    """
    s = FLOW_STRIDE
    c = classes[:-1:s, :-1:s]
    ok = static[c]
    ok &= c == classes[:-1:s, 1::s]
    ok &= c == classes[1::s, :-1:s]
    ok &= depth[:-1:s, :-1:s] < DEPTH_MAX_CODE
    ok &= flow[:-1:s, :-1:s, 2] == 1
    rows, cols = np.nonzero(ok)
    # Flat indices and ``take``: cheaper than 2-D fancy indexing, same values.
    width = depth.shape[1]
    at = rows * (s * width) + cols * s
    flat = depth.reshape(-1)
    d = flat.take(at).astype(np.float64)
    tol = SMOOTH_DEPTH * d
    smooth = (np.abs(flat.take(at + 1) - d) <= tol) & (np.abs(flat.take(at + width) - d) <= tol)
    at, z = at[smooth], d[smooth] / 100.0
    if len(z) == 0:
        return 0, 0.0, 0.0
    rows, cols = np.divmod(at, width)
    u = cols + 0.5
    v = rows + 0.5
    pose0, (fx, fy, cx, cy) = _camera(cam0)
    pose1, intrinsics1 = _camera(cam1)
    world = pose0[:3, :3] @ np.stack([(u - cx) * z / fx, -(v - cy) * z / fy, -z]) + pose0[:3, 3:]
    uv1 = project(world.T, pose1, intrinsics1)  # NaN where the point is behind the next camera
    front = np.isfinite(uv1[:, 0])
    if not front.any():
        return 0, 0.0, 0.0
    code = flow.reshape(-1, 3).take(at[front], axis=0).astype(np.float64)
    du = (code[:, 0] - FLOW_OFFSET) / FLOW_SCALE
    dv = (code[:, 1] - FLOW_OFFSET) / FLOW_SCALE
    epe = np.hypot(uv1[front, 0] - u[front] - du, uv1[front, 1] - v[front] - dv)
    return len(epe), float(epe.mean()), float((epe > FLOW_BAD_PX).mean())


class _VideoState:
    """Accumulators of one video while its frames stream past."""

    def __init__(self, expect: VideoExpect, consistency: bool):
        self.expect = expect
        self.scan = VideoScan(expect.video_id, decoded=expect.decode)
        self.hashes = VideoHashes(expect.n_frames)
        self.hash_ok = expect.decode
        #: The frame that came before one of lower number in the shard (the hash needs order).
        self.out_of_order: int | None = None
        self.consistency = consistency and expect.decode
        self.previous: tuple[int, np.ndarray, np.ndarray, np.ndarray, dict[str, Any]] | None = None


class _Layout:
    """The primary part's look at each member of a shard: a name that is no listed video's
    frame, a sample whose members are split or repeated, a member twice. Every part decodes
    only its own videos; this sees them all, so that none goes unlooked at."""

    def __init__(self, scanner: ShardScanner):
        self.scanner = scanner
        self.current: tuple[str, int] | None = None
        self.exts: set[str] = set()
        self.seen: set[tuple[str, int]] = set()
        #: The listed videos in the order their frames begin in the tar.
        self.videos: list[str] = []

    def member(self, name: str, key: str, sample: tuple[str, int] | None, ext: str, video_id: str | None) -> None:
        add = self.scanner.add
        if sample is None:
            add("integrity", Reason.UNLISTED_MEMBER, f"member {name!r} belongs to no listed video frame",
                video_id=video_id)  # fmt: skip
            return
        if sample != self.current:
            if sample in self.seen:
                add("integrity", Reason.UNLISTED_MEMBER,
                    f"member {name!r}: sample {key} appears twice or its members are not contiguous",
                    video_id=video_id)  # fmt: skip
            elif self.current is None or sample[0] != self.current[0]:
                if sample[0] in self.videos:  # a video never spans shards, nor is split within one
                    add("integrity", Reason.UNLISTED_MEMBER,
                        f"member {name!r}: the frames of {sample[0]} are not contiguous in the tar",
                        video_id=video_id)  # fmt: skip
                else:
                    self.videos.append(sample[0])
            self.seen.add(sample)
            self.current, self.exts = sample, set()
        if ext in self.exts:
            add("integrity", Reason.UNLISTED_MEMBER, f"duplicate member {name!r}", video_id=video_id)
        self.exts.add(ext)

    def check_order(self, listed: Sequence[str]) -> None:
        """Say where the tar holds its videos in another order than the manifest lists them."""
        in_list = set(listed)
        held = [v for v in self.videos if v in in_list]
        in_tar = set(held)
        expected = [v for v in listed if v in in_tar]
        if held != expected:
            at = next(i for i, (a, b) in enumerate(zip(held, expected, strict=True)) if a != b)
            self.scanner.add("integrity", Reason.MANIFEST_INVALID,
                             f"the tar holds {held[at]} where the manifest lists {expected[at]} (video {at + 1} "
                             "of the shard): the manifest's order is not the shard's", video_id=held[at])  # fmt: skip


class ShardScanner:
    """Runs one ``ShardJob``: iterate members, group them into frames, check each frame."""

    def __init__(self, job: ShardJob):
        self.job = job
        self.name = Path(job.path).name
        self.expect = {v.video_id: v for v in job.videos}
        self.states: dict[str, _VideoState] = {}
        self.findings: dict[str, list[Finding]] = {"integrity": [], "encoding": [], "consistency": []}
        self.frames_decoded = 0
        self.lut, self.person, self.static = class_lut()

    def add(self, check: str, reason: Reason, message: str, video_id: str | None = None, **numbers: Any) -> None:
        self.findings[check].append(Finding(reason, message, file=self.name, video_id=video_id, numbers=numbers))

    def run(self) -> ShardScan:
        tar = TarScan()
        frame: dict[str, bytes] = {}
        current: tuple[str, int] | None = None
        # A secondary part reads only its own videos' members; the primary reads every byte
        # and checks every member's name and place, the other parts' videos' too.
        only = None if self.job.primary else (lambda name: name.partition("/")[0] in self.expect)
        layout = _Layout(self) if self.job.primary else None
        for name, data in iter_members(self.job.path, tar, only):
            key, _, ext = name.partition(".")
            vid, _, frame_text = key.partition("/")
            listed = vid in self.expect or vid in self.job.others
            well_formed = listed and frame_text.isdigit() and len(frame_text) == 5 and ext in FRAME_KEYS
            sample = (vid, int(frame_text)) if well_formed else None
            if layout is not None:
                layout.member(name, key, sample, ext, vid if listed else None)
            if sample is None or vid not in self.expect:
                continue  # said by the primary, or another part's video
            if sample != current:
                if current is not None:
                    self._frame(current, frame)
                current, frame = sample, {}
            frame[ext] = data
        if current is not None:
            self._frame(current, frame)
        if layout is not None and self.job.listed_order:
            layout.check_order(self.job.listed_order)
        if not self.job.primary:
            tar.refused, tar.truncated = [], None
        for refusal in tar.refused:
            reason = Reason.UNSAFE_MEMBER if refusal.kind == "unsafe" else Reason.OVERSIZED_MEMBER
            self.add("integrity", reason, f"member {refusal.name!r} refused unread: {refusal.why}")
        if tar.truncated is not None:
            self.add("integrity", Reason.TRUNCATED_SHARD, f"the tar is truncated or damaged: {tar.truncated}")
        videos = {vid: self._finish(vid) for vid in self.expect}
        changed = tar.sha256 != self.job.sha256 or tar.bytes != self.job.bytes
        if self.job.primary and self.job.sha256 is not None and changed:
            self.findings["integrity"].append(Finding(
                Reason.SHARD_BYTES_CHANGED,
                f"tar bytes differ from the manifest ({tar.bytes} bytes, sha256 {tar.sha256[:12]}…; manifest "
                f"{self.job.bytes} bytes, {self.job.sha256[:12]}…); content hashes decide",
                file=self.name, severity="warn",
            ))  # fmt: skip
        return ShardScan(self.job.path, tar, videos, self.findings, self.frames_decoded)

    # --- per frame -------------------------------------------------------------------------

    def _state(self, vid: str) -> _VideoState:
        if vid not in self.states:
            self.states[vid] = _VideoState(self.expect[vid], self.job.consistency)
        return self.states[vid]

    def _frame(self, sample: tuple[str, int], members: dict[str, bytes]) -> None:
        vid, f = sample
        state = self._state(vid)
        missing = [k for k in FRAME_KEYS if k not in members]
        if f >= state.expect.n_frames:
            self.add("integrity", Reason.UNLISTED_MEMBER,
                     f"frame {f:05d} is beyond the video's {state.expect.n_frames} frames", video_id=vid)  # fmt: skip
            return
        if missing:
            self.add("integrity", Reason.MISSING_MEMBER,
                     f"frame {f:05d} lacks {', '.join(missing)}", video_id=vid, frame=f)  # fmt: skip
            state.hash_ok = False
            return
        state.scan.frames.append(f)
        if not state.expect.decode:
            return
        arrays = self._decode_frame(state, f, members)
        meta = self._metadata(vid, f, members["json"])
        if arrays is None:
            state.hash_ok = False
            return
        self.frames_decoded += 1
        if state.hash_ok:
            try:
                state.hashes.add(f, arrays)
            except ValueError:  # frames out of order: the hash cannot be formed
                state.hash_ok = False
                state.out_of_order = f
        self._check_frame(state, f, arrays, meta)

    def _decode_frame(self, state: _VideoState, f: int, members: dict[str, bytes]) -> dict[str, np.ndarray] | None:
        vid, width, height = state.expect.video_id, state.expect.width, state.expect.height
        arrays: dict[str, np.ndarray] = {}
        for m in MODALITIES:
            data = members[m.key]
            where = f"{vid}/{f:05d}.{m.key}"
            header = png_header(data)
            if header is None:
                self.add("encoding", Reason.PNG_FORMAT, f"{where} is not a PNG", video_id=vid, frame=f)
                return None
            w, h, depth, colour = header
            if (w, h) != (width, height):
                self.add("encoding", Reason.PNG_FORMAT,
                         f"{where} is {w}×{h}, the recipe's frames are {width}×{height}",
                         video_id=vid, frame=f)  # fmt: skip
                return None  # never decode an image of unexpected size (decompression bombs)
            if (depth, colour) != _PNG_FORMAT[m.name]:
                want_depth, want_colour = _PNG_FORMAT[m.name]
                self.add(
                    "encoding",
                    Reason.PNG_FORMAT,
                    f"{where}: {m.name} must be {want_depth}-bit colour type {want_colour}, "
                    f"found {depth}-bit colour type {colour}",
                    video_id=vid,
                    frame=f,
                    modality=m.name,
                )
                return None
            image = decode_image(data)
            if image is None or image.shape[:2] != (height, width):
                why = png_damage(data)
                self.add("encoding", Reason.PNG_FORMAT, f"{where} cannot be decoded" + (f": {why}" if why else ""),
                         video_id=vid, frame=f)  # fmt: skip
                return None
            arrays[m.name] = image
        return arrays

    def _metadata(self, vid: str, f: int, data: bytes) -> dict[str, Any] | None:
        try:
            meta = json.loads(data)
            version = meta["metadata_version"]
            meta["camera"], meta["people"]
        except (ValueError, KeyError, TypeError, RecursionError):  # RecursionError: JSON nested too deep
            self.add("encoding", Reason.METADATA_INVALID, f"{vid}/{f:05d}.json is not the frame metadata contract",
                     video_id=vid, frame=f)  # fmt: skip
            return None
        if not _is_int(version) or version > METADATA_VERSION:  # true is no version
            self.add("encoding", Reason.VERSION_UNKNOWN,
                     f"{vid}/{f:05d}.json has metadata version {version!r}; this phav reads ≤ {METADATA_VERSION}",
                     video_id=vid, frame=f)  # fmt: skip
            return None
        broken = _contract_break(meta)
        if broken is not None:
            message = f"{vid}/{f:05d}.json: {broken} is not the frame metadata contract's"
            self.add("encoding", Reason.METADATA_INVALID, message, video_id=vid, frame=f)
            return None
        return meta

    def _check_frame(
        self, state: _VideoState, f: int, arrays: dict[str, np.ndarray], meta: dict[str, Any] | None
    ) -> None:
        vid = state.expect.video_id
        depth, flow = arrays["depth"], arrays["flow"]
        zeros = int(np.count_nonzero(depth == 0))
        if zeros:
            self.add("encoding", Reason.DEPTH_CODE, f"frame {f:05d}: {zeros} depth pixels hold code 0 (never written)",
                     video_id=vid, frame=f, pixels=zeros)  # fmt: skip
        blue = flow[..., 2]
        bad_b = int(np.count_nonzero(blue > 1))
        invalid = blue == 0
        dirty = int(np.count_nonzero(invalid & ((flow[..., 0] != 0) | (flow[..., 1] != 0))))
        if bad_b or dirty:
            self.add("encoding", Reason.FLOW_CODE,
                     f"frame {f:05d}: {bad_b} flow pixels with B ∉ {{0, 1}}, {dirty} invalid pixels not (0, 0, 0)",
                     video_id=vid, frame=f, bad_valid=bad_b, dirty_invalid=dirty)  # fmt: skip
        classes = self.lut[rgb_code(arrays["semantic"])]
        foreign = classes == FOREIGN
        if foreign.any():
            ys, xs = np.nonzero(foreign)
            colour = tuple(int(x) for x in arrays["semantic"][ys[0], xs[0]])
            self.add("encoding", Reason.FOREIGN_COLOUR,
                     f"frame {f:05d}: {len(ys)} semantic pixels outside the palette, "
                     f"e.g. {colour} at ({xs[0]}, {ys[0]})",
                     video_id=vid, frame=f, pixels=len(ys))  # fmt: skip
        if meta is None:  # its people unknown (reported): their colours cannot be told
            return
        inst = rgb_code(arrays["instance"])
        self._instances(state, f, inst, meta["people"])
        if not state.consistency:
            return
        person_sem = self.person[classes]
        person_inst = inst != 0
        state.scan.person_pixels += int(np.count_nonzero(person_sem))
        state.scan.mask_disagree += int(np.count_nonzero(person_sem != person_inst))
        self._joints(state, f, depth, meta)
        if state.previous is not None and state.previous[0] == f - 1:
            t, d0, f0, c0, cam0 = state.previous
            n, epe, bad = flow_against_depth(d0, f0, c0, cam0, meta["camera"], self.static)
            state.scan.flow_epe.append((t, n, epe, bad))
        state.previous = (f, depth, flow, classes, meta["camera"])

    def _instances(self, state: _VideoState, f: int, inst: np.ndarray, people: list[dict[str, Any]]) -> None:
        """Instance colours ↔ the frame's person ids, and pixel counts ↔ the metadata's."""
        vid = state.expect.video_id
        codes, counts = np.unique(inst[inst != 0], return_counts=True)
        by_code = dict(zip(codes.tolist(), counts.tolist(), strict=True))
        for row in people:
            pid = row.get("person_id")
            if not isinstance(pid, int):
                continue
            r, g, b = instance_rgb(pid)
            got = by_code.pop((r << 16) | (g << 8) | b, 0)
            # −1: a frame the scan never read (a truncated shard), not a frame without the person.
            state.scan.instance_pixels.setdefault(pid, [-1] * state.expect.n_frames)[f] = got
            if row.get("pixels") != got:
                self.add("encoding", Reason.INSTANCE_MISMATCH,
                         f"frame {f:05d}: person {pid} covers {got} instance pixels, "
                         f"the metadata says {row.get('pixels')}",
                         video_id=vid, frame=f)  # fmt: skip
        for code, count in by_code.items():
            rgb = ((code >> 16) & 255, (code >> 8) & 255, code & 255)
            self.add("encoding", Reason.INSTANCE_MISMATCH,
                     f"frame {f:05d}: instance colour {rgb} ({count} px) belongs to no person in the metadata",
                     video_id=vid, frame=f)  # fmt: skip

    def _joints(self, state: _VideoState, f: int, depth: np.ndarray, meta: dict[str, Any]) -> None:
        """3-D joints projected with the frame's camera against 2-D joints and the depth image."""
        try:
            pose, intrinsics = _camera(meta["camera"])
        except (KeyError, TypeError, ValueError):
            return
        j3s, j2s, visibles = [], [], []
        for row in meta["people"]:
            try:
                j3 = np.array([np.nan if x is None else x for x in row["joints3d"]], dtype=float).reshape(13, 3)
                j2 = np.array([np.nan if x is None else x for x in row["joints2d"]], dtype=float).reshape(13, 2)
                visible = np.array(row["visible"], dtype=bool).reshape(13)
            except (KeyError, TypeError, ValueError):
                continue
            j3s.append(j3)
            j2s.append(j2)
            visibles.append(visible)
        if not j3s:
            return
        j3, j2, visible = np.concatenate(j3s), np.concatenate(j2s), np.concatenate(visibles)
        w2c = view(pose)
        z = -(j3 @ w2c[2, :3] + w2c[2, 3])  # depth along the camera axis
        uv = project(j3, pose, intrinsics)  # the metadata's own projection and NaN rule
        projected, given = np.isfinite(uv).all(axis=1), np.isfinite(j2).all(axis=1)
        both = projected & given
        err = float("inf") if (projected != given).any() else float(np.abs(uv[both] - j2[both]).max(initial=0.0))
        state.scan.joint_2d_error_px = max(state.scan.joint_2d_error_px, err)
        height, width = depth.shape
        inside = both & (uv[:, 0] >= 0) & (uv[:, 0] < width) & (uv[:, 1] >= 0) & (uv[:, 1] < height)
        at = np.flatnonzero(inside)
        seen = depth[uv[at, 1].astype(int), uv[at, 0].astype(int)] / 100.0
        # Visible: nothing well in front of the joint. Hidden: something in front.
        outlier = np.where(visible[at], seen < z[at] - JOINT_DEPTH_SLACK_M, seen > z[at] + JOINT_DEPTH_TOL_M)
        state.scan.joints_checked += len(at)
        state.scan.joint_depth_outliers += int(np.count_nonzero(outlier))

    def _finish(self, vid: str) -> VideoScan:
        state = self._state(vid)
        scan = state.scan
        expect = state.expect
        if len(scan.frames) != expect.n_frames:
            absent = sorted(set(range(expect.n_frames)) - set(scan.frames))
            if absent:
                shown = ", ".join(f"{a:05d}" for a in absent[:5]) + (" …" if len(absent) > 5 else "")
                self.add("encoding", Reason.FRAME_COUNT,
                         f"{len(scan.frames)} complete frames, the recipe has {expect.n_frames} (missing {shown})",
                         video_id=vid, missing=absent[:50])  # fmt: skip
        if expect.decode and state.hash_ok and len(scan.frames) == expect.n_frames:
            scan.modality_hashes = state.hashes.hexdigests()
            scan.content_hash = state.hashes.video_hash()
        if expect.decode and expect.modality_hashes:
            if scan.content_hash is None:
                why = ("frames are missing or unreadable" if state.out_of_order is None else
                       f"frame {state.out_of_order:05d} comes after a later frame in the shard")  # fmt: skip
                self.add("integrity", Reason.HASH_MISMATCH, f"content hash cannot be recomputed: {why}", video_id=vid)
            else:
                want = expect.modality_hashes
                differ = [m for m in sorted(want) if want[m] != scan.modality_hashes.get(m)]
                if differ:
                    self.add("integrity", Reason.HASH_MISMATCH,
                             f"decoded pixels differ from the manifest's content hash in {', '.join(differ)}",
                             video_id=vid, modalities=differ)  # fmt: skip
        return scan


def scan_shard(job: ShardJob) -> ShardScan:
    """Scan one shard (a pure function of the file and ``job``; safe in a worker process)."""
    crash_point(f"scan:{Path(job.path).name}")
    return ShardScanner(job).run()
