"""Playback and placement of motions (a clip starting part-way into a motion stands where the
recipe puts it) and the smoothing of the physics targets."""

from __future__ import annotations

import numpy as np
import pytest

from phav_generator.motion.animation import (
    MotionParams,
    Pose,
    animate,
    gaussian_smooth,
    play,
    smooth_targets,
    swing_at,
)
from phav_generator.motion.library import get_motion
from phav_generator.motion.reference import REFERENCE_HEIGHT_M
from phav_generator.motion.rotations import quat_to_matrix
from phav_generator.motion.skeleton import DOF_INDEX, LOWER, UPPER, body_dims, clamp_to_limits

REF = body_dims(1.75, 70.0, 0.40, 0.34, 1.0)


@pytest.mark.parametrize("name", ["walk_forward_01", "run_away_panic_01", "walk_circle_01"])
def test_a_clip_starting_part_way_into_a_motion_starts_where_the_recipe_puts_it(name):
    """Started seconds into a travelling motion, the clip's first frame still stands on the
    recipe's position facing its heading (its pelvis turned by the gait's swing), and then
    moves as the motion does from there."""
    motion = get_motion(name)
    dims = REF
    times = np.arange(31) / 30.0
    params = MotionParams(speed=1.0, amplitude=1.0, phase=0.0, style=0.0, mirror=False)
    start = 0.6 * motion.length_s
    placed = animate(motion, times, start, params, dims, (4.0, -2.0, 0.5), 30.0)
    np.testing.assert_allclose(placed.root_pos[0, :2], (4.0, -2.0), atol=1e-9)
    m = quat_to_matrix(placed.root_quat[0])
    swing = np.degrees(swing_at(motion, 0.0, start, params))
    assert np.degrees(np.arctan2(m[1, 0], m[0, 0])) == pytest.approx(30.0 + swing, abs=1e-6)
    # The path from there is the motion's own, rigidly moved: distances along it are kept.
    raw = play(motion, times, start, params).root_pos * (1.75 / REFERENCE_HEIGHT_M)
    np.testing.assert_allclose(np.linalg.norm(np.diff(placed.root_pos[:, :2], axis=0), axis=1),
                               np.linalg.norm(np.diff(raw[:, :2], axis=0), axis=1), atol=1e-9)  # fmt: skip
    assert np.linalg.norm(raw[0, :2]) > 0.5  # the motion had travelled: the anchoring mattered


@pytest.mark.parametrize("name", ["walk_forward_01", "run_away_panic_01", "walk_hand_in_hand_01"])
def test_a_walk_goes_along_its_heading_wherever_in_its_stride_the_clip_starts(name):
    """The clip is turned by the way the motion faces, not by its pelvis's yaw at the first
    frame, which swings ±5° from step to step: taken as the heading, that sent a walk up to
    6° off it (two people walking hand in hand into each other)."""
    motion = get_motion(name)
    times = np.arange(121) / 30.0
    off = []
    for start in np.linspace(0.05, 0.95, 10) * motion.length_s:
        for mirror in (False, True):
            params = MotionParams(speed=1.0, amplitude=1.1, phase=0.3, style=0.2, mirror=mirror)
            placed = animate(motion, times, start, params, REF, (0.0, 0.0, 0.0), 30.0)
            way = placed.root_pos[-1, :2] - placed.root_pos[0, :2]
            off.append(abs(np.degrees(np.arctan2(way[1], way[0])) - 30.0))
    assert max(off) < 0.5, off


def test_a_turning_motion_continues_where_its_last_lap_ended():
    """Played past its end, a motion that turns as it goes starts its next lap where and as
    the last ended: no step in the root at the wrap."""
    motion = get_motion("walk_forward_turn_left_01")
    params = MotionParams(speed=1.0)
    wrap = motion.length_s
    at = np.array([wrap - 1e-4, wrap + 1e-4, 2 * wrap - 1e-4, 2 * wrap + 1e-4])
    pose = play(motion, at, 0.0, params)
    speed = np.linalg.norm(np.diff(play(motion, np.array([0.5, 0.5 + 1e-3]), 0.0, params).root_pos[:, :2], axis=0))
    for k in (0, 2):
        assert np.linalg.norm(pose.root_pos[k + 1, :2] - pose.root_pos[k, :2]) < 10 * speed * 0.2


