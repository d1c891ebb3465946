"""The 15-muscle skeleton of the paper's ragdoll, shared by motions, physics and renderer.

One declaration: the body tree (paper Figure "Ragdoll configuration"), the 30 joint degrees
of freedom with their axes and limits, and the body proportions derived from a human
model (anthropometric ratios of height, after Winter's segment table). The motion library
writes joint-angle curves against ``DOFS``; the MuJoCo model is built from ``BodyDims``;
numpy forward kinematics here gives the same body poses MuJoCo computes (a test checks).

Frames: the person frame has +X forward, +Y to the person's left, +Z up (MuJoCo world
frame, heading 0 faces +X). At rest (all angles 0) every body frame is aligned with the
person frame, the person stands upright with arms hanging, and each body's origin is its
proximal joint. Bilateral degrees of freedom use mirrored axes on the right side, so
mirroring a motion (handedness) swaps left and right values unchanged.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from phav_generator.motion.rotations import axis_angle_matrix, quat_to_matrix
from phav_spec.metadata import JOINT_ORDER
from phav_spec.vocab import MUSCLES

_D = math.pi / 180.0


@dataclass(frozen=True)
class Dof:
    """One hinge degree of freedom of a body, about ``axis`` in the body's frame."""

    name: str
    body: str
    axis: tuple[float, float, float]
    lower: float  # radians
    upper: float
    mirror: str  # name of the DOF that takes this value when the motion is mirrored
    mirror_sign: float  # +1 for bilateral swaps, −1 for central lateral bend and twist


@dataclass(frozen=True)
class Bone:
    """A body of the ragdoll: its parent and the pixel-class joint at its origin."""

    name: str
    parent: str | None
    joint: str | None  # the paper's joint name at this body's origin (None: pelvis, chest)


BONES: tuple[Bone, ...] = (
    Bone("pelvis", None, None),
    Bone("chest", "pelvis", None),
    Bone("head", "chest", "neck"),
    Bone("left_upper_arm", "chest", "left_shoulder"),
    Bone("left_lower_arm", "left_upper_arm", "left_elbow"),
    Bone("left_hand", "left_lower_arm", "left_wrist"),
    Bone("right_upper_arm", "chest", "right_shoulder"),
    Bone("right_lower_arm", "right_upper_arm", "right_elbow"),
    Bone("right_hand", "right_lower_arm", "right_wrist"),
    Bone("left_upper_leg", "pelvis", "left_hip"),
    Bone("left_lower_leg", "left_upper_leg", "left_knee"),
    Bone("left_foot", "left_lower_leg", "left_ankle"),
    Bone("right_upper_leg", "pelvis", "right_hip"),
    Bone("right_lower_leg", "right_upper_leg", "right_knee"),
    Bone("right_foot", "right_lower_leg", "right_ankle"),
)
assert tuple(b.name for b in BONES) == MUSCLES.names
BONE_INDEX: dict[str, int] = {b.name: i for i, b in enumerate(BONES)}
PARENTS: tuple[int, ...] = tuple(-1 if b.parent is None else BONE_INDEX[b.parent] for b in BONES)
#: Each body's first child in ``BONES`` order (the body its distal joint moves), None for a
#: leaf (head, hands, feet).
FIRST_CHILD: tuple[int | None, ...] = tuple(
    next((c for c in range(len(BONES)) if PARENTS[c] == k), None) for k in range(len(BONES))
)

#: The 13 joints of the pixel-class table, in the metadata order (neck to right ankle).
JOINT_NAMES: tuple[str, ...] = JOINT_ORDER
#: Index of the body whose origin is each joint of ``JOINT_NAMES``.
JOINT_BODIES: tuple[int, ...] = tuple(next(i for i, b in enumerate(BONES) if b.joint == j) for j in JOINT_NAMES)


