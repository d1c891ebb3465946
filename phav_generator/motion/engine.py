"""The channel engine: a motion written as data (``Spec``) → a motion function τ → Pose.

A motion is not a hand-written function but a row of data interpreted here:

* **Layers.** A locomotion generator (``gait.Gait``) writes the root path, the feet and the
  arm swing; keyframed postures (``Spec.keys``, monotone C1 cubics) override channels,
  optionally faded in and out over the gait (``Spec.blend``); periodic cycles (``Cycle``)
  and sine oscillators (``Osc``) add on top; a faint idle sway (breathing, head) adds life.
* **Solving.** Legs reach their foot targets by IK (``ik.leg_ik``), the pelvis is lowered
  where a target would be out of reach, postures on the floor are snapped to the ground by
  forward kinematics, arms reach wrist targets (``ik.arm_ik``), and a ground guard lifts
  the body wherever something would dip below the floor.

``MotionParams`` (``speed`` and ``mirror`` are applied by ``animation.play``/``mirror``):

* ``amplitude`` scales every cyclic component (oscillators, cycles, arm swing), gait stride
  (longer steps at a proportionally lower cadence: the motion keeps its speed), jump
  distance and weaving, and keyframed joint angles around the motion's starting posture;
  IK targets (bar, chair, floor, stair treads, the golf grip) stay where they are.
* ``phase`` shifts cyclic components — gait cycle, oscillators, cycles — by that fraction
  of their cycle (one-shot keyframe timing is left alone).
* ``style`` ∈ [−1, 1] is a per-family knob (``FAMILY_STYLE``): for gaits, carriage (arm swing
  width, elbow bend, forward lean); for standing gestures, stance (knee crouch and torso
  lean); for floor and transition postures, torso lean and head carriage; for cycles
  (jumps, hops, crawls, hangs), crouch/tuck depth.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

from phav_generator.motion.animation import MotionFn, MotionParams, Pose, SwingFn
from phav_generator.motion.channels import DEG, Channels, Posture, default, expand
from phav_generator.motion.gait import Gait, GaitOut, generate_gait, moonwalk, pivot_offset
from phav_generator.motion.ik import LegGoal, arm_ik, leg_ik
from phav_generator.motion.keyframes import Keys, fit_period, monotone_cubic, periodic_cubic, track
from phav_generator.motion.reference import (
    ANKLE_H,
    ARM_BODIES,
    CHEST_Z,
    HIP_Y,
    LEG,
    PELVIS_H,
    RADII,
    REF_BODY,
    SHOULDER,
)
from phav_generator.motion.rotations import euler_quat, euler_zyx_matrix, quat_to_matrix, rot_x, rot_y, rot_z
from phav_generator.motion.skeleton import DOF_INDEX, LOWER, N_DOFS, UPPER, capsule_points, forward_kinematics

#: Root channels a keyframe layer adds to the gait's instead of replacing them.
_ROOT_ADD = ("x", "y", "z", "yaw", "pitch", "roll")


@dataclass(frozen=True)
class Osc:
    """An additive sine on one channel: ``amp·sin(2π(t/period + offset + phase))``.

    The period is rounded so a whole number of cycles fits the motion (seamless loops);
    ``env`` (keys of time → weight) fades it in and out.
    """

    channel: str
    amp: float
    period: float
    offset: float = 0.0
    env: Keys | None = None


@dataclass(frozen=True)
class Cycle:
    """An additive periodic keyframe cycle: keys are (fraction of the cycle, channel offsets).

    ``period`` is in seconds (rounded to fit the motion) or, with ``sync``, in gait cycles:
    the cycle then follows the gait's phase (the pelvis dip of each hop, the arms of a jumping
    jack). ``env`` (keys of time → weight) fades it in and out.
    """

    period: float
    keys: tuple[tuple[float, Posture], ...]
    env: Keys | None = None
    sync: bool = False


@dataclass(frozen=True)
class Spec:
    """One motion as data: layers of channels and how to solve them."""

    family: str
    keys: tuple[tuple[float, Posture], ...] = ()
    blend: Keys | None = None  # weight of the keyframe layer over the gait layer
    cycles: tuple[Cycle, ...] = ()
    osc: tuple[Osc, ...] = ()
    gait: Gait | None = None
    hands: str = "chest"  # frame of hand targets: chest | heading
    style: Posture = field(default_factory=dict)  # channel offsets per unit of style
    cyclic: bool = False  # a loop: τ = 0 and τ = length match
    guard: bool = False  # lift the body wherever something would dip below the ground
    custom: str | None = None  # a generator for motions no layer describes (moonwalk)
    advance: float = 0.0  # constant forward root speed, m/s (crawls), scaled by amplitude
    rigid: tuple[str, ...] = ()  # keyframed channels amplitude leaves alone (arms holding one club)
    sole_friction: float = 1.0  # smooth soles for a sliding stance foot (moonwalk)


#: The style knob of each family, as channel offsets per unit of style (see module doc).
FAMILY_STYLE: Mapping[str, Posture] = {
    "gait": {},  # handled inside the gait: arm swing ×(1 + 0.35 s), elbows +12 s, lean +3 s
    "gesture": {"z": -0.035, "waist_flex": 5.0, "neck_flex": -3.0},
    "posture": {"waist_flex": 6.0, "neck_flex": 6.0},
    "cycle": {"z": -0.025, "hip_flex": 6.0, "knee_flex": 8.0},
}

#: Faint idle motion added to every motion (breathing sway, head), phase-shifted by params.
IDLE: tuple[Osc, ...] = (
    Osc("waist_lateral", 0.8, 5.3),
    Osc("waist_twist", 1.2, 6.1, 0.1),
    Osc("neck_twist", 3.0, 7.1, 0.3),
    Osc("neck_flex", 1.5, 4.3, 0.6),
    Osc("shoulder_abd", 1.0, 3.9, 0.2),
)


# --------------------------------------------------------------------------------------
# Layers: Spec → channels.


def _keyframe_layer(spec: Spec, ch: Channels, tau: np.ndarray, p: MotionParams) -> None:
    """Keyframed postures (joint angles scaled by amplitude around the first key): root
    channels add to the gait's, the others replace them, faded by ``spec.blend``."""
    times = np.array([t for t, _ in spec.keys])
    rows = [expand(post) for _, post in spec.keys]
    names = sorted({k for r in rows for k in r})
    vals = np.array([[r.get(k, default(k)) for k in names] for r in rows])
    for c, k in enumerate(names):
        if k in DOF_INDEX and k not in spec.rigid:
            vals[:, c] = vals[0, c] + p.amplitude * (vals[:, c] - vals[0, c])
    cur = monotone_cubic(times, vals, tau)
    w = None if spec.blend is None else np.clip(track(spec.blend, tau), 0.0, 1.0)
    for c, k in enumerate(names):
        if k in _ROOT_ADD:
            ch.add(k, cur[:, c] if w is None else w * cur[:, c])
        elif w is None:
            ch.set(k, cur[:, c])
        else:
            ch.set(k, ch[k] + w * (cur[:, c] - ch[k]))


