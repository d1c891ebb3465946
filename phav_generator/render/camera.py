"""Pinhole cameras as OpenGL matrices, with the metadata contract's pixel convention.

The camera looks down its −Z axis, +Y up, +X right; pixel (u, v) has its centre at
(u + 0.5, v + 0.5) with v growing downwards, so a camera-space point (X, Y, Z) lands at
u + 0.5 = cx + fx·X/(−Z), v + 0.5 = cy − fy·Y/(−Z).
"""

from __future__ import annotations

import numpy as np

#: Near and far clipping planes, metres: depth is encoded up to 655.35 m (sky beyond).
NEAR_M = 0.05
FAR_M = 2000.0


def projection(fx: float, fy: float, cx: float, cy: float, width: int, height: int) -> np.ndarray:
    """OpenGL projection (4, 4) whose window coordinates follow the pixel convention.

    Window x = cx + fx·X/(−Z); window y (GL, upwards) = height − (cy − fy·Y/(−Z)), so row
    ``height − 1 − v`` of the framebuffer is image row v.
    """
    n, f = NEAR_M, FAR_M
    p = np.zeros((4, 4))
    p[0, 0] = 2.0 * fx / width
    p[0, 2] = 1.0 - 2.0 * cx / width
    p[1, 1] = 2.0 * fy / height
    p[1, 2] = 2.0 * cy / height - 1.0
    p[2, 2] = -(f + n) / (f - n)
    p[2, 3] = -2.0 * f * n / (f - n)
    p[3, 2] = -1.0
    return p


def view(cam_to_world: np.ndarray) -> np.ndarray:
    """World → camera (4, 4) from a rigid camera-to-world pose."""
    r = cam_to_world[:3, :3]
    out = np.eye(4)
    out[:3, :3] = r.T
    out[:3, 3] = -r.T @ cam_to_world[:3, 3]
    return out


def project(
    points: np.ndarray,
    cam_to_world: np.ndarray,
    intrinsics: tuple[float, float, float, float],
    *,
    min_depth: float = 1e-9,
) -> np.ndarray:
    """Pixel coordinates (..., 2) as (u + 0.5, v + 0.5) of world points (..., 3), and NaN
    where a point is not at least ``min_depth`` in front of the camera."""
    fx, fy, cx, cy = intrinsics
    v = view(cam_to_world)
    px, py, pz = np.moveaxis(np.asarray(points, dtype=float), -1, 0)
    # Written out rather than ``points @ R.T``: a (N, 3) @ (3, 3) product is slow in BLAS
    # and its rounding may differ between BLAS builds; this is the same on every machine.
    x, y, z = (r[0] * px + r[1] * py + r[2] * pz + t for r, t in zip(v[:3, :3], v[:3, 3], strict=True))
    z = -z
    with np.errstate(divide="ignore", invalid="ignore"):
        out = np.stack([cx + fx * x / z, cy - fy * y / z], axis=-1)
    out[z <= min_depth] = np.nan
    return out