def _central(prefix: str, body: str, limits: tuple[tuple[float, float], ...]) -> list[Dof]:
    (f0, f1), (l0, l1), (t0, t1) = limits
    return [
        Dof(f"{prefix}_flex", body, (0.0, 1.0, 0.0), f0 * _D, f1 * _D, f"{prefix}_flex", 1.0),
        Dof(f"{prefix}_lateral", body, (1.0, 0.0, 0.0), l0 * _D, l1 * _D, f"{prefix}_lateral", -1.0),
        Dof(f"{prefix}_twist", body, (0.0, 0.0, 1.0), t0 * _D, t1 * _D, f"{prefix}_twist", -1.0),
    ]


def _bilateral(joint: str, body: str, spec: tuple[tuple[str, str, float, float], ...]) -> list[Dof]:
    """DOFs of ``left_{joint}`` / ``right_{joint}``; spec rows: (name, axis, lower°, upper°).

    Axis names: ``flex`` about −Y (forward is positive), ``knee`` about +Y, ``abd`` about ±X
    (away from the midline is positive), ``twist`` about ±Z.
    """
    out = []
    for side, sign in (("left", 1.0), ("right", -1.0)):
        other = "right" if side == "left" else "left"
        for name, kind, lo, hi in spec:
            axis = {
                "flex": (0.0, -1.0, 0.0),
                "knee": (0.0, 1.0, 0.0),
                "abd": (sign, 0.0, 0.0),
                "twist": (0.0, 0.0, sign),
            }[kind]
            out.append(
                Dof(f"{side}_{joint}_{name}", f"{side}_{body}", axis, lo * _D, hi * _D, f"{other}_{joint}_{name}", 1.0)
            )
    return out


def _dofs() -> tuple[Dof, ...]:
    rows: list[Dof] = []
    rows += _central("waist", "chest", ((-30, 90), (-40, 40), (-60, 60)))
    rows += _central("neck", "head", ((-50, 70), (-45, 45), (-80, 80)))
    by_body: dict[str, list[Dof]] = {}
    for d in (
        _bilateral("shoulder", "upper_arm", (("flex", "flex", -70, 185), ("abd", "abd", -40, 175),
                                             ("twist", "twist", -90, 90)))
        + _bilateral("elbow", "lower_arm", (("flex", "flex", 0, 150),))
        + _bilateral("wrist", "hand", (("flex", "flex", -75, 75), ("dev", "abd", -35, 35)))
        + _bilateral("hip", "upper_leg", (("flex", "flex", -60, 140), ("abd", "abd", -35, 95),
                                          ("twist", "twist", -50, 50)))
        + _bilateral("knee", "lower_leg", (("flex", "knee", 0, 155),))
        + _bilateral("ankle", "foot", (("flex", "flex", -55, 35), ("inv", "abd", -35, 35)))
    ):  # fmt: skip
        by_body.setdefault(d.body, []).append(d)
    for bone in BONES[3:]:
        rows += by_body[bone.name]
    return tuple(rows)


#: The 30 joint degrees of freedom, in body order (the order of MuJoCo's qpos after the root).
DOFS: tuple[Dof, ...] = _dofs()
DOF_INDEX: dict[str, int] = {d.name: i for i, d in enumerate(DOFS)}
N_DOFS = len(DOFS)
LOWER = np.array([d.lower for d in DOFS])
UPPER = np.array([d.upper for d in DOFS])
#: For each DOF, the index of the DOF holding its mirrored value, and the sign.
MIRROR_INDEX = np.array([DOF_INDEX[d.mirror] for d in DOFS])
MIRROR_SIGN = np.array([d.mirror_sign for d in DOFS])
#: Which body each DOF moves.
DOF_BODY = np.array([BONE_INDEX[d.body] for d in DOFS])

#: Segment mass fractions of total body mass (Winter's table; trunk split chest/pelvis).
MASS_FRACTIONS: dict[str, float] = {
    "pelvis": 0.142, "chest": 0.355, "head": 0.081,
    "upper_arm": 0.028, "lower_arm": 0.016, "hand": 0.006,
    "upper_leg": 0.100, "lower_leg": 0.0465, "foot": 0.0145,
}  # fmt: skip


@dataclass(frozen=True)
class Capsule:
    """A body's collision/visual primitive in its own frame: a capsule (or sphere if a == b)."""

    a: tuple[float, float, float]
    b: tuple[float, float, float]
    radius: float