def _cycle_layer(
    cyc: Cycle, ch: Channels, tau: np.ndarray, p: MotionParams, length: float, gait: GaitOut | None
) -> None:
    """An additive periodic cycle, on its own clock or the gait's phase (``sync``)."""
    rows = [expand(post) for _, post in cyc.keys]
    names = sorted({k for r in rows for k in r})
    vals = np.array([[r.get(k, 0.0) for k in names] for r in rows])
    if cyc.sync:
        u = gait.phase / cyc.period if gait is not None else tau / cyc.period
    else:
        u = tau / fit_period(cyc.period, length) + p.phase
    cur = periodic_cubic([f for f, _ in cyc.keys], vals, u) * p.amplitude
    if cyc.env is not None:
        cur = cur * track(cyc.env, tau)[:, None]
    for c, k in enumerate(names):
        ch.add(k, cur[:, c])


def _osc_layer(o: Osc, ch: Channels, tau: np.ndarray, p: MotionParams, length: float) -> None:
    """An additive sine on one channel (both sides for a shorthand)."""
    val = o.amp * p.amplitude * np.sin(2 * np.pi * (tau / fit_period(o.period, length) + o.offset + p.phase))
    if o.env is not None:
        val = val * track(o.env, tau)
    for k, side in expand({o.channel: 1.0}).items():  # each side with its sign (a shorthand mirrors the right)
        ch.add(k, val * side)