KNEE = DOF_INDEX["right_knee_flex"]


def _kinked_pose(t: np.ndarray) -> Pose:
    """A knee that stops dead at t = 0.3125 s (the corner of a running foot strike) on a root
    walking at a constant 1.4 m/s, turning at a constant rate."""
    q = np.zeros((len(t), 30))
    q[:, KNEE] = 0.3 + 6.0 * np.minimum(t, 0.3125)
    root = np.stack([1.4 * t, 0.2 * t, np.full_like(t, 0.95)], axis=1)
    half = 0.25 * t  # yaw 0.5 rad/s
    quat = np.stack([np.cos(half), 0 * t, 0 * t, np.sin(half)], axis=1)
    return Pose(root, quat, clamp_to_limits(q))


def test_smoothed_targets_are_one_function_of_time_whatever_the_timestep() -> None:
    """The physics targets at 1/240 s are the 1/1920 s targets at the shared instants, so the
    rates integrate the same motion; the corner becomes a continuous velocity."""
    coarse_t = np.arange(241) / 240.0
    fine_t = np.arange(1921) / 1920.0
    coarse = smooth_targets(_kinked_pose, coarse_t)
    fine = smooth_targets(_kinked_pose, fine_t)
    np.testing.assert_allclose(coarse.q, fine.q[::8], atol=1e-12)
    np.testing.assert_allclose(coarse.root_pos, fine.root_pos[::8], atol=1e-12)
    velocity = np.diff(fine.q[:, KNEE]) * 1920.0
    raw = np.diff(_kinked_pose(fine_t).q[:, KNEE]) * 1920.0
    assert np.abs(np.diff(raw)).max() > 5.0  # the raw knee stops within one step
    # Smoothed: the 6 rad/s stop spreads over the Gaussian, whose steepest step is
    # 6 / (σ √(2π)) / 1920 = 0.25 rad/s (0.31 through the C1 cubics on the 240 Hz grid).
    assert np.abs(np.diff(velocity)).max() < 0.35
    far = np.abs(fine_t[1:] - 0.3125) > 0.03  # the 4σ kernel plus the cubics' neighbours
    np.testing.assert_allclose(velocity[far], raw[far], atol=1e-6)  # away from the corner: unchanged


def test_smoothing_keeps_a_steady_root_steady_up_to_the_clip_ends() -> None:
    """Point reflection at the ends continues a constant velocity, so a walking root is not
    slowed in its first or last frames, and its heading stays a unit quaternion."""
    t = np.arange(31) / 30.0
    pose = smooth_targets(_kinked_pose, t)
    np.testing.assert_allclose(pose.root_pos, _kinked_pose(t).root_pos, atol=1e-9)
    np.testing.assert_allclose(np.linalg.norm(pose.root_quat, axis=1), 1.0, atol=1e-12)
    np.testing.assert_allclose(np.abs(pose.root_quat), np.abs(_kinked_pose(t).root_quat), atol=1e-5)
    assert np.all(pose.q >= LOWER - 1e-12) and np.all(pose.q <= UPPER + 1e-12)


def test_smoothing_a_series_shorter_than_its_kernel_keeps_its_length_and_values() -> None:
    """Series shorter than the kernel (a one-frame clip is 9 samples of the 240 Hz grid, the
    kernel 11) are smoothed too: the length is kept, a constant stays constant, values stay
    within their range; from the kernel's half width (4σ) plus one sample on, a line survives."""
    for n in (1, 2, 3, 6, 11):
        y = np.column_stack([np.full(n, 0.4), np.linspace(0.0, 1.0, n)])
        out = gaussian_smooth(y, 2.4)
        assert out.shape == y.shape
        np.testing.assert_allclose(out[:, 0], 0.4, atol=1e-12)
        assert np.all((out[:, 1] >= -1e-12) & (out[:, 1] <= 1.0 + 1e-12))
        if n >= 11:
            np.testing.assert_allclose(out[:, 1], y[:, 1], atol=1e-12)  # point reflection continues a line
