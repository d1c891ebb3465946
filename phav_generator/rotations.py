"""Rotation helpers on numpy arrays: quaternions are (w, x, y, z), MuJoCo's convention.

Pure functions, vectorised over leading axes, shared by the skeleton's forward kinematics,
the motion library, the physics driver and the preview.
"""

from __future__ import annotations

import numpy as np


def axis_angle_matrix(axis: np.ndarray, angle: np.ndarray) -> np.ndarray:
    """Rotation matrices for a fixed unit ``axis`` (3,) and angles of any shape: (..., 3, 3)."""
    x, y, z = (float(v) for v in axis)
    c = np.cos(angle)
    s = np.sin(angle)
    t = 1.0 - c
    out = np.empty((*np.shape(angle), 3, 3))
    out[..., 0, 0] = t * x * x + c
    out[..., 0, 1] = t * x * y - s * z
    out[..., 0, 2] = t * x * z + s * y
    out[..., 1, 0] = t * x * y + s * z
    out[..., 1, 1] = t * y * y + c
    out[..., 1, 2] = t * y * z - s * x
    out[..., 2, 0] = t * x * z - s * y
    out[..., 2, 1] = t * y * z + s * x
    out[..., 2, 2] = t * z * z + c
    return out


def quat_to_matrix(q: np.ndarray) -> np.ndarray:
    """(…, 4) unit quaternions (w, x, y, z) → (…, 3, 3) rotation matrices."""
    q = np.asarray(q, dtype=np.float64)
    w, x, y, z = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
    out = np.empty((*q.shape[:-1], 3, 3))
    out[..., 0, 0] = 1 - 2 * (y * y + z * z)
    out[..., 0, 1] = 2 * (x * y - w * z)
    out[..., 0, 2] = 2 * (x * z + w * y)
    out[..., 1, 0] = 2 * (x * y + w * z)
    out[..., 1, 1] = 1 - 2 * (x * x + z * z)
    out[..., 1, 2] = 2 * (y * z - w * x)
    out[..., 2, 0] = 2 * (x * z - w * y)
    out[..., 2, 1] = 2 * (y * z + w * x)
    out[..., 2, 2] = 1 - 2 * (x * x + y * y)
    return out


def matrix_to_quat(m: np.ndarray) -> np.ndarray:
    """(…, 3, 3) rotation matrices → (…, 4) unit quaternions with w ≥ 0."""
    m = np.asarray(m, dtype=np.float64)
    flat = m.reshape(-1, 3, 3)
    out = np.empty((flat.shape[0], 4))
    for i, r in enumerate(flat):
        trace = r[0, 0] + r[1, 1] + r[2, 2]
        if trace > 0:
            s = 2.0 * np.sqrt(trace + 1.0)
            q = (0.25 * s, (r[2, 1] - r[1, 2]) / s, (r[0, 2] - r[2, 0]) / s, (r[1, 0] - r[0, 1]) / s)
        elif r[0, 0] > r[1, 1] and r[0, 0] > r[2, 2]:
            s = 2.0 * np.sqrt(1.0 + r[0, 0] - r[1, 1] - r[2, 2])
            q = ((r[2, 1] - r[1, 2]) / s, 0.25 * s, (r[0, 1] + r[1, 0]) / s, (r[0, 2] + r[2, 0]) / s)
        elif r[1, 1] > r[2, 2]:
            s = 2.0 * np.sqrt(1.0 + r[1, 1] - r[0, 0] - r[2, 2])
            q = ((r[0, 2] - r[2, 0]) / s, (r[0, 1] + r[1, 0]) / s, 0.25 * s, (r[1, 2] + r[2, 1]) / s)
        else:
            s = 2.0 * np.sqrt(1.0 + r[2, 2] - r[0, 0] - r[1, 1])
            q = ((r[1, 0] - r[0, 1]) / s, (r[0, 2] + r[2, 0]) / s, (r[1, 2] + r[2, 1]) / s, 0.25 * s)
        out[i] = q
    out /= np.linalg.norm(out, axis=1, keepdims=True)
    out[out[:, 0] < 0] *= -1.0
    return out.reshape(*m.shape[:-2], 4)


def relative_rotation_vectors(qa: np.ndarray, qb: np.ndarray) -> np.ndarray:
    """Rotation vectors (..., 3) of qa⁻¹·qb: the turn from frame a to frame b, in a's axes.

    Shortest way round (the relative quaternion's sign is chosen with w ≥ 0).
    """
    wa, va = qa[..., :1], qa[..., 1:]
    wb, vb = qb[..., :1], qb[..., 1:]
    w = wa * wb + np.sum(va * vb, axis=-1, keepdims=True)
    v = wa * vb - wb * va - np.cross(va, vb)
    sign = np.where(w < 0.0, -1.0, 1.0)
    w, v = w * sign, v * sign
    s = np.linalg.norm(v, axis=-1, keepdims=True)
    angle = 2.0 * np.arctan2(s, w)
    # angle / s tends to 2 / w as the turn vanishes.
    scale = np.where(s > 1e-12, angle / np.maximum(s, 1e-300), 2.0 / np.maximum(w, 1e-300))
    return v * scale


def euler_zyx_matrix(yaw: np.ndarray, pitch: np.ndarray, roll: np.ndarray) -> np.ndarray:
    """R = Rz(yaw) · Ry(pitch) · Rx(roll): heading, then forward pitch (+ = nose down), roll."""
    z = np.array([0.0, 0.0, 1.0])
    y = np.array([0.0, 1.0, 0.0])
    x = np.array([1.0, 0.0, 0.0])
    return axis_angle_matrix(z, yaw) @ axis_angle_matrix(y, pitch) @ axis_angle_matrix(x, roll)


def yaw_matrix(yaw: float | np.ndarray) -> np.ndarray:
    """Rotation about +Z (heading)."""
    return axis_angle_matrix(np.array([0.0, 0.0, 1.0]), np.asarray(yaw, dtype=np.float64))


def look_at(eye: np.ndarray, target: np.ndarray, up: np.ndarray | None = None) -> np.ndarray:
    """Camera-to-world rotation (…, 3, 3) for an OpenGL camera at ``eye`` looking at ``target``.

    The camera looks down its −Z axis with +Y up (DESIGN.md). When the view direction is
    parallel to ``up`` (+Z by default), the world +X axis stands in for it, so the result
    is always a proper rotation.
    """
    eye = np.asarray(eye, dtype=np.float64)
    target = np.asarray(target, dtype=np.float64)
    forward = target - eye
    norm = np.linalg.norm(forward, axis=-1, keepdims=True)
    forward = np.where(norm > 1e-9, forward / np.maximum(norm, 1e-12), np.array([1.0, 0.0, 0.0]))
    up_vec = np.array([0.0, 0.0, 1.0]) if up is None else np.asarray(up, dtype=np.float64)
    right = np.cross(forward, up_vec)
    rnorm = np.linalg.norm(right, axis=-1, keepdims=True)
    alt = np.cross(forward, np.array([1.0, 0.0, 0.0]))
    right = np.where(rnorm > 1e-6, right, alt)
    right /= np.linalg.norm(right, axis=-1, keepdims=True)
    true_up = np.cross(right, forward)
    return np.stack([right, true_up, -forward], axis=-1)
