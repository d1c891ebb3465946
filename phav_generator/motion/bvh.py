"""BVH motion capture: parse, retarget onto the 15-body skeleton, play as a motion, export.

The paper's base motions are CMU MoCap takes. No download is possible here, so this module is
the door for users who own BVH files (the CMU BVH conversions or any other exporter):

* ``parse_bvh`` / ``load_bvh`` read the format (HIERARCHY with ROOT/JOINT/End Site, OFFSET,
  CHANNELS in any order and count, MOTION with Frames and Frame Time); malformed input is a
  one-line ``PhavUserError`` naming the file and, where possible, the line.
* ``bvh_forward_kinematics`` gives every joint's global position and orientation per frame.
  BVH rotations are intrinsic in channel order: ``R = R_c1 · R_c2 · R_c3``; a joint's frame is
  its parent's, moved by its OFFSET, then rotated. Position channels *replace* the matching
  OFFSET component (Blender's reading; for the usual zero root OFFSET every reading agrees).
* ``retarget`` turns a clip into a ``Pose`` in the motion frame (``animation``): the BVH up
  axis becomes +Z, the person faces +X at frame 0 (from the hips' left-right line), lengths are
  scaled by leg length to ``REFERENCE_HEIGHT_M``, the root moves relative to frame 0 (planar)
  and its height is the offset from the standing pelvis height. Body orientations come from
  bone *directions* (position-based, so a T-pose or A-pose rest skeleton retargets as well as
  ours), and are solved into our hinge angles body by body, each against its parent's
  achieved frame, clipped to the joint limits.
* ``bvh_motion`` wraps a clip as a ``MotionDef`` for ``library.register_motion``.
* ``export_bvh`` writes our skeleton and a Pose as BVH (Y up) to inspect motions in Blender.

Retargeting, body by body (P: joint positions, G: joint rotations carried from the BVH rest
pose, both converted to our axes):

* pelvis: hip line (left − right hip joint) and up (hip centre → first spine joint);
* chest: up (first spine joint → shoulder midpoint) and the shoulder line;
* upper arm / upper leg: the bone direction, twisted by the bend of the next bone (forearm
  bends towards the upper arm's +X, the shank towards the thigh's −X); when that bone is
  nearly straight the twist comes from the BVH joint's rotation instead;
* lower arm / lower leg: the bone direction (one hinge: the best-fit bend angle);
* head, hands, feet: the direction from the joint to its children's mean (skull top, knuckles,
  toes), twisted by the BVH joint's rotation.

Directions of the limbs are absolute (an arm hanging along −Z is our zero). The central
bodies and the end bodies (head, hands, feet) are taken *relative to the BVH rest pose*: the
rest pose is assumed to stand upright with neutral neck, wrists and ankles, which holds for
T-pose and A-pose rest skeletons and absorbs differences in where exporters put the spine,
skull and toe joints.
"""

from __future__ import annotations

import math
import os
import re
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from phav_generator.motion.animation import MotionDef, MotionParams, Pose
from phav_generator.motion.reference import LEG, PELVIS_H
from phav_generator.motion.rotations import (
    axis_angle_matrix,
    continuous_quats,
    euler_angles,
    matrix_to_quat,
    quat_to_matrix,
    slerp,
)
from phav_generator.motion.skeleton import (
    BODY_DOFS,
    BONE_INDEX,
    BONES,
    DOFS,
    LOWER,
    N_DOFS,
    PARENTS,
    UPPER,
    BodyDims,
    local_rotations,
)
from phav_spec.errors import PhavUserError
from phav_spec.files import read_text

__all__ = [
    "DEFAULT_JOINT_NAMES",
    "BvhClip",
    "RetargetedClip",
    "bvh_forward_kinematics",
    "bvh_motion",
    "export_bvh",
    "load_bvh",
    "parse_bvh",
    "resolve_mapping",
    "retarget",
    "sample_pose",
]

#: The six BVH channel names, canonical spelling → (kind, axis index).
CHANNELS: dict[str, tuple[str, int]] = {
    "Xposition": ("position", 0),
    "Yposition": ("position", 1),
    "Zposition": ("position", 2),
    "Xrotation": ("rotation", 0),
    "Yrotation": ("rotation", 1),
    "Zrotation": ("rotation", 2),
}
_CHANNEL_LOWER = {name.lower(): name for name in CHANNELS}
_KEYWORDS = {"root", "joint", "end", "offset", "channels", "{", "}", "motion", "hierarchy"}
_UNIT = np.eye(3)
#: Sample rate of ``RetargetedClip.pose_30fps``.
RESAMPLE_FPS = 30.0


# --------------------------------------------------------------------------------------
# Parsing


@dataclass(frozen=True, eq=False)
class BvhClip:
    """A parsed BVH file: the joint tree (End Sites included as joints without channels)
    and the per-frame channel values, in the file's own units and axes."""

    source: str
    names: tuple[str, ...]  # joint names; End Sites are named "<parent>/End Site"
    parents: tuple[int, ...]  # −1 for a ROOT; parents precede children
    offsets: np.ndarray  # (J, 3) OFFSET of each joint in its parent's frame
    channels: tuple[tuple[str, ...], ...]  # canonical channel names per joint, file order
    is_end: tuple[bool, ...]
    frame_time: float  # seconds
    frames: np.ndarray  # (F, C) channel values, degrees for rotations

    @property
    def n_frames(self) -> int:
        """Number of frames (rows of ``frames``)."""
        return int(self.frames.shape[0])

    @property
    def length_s(self) -> float:
        """Length of the take: ``n_frames · frame_time`` (the motion's natural length)."""
        return self.n_frames * self.frame_time

    @property
    def channel_starts(self) -> tuple[int, ...]:
        """Column of each joint's first channel in ``frames``."""
        out, k = [], 0
        for ch in self.channels:
            out.append(k)
            k += len(ch)
        return tuple(out)

    def index(self, name: str) -> int:
        """Position of the joint called ``name``."""
        return self.names.index(name)