@dataclass(frozen=True)
class BodyDims:
    """Proportions of one body: body origins relative to parents, primitives, masses."""

    height_m: float
    offsets: np.ndarray  # (15, 3) body origin in the parent frame at rest; pelvis: standing height
    capsules: tuple[Capsule, ...]  # per body
    masses: np.ndarray  # (15,) kg
    sole_height: float  # ankle above the sole: the foot's lowest point is this far below the ankle

    @property
    def standing_pelvis_height(self) -> float:
        """Pelvis height (m) of this body standing upright on flat ground."""
        return float(self.offsets[0, 2])


def body_dims(
    height_m: float, mass_kg: float, shoulder_width_m: float, hip_width_m: float, limb_girth: float
) -> BodyDims:
    """Proportions from shape parameters by anthropometric ratios: the motion library's
    reference body (people's bodies are measured on their meshes, ``phav_generator.body``)."""
    h = float(height_m)
    g = float(limb_girth)
    upper_leg, lower_leg, ankle = 0.245 * h, 0.246 * h, 0.039 * h
    upper_arm, lower_arm, hand = 0.188 * h, 0.145 * h, 0.108 * h
    hip_y = 0.27 * hip_width_m
    shoulder_y = shoulder_width_m / 2.0 - 0.025
    chest_z, neck_z, shoulder_z = 0.10 * h, 0.21 * h, 0.188 * h
    offsets = {
        "pelvis": (0.0, 0.0, upper_leg + lower_leg + ankle),
        "chest": (0.0, 0.0, chest_z),
        "head": (0.0, 0.0, neck_z),
        "left_upper_arm": (0.0, shoulder_y, shoulder_z),
        "left_lower_arm": (0.0, 0.0, -upper_arm),
        "left_hand": (0.0, 0.0, -lower_arm),
        "right_upper_arm": (0.0, -shoulder_y, shoulder_z),
        "right_lower_arm": (0.0, 0.0, -upper_arm),
        "right_hand": (0.0, 0.0, -lower_arm),
        "left_upper_leg": (0.0, hip_y, 0.0),
        "left_lower_leg": (0.0, 0.0, -upper_leg),
        "left_foot": (0.0, 0.0, -lower_leg),
        "right_upper_leg": (0.0, -hip_y, 0.0),
        "right_lower_leg": (0.0, 0.0, -upper_leg),
        "right_foot": (0.0, 0.0, -lower_leg),
    }
    pelvis_r = 0.05 * h * g
    foot_r = 0.45 * ankle
    shapes = {
        "pelvis": Capsule(
            (0.0, -hip_width_m / 2 + pelvis_r, 0.035 * h), (0.0, hip_width_m / 2 - pelvis_r, 0.035 * h), pelvis_r
        ),
        "chest": Capsule((0.0, 0.0, 0.05 * h), (0.0, 0.0, 0.15 * h), 0.075 * h * g),
        "head": Capsule((0.01 * h, 0.0, 0.075 * h), (0.01 * h, 0.0, 0.075 * h), 0.058 * h),
        "upper_arm": Capsule((0.0, 0.0, -0.02 * h), (0.0, 0.0, -upper_arm + 0.02 * h), 0.024 * h * g),
        "lower_arm": Capsule((0.0, 0.0, -0.015 * h), (0.0, 0.0, -lower_arm + 0.012 * h), 0.019 * h * g),
        "hand": Capsule((0.0, 0.0, -0.01 * h), (0.0, 0.0, -0.7 * hand), 0.015 * h * g),
        "upper_leg": Capsule((0.0, 0.0, -0.03 * h), (0.0, 0.0, -upper_leg + 0.025 * h), 0.038 * h * g),
        "lower_leg": Capsule((0.0, 0.0, -0.02 * h), (0.0, 0.0, -lower_leg + 0.03 * h), 0.028 * h * g),
        "foot": Capsule((-0.025 * h, 0.0, -ankle + foot_r), (0.105 * h, 0.0, -ankle + foot_r), foot_r),
    }
    capsules = []
    masses = []
    for bone in BONES:
        kind = bone.name.split("_", 1)[1] if bone.name.startswith(("left_", "right_")) else bone.name
        capsules.append(shapes[kind])
        masses.append(MASS_FRACTIONS[kind] * mass_kg)
    return BodyDims(
        height_m=h,
        offsets=np.array([offsets[b.name] for b in BONES], dtype=np.float64),
        capsules=tuple(capsules),
        masses=np.array(masses),
        sole_height=ankle,
    )


