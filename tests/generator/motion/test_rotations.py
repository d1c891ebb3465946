"""Rotations: relative rotation vectors, and the one Rz·Ry·Rx as a matrix, a quaternion and
decomposed again."""

from __future__ import annotations

import numpy as np

from phav_generator.motion.rotations import (
    axis_angle_matrix,
    euler_angles,
    euler_quat,
    euler_zyx_matrix,
    matrix_to_quat,
    quat_to_matrix,
    relative_rotation_vectors,
    rot_z,
    slerp,
    yaw_matrix,
)


def test_relative_rotation_vectors_recover_known_turns() -> None:
    rng = np.random.default_rng(3)
    qa = rng.normal(size=(6, 4))
    qa /= np.linalg.norm(qa, axis=1, keepdims=True)
    axis = np.array([0.0, 0.6, 0.8])
    angles = np.array([0.3, 1e-9, 3.0, -0.5, 0.0, 2.5])
    qb = matrix_to_quat(quat_to_matrix(qa) @ axis_angle_matrix(axis, angles))
    expected = angles[:, None] * axis
    np.testing.assert_allclose(relative_rotation_vectors(qa, qb), expected, atol=1e-9)
    np.testing.assert_allclose(relative_rotation_vectors(qa, -qb), expected, atol=1e-9)  # q and −q: one turn


def test_euler_matrix_quaternion_and_decomposition_agree() -> None:
    """Rz(yaw)·Ry(pitch)·Rx(roll): the matrix, the quaternion's matrix and the axis-angle
    product are one rotation, and ``euler_angles`` recovers the angles (|pitch| < π/2)."""
    rng = np.random.default_rng(7)
    yaw, pitch, roll = rng.uniform(-3.0, 3.0, 50), rng.uniform(-1.5, 1.5, 50), rng.uniform(-3.0, 3.0, 50)
    m = euler_zyx_matrix(yaw, pitch, roll)
    np.testing.assert_allclose(quat_to_matrix(euler_quat(yaw, pitch, roll)), m, atol=1e-12)
    z, y, x = np.eye(3)[2], np.eye(3)[1], np.eye(3)[0]
    product = axis_angle_matrix(z, yaw) @ axis_angle_matrix(y, pitch) @ axis_angle_matrix(x, roll)
    np.testing.assert_allclose(product, m, atol=1e-12)
    a, b, c = euler_angles(m, (2, 1, 0))
    np.testing.assert_allclose(np.stack([a, b, c]), np.stack([yaw, pitch, roll]), atol=1e-9)
    np.testing.assert_allclose(yaw_matrix(yaw), rot_z(yaw), atol=1e-15)


def test_slerp_runs_the_short_way_between_its_ends() -> None:
    q0 = np.array([[1.0, 0.0, 0.0, 0.0]])
    q1 = -matrix_to_quat(rot_z(np.array([1.0])))  # the same turn, the far sign
    mid = slerp(q0, q1, np.array([[0.5]]))
    np.testing.assert_allclose(mid, matrix_to_quat(rot_z(np.array([0.5]))), atol=1e-12)
    np.testing.assert_allclose(slerp(q0, q1, np.array([[1.0]])), -q1, atol=1e-12)