class _Tokens:
    """Whitespace tokens of the HIERARCHY section with their line numbers."""

    def __init__(self, lines: list[str], stop: int, source: str) -> None:
        self.items: list[tuple[str, int]] = []
        for i in range(stop):
            line = lines[i].replace("{", " { ").replace("}", " } ")
            self.items.extend((tok, i + 1) for tok in line.split())
        self.pos = 0
        self.source = source
        self.last_line = stop if stop > 0 else 1

    def peek(self) -> tuple[str, int] | None:
        """The next token and its line, not consumed; None at the end."""
        return self.items[self.pos] if self.pos < len(self.items) else None

    def next(self, what: str) -> tuple[str, int]:
        """Consume the next token; at the end, an error saying ``what`` was expected."""
        item = self.peek()
        if item is None:
            raise _err(self.source, f"unexpected end of HIERARCHY at line {self.last_line}: expected {what}")
        self.pos += 1
        return item

    def rest_of_line(self, line: int) -> list[str]:
        """Consume the tokens left on ``line`` up to a brace (a joint's name may hold spaces)."""
        out = []
        while (item := self.peek()) is not None and item[1] == line and item[0] not in ("{", "}"):
            out.append(item[0])
            self.pos += 1
        return out


def _err(source: str, message: str, field: str | None = None) -> PhavUserError:
    return PhavUserError(message, source=source, field=field)


def _number(tok: str, line: int, what: str, source: str) -> float:
    try:
        value = float(tok)
    except ValueError:
        raise _err(source, f"line {line}: {what} must be a number, got {tok!r}") from None
    if not math.isfinite(value):
        raise _err(source, f"line {line}: {what} must be finite, got {tok!r}")
    return value


class _Hierarchy:
    """The joint tree of the HIERARCHY section, read by recursive descent over its tokens.

    Joints are numbered in file order (parents before children); End Sites are joints
    without channels named "<parent>/End Site".
    """

    def __init__(self, toks: _Tokens, source: str) -> None:
        self.toks = toks
        self.source = source
        self.names: list[str] = []
        self.parents: list[int] = []
        self.offsets: list[tuple[float, float, float]] = []
        self.channels: list[tuple[str, ...]] = []
        self.is_end: list[bool] = []

    def parse(self) -> None:
        """Read ``HIERARCHY`` and every ROOT tree after it."""
        toks, source = self.toks, self.source
        first = toks.peek()
        if first is None:
            raise _err(source, "empty file: expected HIERARCHY")
        if first[0].upper() != "HIERARCHY":
            raise _err(source, f"line {first[1]}: expected HIERARCHY, got {first[0]!r}")
        toks.next("HIERARCHY")
        while toks.peek() is not None:
            tok, line = toks.next("ROOT")
            if tok.upper() != "ROOT":
                raise _err(source, f"line {line}: expected ROOT, got {tok!r}")
            parts = toks.rest_of_line(line)
            if not parts:
                raise _err(source, f"line {line}: ROOT without a name")
            self._joint(" ".join(parts), -1, False, line)
        if not self.names:
            raise _err(source, "HIERARCHY has no ROOT joint")

    def _joint(self, name: str, parent: int, end: bool, line: int) -> None:
        """Add a joint (or End Site) and read its body."""
        if not end and name in self.names:
            raise _err(self.source, f"line {line}: duplicate joint name {name!r}")
        self.names.append(name)
        self.parents.append(parent)
        self.offsets.append((0.0, 0.0, 0.0))
        self.channels.append(())
        self.is_end.append(end)
        self._body(len(self.names) - 1, name)

    def _body(self, index: int, name: str) -> None:
        """Parse ``{ OFFSET … CHANNELS … children }`` of the joint at ``index``."""
        source = self.source
        tok, line = self.toks.next("'{'")
        if tok != "{":
            raise _err(source, f"line {line}: expected '{{' after {name!r}, got {tok!r}")
        has_offset = False
        while True:
            tok, line = self.toks.next(f"'}}' closing {name!r}")
            key = tok.upper()
            if tok == "}":
                break
            if key == "OFFSET":
                vals = [self.toks.next("an OFFSET value") for _ in range(3)]
                self.offsets[index] = tuple(_number(v, ln, "OFFSET value", source) for v, ln in vals)  # type: ignore[assignment]
                has_offset = True
            elif key == "CHANNELS":
                if self.is_end[index]:
                    raise _err(source, f"line {line}: an End Site has no CHANNELS")
                self.channels[index] = self._channel_list(name)
            elif key in ("JOINT", "END"):
                self._child(index, name, key, line)
            else:
                raise _err(source, f"line {line}: unexpected {tok!r} in joint {name!r}")
        if not has_offset:
            raise _err(source, f"joint {name!r} has no OFFSET")

    def _channel_count(self) -> tuple[int, int]:
        """The count after CHANNELS (0 to 6) and its line."""
        count_tok, count_line = self.toks.next("a channel count")
        try:
            count = int(count_tok)
        except ValueError:
            raise _err(
                self.source, f"line {count_line}: CHANNELS count must be an integer, got {count_tok!r}"
            ) from None
        if not 0 <= count <= 6:
            raise _err(self.source, f"line {count_line}: CHANNELS count must be 0 to 6, got {count}")
        return count, count_line

    def _channel_list(self, name: str) -> tuple[str, ...]:
        """The canonical channel names after CHANNELS, exactly as many as its count says."""
        toks, source = self.toks, self.source
        count, count_line = self._channel_count()
        found: list[str] = []
        for _ in range(count):
            item = toks.peek()
            if item is None or item[0].lower() in _KEYWORDS:
                raise _err(source, f"line {count_line}: CHANNELS declares {count} channels but names only {len(found)}")
            ch_tok, ch_line = toks.next("a channel name")
            canonical = _CHANNEL_LOWER.get(ch_tok.lower())
            if canonical is None:
                raise _err(
                    source,
                    f"line {ch_line}: unknown channel name {ch_tok!r} "
                    "(expected Xposition, Yposition, Zposition, Xrotation, Yrotation or Zrotation)",
                )
            if canonical in found:
                raise _err(source, f"line {ch_line}: channel {canonical} repeated for joint {name!r}")
            found.append(canonical)
        extra = toks.peek()
        if extra is not None and extra[1] == count_line and extra[0].lower() not in _KEYWORDS:
            raise _err(source, f"line {count_line}: CHANNELS declares {count} channels but names more")
        return tuple(found)

    def _child(self, index: int, name: str, key: str, line: int) -> None:
        """A ``JOINT name`` or ``End Site`` inside the joint at ``index``."""
        source = self.source
        if self.is_end[index]:
            raise _err(source, f"line {line}: an End Site cannot have children")
        if key == "END":
            site, site_line = self.toks.next("'Site'")
            if site.upper() != "SITE":
                raise _err(source, f"line {site_line}: expected 'End Site', got 'End {site}'")
            child_name, child_end = f"{name}/End Site", True
        else:
            parts = self.toks.rest_of_line(line)
            if not parts:
                raise _err(source, f"line {line}: JOINT without a name")
            child_name, child_end = " ".join(parts), False
        self._joint(child_name, index, child_end, line)


