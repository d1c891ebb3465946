"""Triangle meshes of the shapes scenes are made of: boxes, capsules, spheres, the ground.

Each builder returns ``Mesh`` arrays in the shape's own frame (float32 positions and unit
normals, uint32 triangles, counter-clockwise seen from outside). Tessellation is fixed so
the same shape always gives the same triangles.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

#: Segments around a capsule or sphere, and rings per hemisphere.
AROUND = 12
RINGS = 3


@dataclass(frozen=True)
class Mesh:
    """Triangles in the shape's own frame. A skinned mesh also carries, per vertex, up to
    four of its drawable's bones and their weights (linear blend skinning, in the shader)."""

    positions: np.ndarray  # (N, 3) float32
    normals: np.ndarray  # (N, 3) float32
    triangles: np.ndarray  # (M, 3) uint32
    bones: np.ndarray | None = None  # (N, 4) uint32: indices into the drawable's transforms
    weights: np.ndarray | None = None  # (N, 4) float32, rows summing to 1

    @property
    def n_triangles(self) -> int:
        return len(self.triangles)


def _mesh(positions, normals, triangles) -> Mesh:
    return Mesh(
        np.ascontiguousarray(positions, dtype=np.float32),
        np.ascontiguousarray(normals, dtype=np.float32),
        np.ascontiguousarray(triangles, dtype=np.uint32),
    )


def ring_triangles(rings: int, around: int, *, closed: bool) -> np.ndarray:
    """Triangles (n, 3) joining ``rings`` consecutive rings of ``around`` vertices each
    (vertex ``i * around + k``), round the ring's end to its start when ``closed``."""
    tris = []
    for i in range(rings - 1):
        for k in range(around if closed else around - 1):
            a, b = i * around + k, i * around + (k + 1) % around
            tris += [(a, b, b + around), (a, b + around, a + around)]
    return np.array(tris)


def box(half: tuple[float, float, float]) -> Mesh:
    """An axis-aligned box centred on the origin: 6 faces of 2 triangles, flat normals."""
    hx, hy, hz = half
    positions, normals, triangles = [], [], []
    for axis in range(3):
        for sign in (-1.0, 1.0):
            n = np.zeros(3)
            n[axis] = sign
            u_axis, v_axis = (axis + 1) % 3, (axis + 2) % 3
            corners = []
            for a, b in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
                p = np.zeros(3)
                p[axis] = sign
                p[u_axis] = a
                p[v_axis] = b
                corners.append(p * (hx, hy, hz))
            base = len(positions)
            positions += corners
            normals += [n] * 4
            # (u, v, n) is right-handed, so u→v turns counter-clockwise seen from +n.
            tri = [(0, 1, 2), (0, 2, 3)] if sign > 0 else [(0, 2, 1), (0, 3, 2)]
            triangles += [(base + i, base + j, base + k) for i, j, k in tri]
    return _mesh(positions, normals, triangles)


def _orthonormal(axis: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    helper = np.array([1.0, 0.0, 0.0]) if abs(axis[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    u = np.cross(axis, helper)
    u /= np.linalg.norm(u)
    return u, np.cross(axis, u)


def capsule(a: tuple[float, float, float], b: tuple[float, float, float], radius: float) -> Mesh:
    """A capsule from ``a`` to ``b`` (a sphere where they coincide): a cylinder and two
    hemispheres, smooth normals, a single vertex at each pole (no degenerate triangles)."""
    a_, b_ = np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64)
    axis = b_ - a_
    length = float(np.linalg.norm(axis))
    axis = axis / length if length > 1e-9 else np.array([0.0, 0.0, 1.0])
    u, v = _orthonormal(axis)
    # Latitude rings between the poles: the hemisphere at a up to its equator, then the one
    # at b from its equator (the cylinder is the band between the two; a sphere has one).
    lats = [(-math.pi / 2 + math.pi / 2 * i / RINGS, a_) for i in range(1, RINGS + 1)]
    lats += [(math.pi / 2 * i / RINGS, b_) for i in range(0 if length > 1e-9 else 1, RINGS)]
    positions, normals = [a_ - radius * axis], [-axis]
    for lat, centre in lats:
        for k in range(AROUND):
            lon = 2 * math.pi * k / AROUND
            n = math.cos(lat) * (math.cos(lon) * u + math.sin(lon) * v) + math.sin(lat) * axis
            positions.append(centre + radius * n)
            normals.append(n)
    positions.append(b_ + radius * axis)
    normals.append(axis)
    last = len(positions) - 1
    ring = lambda r, k: 1 + r * AROUND + k % AROUND  # noqa: E731
    triangles = [(0, ring(0, k + 1), ring(0, k)) for k in range(AROUND)]
    for r in range(len(lats) - 1):
        for k in range(AROUND):
            i0, i1, j0, j1 = ring(r, k), ring(r, k + 1), ring(r + 1, k), ring(r + 1, k + 1)
            triangles += [(i0, i1, j1), (i0, j1, j0)]
    triangles += [(ring(len(lats) - 1, k), ring(len(lats) - 1, k + 1), last) for k in range(AROUND)]
    return _mesh(positions, normals, triangles)


def sphere(radius: float) -> Mesh:
    return capsule((0.0, 0.0, 0.0), (0.0, 0.0, 0.0), radius)


def ground(half_extent: float, z: float = 0.0) -> Mesh:
    """A square of ``half_extent`` metres around the origin at height ``z``, facing +Z."""
    h = half_extent
    positions = [(-h, -h, z), (h, -h, z), (h, h, z), (-h, h, z)]
    return _mesh(positions, [(0.0, 0.0, 1.0)] * 4, [(0, 1, 2), (0, 2, 3)])