def layers(spec: Spec, tau: np.ndarray, p: MotionParams, length: float) -> tuple[Channels, GaitOut | None]:
    """Every channel of ``spec`` at motion times ``tau``, layer on layer, and the gait's feet."""
    ch = Channels(len(tau))
    gait = None
    if spec.gait is not None:
        gait = generate_gait(spec.gait, tau, p, length, spec.cyclic, ch)
    elif spec.custom == "moonwalk":
        gait = moonwalk(tau, p, length, ch)
    if spec.keys:
        _keyframe_layer(spec, ch, tau, p)
    for cyc in spec.cycles:
        _cycle_layer(cyc, ch, tau, p, length, gait)
    for o in spec.osc + IDLE:
        _osc_layer(o, ch, tau, p, length)
    if spec.advance:
        ch.add("x", spec.advance * p.amplitude * tau)
    for k, v in expand({**FAMILY_STYLE.get(spec.family, {}), **spec.style}).items():
        ch.add(k, p.style * v)
    return ch, gait


# --------------------------------------------------------------------------------------
# Solving: channels → Pose.


@dataclass(frozen=True)
class _Heading:
    """The path's heading frame at every sample: ``path`` (T, 4) and its yaw's cos and sin."""

    path: np.ndarray
    cy: np.ndarray
    sy: np.ndarray

    def turn(self, v: np.ndarray) -> np.ndarray:
        """Heading-frame vectors (T, 3) in the motion frame's axes."""
        return np.stack([self.cy * v[:, 0] - self.sy * v[:, 1], self.sy * v[:, 0] + self.cy * v[:, 1], v[:, 2]], 1)

    def point(self, v: np.ndarray) -> np.ndarray:
        """Heading-frame points (T, 3) (z above the ground under the path) in the motion frame."""
        path, cy, sy = self.path, self.cy, self.sy
        return np.stack(
            [path[:, 0] + cy * v[:, 0] - sy * v[:, 1], path[:, 1] + sy * v[:, 0] + cy * v[:, 1], path[:, 3] + v[:, 2]],
            1,
        )


def softmin(values: list[np.ndarray], temp: float = 0.005) -> np.ndarray:
    """A smooth minimum of equal-shaped arrays (log-sum-exp at temperature ``temp``)."""
    v = np.stack(values)
    m = v.min(axis=0)
    return m - temp * np.log(np.exp(-(v - m) / temp).sum(axis=0))