def _motion_line(lines: list[str]) -> int | None:
    """Index of the MOTION keyword's line, or None."""
    motion_at = next((i for i, line in enumerate(lines) if line.split()[:1] == ["MOTION"]), None)
    if motion_at is None:  # tolerate other spellings of the keyword only where the exact one is absent
        motion_at = next((i for i, line in enumerate(lines) if line.upper().split()[:1] == ["MOTION"]), None)
    return motion_at


def _frame_rows(lines: list[str], data_start: int, n_channels: int, frames_count: int, source: str) -> np.ndarray:
    """The frame lines after the MOTION header as an (F, C) array, each checked."""
    rows: list[np.ndarray] = []
    for i in range(data_start, len(lines)):
        parts = lines[i].split()
        if not parts:
            continue
        k = len(rows) + 1
        if len(parts) != n_channels:
            raise _err(
                source, f"line {i + 1}: frame {k} has {len(parts)} values, expected {n_channels} (one per channel)"
            )
        try:
            row = np.array(parts, dtype=np.float64)
        except ValueError:
            bad = next(p for p in parts if not _is_float(p))
            raise _err(source, f"line {i + 1}: frame {k} has a non-numeric value {bad!r}") from None
        if not np.all(np.isfinite(row)):
            raise _err(source, f"line {i + 1}: frame {k} has a non-finite value")
        rows.append(row)
    if len(rows) != frames_count:
        raise _err(source, f"'Frames: {frames_count}' but the file has {len(rows)} frame lines")
    return np.vstack(rows)


def parse_bvh(text: str, *, source: str) -> BvhClip:
    """Parse BVH text into a ``BvhClip``; any malformed input is a one-line PhavUserError.

    ``source`` names the file in error messages. Channel names are matched case-insensitively.
    """
    lines = text.removeprefix("\ufeff").splitlines()
    motion_at = _motion_line(lines)
    stop = len(lines) if motion_at is None else motion_at
    tree = _Hierarchy(_Tokens(lines, stop, source), source)
    tree.parse()
    if motion_at is None:
        raise _err(source, "no MOTION section after the HIERARCHY")
    n_channels = sum(len(c) for c in tree.channels)
    if n_channels == 0:
        raise _err(source, "the HIERARCHY declares no CHANNELS")
    frames_count, frame_time, data_start = _motion_header(lines, motion_at, source)
    return BvhClip(
        source=source,
        names=tuple(tree.names),
        parents=tuple(tree.parents),
        offsets=np.array(tree.offsets, dtype=np.float64),
        channels=tuple(tree.channels),
        is_end=tuple(tree.is_end),
        frame_time=frame_time,
        frames=_frame_rows(lines, data_start, n_channels, frames_count, source),
    )


def _is_float(tok: str) -> bool:
    try:
        float(tok)
    except ValueError:
        return False
    return True


_FRAMES_RE = re.compile(r"^\s*frames\s*:\s*(\S+)\s*$", re.IGNORECASE)
_FRAME_TIME_RE = re.compile(r"^\s*frame\s+time\s*:\s*(\S+)\s*$", re.IGNORECASE)


def _motion_header(lines: list[str], motion_at: int, source: str) -> tuple[int, float, int]:
    """(Frames, Frame Time, index of the first data line) of the MOTION section."""
    rest = lines[motion_at].strip()[len("MOTION") :].strip()
    if rest:
        raise _err(source, f"line {motion_at + 1}: unexpected {rest!r} after MOTION")
    i = motion_at + 1
    header: list[tuple[str, int]] = []
    while i < len(lines) and len(header) < 2:
        if lines[i].strip():
            header.append((lines[i], i + 1))
        i += 1
    if len(header) < 1 or not (m := _FRAMES_RE.match(header[0][0])):
        line = header[0][1] if header else motion_at + 1
        raise _err(source, f"line {line}: expected 'Frames: <count>' after MOTION")
    try:
        count = int(m.group(1))
    except ValueError:
        raise _err(source, f"line {header[0][1]}: Frames must be an integer, got {m.group(1)!r}") from None
    if count < 1:
        raise _err(source, f"line {header[0][1]}: Frames must be at least 1, got {count}")
    if len(header) < 2 or not (m := _FRAME_TIME_RE.match(header[1][0])):
        line = header[1][1] if len(header) > 1 else header[0][1]
        raise _err(source, f"line {line}: expected 'Frame Time: <seconds>' after Frames")
    try:
        frame_time = float(m.group(1))
    except ValueError:
        raise _err(source, f"line {header[1][1]}: Frame Time must be a number, got {m.group(1)!r}") from None
    if not (math.isfinite(frame_time) and frame_time > 0):
        raise _err(source, f"line {header[1][1]}: Frame Time must be > 0 seconds, got {m.group(1)}")
    return count, frame_time, i


def load_bvh(path: str | os.PathLike[str]) -> BvhClip:
    """Read and parse a BVH file; a missing, unreadable or malformed file is a PhavUserError."""
    return parse_bvh(read_text(path, hint="check the path of the BVH file"), source=str(path))


# --------------------------------------------------------------------------------------
# Forward kinematics of the BVH skeleton


def _axis_rotation(axis: int, degrees: np.ndarray) -> np.ndarray:
    return axis_angle_matrix(_UNIT[axis], np.deg2rad(degrees))


