"""Rotations on numpy arrays: quaternions are (w, x, y, z), MuJoCo's convention.

The one rotation module of the package: axis-angle and per-axis matrices, quaternions,
Euler angles (Rz·Ry·Rx built and decomposed), slerp, yaw and look-at. Pure functions,
vectorised over leading axes, shared by the skeleton's forward kinematics, the motion
engine, BVH import and export, the physics driver and the renderer.
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


def _axis_rot(angle: np.ndarray, i: int, j: int) -> np.ndarray:
    """Rotations by ``angle`` in the (i, j) plane, the third axis fixed: exact zeros and ones."""
    a = np.asarray(angle, dtype=np.float64)
    out = np.zeros((*a.shape, 3, 3))
    c, s = np.cos(a), np.sin(a)
    k = 3 - i - j
    out[..., k, k] = 1.0
    out[..., i, i] = c
    out[..., j, j] = c
    out[..., i, j] = -s
    out[..., j, i] = s
    return out


def rot_x(a: np.ndarray) -> np.ndarray:
    """Rotations about +X by angles a (…) → (…, 3, 3)."""
    return _axis_rot(a, 1, 2)


def rot_y(a: np.ndarray) -> np.ndarray:
    """Rotations about +Y by angles a (…) → (…, 3, 3)."""
    return _axis_rot(a, 2, 0)


def rot_z(a: np.ndarray) -> np.ndarray:
    """Rotations about +Z by angles a (…) → (…, 3, 3)."""
    return _axis_rot(a, 0, 1)


def euler_zyx_matrix(yaw: np.ndarray, pitch: np.ndarray, roll: np.ndarray) -> np.ndarray:
    """R = Rz(yaw) · Ry(pitch) · Rx(roll) (…, 3, 3): heading, then forward pitch (+ = nose down), roll."""
    return rot_z(yaw) @ rot_y(pitch) @ rot_x(roll)


def euler_quat(yaw: np.ndarray, pitch: np.ndarray, roll: np.ndarray) -> np.ndarray:
    """Quaternions (w, x, y, z) of Rz(yaw)·Ry(pitch)·Rx(roll), continuous in the angles."""
    hy, hp, hr = 0.5 * np.asarray(yaw), 0.5 * np.asarray(pitch), 0.5 * np.asarray(roll)
    cy, sy, cp, sp, cr, sr = np.cos(hy), np.sin(hy), np.cos(hp), np.sin(hp), np.cos(hr), np.sin(hr)
    return np.stack(
        [
            cy * cp * cr + sy * sp * sr,
            cy * cp * sr - sy * sp * cr,
            cy * sp * cr + sy * cp * sr,
            sy * cp * cr - cy * sp * sr,
        ],
        axis=-1,
    )


def euler_angles(r: np.ndarray, order: tuple[int, int, int]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Angles (a, b, c) with ``r = R_i(a) · R_j(b) · R_k(c)``, (i, j, k) = ``order``.

    The principal solution, |b| ≤ π/2; at gimbal lock c = 0. The axes are permuted onto
    X, Y, Z (with the last flipped for an odd order, keeping the permutation proper).
    """
    i, j, k = order
    eps = 1.0 if (j - i) % 3 == 1 else -1.0
    p = np.zeros((3, 3))
    p[0, i], p[1, j], p[2, k] = 1.0, 1.0, eps
    m = p @ r @ p.T  # = Rx(a) · Ry(b) · Rz(eps · c)
    cb = np.hypot(m[..., 0, 0], m[..., 0, 1])
    b = np.arctan2(m[..., 0, 2], cb)
    ok = cb > 1e-9
    a = np.where(ok, np.arctan2(-m[..., 1, 2], m[..., 2, 2]), np.arctan2(m[..., 2, 1], m[..., 1, 1]))
    c = np.where(ok, np.arctan2(-m[..., 0, 1], m[..., 0, 0]), 0.0)
    return a, b, eps * c


def continuous_quats(quat: np.ndarray) -> np.ndarray:
    """Quaternions (T, 4) with signs flipped so consecutive ones lie in the same hemisphere."""
    out = quat.copy()
    for t in range(1, len(out)):
        if np.dot(out[t], out[t - 1]) < 0:
            out[t] = -out[t]
    return out


def slerp(q0: np.ndarray, q1: np.ndarray, u: np.ndarray) -> np.ndarray:
    """Spherical interpolation from ``q0`` to ``q1`` (…, 4) at fractions ``u`` (…, 1), the short way, w ≥ 0."""
    dot = np.sum(q0 * q1, axis=-1, keepdims=True)
    q1 = np.where(dot < 0, -q1, q1)
    dot = np.abs(dot)
    theta = np.arccos(np.clip(dot, -1.0, 1.0))
    sin = np.sin(theta)
    small = sin < 1e-6
    safe = np.where(small, 1.0, sin)
    w0 = np.where(small, 1.0 - u, np.sin((1.0 - u) * theta) / safe)
    w1 = np.where(small, u, np.sin(u * theta) / safe)
    out = w0 * q0 + w1 * q1
    out /= np.linalg.norm(out, axis=-1, keepdims=True)
    return np.where(out[..., :1] < 0, -out, out)


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


def yaw_matrix(yaw: float | np.ndarray) -> np.ndarray:
    """Rotation about +Z (heading), in ``axis_angle_matrix``'s arithmetic.

    Not ``rot_z``: the two differ in the last bit (here the Z row is (1 − cos) + cos), and
    playback, placement and the physics were recorded with this one.
    """
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