def body_lows(root: np.ndarray, quat: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Lowest surface height of every body (T, 15) for the reference body."""
    pos, rot = forward_kinematics(REF_BODY, root, quat, q)
    wa, wb = capsule_points(REF_BODY, pos, rot)
    return np.minimum(wa[..., 2], wb[..., 2]) - RADII


def _root(ch: Channels, hd: _Heading) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Pelvis position (T, 3) at standing height, yaw (T,), rotation (T, 3, 3) and quaternion (T, 4)."""
    path = hd.path
    yaw = path[:, 2] + ch["yaw"] * DEG
    pitch, roll = ch["pitch"] * DEG, ch["roll"] * DEG
    root = np.stack(
        [
            path[:, 0] + hd.cy * ch["x"] - hd.sy * ch["y"],
            path[:, 1] + hd.sy * ch["x"] + hd.cy * ch["y"],
            PELVIS_H + path[:, 3] + ch["z"],
        ],
        axis=1,
    )
    return root, yaw, euler_zyx_matrix(yaw, pitch, roll), euler_quat(yaw, pitch, roll)


def _direct_angles(ch: Channels) -> np.ndarray:
    """Joint angles (T, 30) the channels set directly, radians, inside the limits."""
    q = np.zeros((ch.n, N_DOFS))
    for name, i in DOF_INDEX.items():
        if name in ch:
            q[:, i] = ch[name] * DEG
    return np.clip(q, LOWER, UPPER)


def _leg_goals(ch: Channels, gait: GaitOut | None, hd: _Heading) -> list[LegGoal]:
    """Foot targets of the legs with IK weight: the gait's feet (nudged by keyframed foot
    channels, to lift a foot to kick) or feet placed by the channels in the heading frame."""
    legs = []
    for i, (side, s, c) in enumerate((("left", 1.0, "l"), ("right", -1.0, "r"))):
        w = np.clip(ch[f"{c}_leg"], 0.0, 1.0)
        if not np.any(w > 0):
            continue
        if gait is not None and gait.active[i]:
            off = np.stack([ch[f"{c}f_x"], ch[f"{c}f_y"] - default(f"{c}f_y"), ch[f"{c}f_z"]], 1)
            ankle = gait.ankle[i] + hd.turn(off)
            frot = gait.foot_rot[i]
        else:
            fp = ch[f"{c}f_pitch"] * DEG
            fyaw = hd.path[:, 2] + ch[f"{c}f_yaw"] * DEG
            ox, oz = pivot_offset(fp)
            sole = hd.point(np.stack([ch[f"{c}f_x"], ch[f"{c}f_y"], ch[f"{c}f_z"]], 1))
            ankle = sole + np.stack([np.cos(fyaw) * ox, np.sin(fyaw) * ox, ANKLE_H + oz], 1)
            frot = rot_z(fyaw) @ rot_y(fp)
        contact = gait.contact[i] if gait is not None and gait.contact is not None else 1.0
        legs.append(LegGoal(side, s, w, ankle, frot, w * contact))
    return legs


def _lower_pelvis(root: np.ndarray, rmat: np.ndarray, legs: list[LegGoal]) -> None:
    """Lower the pelvis (in place) where a planted foot's target would be out of the leg's reach."""
    cands = [root[:, 2]]
    for leg in legs:
        hip_off = rmat @ np.array([0.0, leg.s * HIP_Y, 0.0])
        dh = np.hypot(root[:, 0] + hip_off[:, 0] - leg.ankle[:, 0], root[:, 1] + hip_off[:, 1] - leg.ankle[:, 1])
        reach = leg.ankle[:, 2] - hip_off[:, 2] + np.sqrt(np.maximum((0.995 * LEG) ** 2 - dh * dh, 1e-4))
        cands.append(reach + (1.0 - leg.contact) * 2.0)
    root[:, 2] = softmin(cands)


def _snap_to_floor(
    root: np.ndarray, quat: np.ndarray, q: np.ndarray, arm_w: dict[str, np.ndarray], snap: np.ndarray
) -> None:
    """Lower the root (in place) by ``snap`` × the lowest body point; arms reaching for a
    target (weight > 0.5) do not count, they hold something above the floor."""
    lows = body_lows(root, quat, q)
    for c, bodies in (("l", ARM_BODIES[:3]), ("r", ARM_BODIES[3:])):
        lows[:, bodies] = np.where(arm_w[c][:, None] > 0.5, np.inf, lows[:, bodies])
    root[:, 2] -= snap * lows.min(axis=1)


def _reach_arms(
    spec: Spec,
    ch: Channels,
    q: np.ndarray,
    root: np.ndarray,
    rmat: np.ndarray,
    hd: _Heading,
    arm_w: dict[str, np.ndarray],
) -> None:
    """Arm IK (in place) to the wrist targets, in the chest or heading frame, blended by weight."""
    rch = rmat @ rot_y(q[:, DOF_INDEX["waist_flex"]]) @ rot_x(q[:, DOF_INDEX["waist_lateral"]])
    rch = rch @ rot_z(q[:, DOF_INDEX["waist_twist"]])
    chest = root + rmat @ np.array([0.0, 0.0, CHEST_Z])
    for side, s, c in (("left", 1.0, "l"), ("right", -1.0, "r")):
        w = arm_w[c]
        if not np.any(w > 0):
            continue
        h = np.stack([ch[f"{c}h_x"], ch[f"{c}h_y"], ch[f"{c}h_z"]], 1)
        target = chest + np.einsum("tij,tj->ti", rch, h) if spec.hands == "chest" else hd.point(h)
        sh = chest + rch @ (SHOULDER * np.array([1.0, s, 1.0]))
        d = np.einsum("tji,tj->ti", rch, target - sh)
        pole = np.stack([ch[f"{c}e_x"], ch[f"{c}e_y"], ch[f"{c}e_z"]], 1)
        flex, abd, twist, elbow = arm_ik(d, pole, s, q[:, DOF_INDEX[f"{side}_shoulder_twist"]])
        for name, val in (
            ("shoulder_flex", flex),
            ("shoulder_abd", abd),
            ("shoulder_twist", twist),
            ("elbow_flex", elbow),
        ):
            k = DOF_INDEX[f"{side}_{name}"]
            q[:, k] = (1.0 - w) * q[:, k] + w * val


def solve(spec: Spec, ch: Channels, gait: GaitOut | None) -> Pose:
    """Channels → Pose: leg IK (lowering the pelvis to reach), floor snap, arm IK, ground guard."""
    path = gait.path if gait is not None else np.zeros((ch.n, 4))
    pyaw = path[:, 2]
    hd = _Heading(path, np.cos(pyaw), np.sin(pyaw))
    root, yaw, rmat, quat = _root(ch, hd)
    q = _direct_angles(ch)
    arm_w = {c: np.clip(ch[f"{c}_arm"], 0.0, 1.0) for c in ("l", "r")}

    legs = _leg_goals(ch, gait, hd)
    if legs:
        _lower_pelvis(root, rmat, legs)
    q_direct = q.copy()
    leg_ik(q, legs, root, rmat, yaw)

    # Floor postures: the lowest body point goes onto the ground, then IK feet are re-solved.
    snap = ch["snap"]
    if np.any(snap > 0):
        _snap_to_floor(root, quat, q, arm_w, snap)
        q = q_direct
        leg_ik(q, legs, root, rmat, yaw)

    if any(np.any(w > 0) for w in arm_w.values()):
        _reach_arms(spec, ch, q, root, rmat, hd, arm_w)

    q = np.clip(q, LOWER, UPPER)
    if spec.guard or np.any(snap > 0):
        low = body_lows(root, quat, q).min(axis=1)
        root[:, 2] += np.maximum(0.0, -low)
    root[:, 2] -= PELVIS_H
    return Pose(root, quat, q)


def build_motion(spec: Spec, length: float) -> MotionFn:
    """The motion function of a table row: τ (clipped to [0, length]) → Pose."""

    def fn(tau: np.ndarray, params: MotionParams) -> Pose:
        t = np.clip(np.asarray(tau, dtype=np.float64).reshape(-1), 0.0, length)
        ch, gait = layers(spec, t, params, length)
        return solve(spec, ch, gait)

    return fn


def build_swing(spec: Spec, length: float) -> SwingFn | None:
    """A table row's pelvis yaw about its path's heading (rad), τ clipped as ``build_motion``'s:
    the swing of a gait's pelvis from step to step, which the way it walks leaves out. None
    for a row without a gait, whose pelvis faces the way it goes."""
    if spec.gait is None and spec.custom != "moonwalk":
        return None

    def swing(tau: np.ndarray, params: MotionParams) -> np.ndarray:
        t = np.clip(np.asarray(tau, dtype=np.float64).reshape(-1), 0.0, length)
        ch, gait = layers(spec, t, params, length)
        heading = gait.path[:, 2] if gait is not None else 0.0  # a gait's rows always have one
        m = quat_to_matrix(solve(spec, ch, gait).root_quat)
        return (np.arctan2(m[:, 1, 0], m[:, 0, 0]) - heading + np.pi) % (2.0 * np.pi) - np.pi

    return swing