def bvh_forward_kinematics(clip: BvhClip, frames: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Global joint positions (F, J, 3) and orientations (F, J, 3, 3) of every frame.

    In the file's axes and units. ``frames`` (F, C) replaces the clip's channel values (all
    zeros gives the rest pose, apart from position channels, which replace OFFSETs).
    """
    values = clip.frames if frames is None else np.asarray(frames, dtype=np.float64)
    n = values.shape[0]
    n_joints = len(clip.names)
    pos = np.empty((n, n_joints, 3))
    rot = np.empty((n, n_joints, 3, 3))
    for j, (parent, chans, start) in enumerate(zip(clip.parents, clip.channels, clip.channel_starts, strict=True)):
        trans = np.broadcast_to(clip.offsets[j], (n, 3)).copy()
        local = None
        for k, ch in enumerate(chans):
            kind, axis = CHANNELS[ch]
            col = values[:, start + k]
            if kind == "position":
                trans[:, axis] = col
            else:
                r = _axis_rotation(axis, col)
                local = r if local is None else local @ r
        if parent < 0:
            pos[:, j] = trans
            rot[:, j] = _UNIT if local is None else local
        else:
            pos[:, j] = pos[:, parent] + np.einsum("tij,tj->ti", rot[:, parent], trans)
            rot[:, j] = rot[:, parent] if local is None else rot[:, parent] @ local
    return pos, rot


def _rest_positions(clip: BvhClip) -> np.ndarray:
    """Joint positions (J, 3) of the rest pose: OFFSETs chained, no channel applied."""
    pos = np.zeros((len(clip.names), 3))
    for j, parent in enumerate(clip.parents):
        pos[j] = clip.offsets[j] + (pos[parent] if parent >= 0 else 0.0)
    return pos


# --------------------------------------------------------------------------------------
# Name mapping


def _mirror_names(names: tuple[str, ...]) -> tuple[str, ...]:
    out = []
    for n in names:
        if n.startswith("Left"):
            out.append("Right" + n[4:])
        elif n.endswith("_l"):
            out.append(n[:-2] + "_r")
        elif n.startswith("l") and n[1:2].isupper():
            out.append("r" + n[1:])
        elif n.startswith("left_"):
            out.append("right_" + n[5:])
        else:
            out.append(n)
    return tuple(out)


_LEFT_NAMES: dict[str, tuple[str, ...]] = {
    "upper_arm": ("left_upper_arm", "LeftArm", "LeftUpArm", "LeftUpperArm", "lShldr", "upperarm_l"),
    "lower_arm": ("left_lower_arm", "LeftForeArm", "LeftLowArm", "LeftLowerArm", "LeftElbow", "lForeArm", "lowerarm_l"),
    "hand": ("left_hand", "LeftHand", "LeftWrist", "lHand", "hand_l"),
    "upper_leg": ("left_upper_leg", "LeftUpLeg", "LeftUpperLeg", "LeftThigh", "LeftHip", "lThigh", "thigh_l"),
    "lower_leg": ("left_lower_leg", "LeftLeg", "LeftLowLeg", "LeftLowerLeg", "LeftShin", "LeftKnee", "lShin", "calf_l"),
    "foot": ("left_foot", "LeftFoot", "LeftAnkle", "lFoot", "foot_l"),
}

#: Candidate BVH joint names for each of our bodies, tried in order: exact spelling first,
#: then ignoring case and any "namespace:" prefix. The first name is ours (``export_bvh``),
#: then the CMU conversions' names, then common alternatives. The chest is the *first* spine
#: joint above the hips (its position moves rigidly with the pelvis), the head is the skull.
DEFAULT_JOINT_NAMES: dict[str, tuple[str, ...]] = {
    "pelvis": ("pelvis", "Hips", "Hip", "Pelvis", "Root"),
    "chest": ("chest", "LowerBack", "Spine", "Abdomen", "Torso", "spine_01", "Spine1", "Chest"),
    "head": ("head", "Head"),
    **{
        f"{side}_{k}": v if side == "left" else _mirror_names(v)
        for side in ("left", "right")
        for k, v in _LEFT_NAMES.items()
    },
}


def _plain(name: str) -> str:
    return name.rsplit(":", 1)[-1].replace(" ", "").lower()


def resolve_mapping(clip: BvhClip, mapping: Mapping[str, str] | None = None) -> dict[str, int]:
    """Joint index in ``clip`` for each of our 15 bodies: ``mapping`` (body → BVH joint name)
    where given, else the first of ``DEFAULT_JOINT_NAMES`` the file has."""
    mapping = dict(mapping or {})
    unknown = sorted(set(mapping) - set(BONE_INDEX))
    if unknown:
        raise _err(
            clip.source,
            f"unknown body {unknown[0]!r} in the joint mapping (bodies: {', '.join(BONE_INDEX)})",
            "mapping",
        )
    joints = {n: i for i, n in enumerate(clip.names) if not clip.is_end[i]}
    plain: dict[str, int] = {}
    for n, i in joints.items():
        plain.setdefault(_plain(n), i)
    out: dict[str, int] = {}
    missing = []
    for bone in BONES:
        if bone.name in mapping:
            name = mapping[bone.name]
            if name not in joints:
                raise _err(clip.source, f"joint {name!r} mapped to {bone.name} is not in the file", "mapping")
            out[bone.name] = joints[name]
            continue
        candidates = DEFAULT_JOINT_NAMES[bone.name]
        hit = next((joints[c] for c in candidates if c in joints), None)
        if hit is None:
            hit = next((plain[_plain(c)] for c in candidates if _plain(c) in plain), None)
        if hit is None:
            missing.append(bone.name)
        else:
            out[bone.name] = hit
    if missing:
        raise _err(
            clip.source,
            f"no joint found for {', '.join(missing)}; pass a mapping body → joint name "
            f"(the file's joints: {', '.join(n for n in joints)})",
            "mapping",
        )
    seen: dict[int, str] = {}
    for body, j in out.items():
        if j in seen:
            raise _err(clip.source, f"joint {clip.names[j]!r} is mapped to both {seen[j]} and {body}", "mapping")
        seen[j] = body
    return out


# --------------------------------------------------------------------------------------
# Rotation helpers


def _unit(v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Unit vectors along the last axis and their norms."""
    n = np.linalg.norm(v, axis=-1, keepdims=True)
    return v / np.maximum(n, 1e-12), n[..., 0]


def _perp(v: np.ndarray, d: np.ndarray) -> np.ndarray:
    """The part of ``v`` perpendicular to the unit vectors ``d``."""
    return v - np.sum(v * d, axis=-1, keepdims=True) * d


def _any_perp(d: np.ndarray) -> np.ndarray:
    """Some unit vector perpendicular to each unit vector ``d``."""
    alt = np.where(np.abs(d[..., :1]) < 0.9, np.array([1.0, 0.0, 0.0]), np.array([0.0, 1.0, 0.0]))
    return _unit(_perp(alt, d))[0]


def _frame(d: np.ndarray, s: np.ndarray) -> np.ndarray:
    """Orthonormal frames (…, 3, 3), columns [d, s⊥, d × s⊥]; ``d`` unit, ``s`` any."""
    s_perp, norm = _unit(_perp(s, d))
    s_perp = np.where((norm > 1e-9)[..., None], s_perp, _any_perp(d))
    return np.stack([d, s_perp, np.cross(d, s_perp)], axis=-1)


def _triad(a: np.ndarray, c: np.ndarray, d: np.ndarray, s: np.ndarray) -> np.ndarray:
    """Rotation R taking body vector ``a`` exactly onto world ``d`` and ``c`` towards ``s``."""
    return _frame(d, s) @ np.swapaxes(_frame(np.broadcast_to(a, d.shape), np.broadcast_to(c, d.shape)), -1, -2)


def _swing(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The smallest rotation (3, 3) taking unit vector ``a`` to unit vector ``b``."""
    axis = np.cross(a, b)
    sin, cos = np.linalg.norm(axis), float(np.dot(a, b))
    if sin < 1e-9:
        if cos > 0:
            return np.eye(3)
        return axis_angle_matrix(_any_perp(a), np.array(math.pi))
    return axis_angle_matrix(axis / sin, np.array(math.atan2(sin, cos)))


def _hinge_signs() -> tuple[tuple[float, ...], ...]:
    """The axis signs of each body's DOFs: our hinge sequences are all prefixes of Y, X, Z
    (flex, lateral/abduction, twist)."""
    out = []
    for dofs in BODY_DOFS:
        signs = []
        for n, i in enumerate(dofs):
            axis = np.array(DOFS[i].axis)
            k = (1, 0, 2)[n]
            if abs(abs(axis[k]) - 1.0) > 1e-12 or np.count_nonzero(axis) != 1:
                raise AssertionError(f"DOF {DOFS[i].name}: axes are not a Y, X, Z sequence")
            signs.append(float(axis[k]))
        out.append(tuple(signs))
    return tuple(out)


_BODY_SIGNS = _hinge_signs()


def _hinge_rotation(angles: np.ndarray, body: int) -> np.ndarray:
    """The local rotation (T, 3, 3) of ``body`` at its hinge angles (T, n), as the skeleton composes it."""
    out = np.broadcast_to(_UNIT, (angles.shape[0], 3, 3)).copy()
    for m, i in enumerate(BODY_DOFS[body]):
        out = out @ axis_angle_matrix(np.array(DOFS[i].axis), angles[:, m])
    return out


def _to_interval(angle: np.ndarray, lo: float, hi: float) -> tuple[np.ndarray, np.ndarray]:
    """The representative of angle (mod 2π) nearest the interval [lo, hi], and its distance."""
    best = angle
    best_dist = np.maximum(lo - angle, 0.0) + np.maximum(angle - hi, 0.0)
    for shift in (-2 * math.pi, 2 * math.pi):
        cand = angle + shift
        dist = np.maximum(lo - cand, 0.0) + np.maximum(cand - hi, 0.0)
        better = dist < best_dist - 1e-12
        best = np.where(better, cand, best)
        best_dist = np.where(better, dist, best_dist)
    return best, best_dist


def _solve_hinges(local: np.ndarray, body: int) -> tuple[np.ndarray, np.ndarray]:
    """Joint angles (T, n) of ``body`` best reproducing the local rotations (T, 3, 3), and
    how far (T,) the limits moved them (radians, summed over the body's hinges).

    Three hinges: the exact Y·X·Z Euler decomposition; two: the first two angles (keeps the
    body's Z axis, the hand's length and the sole's normal); one: the bend of the Z axis in
    the X-Z plane. Of the two Euler solutions, the one nearer the limits wins; then clipped.
    """
    dofs = BODY_DOFS[body]
    signs = np.array(_BODY_SIGNS[body])
    lo, hi = LOWER[list(dofs)], UPPER[list(dofs)]
    n = len(dofs)
    y, x, z = euler_angles(local, (1, 0, 2))
    candidates = [np.stack([y, x, z], axis=-1)[..., :n]]
    if n > 1:
        candidates.append(np.stack([y + math.pi, math.pi - x, z + math.pi], axis=-1)[..., :n])
    best = None
    best_dist = None
    for cand in candidates:
        angles = cand * signs
        fitted = np.empty_like(angles)
        dist = np.zeros(angles.shape[0])
        for m in range(n):
            fitted[:, m], d = _to_interval(angles[:, m], lo[m], hi[m])
            dist += d
        if best is None:
            best, best_dist = fitted, dist
        else:
            better = dist < best_dist - 1e-9
            best = np.where(better[:, None], fitted, best)
            best_dist = np.where(better, dist, best_dist)
    assert best is not None and best_dist is not None
    return np.clip(best, lo, hi), best_dist


# --------------------------------------------------------------------------------------
# Retargeting


@dataclass(frozen=True, eq=False)
class RetargetedClip:
    """A BVH clip as our skeleton's pose, motion frame, ``REFERENCE_HEIGHT_M`` person."""

    source: str
    times: np.ndarray  # (F,) seconds of the clip's frames
    pose: Pose  # at ``times``
    times_30fps: np.ndarray  # 0, 1/30 s, … up to the clip's length
    pose_30fps: Pose  # resampled at ``RESAMPLE_FPS`` (the last frame held to the end)
    length_s: float  # n_frames · frame_time
    scale: float  # metres of the reference person per BVH unit
    clipped_fraction: float  # share of (frame, joint) samples the limits moved by > 1°


_CENTRAL = ("pelvis", "chest")
_LIMBS = ("left_upper_arm", "right_upper_arm", "left_upper_leg", "right_upper_leg")
_LOWER_LIMBS = ("left_lower_arm", "right_lower_arm", "left_lower_leg", "right_lower_leg")
_ENDS = ("head", "left_hand", "right_hand", "left_foot", "right_foot")
_DOWN = np.array([0.0, 0.0, -1.0])
_FWD = np.array([1.0, 0.0, 0.0])
_LEFT = np.array([0.0, 1.0, 0.0])


def _up_matrix(up: str, source: str) -> np.ndarray:
    """Rotation taking the file's axes to ours with its ``up`` axis onto +Z (a cyclic shift)."""
    k = {"x": 0, "y": 1, "z": 2}.get(str(up).lower())
    if k is None:
        raise _err(source, f"up axis must be 'x', 'y' or 'z', got {up!r}", "up")
    m = np.zeros((3, 3))
    for our in range(3):  # our axis `our` takes file axis (k + 1 + our) mod 3; Z takes `up`
        m[our, (k + 1 + our) % 3] = 1.0
    return m


def _facing(up_matrix: np.ndarray, hip_line: np.ndarray, source: str, when: str) -> np.ndarray:
    """Yaw · up conversion making the hip line (left − right hip, file axes) point +Y."""
    h = up_matrix @ hip_line
    if not math.hypot(h[0], h[1]) > 1e-6 * float(np.linalg.norm(h)):
        raise _err(source, f"the hips' left-right line is vertical {when}; is the up axis right?", "up")
    yaw = math.pi / 2 - math.atan2(h[1], h[0])
    return axis_angle_matrix(np.array([0.0, 0.0, 1.0]), np.array(yaw)) @ up_matrix


def _children(clip: BvhClip) -> list[list[int]]:
    out: list[list[int]] = [[] for _ in clip.names]
    for j, p in enumerate(clip.parents):
        if p >= 0:
            out[p].append(j)
    return out


def _next_body(name: str) -> str:
    """The body hanging from a limb segment (upper arm → lower arm → hand, legs alike)."""
    return next(b.name for b in BONES if b.parent == name)


@dataclass
class _Landmarks:
    """Where each body's target directions come from, as joint indices of the clip."""

    source: str
    names: tuple[str, ...]
    origin: dict[str, int]
    ends: dict[str, list[int]]  # for head, hands, feet: the bone's far end is these joints' mean

    def far(self, pos: np.ndarray, body: str) -> np.ndarray:
        """The far end (T, 3) of ``body``'s bone: the next body's joint, or the children's mean."""
        if body in self.ends:
            return pos[:, self.ends[body]].mean(axis=1)
        return pos[:, self.origin[_next_body(body)]]


def _landmarks(clip: BvhClip, idx: dict[str, int]) -> _Landmarks:
    children = _children(clip)
    ends: dict[str, list[int]] = {}
    for body in _ENDS:
        j = idx[body]
        if not children[j]:
            raise _err(clip.source, f"joint {clip.names[j]!r} ({body}) has no child or End Site", "mapping")
        ends[body] = children[j]
    return _Landmarks(source=clip.source, names=clip.names, origin=dict(idx), ends=ends)


def _body_targets(
    pos: np.ndarray, rot: np.ndarray, lm: _Landmarks, consts: dict[str, tuple[np.ndarray, ...]] | None
) -> tuple[np.ndarray, dict[str, tuple[np.ndarray, ...]]]:
    """Target world orientations (T, 15, 3, 3) of our bodies from joint positions and rotations.

    With ``consts`` None this is the rest pass (T = 1, rotations identity): it also returns
    each body's constants (body-frame vectors a, c and the rest twist reference u) that make
    the rest pose neutral for the central and end bodies.
    """
    rest = consts is None
    consts = {} if consts is None else consts
    n = pos.shape[0]
    o = lm.origin
    w = np.empty((n, len(BONES), 3, 3))
    hip_c = 0.5 * (pos[:, o["left_upper_leg"]] + pos[:, o["right_upper_leg"]])
    for b, bone in enumerate(BONES):
        name = bone.name
        wp = np.broadcast_to(_UNIT, (n, 3, 3)) if bone.parent is None else w[:, PARENTS[b]]
        if name in _CENTRAL:
            shoulders = 0.5 * (pos[:, o["left_upper_arm"]] + pos[:, o["right_upper_arm"]])
            if name == "pelvis":
                d = pos[:, o["left_upper_leg"]] - pos[:, o["right_upper_leg"]]
                s = pos[:, o["chest"]] - hip_c
                if rest:  # a spine joint level with the hips tells no "up": use the shoulders then
                    use_shoulders = np.linalg.norm(s[0]) < 0.2 * np.linalg.norm(d[0])
                    consts["pelvis_up_from_shoulders"] = (np.array(use_shoulders),)
                if bool(consts["pelvis_up_from_shoulders"][0]):
                    s = shoulders - hip_c
            else:
                d = shoulders - pos[:, o["chest"]]
                s = pos[:, o["left_upper_arm"]] - pos[:, o["right_upper_arm"]]
            d, _ = _unit(d)
            if rest:
                consts[name] = (wp[0].T @ d[0], wp[0].T @ s[0])
            a, c = consts[name]
            w[:, b] = _triad(a, c, d, s)
            continue
        j = o[name]
        d, norm = _unit(lm.far(pos, name) - pos[:, j])
        if rest:
            if norm[0] < 1e-9:
                joint = lm.names[lm.origin[name]]
                raise _err(lm.source, f"the bone from {joint!r} ({name}) has zero length in the rest pose", "mapping")
            if name in _ENDS:
                ref_axis = wp[0] @ (_LEFT if name.endswith("foot") else _FWD)
                u, u_norm = _unit(_perp(ref_axis, d[0]))
                if u_norm < 1e-6:
                    u = _any_perp(d[0])
                consts[name] = (wp[0].T @ d[0], wp[0].T @ u, u)
            else:
                u = _swing(wp[0] @ _DOWN, d[0]) @ (wp[0] @ _FWD)
                consts[name] = (_DOWN, _FWD, u)
        a, c, u = consts[name]
        # Where a bone collapses (coincident joints), keep it neutral relative to its parent.
        d = np.where((norm > 1e-9)[:, None], d, np.einsum("tij,j->ti", wp, a))
        carried = np.einsum("tij,j->ti", rot[:, j], u)
        s = _unit(_perp(carried, d))[0]
        if name in _LIMBS and not rest:
            # Twist from the bend of the next bone, where it is bent enough to tell.
            e = _unit(lm.far(pos, _next_body(name)) - lm.far(pos, name))[0]
            bend = _perp(e, d) * (1.0 if "arm" in name else -1.0)
            bend_u, sin_bend = _unit(bend)
            weight = np.clip((sin_bend - 0.1) / 0.3, 0.0, 1.0)[:, None]
            s = weight * bend_u + (1.0 - weight) * s
        w[:, b] = _triad(a, c, d, s)
    return w, consts


def _scale(clip: BvhClip, rest: np.ndarray, idx: dict[str, int]) -> float:
    """Metres of the reference person per BVH unit: the ratio of leg lengths (hip, knee, ankle)."""
    legs = []
    for side in ("left", "right"):
        hip, knee, ankle = (rest[idx[f"{side}_{b}"]] for b in ("upper_leg", "lower_leg", "foot"))
        legs.append(np.linalg.norm(knee - hip) + np.linalg.norm(ankle - knee))
    leg = float(np.mean(legs))
    if not leg > 1e-9:
        raise _err(clip.source, "the legs have zero length in the rest pose", "mapping")
    return LEG / leg


def _joint_angles(targets: np.ndarray) -> tuple[np.ndarray, int]:
    """Our joint angles (T, 30) reproducing target body orientations (T, 15, 3, 3), each body
    solved against its parent's achieved frame; and how many (frame, body) samples the
    limits moved by more than 1°."""
    n = targets.shape[0]
    q = np.zeros((n, N_DOFS))
    achieved = np.empty_like(targets)
    achieved[:, 0] = targets[:, 0]
    clipped = 0
    for b in range(1, len(BONES)):
        p = PARENTS[b]
        local = np.swapaxes(achieved[:, p], -1, -2) @ targets[:, b]
        dofs = list(BODY_DOFS[b])
        q[:, dofs], excess = _solve_hinges(local, b)
        achieved[:, b] = achieved[:, p] @ _hinge_rotation(q[:, dofs], b)
        clipped += int(np.count_nonzero(excess > math.radians(1.0)))
    return q, clipped


def retarget(
    clip: BvhClip,
    *,
    mapping: Mapping[str, str] | None = None,
    up: str = "y",
    ground: float | None = 0.0,
) -> RetargetedClip:
    """Retarget a BVH clip onto our 15 bodies: a Pose in the motion frame (see module doc).

    ``mapping`` names BVH joints for some or all bodies (defaults: ``DEFAULT_JOINT_NAMES``);
    ``up`` is the file's up axis; ``ground`` its floor height along ``up`` in file units
    (None: the clip's lowest foot point), which sets the pelvis height offset.
    """
    idx = resolve_mapping(clip, mapping)
    lm = _landmarks(clip, idx)
    pos, rot = bvh_forward_kinematics(clip)
    rest = _rest_positions(clip)
    up_m = _up_matrix(up, clip.source)
    lh, rh = idx["left_upper_leg"], idx["right_upper_leg"]
    a_rest = _facing(up_m, rest[lh] - rest[rh], clip.source, "in the rest pose")
    a_now = _facing(up_m, pos[0, lh] - pos[0, rh], clip.source, "at frame 0")
    scale = _scale(clip, rest, idx)

    world = scale * np.einsum("ij,tkj->tki", a_now, pos)
    up_k = "xyz".index(str(up).lower())
    if ground is None:
        feet = [idx["left_foot"], idx["right_foot"], *lm.ends["left_foot"], *lm.ends["right_foot"]]
        ground = float(pos[:, feet, up_k].min())
    world[..., 2] -= scale * float(ground)
    rest_world = scale * rest @ a_rest.T
    carried = np.einsum("ij,tkjl,ml->tkim", a_now, rot, a_rest)  # A · G · A_rest^T

    _, consts = _body_targets(rest_world[None], np.broadcast_to(_UNIT, (1, len(clip.names), 3, 3)), lm, None)
    targets, _ = _body_targets(world, carried, lm, consts)
    q, clipped = _joint_angles(targets)

    hip_c = 0.5 * (world[:, lh] + world[:, rh])
    root_pos = hip_c.copy()
    root_pos[:, :2] -= hip_c[0, :2]
    root_pos[:, 2] -= PELVIS_H
    pose = Pose(root_pos, continuous_quats(matrix_to_quat(targets[:, 0])), q)
    n = clip.n_frames
    times = np.arange(n) * clip.frame_time
    times_30 = np.arange(0.0, clip.length_s - 1e-9, 1.0 / RESAMPLE_FPS)  # the motion's [0, length)
    return RetargetedClip(
        source=clip.source,
        times=times,
        pose=pose,
        times_30fps=times_30,
        pose_30fps=sample_pose(pose, times, times_30),
        length_s=clip.length_s,
        scale=scale,
        clipped_fraction=clipped / float(n * (len(BONES) - 1)),
    )


def sample_pose(pose: Pose, times: np.ndarray, tau: np.ndarray) -> Pose:
    """``pose`` (sampled at increasing ``times``) at times ``tau``, held at the ends.

    Linear on the root position and joint angles, slerp on the root orientation.
    """
    times = np.asarray(times, dtype=np.float64)
    tau = np.clip(np.asarray(tau, dtype=np.float64), times[0], times[-1])
    if len(times) == 1:
        k = np.zeros(tau.shape, dtype=int)
        return Pose(pose.root_pos[k], pose.root_quat[k], pose.q[k])
    i = np.clip(np.searchsorted(times, tau, side="right") - 1, 0, len(times) - 2)
    u = ((tau - times[i]) / (times[i + 1] - times[i]))[:, None]
    lerp = lambda x: (1.0 - u) * x[i] + u * x[i + 1]  # noqa: E731
    return Pose(lerp(pose.root_pos), slerp(pose.root_quat[i], pose.root_quat[i + 1], u), lerp(pose.q))


# --------------------------------------------------------------------------------------
# Motion


def bvh_motion(
    clip_or_path: BvhClip | str | os.PathLike[str],
    *,
    name: str,
    description: str,
    mapping: Mapping[str, str] | None = None,
    up: str = "y",
    ground: float | None = 0.0,
) -> MotionDef:
    """A playable ``MotionDef`` from a BVH clip or file, ready for ``register_motion``.

    Its length is ``n_frames · frame_time``; the pose at τ interpolates the retargeted frames.
    ``MotionParams.amplitude`` scales joint excursions around the clip's mean pose; phase and
    style have no meaning for a capture and are ignored. ``description`` must be lowercase,
    as in the motion catalogue, so θ's regular expressions can match it.
    """
    clip = clip_or_path if isinstance(clip_or_path, BvhClip) else load_bvh(Path(clip_or_path))
    if not isinstance(name, str) or not name.isidentifier() or name != name.lower():
        raise _err(clip.source, f"motion name {name!r} must be snake_case", "name")
    if not isinstance(description, str) or not description.strip() or description != description.lower():
        raise _err(clip.source, f"motion description {description!r} must be non-empty lowercase", "description")
    result = retarget(clip, mapping=mapping, up=up, ground=ground)
    pose, times = result.pose, result.times
    mean_q = pose.q.mean(axis=0)

    def fn(tau: np.ndarray, params: MotionParams) -> Pose:
        sampled = sample_pose(pose, times, np.atleast_1d(np.asarray(tau, dtype=np.float64)))
        q = mean_q + params.amplitude * (sampled.q - mean_q)
        return Pose(sampled.root_pos, sampled.root_quat, np.clip(q, LOWER, UPPER))

    return MotionDef(name=name, length_s=result.length_s, fn=fn, description=description)


# --------------------------------------------------------------------------------------
# Export

#: Our axes → BVH's Y-up axes: BVH x = our left (+Y), y = up (+Z), z = forward (+X).
_TO_BVH = np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]])


def _end_site(dims: BodyDims, body: str) -> np.ndarray | None:
    """End Site offset (our axes) of a leaf body: skull top, hand tip, toe."""
    cap = dims.capsules[BONE_INDEX[body]]
    if body == "head":
        return np.array([0.0, 0.0, cap.a[2] + cap.radius])
    if body.endswith("hand"):
        return np.array([0.0, 0.0, cap.b[2] - cap.radius])
    if body.endswith("foot"):
        return np.array([cap.b[0] + cap.radius, 0.0, cap.b[2]])
    return None


def export_bvh(pose: Pose, dims: BodyDims, fps: float) -> str:
    """BVH text of our skeleton (joints named as our bodies, metres) playing a world-frame pose.

    ``pose.root_pos`` is the pelvis position in the world, as ``animation.place`` returns
    (place a motion-frame pose first). Our Z-up axes become BVH's Y up, the person facing
    +Z with +X to their left; every joint has ``Zrotation Yrotation Xrotation`` channels
    (intrinsic, R = Rz · Ry · Rx, degrees), the root also ``Xposition Yposition Zposition``.
    """
    if not (math.isfinite(fps) and fps > 0):
        raise ValueError(f"fps must be finite and > 0, got {fps}")
    n = len(pose)
    local = local_rotations(pose.q)
    local[:, 0] = quat_to_matrix(pose.root_quat) @ local[:, 0]
    local_bvh = _TO_BVH @ local @ _TO_BVH.T
    z, y, x = euler_angles(local_bvh, (2, 1, 0))
    angles = np.rad2deg(np.stack([z, y, x], axis=-1))  # (T, 15, 3)
    root = pose.root_pos @ _TO_BVH.T

    fmt = "{:.6f}".format
    out = ["HIERARCHY"]

    def write(b: int, depth: int) -> None:
        bone = BONES[b]
        pad = "\t" * depth
        off = np.zeros(3) if b == 0 else _TO_BVH @ dims.offsets[b]
        out.append(f"{pad}{'ROOT' if b == 0 else 'JOINT'} {bone.name}")
        out.append(f"{pad}{{")
        out.append(f"{pad}\tOFFSET {' '.join(fmt(v) for v in off)}")
        pos_ch = "Xposition Yposition Zposition " if b == 0 else ""
        out.append(f"{pad}\tCHANNELS {6 if b == 0 else 3} {pos_ch}Zrotation Yrotation Xrotation")
        kids = [k for k in range(len(BONES)) if PARENTS[k] == b]
        for k in kids:
            write(k, depth + 1)
        end = _end_site(dims, bone.name)
        if end is not None:
            out.append(f"{pad}\tEnd Site")
            out.append(f"{pad}\t{{")
            out.append(f"{pad}\t\tOFFSET {' '.join(fmt(v) for v in _TO_BVH @ end)}")
            out.append(f"{pad}\t}}")
        out.append(f"{pad}}}")

    write(0, 0)
    out.append("MOTION")
    out.append(f"Frames: {n}")
    out.append(f"Frame Time: {1.0 / fps:.8f}")
    order = _export_order()
    for t in range(n):
        values = list(root[t]) + [v for b in order for v in angles[t, b]]
        out.append(" ".join(fmt(v) for v in values))
    return "\n".join(out) + "\n"


def _export_order() -> list[int]:
    """Bodies in the depth-first order ``export_bvh`` writes them (the channel order)."""
    order: list[int] = []

    def visit(b: int) -> None:
        order.append(b)
        for k in range(len(BONES)):
            if PARENTS[k] == b:
                visit(k)

    visit(0)
    return order