_AXES = tuple(np.array(d.axis) for d in DOFS)
#: The DOF indices of each body, in composition order (a prefix of flex, lateral/abd, twist).
BODY_DOFS: tuple[tuple[int, ...], ...] = tuple(tuple(i for i, d in enumerate(DOFS) if d.body == b.name) for b in BONES)


def local_rotations(q: np.ndarray) -> np.ndarray:
    """Per-body joint rotations (T, 15, 3, 3) from joint angles (T, 30), composed in DOF order."""
    q = np.asarray(q, dtype=np.float64)
    n = q.shape[0]
    out = np.broadcast_to(np.eye(3), (n, len(BONES), 3, 3)).copy()
    for b, dofs in enumerate(BODY_DOFS):
        for i in dofs:
            out[:, b] = out[:, b] @ axis_angle_matrix(_AXES[i], q[:, i])
    return out


def forward_kinematics(
    dims: BodyDims, root_pos: np.ndarray, root_quat: np.ndarray, q: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """World body origins (T, 15, 3) and orientations (T, 15, 3, 3) of an animated pose.

    ``root_pos`` is the pelvis origin (T, 3), ``root_quat`` its orientation (T, 4), ``q``
    the joint angles (T, 30). The same composition as MuJoCo's kinematics: a body's frame is
    its parent's, moved by its offset, then rotated by its hinges in order.
    """
    root_pos = np.asarray(root_pos, dtype=np.float64)
    local = local_rotations(q)
    n = root_pos.shape[0]
    pos = np.empty((n, len(BONES), 3))
    rot = np.empty((n, len(BONES), 3, 3))
    pos[:, 0] = root_pos
    rot[:, 0] = quat_to_matrix(root_quat) @ local[:, 0]
    for b in range(1, len(BONES)):
        p = PARENTS[b]
        pos[:, b] = pos[:, p] + np.einsum("tij,j->ti", rot[:, p], dims.offsets[b])
        rot[:, b] = rot[:, p] @ local[:, b]
    return pos, rot


def joints_from_bodies(body_pos: np.ndarray) -> np.ndarray:
    """The 13 metadata joints (…, 13, 3) from body origins (…, 15, 3)."""
    return np.asarray(body_pos)[..., list(JOINT_BODIES), :]


def capsule_points(dims: BodyDims, body_pos: np.ndarray, body_rot: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """World end points (…, 15, 3) a and b of every body's capsule."""
    a = np.array([c.a for c in dims.capsules])
    b = np.array([c.b for c in dims.capsules])
    wa = body_pos + np.einsum("...kij,kj->...ki", body_rot, a)
    wb = body_pos + np.einsum("...kij,kj->...ki", body_rot, b)
    return wa, wb


def lowest_point(dims: BodyDims, body_pos: np.ndarray, body_rot: np.ndarray) -> np.ndarray:
    """Height (…,) of the lowest point of the body surface: where it touches the ground."""
    wa, wb = capsule_points(dims, body_pos, body_rot)
    r = np.array([c.radius for c in dims.capsules])
    return np.minimum(wa[..., 2] - r, wb[..., 2] - r).min(axis=-1)


def clamp_to_limits(q: np.ndarray) -> np.ndarray:
    """Joint angles clipped into the skeleton's limits."""
    return np.clip(q, LOWER, UPPER)


def mirror_dofs(q: np.ndarray) -> np.ndarray:
    """Joint angles of the mirror image (left ↔ right) of a pose (…, 30)."""
    q = np.asarray(q)
    return q[..., MIRROR_INDEX] * MIRROR_SIGN
