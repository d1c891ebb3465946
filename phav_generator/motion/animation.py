"""Kinematic animation: poses over time, motion playback, mirroring, blending and placement.

A motion is a function of motion time τ (seconds) returning a ``Pose`` in the *motion
frame*: the person starts at the origin facing +X, the root position is the pelvis offset
from its standing height, and lengths are those of a 1.75 m person (``REFERENCE_HEIGHT_M``).
``animate`` plays a motion back for a recipe: from ``start_s`` at ``speed``, wrapping to the
start when it runs out (MotionSpec's contract) while carrying the root's displacement and
heading over, so a walk keeps walking; then mirrored for handedness and scaled to the human
by leg length (``motion_scale``).
Playback takes the ``MotionDef`` itself; ``library.get_motion`` finds one by name.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from phav_generator.motion.keyframes import hermite
from phav_generator.motion.reference import ANKLE_H, PELVIS_H
from phav_generator.motion.rotations import matrix_to_quat, quat_to_matrix, yaw_matrix
from phav_generator.motion.skeleton import BONE_INDEX, DOF_BODY, N_DOFS, BodyDims, clamp_to_limits, mirror_dofs
from phav_spec.seeding import stream


@dataclass(frozen=True)
class Pose:
    """Poses over T samples: pelvis position (T, 3), pelvis orientation (T, 4), angles (T, 30)."""

    root_pos: np.ndarray
    root_quat: np.ndarray
    q: np.ndarray

    def __post_init__(self) -> None:
        n = self.root_pos.shape[0]
        if self.root_pos.shape != (n, 3) or self.root_quat.shape != (n, 4) or self.q.shape != (n, N_DOFS):
            raise ValueError(
                f"pose arrays disagree: root_pos {self.root_pos.shape}, "
                f"root_quat {self.root_quat.shape}, q {self.q.shape}"
            )

    def __len__(self) -> int:
        return self.root_pos.shape[0]

    def take(self, index: np.ndarray | slice) -> Pose:
        """The samples at ``index`` (an index array, mask or slice)."""
        return Pose(self.root_pos[index], self.root_quat[index], self.q[index])


@dataclass(frozen=True)
class MotionParams:
    """How one recipe plays a motion, so two recipes of the same motion differ.

    ``amplitude`` scales every joint excursion around the motion's own neutral pose,
    ``phase`` shifts cyclic parts by a fraction of their cycle, ``style`` ∈ [−1, 1] is a
    motion-specific knob (arm swing, crouch, torso lean …) documented by each motion.
    Speed, start and mirroring come from the recipe's MotionSpec; the rest from the
    recipe's physics seed (``motion_params``).
    """

    speed: float = 1.0
    amplitude: float = 1.0
    phase: float = 0.0
    style: float = 0.0
    mirror: bool = False


#: A motion: (τ seconds (T,), params) → Pose in the motion frame, reference height.
MotionFn = Callable[[np.ndarray, MotionParams], Pose]
#: A motion's pelvis yaw about the way it faces (rad) at τ seconds (T,): a gait's swing.
SwingFn = Callable[[np.ndarray, MotionParams], np.ndarray]


@dataclass(frozen=True)
class MotionDef:
    """A playable motion: its function and natural length (equal to the catalogue's)."""

    name: str
    length_s: float
    fn: MotionFn
    description: str = ""
    #: Friction of the feet on the floor: 1 for shoes; a gait whose stance foot slides
    #: (the moonwalk) needs smooth soles, or friction holds the foot back.
    sole_friction: float = 1.0
    #: A stairs motion's own flight (``gait.STAIR_*`` geometry): +1 up, −1 down,
    #: 0 for none. The physics builds exactly those treads under the feet.
    stairs: int = 0
    #: The pelvis's yaw about the way the motion faces (a gait's swing from step to step);
    #: None where the pelvis faces that way (``anchor`` turns the clip by what it faces).
    swing: SwingFn | None = None


def _yaw_of(quat: np.ndarray) -> np.ndarray:
    m = quat_to_matrix(quat)
    return np.arctan2(m[..., 1, 0], m[..., 0, 0])


def play(motion: MotionDef, clip_times: np.ndarray, start_s: float, params: MotionParams) -> Pose:
    """Sample ``motion`` at clip times (s): τ = start + speed·t, wrapped with root carry-over.

    When τ passes the motion's length, playback restarts at τ − k·length and the root's
    planar displacement and heading at the end of each completed pass are carried over,
    so cyclic motions continue seamlessly and one-shot motions repeat from where they are.
    """
    length = motion.length_s
    tau = start_s + params.speed * np.asarray(clip_times, dtype=np.float64)
    laps = np.floor(tau / length)
    local = tau - laps * length
    pose = motion.fn(local, params)
    if not np.any(laps > 0):
        return pose
    ends = motion.fn(np.array([0.0, length]), params)
    d_yaw = float(_yaw_of(ends.root_quat[1]) - _yaw_of(ends.root_quat[0]))
    # A lap turned by d_yaw starts where the last ended: its start, turned, lands on the end.
    d_pos = ends.root_pos[1] - yaw_matrix(d_yaw) @ ends.root_pos[0]
    d_pos[2] = 0.0
    root_pos = pose.root_pos.copy()
    root_rot = quat_to_matrix(pose.root_quat)
    for k in np.unique(laps[laps > 0]).astype(int):
        sel = laps == k
        # Compose k laps: each lap rotates by d_yaw and translates by the lap displacement.
        offset = np.zeros(3)
        yaw = 0.0
        for _ in range(k):
            offset = offset + yaw_matrix(yaw) @ d_pos
            yaw += d_yaw
        r = yaw_matrix(yaw)
        root_pos[sel] = offset + root_pos[sel] @ r.T
        root_rot[sel] = r @ root_rot[sel]
    return Pose(root_pos, matrix_to_quat(root_rot), pose.q)


def mirror(pose: Pose) -> Pose:
    """The mirror image of a pose across the person's sagittal plane (y → −y)."""
    m = np.diag([1.0, -1.0, 1.0])
    root_pos = pose.root_pos * np.array([1.0, -1.0, 1.0])
    rot = m @ quat_to_matrix(pose.root_quat) @ m
    return Pose(root_pos, matrix_to_quat(rot), mirror_dofs(pose.q))


def muscle_dof_mask(muscles: tuple[str, ...] | list[str]) -> np.ndarray:
    """Boolean mask over the 30 DOFs: those that move any of ``muscles``."""
    bodies = [BONE_INDEX[m] for m in muscles]
    return np.isin(DOF_BODY, bodies)


def blend(base: Pose, other: Pose, muscles: tuple[str, ...] | list[str], weight: float | np.ndarray) -> Pose:
    """Action blending: the DOFs of ``muscles`` follow ``other`` with ``weight`` (one value or
    one per sample); root from base."""
    mask = muscle_dof_mask(muscles)
    w = np.asarray(weight, dtype=np.float64)
    w = w[:, None] if w.ndim == 1 else w
    q = base.q.copy()
    q[:, mask] = (1.0 - w) * base.q[:, mask] + w * other.q[:, mask]
    return Pose(base.root_pos, base.root_quat, q)


def anchor(pose: Pose, swing: float = 0.0) -> Pose:
    """The pose re-expressed so its first sample stands at the motion frame's origin facing
    +X (planar position and yaw; height and joints unchanged). A clip that starts part-way
    into a motion then starts where the recipe puts the person, facing its heading, instead
    of wherever the motion had travelled by then. ``swing`` (rad) is the first sample's
    pelvis yaw about the way it faces (``swing_at``): a walk goes along the heading, not
    off it by where in its stride the clip starts."""
    undo = yaw_matrix(-(float(_yaw_of(pose.root_quat[0])) - swing))
    offset = pose.root_pos[0] * np.array([1.0, 1.0, 0.0])
    root_pos = (pose.root_pos - offset) @ undo.T
    root_rot = undo @ quat_to_matrix(pose.root_quat)
    return Pose(root_pos, matrix_to_quat(root_rot), pose.q)


def swing_at(motion: MotionDef, t: float, start_s: float, params: MotionParams) -> float:
    """The played pelvis's yaw about the way the motion faces (rad) at clip time ``t``
    (``MotionDef.swing`` where ``play`` samples it, the other way when mirrored); 0 for a
    motion whose pelvis faces its way."""
    if motion.swing is None:
        return 0.0
    tau = start_s + params.speed * t
    local = tau - math.floor(tau / motion.length_s) * motion.length_s
    s = float(motion.swing(np.array([local]), params)[0])
    return -s if params.mirror else s


def motion_scale(dims: BodyDims) -> float:
    """How much a motion's root travel scales for a body: by leg length (standing pelvis
    height), so that feet keep their steps on a child or a long-legged adult alike."""
    return (dims.standing_pelvis_height - dims.sole_height) / (PELVIS_H - ANKLE_H)


def place(pose: Pose, dims: BodyDims, position: tuple[float, float, float], heading_deg: float) -> Pose:
    """Motion frame → world: scale to the human, stand on ``position``, face ``heading_deg``."""
    scale = motion_scale(dims)
    r = yaw_matrix(np.deg2rad(heading_deg))
    local = pose.root_pos * scale + np.array([0.0, 0.0, dims.standing_pelvis_height])
    root_pos = local @ r.T + np.asarray(position, dtype=np.float64)
    root_rot = r @ quat_to_matrix(pose.root_quat)
    return Pose(root_pos, matrix_to_quat(root_rot), clamp_to_limits(pose.q))


@dataclass(frozen=True)
class Placement:
    """How ``animate`` maps one clip's motion frame to the world: ``anchor`` removes the
    planar position ``origin`` and facing ``yaw0`` of the clip's first sample, ``place`` scales
    by ``scale`` and turns to ``heading_rad`` about ``position``."""

    origin: np.ndarray  # (3,), z = 0
    yaw0: float
    scale: float
    heading_rad: float
    position: np.ndarray  # (3,)

    @property
    def _turn(self) -> np.ndarray:
        return yaw_matrix(self.heading_rad - self.yaw0)

    def to_world(self, points: np.ndarray) -> np.ndarray:
        """Motion-frame ground points (…, 3) (z: height above the motion's floor) → world."""
        return (np.asarray(points, dtype=np.float64) - self.origin) @ self._turn.T * self.scale + self.position

    def to_motion(self, points: np.ndarray) -> np.ndarray:
        """The inverse of ``to_world``."""
        return (np.asarray(points, dtype=np.float64) - self.position) / self.scale @ self._turn + self.origin


def placement(
    motion: MotionDef,
    start_s: float,
    params: MotionParams,
    dims: BodyDims,
    position: tuple[float, float, float],
    heading_deg: float,
) -> Placement:
    """The motion-frame → world map of the clip ``animate`` makes with the same arguments."""
    pose = play(motion, np.zeros(1), start_s, params)
    if params.mirror:
        pose = mirror(pose)
    origin = pose.root_pos[0] * np.array([1.0, 1.0, 0.0])
    yaw0 = float(_yaw_of(pose.root_quat[0])) - swing_at(motion, 0.0, start_s, params)
    heading = float(np.deg2rad(heading_deg))
    return Placement(origin, yaw0, motion_scale(dims), heading, np.asarray(position, dtype=np.float64))


def motion_params(speed: float, mirror_motion: bool, seed: int, role: str = "protagonist") -> MotionParams:
    """Amplitude, phase and style drawn from a recipe seed, for one person (``role``)."""
    rng = stream(seed, f"motion/{role}")
    amplitude = 0.85 + 0.3 * rng.random()
    phase = rng.random()
    style = 2.0 * rng.random() - 1.0
    return MotionParams(speed=speed, amplitude=amplitude, phase=phase, style=style, mirror=mirror_motion)


def animate(
    motion: MotionDef,
    clip_times: np.ndarray,
    start_s: float,
    params: MotionParams,
    dims: BodyDims,
    position: tuple[float, float, float],
    heading_deg: float,
) -> Pose:
    """A motion played for a clip and placed in the world: the pins' and servos' targets.

    The clip's first frame stands on ``position`` facing ``heading_deg`` (``anchor``),
    wherever in the motion ``start_s`` falls."""
    pose = play(motion, clip_times, start_s, params)
    if params.mirror:
        pose = mirror(pose)
    swing = swing_at(motion, float(np.asarray(clip_times, dtype=np.float64).reshape(-1)[0]), start_s, params)
    return place(anchor(pose, swing), dims, position, heading_deg)


#: Physics targets are the animation convolved with a Gaussian of this width (s). Procedural
#: curves have corners (a running foot lands at speed, a joint clamped at its limit stops
#: dead) that servos could follow only with an infinite torque, and each timestep resolved
#: a corner differently (1 cm apart at a running foot strike). 5 ms is about the time a
#: heel strike takes to stop the foot, and a sixth of a frame.
TARGET_SMOOTHING_S = 0.005
#: The fixed grid (Hz) the animation is sampled and smoothed on, so the smoothed targets are
#: the same function of time whatever the physics timestep.
TARGET_GRID_HZ = 240


def _odd_pad(y: np.ndarray, n: int) -> np.ndarray:
    """``y`` extended by ``n`` samples at both ends, point-reflected through the end values:
    a linear trend continues, so smoothing does not slow a moving root near the clip's ends."""
    n = min(n, len(y) - 1)
    if n <= 0:
        return y
    head = 2.0 * y[0] - y[n:0:-1]
    tail = 2.0 * y[-1] - y[-2 : -n - 2 : -1]
    return np.concatenate([head, y, tail])


def gaussian_smooth(y: np.ndarray, sigma_samples: float) -> np.ndarray:
    """Each column of ``y`` (T, C) convolved with a normalised Gaussian truncated at 4σ
    (ends extended by point reflection)."""
    n = math.ceil(4.0 * sigma_samples)
    if n == 0 or len(y) < 2:
        return y.copy()
    kernel = np.exp(-0.5 * (np.arange(-n, n + 1) / sigma_samples) ** 2)
    kernel /= kernel.sum()
    padded = _odd_pad(y, n)
    short = n - (len(padded) - len(y)) // 2  # a series shorter than the kernel: hold its ends
    if short > 0:
        padded = np.pad(padded, ((short, short), (0, 0)), mode="edge")
    out = np.empty_like(y)
    for c in range(y.shape[1]):
        out[:, c] = np.convolve(padded[:, c], kernel, mode="valid")
    return out


def _cubic_at(grid: np.ndarray, y: np.ndarray, times: np.ndarray) -> np.ndarray:
    """C1 cubic Hermite interpolation of samples ``y`` on a uniform ``grid`` (≥ 2 samples) at
    ``times``, with central-difference slopes."""
    slopes = np.gradient(y, grid, axis=0)
    return hermite(grid, y, slopes, times)


def _continuous_signs(quat: np.ndarray) -> np.ndarray:
    """Quaternions (T, 4) with each sample's sign flipped to agree with the one before it
    (q and −q are one rotation), so interpolating between them takes the short way."""
    quat = quat.copy()
    flips = np.sign(np.einsum("ij,ij->i", quat[1:], quat[:-1]))
    quat[1:] *= np.cumprod(np.where(flips == 0, 1.0, flips))[:, None]
    return quat


def resample(pose: Pose, times: np.ndarray, at: np.ndarray) -> Pose:
    """``pose``, sampled at the uniform ``times``, at the times ``at`` (within them): the
    same C1 cubics as ``smooth_targets``, so a pose played back at another clock stays as
    smooth as it was."""
    quat_t = _cubic_at(times, _continuous_signs(pose.root_quat), at)
    quat_t /= np.linalg.norm(quat_t, axis=1, keepdims=True)
    return Pose(_cubic_at(times, pose.root_pos, at), quat_t, clamp_to_limits(_cubic_at(times, pose.q, at)))


def smooth_targets(
    pose_at: Callable[[np.ndarray], Pose],
    times: np.ndarray,
    *,
    sigma_s: float = TARGET_SMOOTHING_S,
    grid_hz: int = TARGET_GRID_HZ,
) -> Pose:
    """The pose ``pose_at`` gives, smoothed over ``sigma_s`` and sampled at ``times`` (s, from 0).

    The animation is sampled on a fixed grid from ``times[0]`` to past ``times[-1]``,
    convolved with a Gaussian and interpolated with C1 cubics, so the result is one smooth
    function of time (continuous velocities) whatever the sampling of ``times``.
    """
    times = np.asarray(times, dtype=np.float64)
    t0 = float(times[0])
    count = max(1, math.ceil((float(times[-1]) - t0) * grid_hz - 1e-9))
    grid = t0 + np.arange(count + 1) / grid_hz
    pose = pose_at(grid)
    sigma = sigma_s * grid_hz
    q = gaussian_smooth(pose.q, sigma)
    root_pos = gaussian_smooth(pose.root_pos, sigma)
    # Quaternions: make consecutive samples agree in sign, smooth, renormalise.
    quat = gaussian_smooth(_continuous_signs(pose.root_quat), sigma)
    q_t = clamp_to_limits(_cubic_at(grid, q, times))
    pos_t = _cubic_at(grid, root_pos, times)
    quat_t = _cubic_at(grid, quat, times)
    quat_t /= np.linalg.norm(quat_t, axis=1, keepdims=True)
    return Pose(pos_t, quat_t, q_t)


def identity_quats(n: int) -> np.ndarray:
    """(n, 4) identity quaternions."""
    out = np.zeros((n, 4))
    out[:, 0] = 1.0
    return out


def rest_pose(n: int) -> Pose:
    """Standing still at the origin for n samples."""
    return Pose(np.zeros((n, 3)), identity_quats(n), np.zeros((n, N_DOFS)))
