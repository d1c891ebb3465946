"""The built-in motion library: a procedural animation for every catalogue motion.

Each of the 128 motions of ``phav_spec.motions.MOTIONS`` is registered here at import as a
``MotionDef`` with the catalogue's name, natural length and description. A motion is not a
hand-written function but a row of data (``Spec``) interpreted by one small engine:

* **Channels.** A motion is a set of named curves over motion time: joint angles (DOF names
  of ``skeleton.DOFS``, degrees; ``shoulder_flex`` without a side sets both sides), root
  offsets (``x y z`` metres in the heading frame, ``yaw pitch roll`` degrees), foot targets
  (``lf_* rf_*``: sole position and pitch/yaw in the heading frame), hand targets
  (``lh_* rh_*``: wrist position in the chest or heading frame) and blend weights
  (``l_leg r_leg``: leg IK, default on; ``l_arm r_arm``: arm IK, default off; ``snap``: put
  the lowest body point on the ground).
* **Layers.** A locomotion generator (``Gait``) writes the root path, the feet and the arm
  swing; keyframed postures (``Spec.keys``, monotone C1 cubics) override channels, optionally
  faded in and out over the gait (``Spec.blend``); periodic cycles (``Cycle``) and sine
  oscillators (``Osc``) add on top; a faint idle sway (breathing, head) adds life.
* **Solving.** Legs reach their foot targets by analytic two-link IK (hip flex/abd/twist,
  knee, ankle; the heel rises where the ankle would over-flex), the pelvis is lowered where a
  target would be out of reach, postures on the floor are snapped to the ground by forward
  kinematics, and arms reach wrist targets by pole-vector IK (hands on a pull-up bar, a
  cart, a rifle). Swings that hold one club or bat with both hands are solved once per
  keyframe (``posed_arms``) and interpolated in joint space, so the arms never flip.

Because feet in stance are IK targets that do not move, gaits do not slide; because the
root advances by the footstep plan, speed is tied to stride length and cadence.

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

Families (``Spec.family``; the table ``SPECS`` groups the rows by what the take shows):
``gait`` (walks, runs, limps, stairs, staggers, the moonwalk, pushing a cart or a box, the
run-ups and stops of composite takes), ``gesture`` (standing upper-body actions on planted
feet: hair, catch/throw, clap/wave, golf/baseball/basketball/kicks, archery, firearms,
pouring, hugs, idling), ``posture`` (transitions through keyframed whole-body postures:
sitting, standing up, kneeling, rolls, dives, falls, splits) and ``cycle`` (periodic
exercises and hops: jumps, jump rope, hopping, crawls, pull-ups, push-ups, sit-ups).

Scene conventions the physics can rely on (motion frame, reference person): the chair's
seat is behind the start, the seated pelvis 0.45 m below standing and 0.40 m behind the feet;
the staircase starts ``STAIR_START`` ahead along +X with ``STAIR_RISE``/``STAIR_RUN`` treads
(up for the climbs, down for ``go_down_stairs_01``) and its handrail is 0.42 m to the right,
1.0 m above the treads; the pull-up bar is 2.3 m high just ahead of the start (wrists at
2.25 m); pouring at a table puts the hands 0.95–1.2 m high.

Lengths are for the reference person (``animation.REFERENCE_HEIGHT_M``); the reference body
is ``body_dims(1.75, 70, 0.40, 0.34, 1.0)``.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field, replace

import numpy as np

from phav_generator.animation import REFERENCE_HEIGHT_M, MotionDef, MotionFn, MotionParams, Pose, register_motion
from phav_generator.keyframes import ease, euler_matrix, euler_quat, monotone_cubic, periodic_cubic, rot_x, rot_y, rot_z
from phav_generator.skeleton import (
    BONE_INDEX,
    DOF_INDEX,
    LOWER,
    N_DOFS,
    UPPER,
    body_dims,
    capsule_points,
    forward_kinematics,
)
from phav_spec.motions import MOTIONS

# --------------------------------------------------------------------------------------
# The reference body.

REF_BODY = body_dims(REFERENCE_HEIGHT_M, 70.0, 0.40, 0.34, 1.0)
_OFF = REF_BODY.offsets
PELVIS_H = REF_BODY.standing_pelvis_height
THIGH = float(-_OFF[BONE_INDEX["left_lower_leg"], 2])
SHIN = float(-_OFF[BONE_INDEX["left_foot"], 2])
ANKLE_H = REF_BODY.sole_height
HIP_Y = float(_OFF[BONE_INDEX["left_upper_leg"], 1])
CHEST_Z = float(_OFF[BONE_INDEX["chest"], 2])
SHOULDER = _OFF[BONE_INDEX["left_upper_arm"]].copy()  # left shoulder in the chest frame
UPPER_ARM = float(-_OFF[BONE_INDEX["left_lower_arm"], 2])
FOREARM = float(-_OFF[BONE_INDEX["left_hand"], 2])
_FOOT = REF_BODY.capsules[BONE_INDEX["left_foot"]]
TOE = np.array([_FOOT.b[0], _FOOT.b[2]])  # toe sphere centre (x, z) in the foot frame
HEEL = np.array([_FOOT.a[0], _FOOT.a[2]])
LEG = THIGH + SHIN
_RADII = np.array([c.radius for c in REF_BODY.capsules])
_HIP_LIMITS = tuple(
    float(v)
    for v in (
        LOWER[DOF_INDEX["left_hip_flex"]],
        UPPER[DOF_INDEX["left_hip_flex"]],
        LOWER[DOF_INDEX["left_hip_abd"]],
        UPPER[DOF_INDEX["left_hip_abd"]],
    )
)
_SHOULDER_LIMITS = tuple(
    float(v)
    for v in (
        LOWER[DOF_INDEX["left_shoulder_flex"]],
        UPPER[DOF_INDEX["left_shoulder_flex"]],
        LOWER[DOF_INDEX["left_shoulder_abd"]],
        UPPER[DOF_INDEX["left_shoulder_abd"]],
    )
)
_ARM_BODIES = [BONE_INDEX[f"{s}_{b}"] for s in ("left", "right") for b in ("upper_arm", "lower_arm", "hand")]

#: Staircase of the stairs motions (the physics builds it): first riser this far ahead.
STAIR_START, STAIR_RISE, STAIR_RUN = 0.40, 0.17, 0.30

_D = math.pi / 180.0
_ROOT_ADD = ("x", "y", "z", "yaw", "pitch", "roll")

Keys = tuple[tuple[float, float], ...]
Posture = Mapping[str, float]

# --------------------------------------------------------------------------------------
# Channels.

_BILATERAL = {d.split("_", 1)[1] for d in DOF_INDEX if d.startswith("left_")}
_DEFAULTS: dict[str, float] = {
    "l_leg": 1.0, "r_leg": 1.0, "l_arm": 0.0, "r_arm": 0.0, "snap": 0.0,
    "lf_y": HIP_Y, "rf_y": -HIP_Y, "lf_yaw": 6.0, "rf_yaw": -6.0,
    "lh_x": 0.05, "rh_x": 0.05, "lh_y": 0.18, "rh_y": -0.18, "lh_z": -0.24, "rh_z": -0.24,
    "le_x": -0.2, "re_x": -0.2, "le_y": 0.4, "re_y": -0.4, "le_z": -1.0, "re_z": -1.0,
}  # fmt: skip


def expand(posture: Posture) -> dict[str, float]:
    """Channel values of a posture written with shorthands.

    ``shoulder_flex`` (no side) sets both sides; ``leg``/``arm`` both IK weights; ``f_x``,
    ``f_z``, ``f_pitch`` both feet; ``f_w`` the feet's half-width (left +, right −); ``f_out``
    the toe-out angle; ``h_x``, ``h_z`` both hands, ``h_w`` the hands' half-width.
    """
    out: dict[str, float] = {}
    for key, value in posture.items():
        v = float(value)
        if key in _BILATERAL:
            out[f"left_{key}"] = out[f"right_{key}"] = v
        elif key in ("leg", "arm"):
            out[f"l_{key}"] = out[f"r_{key}"] = v
        elif key in ("f_x", "f_z", "f_pitch", "h_x", "h_z", "e_x", "e_z"):
            out[f"l{key}"] = out[f"r{key}"] = v
        elif key == "f_w":
            out["lf_y"], out["rf_y"] = v, -v
        elif key == "f_out":
            out["lf_yaw"], out["rf_yaw"] = v, -v
        elif key in ("h_w", "e_w"):
            out[f"l{key[0]}_y"], out[f"r{key[0]}_y"] = v, -v
        else:
            out[key] = v
    return out


def _default(name: str) -> float:
    return _DEFAULTS.get(name, 0.0)


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
class Gait:
    """Parameters of the locomotion generator (footstep plan → feet, pelvis, arm swing).

    Speeds may be constants or keys ((t, value), …). ``cadence`` is steps per second at the
    top speed (hops per second for ``feet`` other than ``alt``), falling with the square root
    of speed, or ``None`` for people's usual step frequency at each speed. Each stance plants
    the foot where the path is ``plant_at`` of the way through that stance, so the hip passes
    over a foot that stays put; swing feet travel between plants on a lifted curve.
    """

    speed: float | Keys = 1.3  # forward speed along the heading, m/s (negative: backwards)
    side: float | Keys = 0.0  # lateral speed, m/s (left +)
    turn: float | Keys = 0.0  # yaw rate, deg/s
    cadence: float | None = 1.8  # None: from the speed (the usual step frequency of people)
    duty: float | None = 0.62  # stance fraction of the cycle; None: from speed (walk → run)
    lift: float = 0.09  # swing foot clearance, m
    width: float = HIP_Y  # foot offset from the path, m
    width2: float | None = None  # every other plant at this width (jumping jacks)
    loop_multiple: int = 1  # a loop holds a multiple of this many gait cycles (jacks: 2)
    toe_out: float = 6.0
    crouch: float = -0.005  # pelvis offset from standing height, m
    bob: float = 0.012  # pelvis bob, m (+: high at mid-stance, walking; −: low, running)
    sway: float = 0.022  # pelvis sway over the stance foot, m
    pelvis_yaw: float = 5.0
    pelvis_roll: float = 3.0
    heel_off: float = 38.0  # heel lift at toe-off, deg
    heel_strike: float = 8.0  # toes up at heel strike, deg
    swing: float = 20.0  # arm swing, deg
    arm_fwd: float = 0.0  # mean shoulder flex, deg
    elbow: float = 14.0
    elbow_swing: float = 14.0
    arm_out: float = 7.0
    lean: float = 2.0  # pelvis pitch, deg
    torso: float = 2.0  # waist flex, deg
    feet: str = "alt"  # alt | both | left | right
    limp: float = 0.0  # shorter stance on the left (+) or right (−) leg, cycle fraction
    stiff: float = 0.0  # circumduction of the stiff (painful) leg's swing, m
    stiff_lift: float = 1.0  # the painful leg's swing lift relative to the sound leg's (a stiff knee)
    stairs: int = 0  # +1 up, −1 down (a stride of two treads climbs two at a time)
    phase_keys: Keys | None = None  # explicit gait phase over time (one-shot jumps)
    px: Keys | None = None  # extra displacement along the heading (jumps), m
    lift_pow: float = 1.5
    lift_skew: float = 0.0  # > 0: the swing foot rises early (running: heel to the buttocks)
    release: float = 0.0  # 1: a foot leaving the ground stops holding the pelvis down (flight)
    swing_linear: float = 0.0  # share of constant speed in the swing foot's forward travel
    weave: float = 0.0  # lateral weaving of the path, m
    weave_period: float = 4.0
    wander: float = 0.0  # heading wander, deg
    wander_period: float = 7.0
    plant_at: float = 0.4  # fraction of stance at which the hip passes over the ankle
    heel_off_at: float = 0.45  # fraction of stance at which the heel starts to rise


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
FAMILY_STYLE: dict[str, Posture] = {
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


def _track(keys: float | Keys, t: np.ndarray) -> np.ndarray:
    if isinstance(keys, (int, float)):
        return np.full(t.shape, float(keys))
    ks = np.array(keys, dtype=np.float64)
    return monotone_cubic(ks[:, 0], ks[:, 1], t)[:, 0]


def _fit_period(period: float, length: float) -> float:
    return length / max(1, round(length / period))


class _Channels:
    """Channel curves over the sample times; missing channels read as their default."""

    def __init__(self, n: int) -> None:
        self.n = n
        self.data: dict[str, np.ndarray] = {}

    def __getitem__(self, name: str) -> np.ndarray:
        if name in self.data:
            return self.data[name]
        return np.full(self.n, _default(name))

    def __contains__(self, name: str) -> bool:
        return name in self.data

    def set(self, name: str, value: np.ndarray | float) -> None:
        self.data[name] = np.broadcast_to(np.asarray(value, dtype=np.float64), (self.n,)).copy()

    def add(self, name: str, value: np.ndarray | float) -> None:
        self.set(name, self[name] + value)


# --------------------------------------------------------------------------------------
# Locomotion.


@dataclass
class _GaitOut:
    path: np.ndarray  # (T, 4): x, y, yaw (rad), ground z under the path
    ankle: np.ndarray  # (2, T, 3) ankle targets (left, right), motion frame
    foot_rot: np.ndarray  # (2, T, 3, 3)
    active: tuple[bool, bool]
    phase: np.ndarray  # (T,) gait phase in cycles
    contact: np.ndarray | None = None  # (2, T) weight of each foot in the pelvis-height constraint


def _pivot_offset(pitch: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Ankle displacement (x, z in the foot's heading frame) when the foot rolls by ``pitch``.

    Heel up (pitch > 0) rolls about the toe sphere, toes up (< 0) about the heel sphere, so
    the contact point stays put and the sole's lowest point stays on the ground.
    """
    c = np.where(pitch[:, None] >= 0, TOE, HEEL)
    cp, sp = np.cos(pitch), np.sin(pitch)
    # rotation about +Y by pitch applied to (−c), plus c
    x = c[:, 0] + (-c[:, 0] * cp - c[:, 1] * sp)
    z = c[:, 1] + (c[:, 0] * sp - c[:, 1] * cp)
    return x, z


def _stair_plant(x: np.ndarray, direction: int) -> tuple[np.ndarray, np.ndarray]:
    """Snap raw plant positions along +X onto the staircase's treads: (x, sole height)."""
    n = np.maximum(0, np.round((x - STAIR_START - 0.08) / STAIR_RUN))
    on = x >= STAIR_START - 0.1
    xs = np.where(on, STAIR_START + 0.08 + (0.02 if direction < 0 else 0.0) + STAIR_RUN * n, np.minimum(x, 0.17))
    zs = np.where(on, direction * STAIR_RISE * (n + 1), 0.0)
    return xs, zs


def stair_height(x: np.ndarray, direction: int) -> np.ndarray:
    """Height of the staircase surface at x (0 before the first riser)."""
    x = np.asarray(x, dtype=np.float64)
    n = np.floor((x - STAIR_START) / STAIR_RUN) + 1
    return np.where(x >= STAIR_START, direction * STAIR_RISE * n, 0.0)


def _gait(g: Gait, tau: np.ndarray, p: MotionParams, length: float, cyclic: bool, ch: _Channels) -> _GaitOut:
    """Footstep plan and pelvis/arm channels of a gait, evaluated at ``tau``."""
    dt, pad = 1.0 / 60.0, 3.0
    tg = -pad + dt * np.arange(round((length + 2 * pad) / dt) + 1)
    # amplitude: longer strides at a lower cadence (same speed), bigger jumps, wider weaving
    amp = p.amplitude if not g.stairs else 1.0
    v = _track(g.speed, tg)
    vy = _track(g.side, tg)
    yaw = np.concatenate([[0.0], np.cumsum(0.5 * (_track(g.turn, tg)[1:] + _track(g.turn, tg)[:-1]) * dt)]) * _D
    vx_w = v * np.cos(yaw) - vy * np.sin(yaw)
    vy_w = v * np.sin(yaw) + vy * np.cos(yaw)
    x = np.concatenate([[0.0], np.cumsum(0.5 * (vx_w[1:] + vx_w[:-1]) * dt)])
    y = np.concatenate([[0.0], np.cumsum(0.5 * (vy_w[1:] + vy_w[:-1]) * dt)])
    if g.px is not None:
        extra = _track(g.px, tg) * amp
        x, y = x + np.cos(yaw) * extra, y + np.sin(yaw) * extra
    i0 = round(pad / dt)
    if g.wander:
        yaw = yaw + g.wander * _D * np.sin(2 * np.pi * (tg / _fit_period(g.wander_period, length) + p.phase))
    if g.weave:
        w = g.weave * amp * np.sin(2 * np.pi * (tg / _fit_period(g.weave_period, length) + p.phase))
        x, y = x - np.sin(yaw) * w, y + np.cos(yaw) * w
    x, y, yaw = x - x[i0], y - y[i0], yaw - yaw[i0]

    alt = g.feet == "alt"
    if g.phase_keys is not None:
        phi = _track(g.phase_keys, tg)
    else:
        vref = float(np.max(np.abs(_track(g.speed, tg)))) if not isinstance(g.speed, (int, float)) else abs(g.speed)
        if g.cadence is None:  # human step frequency at each speed, walking then running
            steps = np.interp(
                np.abs(v), [0.0, 0.6, 1.3, 1.9, 2.3, 3.5, 5.0, 6.5], [1.3, 1.5, 1.8, 2.1, 2.6, 2.9, 3.45, 3.8]
            )
        else:
            steps = g.cadence * np.sqrt((np.abs(v) + 0.5) / (vref + 0.5))
        f = steps / amp * (0.5 if alt else 1.0)
        if cyclic:
            m = g.loop_multiple
            f = np.full_like(f, max(m, m * round(f[i0] * length / m)) / length)
        phi = np.concatenate([[0.0], np.cumsum(0.5 * (f[1:] + f[:-1]) * dt)])
        phi = phi - phi[i0] + p.phase
    phi = phi + 1e-7 * (tg - tg[0])  # strictly increasing for inversion

    speed_abs = np.abs(v)
    if g.duty is None:
        duty_g = np.interp(speed_abs, [0.0, 1.5, 2.4, 3.5, 5.0, 6.0], [0.6, 0.55, 0.4, 0.32, 0.27, 0.25])
    else:
        duty_g = np.full_like(tg, g.duty)
    offsets = {"alt": (0.0, 0.5 - g.limp), "both": (0.0, 0.0), "left": (0.0, 0.0), "right": (0.0, 0.0)}[g.feet]
    active = (g.feet in ("alt", "both", "left"), g.feet in ("alt", "both", "right"))
    sgn = np.sign(v + 1e-9)

    def at(arr: np.ndarray, t: np.ndarray) -> np.ndarray:
        return np.interp(t, tg, arr)

    phase = at(phi, tau)
    gw = np.clip(np.abs(at(v, tau)) / 0.6, 0.0, 1.0) if alt else np.ones_like(tau)
    gw = gw * gw * (3 - 2 * gw)
    sg = at(sgn, tau)
    style = p.style
    n = len(tau)
    ankle = np.zeros((2, n, 3))
    foot_rot = np.zeros((2, n, 3, 3))
    contact = np.ones((2, n))
    plants_t: list[np.ndarray] = []
    plants_z: list[np.ndarray] = []
    for i, s in enumerate((1.0, -1.0)):
        if not active[i]:
            foot_rot[i] = np.eye(3)
            continue
        beta_g = duty_g + (-g.limp if i == 0 else g.limp)
        phi_i = phi - offsets[i]
        ks = np.arange(math.floor(phi_i[0]) - 1, math.ceil(phi_i[-1]) + 2)
        beta_k = np.interp(ks + 0.3, phi_i, beta_g)
        tk = np.interp(ks + beta_k * g.plant_at, phi_i, tg)
        yk = np.interp(tk, tg, yaw)
        wk = np.full(len(ks), g.width)
        if g.width2 is not None:
            wk = np.where(ks % 2 == 0, g.width, g.width2)
        pkx = np.interp(tk, tg, x) - np.sin(yk) * s * wk
        pky = np.interp(tk, tg, y) + np.cos(yk) * s * wk
        pkz = np.zeros(len(ks))
        if g.stairs:
            pkx, pkz = _stair_plant(pkx, g.stairs)
        yawk = yk + s * g.toe_out * _D
        step = np.hypot(np.diff(pkx), np.diff(pky))
        liftk = np.full(len(ks) - 1, g.lift * (1.0 + 0.25 * style))
        if alt and not g.stairs:
            liftk = liftk * np.clip(step / 0.25, 0.0, 1.0)
        plants_t.append(tk)
        plants_z.append(pkz)

        ph = phase - offsets[i]
        k = np.floor(ph).astype(int)
        j = np.clip(k - ks[0], 0, len(ks) - 2)
        u = ph - k
        beta = at(beta_g, tau)
        stance = u < beta
        sig = np.clip(u / beta, 0.0, 1.0)
        sw = np.clip((u - beta) / (1.0 - beta), 0.0, 1.0)
        if g.stairs > 0:
            hprog, vprog = ease((sw - 0.2) / 0.8), ease(sw / 0.7)
        elif g.stairs < 0:
            hprog, vprog = ease(sw / 0.8), ease((sw - 0.35) / 0.65)
        else:
            hprog = g.swing_linear * sw + (1 - g.swing_linear) * sw * sw * (3 - 2 * sw)
            vprog = hprog
        shape = np.where(sw < 0.5, np.cos(np.pi * sw) ** 2, ease((sw - 0.5) / 0.3))
        contact[i] = np.where(stance, 1.0, 1.0 - g.release * (1.0 - shape))
        hprog = np.where(stance, 0.0, hprog)
        vprog = np.where(stance, 0.0, vprog)
        grid = np.linspace(0.0, 1.0, 101)
        norm = np.max(np.sin(np.pi * grid) ** g.lift_pow * (1.0 - g.lift_skew * grid))
        shape = np.sin(np.pi * sw) ** g.lift_pow * (1.0 - g.lift_skew * sw) / norm
        painful = g.limp != 0 and i == (0 if g.limp > 0 else 1)
        lift = np.where(stance, 0.0, liftk[j] * shape * (g.stiff_lift if painful else 1.0))
        if g.stiff and painful:
            out = np.where(stance, 0.0, g.stiff * np.sin(np.pi * sw))
        else:
            out = 0.0
        fx = pkx[j] + hprog * (pkx[j + 1] - pkx[j])
        fy = pky[j] + hprog * (pky[j + 1] - pky[j])
        fz = pkz[j] + vprog * (pkz[j + 1] - pkz[j]) + lift
        fyaw = yawk[j] + hprog * (yawk[j + 1] - yawk[j])
        fy = fy + s * out * np.cos(fyaw)
        fx = fx - s * out * np.sin(fyaw)
        ho = g.heel_off * _D * gw * sg * (g.stiff_lift if painful else 1.0)  # no push-off on a stiff leg
        hs = g.heel_strike * _D * gw * sg
        if g.feet != "alt":
            ho, hs = g.heel_off * _D * np.ones(n), g.heel_strike * _D * np.ones(n)
        h0 = g.heel_off_at
        pitch_st = -hs * (1 - ease(sig / 0.15)) + ho * ease((sig - h0) / (1 - h0))
        pitch_sw = ho * (1 - ease(sw / 0.75)) - hs * ease((sw - 0.6) / 0.4)
        pitch = np.where(stance, pitch_st, pitch_sw)
        ox, oz = _pivot_offset(pitch)
        ankle[i, :, 0] = fx + np.cos(fyaw) * ox
        ankle[i, :, 1] = fy + np.sin(fyaw) * ox
        ankle[i, :, 2] = fz + ANKLE_H + oz
        foot_rot[i] = rot_z(fyaw) @ rot_y(pitch)

    # Ground under the path: the stance heights, smoothed through the plant times.
    if g.stairs:
        tt = np.concatenate(plants_t)
        zz = np.concatenate(plants_z)
        order = np.argsort(tt, kind="stable")
        tt, zz = tt[order], zz[order]
        keep = np.concatenate([[True], np.diff(tt) > 1e-6])
        ground = monotone_cubic(tt[keep], zz[keep], tau)[:, 0]
    else:
        ground = np.zeros(n)

    # Pelvis and upper body: channels, phase-locked to the left foot.
    beta_l = at(duty_g, tau) - g.limp
    c1 = np.cos(2 * np.pi * (phase - beta_l / 2))
    path = np.stack([at(x, tau), at(y, tau), at(yaw, tau), ground], axis=1)
    arm_gain = amp * (1.0 + 0.35 * style)
    if alt:
        yaw_osc = -g.pelvis_yaw * gw * sg * np.cos(2 * np.pi * phase) * amp
        ch.set("y", g.sway * gw * c1)
        ch.set("roll", g.pelvis_roll * gw * c1 * amp)
        ch.set("yaw", yaw_osc)
        ch.set("z", g.crouch + g.bob * gw * np.cos(4 * np.pi * (phase - beta_l / 2)))
        if g.limp:
            # dip onto the sound leg, lean the torso over the painful one
            ch.add("z", -0.02 * abs(g.limp) / 0.1 * gw * np.cos(2 * np.pi * (phase - beta_l / 2)) * np.sign(g.limp))
            ch.set("waist_lateral", 6.0 * gw * c1 * np.sign(g.limp) * abs(g.limp) / 0.1)
        for side, o in (("left", offsets[0]), ("right", offsets[1])):
            c = np.cos(2 * np.pi * (phase - o))
            ch.set(f"{side}_shoulder_flex", g.arm_fwd - g.swing * arm_gain * gw * sg * c)
            ch.set(f"{side}_elbow_flex", g.elbow + 12.0 * style + g.elbow_swing * arm_gain * gw * (1 + sg * c) / 2)
            ch.set(f"{side}_shoulder_abd", g.arm_out)
        ch.set("waist_twist", -0.7 * yaw_osc)
        ch.set("neck_twist", -0.3 * yaw_osc)
    else:
        ch.set("z", g.crouch)
        ch.set("elbow_flex", g.elbow + 12.0 * style)
        ch.set("shoulder_abd", g.arm_out)
        ch.set("shoulder_flex", g.arm_fwd)
    lean = g.lean + 3.0 * style
    ch.set("pitch", lean)
    ch.set("waist_flex", g.torso + 2.0 * style)
    ch.set("neck_flex", -0.6 * (lean + g.torso))
    for name in ("left_elbow_flex", "right_elbow_flex"):
        if name in ch:
            ch.set(name, np.maximum(ch[name], 0.0))
    return _GaitOut(path, ankle, foot_rot, active, phase, contact)


# --------------------------------------------------------------------------------------
# Inverse kinematics.


def _limb_ik(
    d: np.ndarray,
    l1: float,
    l2: float,
    s: float,
    e: float,
    twist: np.ndarray,
    hint: tuple[np.ndarray, np.ndarray],
    limits: tuple[float, float, float, float],
    soft: float | np.ndarray,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Two-link IK (the legs): (flex, abd, bend) bringing the limb end to ``d`` (T, 3, parent frame).

    The chain is R_y(−flex)·R_x(s·abd)·R_z(s·twist)·R_y(−e·bend) (``s`` the side, ``e`` +1 for
    an elbow bending forward, −1 for a knee bending backward); ``twist`` (the DOF value) is
    given and swivels the bend plane. Of the two (flex, abd) solutions the one inside the
    joint ``limits`` (flex lo, hi, abd lo, hi) wins, ties going to the one nearer ``hint``
    (the motion's own direct angles), and flex is read around the hint so that a rolling or
    inverted pelvis does not wrap it. Targets beyond ``soft``·(l1 + l2) are pulled in
    smoothly (tanh), so the limb straightens with bounded joint speed instead of snapping.
    """
    dist = np.linalg.norm(d, axis=1)
    reach = l1 + l2
    knee0 = soft * reach
    span = reach - knee0
    dc = np.where(dist > knee0, knee0 + span * np.tanh((dist - knee0) / span), dist)
    dc = np.clip(dc, abs(l1 - l2) + 0.02, reach * 0.99999)
    dd = d * (dc / np.maximum(dist, 1e-9))[:, None]
    cosk = (dc * dc - l1 * l1 - l2 * l2) / (2 * l1 * l2)
    bend = np.arccos(np.clip(cosk, -1.0, 1.0))
    v0x = e * l2 * np.sin(bend)
    vz = -l1 - l2 * np.cos(bend)
    vx = v0x * np.cos(s * twist)
    vy = v0x * np.sin(s * twist)
    r = np.hypot(vy, vz)
    psi = np.arctan2(-vz, vy)
    gap = np.arccos(np.clip(dd[:, 1] / r, -1.0, 1.0))
    f_lo, f_hi, a_lo, a_hi = limits
    wrap = hint[0] - np.pi  # angles read around the motion's own pose: no wrap-around jumps
    best = None
    for b in (psi - gap, psi + gap):
        zp = vy * np.sin(b) + vz * np.cos(b)
        flex = np.arctan2(dd[:, 2], dd[:, 0]) - np.arctan2(zp, vx)
        flex = wrap + np.mod(flex - wrap, 2 * np.pi)
        abd = np.angle(np.exp(1j * s * b))
        out = (
            np.maximum(0, f_lo - flex)
            + np.maximum(0, flex - f_hi)
            + np.maximum(0, a_lo - abd)
            + np.maximum(0, abd - a_hi)
        )
        cost = out + 0.05 * (np.abs(flex - hint[0]) + np.abs(abd - hint[1]))
        if best is None:
            best = (cost, flex, abd)
        else:
            pick = cost < best[0] - 0.05
            best = (np.where(pick, cost, best[0]), np.where(pick, flex, best[1]), np.where(pick, abd, best[2]))
    return best[1], best[2], bend


def _limb_matrix(
    flex: np.ndarray, abd: np.ndarray, twist: np.ndarray, bend: np.ndarray, s: float, e: float
) -> np.ndarray:
    return rot_y(-flex) @ rot_x(s * abd) @ rot_z(s * twist) @ rot_y(-e * bend)


def _terminal(m: np.ndarray, s: float) -> tuple[np.ndarray, np.ndarray]:
    """(flex, deviation) of an ankle/wrist whose rotation is m = R_y(−flex)·R_x(s·dev)."""
    a = np.arctan2(-m[:, 2, 0], np.maximum(m[:, 0, 0], 0.05))  # beyond ±90°: held near the limit
    b = np.arctan2(-m[:, 1, 2], np.maximum(m[:, 1, 1], 0.05))
    return -a, s * b


def _arm_ik(
    d: np.ndarray, pole: np.ndarray, s: float, fallback_twist: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Arm IK with a pole vector: (flex, abd, twist, elbow) putting the wrist at ``d``.

    ``d`` is the wrist relative to the shoulder and ``pole`` the direction the elbow should
    point, both in the chest frame (T, 3). Of the circle of possible elbow positions the one
    nearest the pole is taken; the upper arm's direction gives flex and abduction (read with
    |abd| ≤ 90° unless that reading leaves the flex limits, as for an arm reaching behind), the
    forearm's direction in the upper arm's frame gives twist and elbow. Targets beyond 85 %
    of the reach are pulled in smoothly, so the arm straightens with bounded speed.
    """
    l1, l2 = UPPER_ARM, FOREARM
    # a wrist target inside the shoulder is pushed out in front (the arm cannot fold further)
    near = np.clip(0.2 - np.linalg.norm(d, axis=1), 0.0, None)
    d = d + near[:, None] * np.array([1.0, 0.0, -0.3])
    dist = np.linalg.norm(d, axis=1)
    reach = l1 + l2
    knee0 = 0.85 * reach
    dc = np.where(dist > knee0, knee0 + (reach - knee0) * np.tanh((dist - knee0) / (reach - knee0)), dist)
    dc = np.clip(dc, abs(l1 - l2) + 0.02, reach * 0.99999)
    n = d / np.maximum(dist, 1e-9)[:, None]
    a = (l1 * l1 - l2 * l2 + dc * dc) / (2 * dc)
    r = np.sqrt(np.maximum(l1 * l1 - a * a, 0.0))
    pole = pole / np.maximum(np.linalg.norm(pole, axis=1), 1e-9)[:, None]
    perp = pole - np.sum(pole * n, axis=1)[:, None] * n
    # a pole along the shoulder–wrist line says nothing: lean on "elbow back and out" then
    back = np.array([-0.8, 0.6 * s, -0.3]) - np.outer(n @ np.array([-0.8, 0.6 * s, -0.3]), np.ones(3)) * n
    perp = perp + np.clip(0.35 - np.linalg.norm(perp, axis=1), 0.0, None)[:, None] * back
    perp = perp / np.maximum(np.linalg.norm(perp, axis=1), 1e-9)[:, None]
    elbow_pos = a[:, None] * n + r[:, None] * perp
    u = elbow_pos / l1
    w = (dc[:, None] * n - elbow_pos) / l2
    bend = np.arccos(np.clip(np.sum(u * w, axis=1), -1.0, 1.0))
    f_lo, f_hi, a_lo, a_hi = _SHOULDER_LIMITS
    wrap = 0.5 * (f_hi + f_lo) - np.pi
    b1 = np.arcsin(np.clip(s * u[:, 1], -1.0, 1.0))
    a1 = np.arctan2(u[:, 0], -u[:, 2])
    best = None
    for flex, abd in ((a1, b1), (a1 + np.pi, np.pi - b1)):
        flex = wrap + np.mod(flex - wrap, 2 * np.pi)
        abd = np.angle(np.exp(1j * abd))
        out = (
            np.maximum(0, f_lo - flex)
            + np.maximum(0, flex - f_hi)
            + np.maximum(0, a_lo - abd)
            + np.maximum(0, abd - a_hi)
        )
        # forearm in the upper arm's frame gives the twist
        wl = np.einsum("tji,tj->ti", rot_y(-flex) @ rot_x(s * abd), w)
        twist = s * np.arctan2(wl[:, 1], wl[:, 0])
        sb = np.clip(np.sin(bend) / 0.25, 0.0, 1.0)
        twist = sb * twist + (1 - sb) * fallback_twist
        out = np.maximum(out - 0.25, 0.0)
        cand = (out, flex, abd, np.clip(twist, -0.5 * np.pi, 0.5 * np.pi))
        if best is None:
            best = cand
        else:
            pick = out < best[0] - 1e-3
            best = tuple(np.where(pick, x, y) for x, y in zip(cand, best, strict=True))
    return best[1], best[2], best[3], bend


_ARM_DOFS = ("shoulder_flex", "shoulder_abd", "shoulder_twist", "elbow_flex")
_ARM_CHANNELS = tuple(f"{side}_{d}" for side in ("left", "right") for d in _ARM_DOFS)


def _arm_points(x: np.ndarray, s: float) -> tuple[np.ndarray, np.ndarray]:
    """Elbows and wrists (N, 3), chest frame, of one arm posed at x (N, 4) = (flex, abd, twist, elbow)."""
    r = rot_y(-x[:, 0]) @ rot_x(s * x[:, 1]) @ rot_z(s * x[:, 2])
    shoulder = SHOULDER * np.array([1.0, s, 1.0])
    elbow = shoulder + r @ np.array([0.0, 0.0, -UPPER_ARM])
    wrist = elbow + (r @ rot_y(-x[:, 3])) @ np.array([0.0, 0.0, -FOREARM])
    return elbow, wrist


def fit_arm(side: str, target: np.ndarray, pole: np.ndarray, seed: np.ndarray) -> np.ndarray:
    """Joint angles (radians) putting one wrist at ``target`` (chest frame), elbow toward ``pole``.

    Damped least squares inside the joint limits, started from ``seed``: solving a sequence
    of keyframes each from the previous one's answer keeps the arm in one continuous
    configuration, which per-sample analytic IK cannot promise near the shoulder's gimbal.
    """
    s = 1.0 if side == "left" else -1.0
    idx = [DOF_INDEX[f"{side}_{d}"] for d in _ARM_DOFS]
    lo, hi = LOWER[idx], UPPER[idx]
    pole = np.asarray(pole, dtype=np.float64) / np.linalg.norm(pole)
    seed = np.clip(np.asarray(seed, dtype=np.float64), lo, hi)
    shoulder = SHOULDER * np.array([1.0, s, 1.0])

    def residuals(v: np.ndarray) -> np.ndarray:  # (N, 4) → (N, 10)
        elbow, wrist = _arm_points(v, s)
        e = (elbow - shoulder) / UPPER_ARM
        return np.concatenate([wrist - target, 0.08 * (e - pole), 0.02 * (v - seed)], axis=1)

    x, lam, h = seed.copy(), 1e-3, 1e-6
    r0 = residuals(x[None])[0]
    for _ in range(60):
        rr = residuals(x[None] + h * np.eye(4))
        jac = ((rr - r0) / h).T
        step = np.linalg.solve(jac.T @ jac + lam * np.eye(4), -jac.T @ r0)
        x_new = np.clip(x + step, lo, hi)
        r_new = residuals(x_new[None])[0]
        if r_new @ r_new < r0 @ r0:
            x, r0, lam = x_new, r_new, lam * 0.5
            if np.abs(step).max() < 1e-7:
                break
        else:
            lam *= 4.0
    return x


def posed_arms(keys: tuple[tuple[float, Posture], ...]) -> tuple[tuple[float, Posture], ...]:
    """Keyframes whose hand targets (chest frame, ``arm`` weight 1) are replaced by joint angles.

    Each key's arms are fitted from the previous key's angles (``fit_arm``), so the motion
    interpolates in joint space between solved keys: hands meet at every key and the arms
    never flip configuration between them.
    """
    seeds = {side: np.array([0.5, 0.2, 0.0, 0.5]) for side in ("left", "right")}
    out = []
    for t, post in keys:
        ch = expand(post)
        new = dict(ch)
        for side, c in (("left", "l"), ("right", "r")):
            if ch.get(f"{c}_arm", 0.0) < 0.5:
                continue
            target = np.array([ch.get(f"{c}h_{a}", _default(f"{c}h_{a}")) for a in "xyz"])
            pole = np.array([ch.get(f"{c}e_{a}", _default(f"{c}e_{a}")) for a in "xyz"])
            x = fit_arm(side, target, pole, seeds[side])
            seeds[side] = x
            for d, v in zip(_ARM_DOFS, x, strict=True):
                new[f"{side}_{d}"] = float(v / _D)
            new[f"{c}_arm"] = 0.0
        out.append((t, new))
    return tuple(out)


def _softmin(values: list[np.ndarray], temp: float = 0.005) -> np.ndarray:
    v = np.stack(values)
    m = v.min(axis=0)
    return m - temp * np.log(np.exp(-(v - m) / temp).sum(axis=0))


def _body_lows(root: np.ndarray, quat: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Lowest surface height of every body (T, 15) for the reference body."""
    pos, rot = forward_kinematics(REF_BODY, root, quat, q)
    wa, wb = capsule_points(REF_BODY, pos, rot)
    return np.minimum(wa[..., 2], wb[..., 2]) - _RADII


# --------------------------------------------------------------------------------------
# Evaluation.


def _layers(spec: Spec, tau: np.ndarray, p: MotionParams, length: float) -> tuple[_Channels, _GaitOut | None]:
    ch = _Channels(len(tau))
    gait = None
    if spec.gait is not None:
        gait = _gait(spec.gait, tau, p, length, spec.cyclic, ch)
    elif spec.custom == "moonwalk":
        gait = _moonwalk(tau, p, length, ch)
    if spec.keys:
        times = np.array([t for t, _ in spec.keys])
        rows = [expand(post) for _, post in spec.keys]
        names = sorted({k for r in rows for k in r})
        vals = np.array([[r.get(k, _default(k)) for k in names] for r in rows])
        for c, k in enumerate(names):
            if k in DOF_INDEX and k not in spec.rigid:
                vals[:, c] = vals[0, c] + p.amplitude * (vals[:, c] - vals[0, c])
        cur = monotone_cubic(times, vals, tau)
        w = None if spec.blend is None else np.clip(_track(spec.blend, tau), 0.0, 1.0)
        for c, k in enumerate(names):
            if k in _ROOT_ADD:
                ch.add(k, cur[:, c] if w is None else w * cur[:, c])
            elif w is None:
                ch.set(k, cur[:, c])
            else:
                ch.set(k, ch[k] + w * (cur[:, c] - ch[k]))
    for cyc in spec.cycles:
        rows = [expand(post) for _, post in cyc.keys]
        names = sorted({k for r in rows for k in r})
        vals = np.array([[r.get(k, 0.0) for k in names] for r in rows])
        if cyc.sync:
            u = gait.phase / cyc.period if gait is not None else tau / cyc.period
        else:
            u = tau / _fit_period(cyc.period, length) + p.phase
        cur = periodic_cubic([f for f, _ in cyc.keys], vals, u) * p.amplitude
        if cyc.env is not None:
            cur = cur * _track(cyc.env, tau)[:, None]
        for c, k in enumerate(names):
            ch.add(k, cur[:, c])
    for o in spec.osc + IDLE:
        val = o.amp * p.amplitude * np.sin(2 * np.pi * (tau / _fit_period(o.period, length) + o.offset + p.phase))
        if o.env is not None:
            val = val * _track(o.env, tau)
        for k in expand({o.channel: 1.0}):
            ch.add(k, val * (-1.0 if k in ("rf_y", "rh_y", "re_y") else 1.0))
    if spec.advance:
        ch.add("x", spec.advance * p.amplitude * tau)
    for k, v in expand({**FAMILY_STYLE.get(spec.family, {}), **spec.style}).items():
        ch.add(k, p.style * v * (-1.0 if k in ("rf_y", "rh_y", "re_y") else 1.0))
    return ch, gait


def _leg_ik(q: np.ndarray, legs: list, root: np.ndarray, rmat: np.ndarray, yaw: np.ndarray) -> None:
    """Solve each leg for its ankle target and foot orientation, blended by its IK weight (in place).

    Where the foot would need more dorsiflexion than the ankle allows (a trailing foot far
    behind, a foot on a lower stair), the heel rises instead, rolling about the toe.
    """
    toe = np.array([TOE[0], 0.0, TOE[1]])
    hi = UPPER[DOF_INDEX["left_ankle_flex"]] - 2 * _D
    for side, s, w, ankle, frot, wc in legs:
        soft = 0.985 - 0.12 * (1.0 - wc)  # a swinging foot may fall short of its target: no knee snap
        hip = root + rmat @ np.array([0.0, s * HIP_Y, 0.0])
        fyaw = np.arctan2(frot[:, 1, 0], frot[:, 0, 0])
        twist = s * np.clip(np.angle(np.exp(1j * (fyaw - yaw))), -0.7, 0.7)
        hint = (q[:, DOF_INDEX[f"{side}_hip_flex"]], q[:, DOF_INDEX[f"{side}_hip_abd"]])
        for attempt in range(3):
            d = np.einsum("tji,tj->ti", rmat, ankle - hip)
            flex, abd, knee = _limb_ik(d, THIGH, SHIN, s, -1.0, twist, hint, _HIP_LIMITS, soft)
            m = rmat @ _limb_matrix(flex, abd, twist, knee, s, -1.0)
            af, ai = _terminal(np.einsum("tji,tjk->tik", m, frot), s)
            if attempt == 2:
                break
            # the ankle cannot yaw: correct the hip twist until the foot points where it should
            got = m @ rot_y(-af) @ rot_x(s * ai)
            err = np.angle(np.exp(1j * (fyaw - np.arctan2(got[:, 1, 0], got[:, 0, 0]))))
            twist = np.clip(twist + s * np.clip(err, -0.3, 0.3) * np.clip(wc, 0.0, 1.0) ** 2, -0.8, 0.8)
            excess = np.maximum(af - hi, 0.0)
            if attempt == 0 and np.any(excess > 0):
                toe_w = ankle + frot @ toe
                frot = frot @ rot_y(excess)
                ankle = toe_w - frot @ toe
        for name, val in (
            ("hip_flex", flex),
            ("hip_abd", abd),
            ("hip_twist", twist),
            ("knee_flex", knee),
            ("ankle_flex", af),
            ("ankle_inv", ai),
        ):
            k = DOF_INDEX[f"{side}_{name}"]
            q[:, k] = (1.0 - w) * q[:, k] + w * val


def _solve(spec: Spec, ch: _Channels, gait: _GaitOut | None) -> Pose:
    """Channels → Pose: leg IK (lowering the pelvis to reach), floor snap, arm IK, ground guard."""
    n = ch.n
    path = gait.path if gait is not None else np.zeros((n, 4))
    pyaw = path[:, 2]
    cy, sy = np.cos(pyaw), np.sin(pyaw)
    yaw = pyaw + ch["yaw"] * _D
    pitch, roll = ch["pitch"] * _D, ch["roll"] * _D
    root = np.stack(
        [
            path[:, 0] + cy * ch["x"] - sy * ch["y"],
            path[:, 1] + sy * ch["x"] + cy * ch["y"],
            PELVIS_H + path[:, 3] + ch["z"],
        ],
        axis=1,
    )
    rmat = euler_matrix(yaw, pitch, roll)
    quat = euler_quat(yaw, pitch, roll)
    q = np.zeros((n, N_DOFS))
    for name, i in DOF_INDEX.items():
        if name in ch:
            q[:, i] = ch[name] * _D
    q = np.clip(q, LOWER, UPPER)

    def heading(v: np.ndarray) -> np.ndarray:
        return np.stack(
            [path[:, 0] + cy * v[:, 0] - sy * v[:, 1], path[:, 1] + sy * v[:, 0] + cy * v[:, 1], path[:, 3] + v[:, 2]],
            1,
        )

    arm_w = {c: np.clip(ch[f"{c}_arm"], 0.0, 1.0) for c in ("l", "r")}

    # Legs: foot targets (gait or heading-frame channels) reached by IK; pelvis lowered to reach.
    legs = []
    for i, (side, s, c) in enumerate((("left", 1.0, "l"), ("right", -1.0, "r"))):
        w = np.clip(ch[f"{c}_leg"], 0.0, 1.0)
        if not np.any(w > 0):
            continue
        if gait is not None and gait.active[i]:
            # keyframed foot channels nudge the gait's targets (lift a foot to kick)
            off = np.stack([ch[f"{c}f_x"], ch[f"{c}f_y"] - _default(f"{c}f_y"), ch[f"{c}f_z"]], 1)
            ankle = gait.ankle[i] + np.stack(
                [cy * off[:, 0] - sy * off[:, 1], sy * off[:, 0] + cy * off[:, 1], off[:, 2]], 1
            )
            frot = gait.foot_rot[i]
        else:
            fp = ch[f"{c}f_pitch"] * _D
            fyaw = pyaw + ch[f"{c}f_yaw"] * _D
            ox, oz = _pivot_offset(fp)
            sole = heading(np.stack([ch[f"{c}f_x"], ch[f"{c}f_y"], ch[f"{c}f_z"]], 1))
            ankle = sole + np.stack([np.cos(fyaw) * ox, np.sin(fyaw) * ox, ANKLE_H + oz], 1)
            frot = rot_z(fyaw) @ rot_y(fp)
        contact = gait.contact[i] if gait is not None and gait.contact is not None else 1.0
        legs.append((side, s, w, ankle, frot, w * contact))
    if legs:
        cands = [root[:, 2]]
        for _, s, _, ankle, _, wc in legs:
            hip_off = rmat @ np.array([0.0, s * HIP_Y, 0.0])
            dh = np.hypot(root[:, 0] + hip_off[:, 0] - ankle[:, 0], root[:, 1] + hip_off[:, 1] - ankle[:, 1])
            reach = ankle[:, 2] - hip_off[:, 2] + np.sqrt(np.maximum((0.995 * LEG) ** 2 - dh * dh, 1e-4))
            cands.append(reach + (1.0 - wc) * 2.0)
        root[:, 2] = _softmin(cands)
    q_direct = q.copy()
    _leg_ik(q, legs, root, rmat, yaw)

    # Floor postures: the lowest body point goes onto the ground, then IK feet are re-solved.
    snap = ch["snap"]
    if np.any(snap > 0):
        lows = _body_lows(root, quat, q)
        for c, bodies in (("l", _ARM_BODIES[:3]), ("r", _ARM_BODIES[3:])):
            lows[:, bodies] = np.where(arm_w[c][:, None] > 0.5, np.inf, lows[:, bodies])
        root[:, 2] -= snap * lows.min(axis=1)
        q = q_direct
        _leg_ik(q, legs, root, rmat, yaw)

    # Arms: hand (wrist) targets in the chest or heading frame.
    if any(np.any(w > 0) for w in arm_w.values()):
        rch = rmat @ rot_y(q[:, DOF_INDEX["waist_flex"]]) @ rot_x(q[:, DOF_INDEX["waist_lateral"]])
        rch = rch @ rot_z(q[:, DOF_INDEX["waist_twist"]])
        chest = root + rmat @ np.array([0.0, 0.0, CHEST_Z])
        for side, s, c in (("left", 1.0, "l"), ("right", -1.0, "r")):
            w = arm_w[c]
            if not np.any(w > 0):
                continue
            h = np.stack([ch[f"{c}h_x"], ch[f"{c}h_y"], ch[f"{c}h_z"]], 1)
            target = chest + np.einsum("tij,tj->ti", rch, h) if spec.hands == "chest" else heading(h)
            sh = chest + rch @ (SHOULDER * np.array([1.0, s, 1.0]))
            d = np.einsum("tji,tj->ti", rch, target - sh)
            pole = np.stack([ch[f"{c}e_x"], ch[f"{c}e_y"], ch[f"{c}e_z"]], 1)
            flex, abd, twist, elbow = _arm_ik(d, pole, s, q[:, DOF_INDEX[f"{side}_shoulder_twist"]])
            for name, val in (
                ("shoulder_flex", flex),
                ("shoulder_abd", abd),
                ("shoulder_twist", twist),
                ("elbow_flex", elbow),
            ):
                k = DOF_INDEX[f"{side}_{name}"]
                q[:, k] = (1.0 - w) * q[:, k] + w * val

    q = np.clip(q, LOWER, UPPER)
    if spec.guard or np.any(snap > 0):
        low = _body_lows(root, quat, q).min(axis=1)
        root[:, 2] += np.maximum(0.0, -low)
    root[:, 2] -= PELVIS_H
    return Pose(root, quat, q)


def _moonwalk(tau: np.ndarray, p: MotionParams, length: float, ch: _Channels) -> _GaitOut:
    """Moonwalk: the flat foot slides back while the other stands on its toes, then they swap.

    Each foot alternates half a cycle sliding back flat at twice the body's speed and half a
    cycle standing still with the heel raised (rolled about the toe), so the body glides
    backwards with a foot always on the floor. The slide is the point: it is the one gait
    whose stance foot moves.
    """
    period = _fit_period(1.1, length)
    v = 0.42 * p.amplitude  # backward speed of the body, m/s
    u = tau / period + p.phase
    ankle = np.zeros((2, len(tau), 3))
    rot = np.zeros((2, len(tau), 3, 3))
    for i, s in enumerate((1.0, -1.0)):
        ui = u + 0.5 * i
        k = np.floor(ui)
        f = ui - k
        c = v * period * (0.25 + 0.5 * i + p.phase)
        fx = -v * period * (k + ease(f / 0.5)) + c
        pitch = (30.0 + 8.0 * p.style) * _D * np.sin(np.pi * np.clip((f - 0.5) / 0.5, 0.0, 1.0)) ** 0.7
        ox, oz = _pivot_offset(pitch)
        ankle[i, :, 0] = fx + ox
        ankle[i, :, 1] = s * HIP_Y
        ankle[i, :, 2] = ANKLE_H + oz
        rot[i] = rot_y(pitch)
    ch.set("z", -0.035 + 0.01 * np.cos(4 * np.pi * u))
    ch.set("pitch", 3.0)
    ch.set("waist_flex", 4.0)
    ch.set("left_shoulder_flex", 12.0 * np.sin(2 * np.pi * u) * p.amplitude)
    ch.set("right_shoulder_flex", -12.0 * np.sin(2 * np.pi * u) * p.amplitude)
    ch.set("elbow_flex", 40.0 + 15.0 * p.style)
    ch.set("shoulder_abd", 12.0)
    x = -v * (tau - 0.0)
    path = np.stack([x, np.zeros_like(x), np.zeros_like(x), np.zeros_like(x)], 1)
    return _GaitOut(path, ankle, rot, (True, True), u)


def _build(spec: Spec, length: float) -> MotionFn:
    """The motion function of a table row: τ (clipped to [0, length]) → Pose."""

    def fn(tau: np.ndarray, params: MotionParams) -> Pose:
        t = np.clip(np.asarray(tau, dtype=np.float64).reshape(-1), 0.0, length)
        ch, gait = _layers(spec, t, params, length)
        return _solve(spec, ch, gait)

    return fn


# --------------------------------------------------------------------------------------
# Table helpers.

_MIRROR_NEG = {"y", "yaw", "roll", "waist_lateral", "waist_twist", "neck_lateral", "neck_twist"}


def mirror_posture(post: Posture) -> dict[str, float]:
    """The left–right mirror image of a posture (for left-handed variants)."""
    out: dict[str, float] = {}
    for k, v in expand(post).items():
        if k.startswith("left_"):
            out["right_" + k[5:]] = v
        elif k.startswith("right_"):
            out["left_" + k[6:]] = v
        elif k[:2] in ("lf", "rf", "lh", "rh", "le", "re") and k[2] == "_":
            other = ("r" if k[0] == "l" else "l") + k[1:]
            out[other] = -v if k.endswith(("_y", "_yaw")) else v
        elif k in ("l_leg", "r_leg", "l_arm", "r_arm"):
            out[("r" if k[0] == "l" else "l") + k[1:]] = v
        else:
            out[k] = -v if k in _MIRROR_NEG else v
    return out


def repeat(keys: tuple[tuple[float, Posture], ...], period: float, count: int, start: float = 0.0) -> tuple:
    """One cycle of keys (times in [0, period]) repeated ``count`` times from ``start``."""
    out: list[tuple[float, Posture]] = []
    for i in range(count):
        for t, post in keys:
            tt = start + i * period + t
            if out and tt <= out[-1][0] + 1e-9:
                continue
            out.append((tt, post))
    return tuple(out)


def seq(*items: tuple[float, Posture]) -> tuple[tuple[float, Posture], ...]:
    """Keyframes (time s, posture)."""
    return tuple(items)


def _gait_spec(base: Gait, cyclic: bool, kw: dict) -> Spec:
    gfields = {k: v for k, v in kw.items() if k in Gait.__dataclass_fields__}
    sfields = {k: v for k, v in kw.items() if k not in gfields}
    return Spec(family="gait", gait=replace(base, **gfields), cyclic=cyclic, **sfields)


def walk(*, cyclic: bool = True, **kw: object) -> Spec:
    """A walking motion: ``kw`` are Gait fields (speed, cadence …) and Spec fields (keys …)."""
    return _gait_spec(WALK, cyclic, kw)


def run(*, cyclic: bool = True, **kw: object) -> Spec:
    """A running motion (flight phases): as ``walk`` from the running defaults."""
    return _gait_spec(RUN, cyclic, kw)


def gesture(keys: tuple = (), **kw: object) -> Spec:
    """A standing motion: feet planted (leg IK), upper-body keyframes, cycles, oscillators."""
    return Spec(family="gesture", keys=keys, **kw)  # type: ignore[arg-type]


def posture(keys: tuple, **kw: object) -> Spec:
    """A whole-body posture sequence (sitting, kneeling, floor): keyframes, ground guard on."""
    return Spec(family="posture", keys=keys, guard=True, **kw)  # type: ignore[arg-type]


def cycle(**kw: object) -> Spec:
    """A periodic whole-body exercise or hop (jumps, crawls, hangs)."""
    return Spec(family="cycle", guard=True, **kw)  # type: ignore[arg-type]


# fmt: off
# --------------------------------------------------------------------------------------
# Gaits and postures.

WALK = Gait()
RUN = Gait(speed=3.5, cadence=None, duty=None, lift=0.2, crouch=-0.06, bob=-0.03, sway=0.012, pelvis_yaw=6.0,
    pelvis_roll=2.0, heel_off=50.0, heel_off_at=0.3, heel_strike=3.0, swing=38.0, arm_fwd=12.0, elbow=80.0,
    elbow_swing=20.0, arm_out=10.0, lean=7.0, torso=3.0, lift_pow=1.0, lift_skew=0.6, plant_at=0.38, release=1.0,
    swing_linear=0.4,
)  # fmt: skip
SPRINT = replace(RUN, speed=5.2, duty=None, lift=0.3, swing=50.0, elbow=85.0, lean=11.0, heel_off=55.0)
HOP = Gait(
    speed=0.0, feet="both", cadence=2.0, duty=0.5, lift=0.08, width=0.1, crouch=0.0, heel_off=30.0, heel_off_at=0.6,
    heel_strike=0.0, lift_pow=1.0, swing=0.0, elbow=40.0, arm_out=12.0, lean=3.0, torso=2.0, toe_out=8.0,
)  # fmt: skip

STAND: Posture = {}
ARMS_REST: Posture = {"shoulder_flex": 4.0, "elbow_flex": 12.0, "shoulder_abd": 6.0}
SIT: Posture = {
    "z": -0.45, "x": -0.40, "pitch": -4.0, "waist_flex": 6.0, "neck_flex": 4.0, "f_w": 0.12, "f_out": 10.0,
    "shoulder_flex": 28.0, "elbow_flex": 55.0, "shoulder_abd": 8.0}  # fmt: skip
SIT_LEAN: Posture = {
    "z": -0.25, "x": -0.24, "pitch": 32.0, "waist_flex": 12.0, "neck_flex": -18.0, "f_w": 0.12, "f_out": 10.0,
    "shoulder_flex": 35.0, "elbow_flex": 25.0}  # fmt: skip
SQUAT: Posture = {"z": -0.5, "x": -0.1, "pitch": 38.0, "waist_flex": 15.0, "neck_flex": -25.0, "f_w": 0.15,
    "f_out": 15.0}
KNEEL: Posture = {
    "leg": 0.0, "snap": 1.0, "z": -0.45, "hip_flex": 0.0, "knee_flex": 92.0, "ankle_flex": -50.0, "hip_abd": 4.0,
}  # fmt: skip
HALF_KNEEL: Posture = {"snap": 1.0, "r_leg": 0.0, "z": -0.45, "lf_x": 0.42, "lf_y": 0.12, "right_hip_flex": -3.0,
    "right_knee_flex": 92.0, "right_ankle_flex": -50.0, "right_hip_abd": 4.0}  # fmt: skip
PRONE: Posture = {
    "leg": 0.0, "snap": 1.0, "pitch": 90.0, "z": -0.78, "ankle_flex": -40.0, "hip_abd": 6.0, "neck_flex": -35.0,
    "shoulder_flex": 150.0, "shoulder_abd": 40.0, "elbow_flex": 110.0}  # fmt: skip
CRAWL: Posture = {
    "leg": 0.0, "snap": 1.0, "pitch": 80.0, "z": -0.45, "waist_flex": -15.0, "neck_flex": -40.0, "hip_flex": 80.0,
    "knee_flex": 105.0, "ankle_flex": -55.0, "hip_abd": 5.0, "shoulder_flex": 68.0, "elbow_flex": 6.0,
    "wrist_flex": -60.0, "shoulder_abd": 4.0}  # fmt: skip
HANDS_UP: Posture = {"shoulder_abd": 85.0, "shoulder_twist": 80.0, "elbow_flex": 85.0, "shoulder_flex": 8.0}
ARMS_OVERHEAD: Posture = {"shoulder_flex": 168.0, "shoulder_abd": 12.0, "elbow_flex": 8.0}
WAVE_UP: Posture = {
    "right_shoulder_abd": 80.0, "right_shoulder_flex": 20.0, "right_shoulder_twist": 80.0, "right_elbow_flex": 80.0,
    "right_wrist_flex": -10.0, "neck_twist": -8.0}  # fmt: skip
HUG: Posture = {"arm": 1.0, "lh_x": 0.36, "lh_y": -0.16, "lh_z": 0.26, "rh_x": 0.33, "rh_y": 0.18, "rh_z": 0.16,
    "left_shoulder_twist": -35.0, "right_shoulder_twist": -35.0, "neck_twist": -20.0, "neck_flex": 8.0}  # fmt: skip
GUARD: Posture = {"shoulder_flex": 45.0, "shoulder_abd": 25.0, "elbow_flex": 115.0, "shoulder_twist": -20.0}
PHONE: Posture = {
    "right_shoulder_flex": 38.0, "right_shoulder_abd": 6.0, "right_elbow_flex": 105.0, "right_wrist_flex": -20.0,
    "right_shoulder_twist": -15.0, "neck_flex": 32.0}  # fmt: skip
HOLD_HAND: Posture = {
    "right_shoulder_abd": 18.0, "right_shoulder_flex": 6.0, "right_elbow_flex": 20.0, "right_shoulder_twist": 10.0,
}  # fmt: skip
ARMS_OUT: Posture = {"shoulder_abd": 80.0, "elbow_flex": 12.0, "shoulder_twist": 10.0, "shoulder_flex": 5.0}
CARRY_BALL: Posture = {"arm": 1.0, "h_x": 0.33, "h_w": 0.11, "h_z": 0.18, "shoulder_twist": -10.0}
GUN: Posture = {"arm": 1.0, "lh_x": 0.52, "lh_y": -0.04, "lh_z": 0.30, "rh_x": 0.55, "rh_y": -0.06, "rh_z": 0.31,
    "neck_flex": 4.0, "neck_twist": -6.0, "wrist_flex": -5.0}  # fmt: skip


#: The hands' path in a golf swing (chest frame) by swing angle: back over the right
#: shoulder (−), hanging at address (0), through to the left (+); the skeleton's shoulder
#: adduction limit (40°) bounds how far across the chest the arms can go.
_GOLF_PATH = ((-120.0, -90.0, -45.0, 0.0, 45.0, 90.0, 130.0),
    ((0.20, -0.20, 0.55), (0.28, -0.24, 0.35), (0.34, -0.20, 0.12), (0.37, 0.0, -0.06), (0.34, 0.20, 0.12),
     (0.28, 0.24, 0.35), (0.20, 0.20, 0.55)),)  # fmt: skip


def _arc(angle: float, *, r: float = 0.3, grip: float = 0.07, plane: str = "golf") -> dict[str, float]:
    """Both hands on one grip, swung to ``angle`` degrees (chest frame targets).

    ``golf``: along ``_GOLF_PATH``; ``bat``: around the chest's vertical axis below
    shoulder height at radius ``r`` (0 = in front, − toward the right shoulder). The right
    hand holds the grip ``grip`` further from the shoulders.
    """
    out: dict[str, float] = {"arm": 1.0}
    if plane == "golf":
        pts = np.array(_GOLF_PATH[1])
        p = np.array([np.interp(angle, _GOLF_PATH[0], pts[:, i]) for i in range(3)])
        centre = np.array([0.0, 0.0, SHOULDER[2]])
        away = (p - centre) / np.linalg.norm(p - centre)
        for c, extra in (("l", 0.0), ("r", grip)):
            q = p + extra * away
            out[f"{c}h_x"], out[f"{c}h_y"], out[f"{c}h_z"] = float(q[0]), float(q[1]), float(q[2])
        return out
    a = angle * _D
    for c, extra in (("l", 0.0), ("r", grip)):
        out[f"{c}h_x"], out[f"{c}h_y"] = (r + extra) * math.cos(a), (r + extra) * math.sin(a)
        out[f"{c}h_z"] = SHOULDER[2] - 0.12 - (0.06 if c == "l" else 0.0)
    return out


_GOLF_STANCE: Posture = {"z": -0.06, "pitch": 18.0, "waist_flex": 24.0, "neck_flex": 20.0, "f_w": 0.22, "f_out": 10.0,
    "e_x": 0.6, "e_z": -0.8, "e_w": 0.15,  # elbows toward the ground
}  # fmt: skip


def golf_swing(t: float, scale: float = 1.0) -> tuple[tuple[float, Posture], ...]:
    """One golf swing starting at ``t``: address, backswing, impact, follow-through, recover.

    ``scale`` < 1 gives half swings and chips (shorter arc, less body turn).
    """
    s = scale
    addr = {**_GOLF_STANCE, **_arc(0.0)}
    return seq((t, addr),
        (t + 1.0 * s + 0.2, {**addr, **_arc(-80 * s), "waist_twist": -25 * s, "yaw": -8 * s, "neck_twist": 20 * s}),
        (t + 1.5 * s + 0.3, {**addr, **_arc(-120 * s), "waist_twist": -45 * s, "yaw": -15 * s, "neck_twist": 40 * s}),
        (t + 1.8 * s + 0.35, {**addr, **_arc(-60 * s), "waist_twist": -15 * s, "yaw": -5 * s, "neck_twist": 15 * s}),
        (t + 1.95 * s + 0.4, {**addr, **_arc(8.0), "waist_twist": 8 * s, "yaw": 8 * s}), (t + 2.15 * s + 0.45, {
                **addr, **_arc(95 * s), "waist_twist": 35 * s, "yaw": 22 * s, "neck_twist": -25 * s,
                "rf_pitch": 25 * s, "waist_flex": 12.0},), (t + 2.6 * s + 0.6, {**addr, **_arc(135 * s),
                "waist_twist": 50 * s, "yaw": 30 * s, "neck_twist": -45 * s, "rf_pitch": 35 * s, "waist_flex": 10.0,
                "pitch": 8.0},), (t + 3.6 * s + 1.0, {**addr, **_arc(130 * s), "waist_twist": 48 * s, "yaw": 28 * s,
                "neck_twist": -45 * s, "rf_pitch": 35 * s, "waist_flex": 10.0, "pitch": 8.0},))


_BAT_STANCE: Posture = {
    "z": -0.07, "pitch": 10.0, "waist_flex": 6.0, "f_w": 0.26, "f_out": 8.0, "neck_twist": 30.0, "yaw": -10.0,
    "shoulder_flex": 60.0, "e_z": -1.0, "e_x": 0.0, "e_w": 0.3}  # fmt: skip


def bat_swing(t: float) -> tuple[tuple[float, Posture], ...]:
    """One right-handed baseball swing from ``t``: load, stride, swing through, follow-through."""
    st = {**_BAT_STANCE, **_arc(-45, r=0.32, plane="bat"), "rh_z": 0.36, "lh_z": 0.30}
    return seq((t, st), (t + 0.7, {**st, **_arc(-55, r=0.30, plane="bat"), "rh_z": 0.38, "lh_z": 0.32,
                "waist_twist": -20.0, "lf_z": 0.08, "lf_y": 0.30},), (t + 1.1,
            {**st, **_arc(-55, r=0.30, plane="bat"), "rh_z": 0.36, "lh_z": 0.30, "waist_twist": -22.0, "lf_y": 0.40},
        ), (t + 1.3, {**st, **_arc(-30, r=0.42, plane="bat"), "waist_twist": 10.0, "yaw": 10.0, "lf_y": 0.40}), (
            t + 1.42, {**st, **_arc(20, r=0.50, plane="bat"), "waist_twist": 35.0, "yaw": 30.0, "lf_y": 0.40,
                "rf_pitch": 25.0, "neck_twist": 15.0},), (t + 1.65, {**st, **_arc(55, r=0.30, plane="bat"),
                "lh_z": 0.45, "rh_z": 0.5, "waist_twist": 50.0, "yaw": 40.0, "lf_y": 0.40, "rf_pitch": 35.0,
                "neck_twist": 0.0},), (t + 2.6, {**st, **_arc(58, r=0.28, plane="bat"), "lh_z": 0.45, "rh_z": 0.5,
                "waist_twist": 45.0, "yaw": 35.0, "lf_y": 0.40, "rf_pitch": 30.0, "neck_twist": 0.0},))


def bow_draw(t: float, *, hold: float = 1.5, release: bool = True) -> tuple[tuple[float, Posture], ...]:
    """Raise a bow (left arm straight forward), nock, draw the right hand back to the chin, release.

    The bow hand is an IK target at shoulder height; the drawing arm is posed directly (elbow
    out at shoulder height, hand at the jaw), fitted once against the skeleton.
    """
    base = {"l_arm": 1.0, "lh_x": 0.75, "lh_y": 0.08, "lh_z": SHOULDER[2], "neck_twist": 5.0, "neck_flex": 3.0,
        "waist_twist": -8.0}
    nock = {**base, "right_shoulder_flex": 84.0, "right_shoulder_abd": -2.0, "right_shoulder_twist": -72.0,
        "right_elbow_flex": 40.0}
    full = {**base, "right_shoulder_flex": 123.0, "right_shoulder_abd": 33.0, "right_shoulder_twist": -90.0,
        "right_elbow_flex": 148.0, "neck_lateral": 6.0, "neck_flex": 8.0}
    after = {**full, "right_shoulder_flex": 105.0, "right_shoulder_abd": 58.0, "right_elbow_flex": 122.0,
        "right_wrist_flex": -30.0}
    out = [(t, nock), (t + 0.6, nock), (t + 2.0, full), (t + 2.0 + hold, {**full, "right_shoulder_abd": 34.0})]
    if release:
        out += [(t + 2.1 + hold, after), (t + 3.2 + hold, after)]
    return tuple(out)


def hop_z(rise: float, dip: float, duty: float = 0.5) -> Cycle:
    """The pelvis of a hop, synced to the gait phase: dip in stance, rise in flight."""
    return Cycle(1.0,
        ((0.0, {"z": -dip * 0.4}), (duty / 2, {"z": -dip}), (duty, {"z": 0.0}), ((1 + duty) / 2, {"z": rise})),
        sync=True)


def _w(t0: float, t1: float, ramp: float = 0.8) -> Keys:
    """Blend weights: 0 before t0, up to 1 over ``ramp`` s, down again from t1."""
    return ((0.0, 0.0), (t0, 0.0), (t0 + ramp, 1.0), (t1, 1.0), (t1 + ramp, 0.0))


def _w_on(t0: float, ramp: float = 0.8) -> Keys:
    return ((0.0, 0.0), (t0, 0.0), (t0 + ramp, 1.0))


_CLAP: Cycle = Cycle(0.5, ((0.0, {}), (0.12, {}), (0.55, {"h_w": 0.12, "elbow_flex": 8.0})))
_CLAP_POSE: Posture = {"arm": 1.0, "h_x": 0.31, "h_w": 0.03, "h_z": 0.16, "shoulder_twist": -25.0, "wrist_flex": -20.0}
_HAIR_R: Posture = {"r_arm": 1.0, "rh_x": 0.05, "rh_y": -0.16, "rh_z": 0.6, "right_shoulder_flex": 110.0,
    "right_shoulder_abd": 60.0, "re_x": 0.6, "re_y": -0.8, "re_z": 0.2, "neck_lateral": -6.0, "neck_flex": 6.0}
_HAIR_STROKE_R = Cycle(1.6, ((0.0, {"rh_x": 0.1, "rh_z": -0.05}), (0.5, {"rh_x": -0.1, "rh_z": 0.0}),
        (0.75, {"rh_x": -0.12, "rh_z": -0.1, "rh_y": -0.03}),))
_TABLE = {"z": -0.03, "pitch": 8.0, "waist_flex": 10.0, "neck_flex": 12.0}
_HANG: Posture = {
    "arm": 1.0, "h_x": 0.04, "h_w": 0.28, "h_z": 2.25, "z": 0.225, "leg": 0.0, "hip_flex": 18.0, "knee_flex": 55.0,
    "ankle_flex": -30.0, "shoulder_flex": 165.0, "shoulder_abd": 20.0, "e_w": 1.0, "e_z": -0.4, "e_x": 0.3,
    "neck_flex": -8.0}  # fmt: skip
_PULL = Cycle(3.0, ((0.0, {}), (0.15, {}),
        (0.5, {"z": 0.42, "neck_flex": -15.0, "knee_flex": 15.0, "hip_flex": 10.0}),
        (0.62, {"z": 0.43, "neck_flex": -15.0, "knee_flex": 15.0, "hip_flex": 10.0}),))
_SUPINE: Posture = {
    "leg": 0.0, "snap": 1.0, "pitch": -88.0, "z": -0.75, "hip_flex": 55.0, "knee_flex": 105.0, "ankle_flex": 5.0,
    "hip_abd": 8.0, "shoulder_flex": 165.0, "shoulder_abd": 55.0, "elbow_flex": 135.0, "neck_flex": 15.0}  # fmt: skip
_PLANK: Posture = {
    "leg": 0.0, "snap": 1.0, "pitch": 71.0, "z": -0.5, "ankle_flex": 25.0, "hip_abd": 3.0, "waist_flex": -2.0,
    "neck_flex": -25.0, "arm": 1.0, "h_x": 0.52, "h_w": 0.24, "h_z": 0.09, "wrist_flex": -60.0,
    "shoulder_twist": -10.0}  # fmt: skip
_CROSS: Posture = {
    "leg": 0.0, "snap": 1.0, "z": -0.8, "pitch": -18.0, "hip_flex": 122.0, "hip_abd": 45.0, "hip_twist": 40.0,
    "knee_flex": 135.0, "ankle_flex": -20.0, "waist_flex": 24.0, "neck_flex": 4.0, "shoulder_flex": 40.0,
    "elbow_flex": 95.0, "shoulder_abd": 12.0}  # fmt: skip
_SIDE_SPLIT: Posture = {
    "leg": 0.0, "snap": 1.0, "z": -0.7, "hip_abd": 86.0, "hip_twist": 20.0, "ankle_flex": 15.0, "waist_flex": 12.0,
    "shoulder_flex": 40.0, "elbow_flex": 20.0, "shoulder_abd": 15.0}  # fmt: skip
_FRONT_SPLIT: Posture = {
    "leg": 0.0, "snap": 1.0, "z": -0.7, "pitch": 30.0, "waist_flex": -22.0, "left_hip_flex": 118.0,
    "right_hip_flex": -60.0, "left_ankle_flex": -5.0, "right_ankle_flex": -45.0, "shoulder_abd": 70.0,
    "elbow_flex": 10.0, "neck_flex": 5.0}  # fmt: skip
_LONG_SIT: Posture = {
    "leg": 0.0, "snap": 1.0, "z": -0.75, "pitch": -12.0, "hip_flex": 95.0, "knee_flex": 8.0, "ankle_flex": -15.0,
    "waist_flex": 8.0, "shoulder_flex": -25.0, "shoulder_abd": 12.0, "elbow_flex": 5.0, "wrist_flex": -60.0,
}  # fmt: skip
_CRAWL_CYCLE = Cycle(1.3, ((0.0, {"left_shoulder_flex": 14.0, "right_shoulder_flex": -14.0, "right_hip_flex": 14.0,
                "left_hip_flex": -14.0, "roll": 4.0, "waist_twist": 4.0},), (0.5, {"left_shoulder_flex": -14.0,
                "right_shoulder_flex": 14.0, "right_hip_flex": -14.0, "left_hip_flex": 14.0, "roll": -4.0,
                "waist_twist": -4.0},),))
_ARMY = Cycle(2.0, ((0.0, {"left_shoulder_flex": 25.0, "left_elbow_flex": -50.0, "right_shoulder_flex": -20.0,
                "left_hip_abd": 25.0, "left_hip_flex": 45.0, "left_knee_flex": 75.0, "left_hip_twist": 30.0,
                "yaw": 6.0, "waist_lateral": -8.0},), (0.5, {"right_shoulder_flex": 25.0, "right_elbow_flex": -50.0,
                "left_shoulder_flex": -20.0, "right_hip_abd": 25.0, "right_hip_flex": 45.0, "right_knee_flex": 75.0,
                "right_hip_twist": 30.0, "yaw": -6.0, "waist_lateral": 8.0},),))
_PRONE_CRAWL: Posture = {**PRONE, "shoulder_flex": 140.0, "shoulder_abd": 30.0, "elbow_flex": 100.0, "z": -0.8}
_JACK_ARMS = Cycle(2.0, ((0.12, {"shoulder_abd": 0.0}), (0.6, {"shoulder_abd": 150.0, "elbow_flex": -25.0})), sync=True)
_ROPE_ARMS = Cycle(1.0,
    ((0.0, {"shoulder_flex": 8.0, "shoulder_abd": -6.0}), (0.5, {"shoulder_flex": -8.0, "shoulder_abd": 6.0})),
    sync=True)
_DRIBBLE = Cycle(0.6, ((0.0, {"rh_z": 0.0}), (0.45, {"rh_z": -0.32, "rh_x": 0.06, "right_wrist_flex": 50.0}),
        (0.6, {"rh_z": -0.3, "rh_x": 0.06, "right_wrist_flex": 30.0}),))
_DRIBBLE_POSE: Posture = {"z": -0.1, "pitch": 12.0, "waist_flex": 12.0, "neck_flex": -8.0, "r_arm": 1.0, "rh_x": 0.3,
    "rh_y": -0.28, "rh_z": -0.05, "left_shoulder_flex": 40.0, "left_elbow_flex": 60.0, "left_shoulder_abd": 25.0,
    "f_w": 0.16}
_SHOT_HOLD: Posture = {**CARRY_BALL, "h_z": 0.22, "h_x": 0.30}
_SHOT_DIP: Posture = {**_SHOT_HOLD, "z": -0.14, "pitch": 10.0, "h_z": 0.14, "f_w": 0.14}
_SHOT_UP: Posture = {**CARRY_BALL, "h_x": 0.22, "h_w": 0.09, "h_z": 0.78, "f_pitch": 20.0, "f_w": 0.14,
    "neck_flex": -12.0, "right_shoulder_twist": 30.0}
_SHOT_FOLLOW: Posture = {**_SHOT_UP, "h_x": 0.38, "h_z": 0.74, "wrist_flex": 70.0, "f_pitch": 5.0}
_KICK_BACK = {"r_leg": 0.0, "right_hip_flex": -35.0, "right_knee_flex": 95.0, "right_ankle_flex": -35.0,
    "left_shoulder_abd": 45.0, "right_shoulder_flex": -25.0, "pitch": -2.0, "waist_twist": -10.0}
_KICK_HIT = {"r_leg": 0.0, "right_hip_flex": 50.0, "right_knee_flex": 38.0, "right_ankle_flex": -25.0, "z": 0.02,
    "left_shoulder_abd": 50.0, "right_shoulder_flex": -20.0, "left_shoulder_flex": 20.0, "pitch": -6.0,
    "waist_twist": 12.0}
_KICK_FOLLOW = {**_KICK_HIT, "right_hip_flex": 80.0, "right_knee_flex": 20.0, "pitch": -10.0}


def kick(t: float, extra: Posture = STAND, down: Posture = STAND) -> tuple[tuple[float, Posture], ...]:
    """A right-footed kick from ``t``: lift, draw back, swing through with a folded knee,
    extend into the ball, follow through, put the foot down (``down``)."""
    return seq((t, extra), (t + 0.25, {**extra, "rf_z": 0.2, "rf_x": extra.get("rf_x", 0.0) - 0.15,
                "left_shoulder_abd": 30.0, "right_hip_flex": -10.0, "right_knee_flex": 80.0},),
        (t + 0.5, {**extra, **_KICK_BACK}),
        (t + 0.65, {**extra, **_KICK_BACK, "right_hip_flex": 30.0, "right_knee_flex": 128.0, "right_ankle_flex": -5.0}),
        (t + 0.8, {**extra, **_KICK_HIT}), (t + 1.0, {**extra, **_KICK_FOLLOW}),
        (t + 1.35, {**down, **extra, "rf_z": 0.18, "rf_x": down.get("rf_x", 0.0) + 0.1}), (t + 1.75, down))


_FLINCH: Posture = {"z": -0.1, "x": -0.05, "pitch": 12.0, "waist_flex": 18.0, "neck_flex": 25.0,
    "shoulder_flex": 70.0, "shoulder_abd": 35.0, "elbow_flex": 125.0, "shoulder_twist": -30.0, "f_w": 0.13}
_RECOIL: Posture = {"waist_flex": -12.0, "pitch": -6.0, "neck_flex": -12.0, "shoulder_flex": 45.0, "elbow_flex": 70.0,
    "shoulder_abd": 20.0}
_PICK_LOW: Posture = {"z": -0.45, "pitch": 30.0, "waist_flex": 40.0, "neck_flex": -10.0, "r_arm": 1.0, "rh_x": 0.45,
    "rh_y": -0.16, "rh_z": 0.22, "left_shoulder_flex": 25.0, "left_elbow_flex": 40.0}
_POUR_BASE: Posture = {"arm": 1.0, "lh_x": 0.36, "lh_y": 0.02, "lh_z": 0.02, "rh_x": 0.36, "rh_y": -0.12,
    "rh_z": 0.14, "neck_flex": 18.0, "waist_flex": 6.0, "left_shoulder_twist": -20.0}
_POUR_TILT: Posture = {**_POUR_BASE, "rh_y": -0.06, "rh_z": 0.2, "right_wrist_dev": 30.0, "right_wrist_flex": 40.0,
    "right_shoulder_twist": -45.0}
_SURRENDER_KNEEL: Posture = {**KNEEL, **HANDS_UP, "neck_flex": 5.0}
_FLOOR_STAND: Posture = {"leg": 0.0, "snap": 1.0}  # standing on directly posed legs (for rolls)
_DEEP_SQUAT: Posture = {"leg": 0.0, "snap": 1.0, "hip_flex": 110.0, "knee_flex": 135.0, "ankle_flex": 30.0,
    "waist_flex": 20.0, "hip_abd": 10.0}


def _wave_osc(t0: float, t1: float, amp: float = 22.0, period: float = 0.55) -> Osc:
    return Osc("right_elbow_flex", amp, period, env=((t0, 0.0), (t0 + 0.3, 1.0), (t1 - 0.3, 1.0), (t1, 0.0)))


SPECS: dict[str, Spec] = {
    # ---- Walking.
    "walk_forward_01": walk(),
    "walk_forward_turn_left_01": walk(cyclic=False, speed=((0.0, 1.25), (10.5, 1.25), (12.2, 0.0)),
        turn=((0.0, 0.0), (4.5, 0.0), (5.2, 45.0), (6.5, 45.0), (7.2, 0.0))),
    "walk_circle_01": walk(speed=1.1, cadence=1.7, turn=360.0 / 28.0, style={"roll": -2.0}),
    "walk_looking_at_phone_01": walk(speed=0.95, cadence=1.6, swing=12.0, keys=seq((0.0, PHONE))),
    "walk_distracted_01": walk(speed=1.1, cadence=1.7, wander=8.0,
        keys=seq((0.0, {"neck_twist": 50.0, "waist_twist": 8.0, "neck_flex": -5.0})),
        osc=(Osc("neck_twist", 12.0, 5.0),)),
    "walk_side_by_side_01": walk(speed=1.15, cadence=1.75, osc=(Osc("neck_twist", -25.0, 7.6),)),
    "walk_hand_in_hand_01": walk(speed=1.0, cadence=1.6, swing=16.0, keys=seq((0.0, HOLD_HAND))),
    "walk_heel_to_toe_01": walk(speed=0.33, cadence=1.15, width=0.0, lift=0.05, sway=0.01, pelvis_yaw=2.0,
        heel_off=15.0, heel_strike=4.0, swing=4.0,
        keys=seq((0.0, {"shoulder_abd": 35.0, "elbow_flex": 25.0, "neck_flex": 25.0}))),
    "walk_balance_beam_01": walk(speed=0.42, cadence=1.15, width=0.0, lift=0.06, sway=0.015, heel_off=15.0, swing=0.0,
        keys=seq((0.0, {**ARMS_OUT, "neck_flex": 20.0})), osc=(Osc("left_shoulder_abd", 10.0, 2.6),
            Osc("right_shoulder_abd", -10.0, 2.6), Osc("waist_lateral", 4.0, 2.6),)),
    "walk_backwards_01": walk(speed=-0.6, cadence=1.5, lean=-1.0, torso=4.0, lift=0.07, style={"neck_twist": 8.0}),
    "walk_backward_look_back_01": walk(
        speed=-0.7, cadence=1.6, lift=0.07, osc=(Osc("neck_twist", 65.0, 5.4), Osc("waist_twist", 18.0, 5.4))),
    "walk_injured_knee_01": walk(speed=0.75, cadence=1.5, limp=0.08, stiff=0.07, stiff_lift=0.3, lift=0.07,
        heel_off=25.0, swing=14.0),
    "walk_with_limp_01": walk(speed=0.6, cadence=1.3, limp=0.06, stiff=0.06, stiff_lift=0.2, lift=0.07, swing=12.0),
    "walk_up_to_friend_hug_01": walk(cyclic=False, speed=((0.0, 1.2), (5.5, 1.2), (7.0, 0.0)), keys=seq((0.0, HUG)),
        blend=_w_on(6.3, 1.2), osc=(Osc("rh_z", 0.05, 0.6, env=((8.5, 0.0), (9.0, 1.0), (12.0, 1.0), (12.5, 0.0))),),
    ),
    "walk_bump_into_someone_01": walk(cyclic=False,
        speed=((0.0, 1.2), (4.3, 1.2), (4.6, 0.0), (5.1, 0.0), (5.5, -0.7), (7.0, -0.7), (7.6, 0.0)),
        keys=seq((0.0, _RECOIL)), blend=((0.0, 0.0), (4.3, 0.0), (4.55, 1.0), (5.6, 1.0), (7.2, 0.0))),
    "walk_dizzy_01": walk(speed=0.8, cadence=1.6, width=0.13, weave=0.25, weave_period=4.6, wander=10.0, sway=0.04,
        keys=seq((0.0, {"shoulder_abd": 25.0, "elbow_flex": 20.0})),
        osc=(Osc("waist_lateral", 8.0, 4.6), Osc("roll", 4.0, 4.6), Osc("neck_lateral", 10.0, 3.1))),
    "walk_stop_wave_01": walk(cyclic=False, speed=((0.0, 1.2), (6.0, 1.2), (7.5, 0.0)), keys=seq((0.0, WAVE_UP)),
        blend=_w_on(7.6, 0.8), osc=(_wave_osc(8.4, 15.6),)),
    "walk_pick_up_litter_01": walk(cyclic=False, speed=((0.0, 1.2), (8.0, 1.2), (9.3, 0.0), (13.7, 0.0), (15.0, 1.2)),
        hands="heading", keys=seq((0.0, _PICK_LOW)), blend=_w(9.5, 12.2, 1.2)),
    # ---- Running.
    "run_forward_01": run(),
    "jog_circle_01": run(speed=2.5, cadence=2.7, duty=0.38, lift=0.13, bob=-0.025, swing=28.0, elbow=75.0,
        turn=720.0 / 33.0, style={"roll": -4.0}),
    "jog_slow_tired_01": run(speed=2.0, cadence=2.5, duty=0.42, lift=0.08, bob=-0.02, swing=16.0, arm_fwd=2.0,
        elbow=60.0, lean=10.0, torso=8.0, keys=seq((0.0, {"neck_flex": 12.0}))),
    "sprint_short_01": _gait_spec(
        SPRINT, False, {"speed": ((0.0, 0.0), (0.3, 0.0), (2.2, 5.0), (5.2, 5.2), (8.0, 2.6), (9.2, 2.5))}),
    "run_away_panic_01": run(speed=4.0, swing=40.0, arm_out=14.0,
        osc=(Osc("neck_twist", 60.0, 3.5), Osc("waist_twist", 15.0, 3.5))),
    "sprint_away_01": _gait_spec(SPRINT, False, {"speed": ((0.0, 0.0), (0.4, 0.0), (2.6, 5.0), (10.4, 5.2))}),
    "turn_escape_running_01": run(cyclic=False, speed=((0.0, 0.0), (1.6, 0.0), (2.8, 4.5), (12.0, 5.0)),
        turn=((0.0, 0.0), (0.3, 0.0), (0.9, 150.0), (1.5, 150.0), (2.1, 0.0)), duty=None),
    "startled_flee_01": run(cyclic=False, speed=((0.0, 0.0), (1.3, 0.0), (2.5, 4.6), (8.8, 4.8)), duty=None,
        turn=((0.0, 0.0), (1.0, 0.0), (1.4, 170.0), (1.8, 170.0), (2.2, 0.0)), keys=seq((0.0, _FLINCH)),
        blend=((0.0, 0.0), (0.25, 0.0), (0.45, 1.0), (1.0, 1.0), (1.6, 0.0))),
    # ---- Stairs (rise 0.17 m, run 0.30 m, first riser 0.4 m ahead).
    "climb_up_stairs_01": walk(cyclic=False, stairs=1, speed=((0.0, 0.0), (0.3, 0.0), (1.5, 0.45), (16.0, 0.45)),
        cadence=1.5, lift=0.05, lean=8.0, torso=4.0, heel_off=30.0, plant_at=0.6),
    "climb_staircase_handrail_01": walk(cyclic=False, stairs=1,
        speed=((0.0, 0.0), (0.5, 0.0), (1.8, 0.36), (22.4, 0.36)), cadence=1.2, lift=0.05, lean=8.0, torso=4.0,
        heel_off=30.0, plant_at=0.6, hands="heading",
        keys=seq((0.0, {"r_arm": 1.0, "rh_x": 0.3, "rh_y": -0.42, "rh_z": 1.0, "right_shoulder_twist": 20.0}))),
    "go_down_stairs_01": walk(cyclic=False, stairs=-1, speed=((0.0, 0.0), (0.4, 0.0), (1.8, 0.39), (18.8, 0.39)),
        cadence=1.3, lift=0.04, lean=-2.0, torso=6.0, heel_off=5.0, heel_strike=-10.0, plant_at=0.35,
        keys=seq((0.0, {"neck_flex": 25.0}))),
    "run_up_stairs_01": run(cyclic=False, stairs=1, speed=((0.0, 0.0), (0.3, 0.0), (1.5, 1.2), (9.6, 1.2)),
        cadence=2.0, duty=0.45, lift=0.1, lean=16.0, bob=-0.02, plant_at=0.6, heel_off=35.0),
    # ---- Hair.
    "comb_hair_right_hand_01": gesture(seq((0.0, STAND), (1.2, _HAIR_R), (16.8, _HAIR_R), (18.0, STAND)),
        cycles=(Cycle(1.6, _HAIR_STROKE_R.keys, env=((1.2, 0.0), (1.6, 1.0), (16.5, 1.0), (16.8, 0.0))),)),
    "brush_hair_left_hand_01": gesture(
        seq((0.0, STAND), (1.5, mirror_posture(_HAIR_R)), (23.5, mirror_posture(_HAIR_R)), (25.0, STAND)), cycles=(
            Cycle(2.5, tuple((f, mirror_posture(k)) for f, k in _HAIR_STROKE_R.keys),
                env=((1.5, 0.0), (2.0, 1.0), (23.0, 1.0), (23.5, 0.0))),)),
    "brush_long_hair_seated_01": posture(seq(
            (0.0, {**SIT, **_HAIR_R, "rh_y": -0.12, "rh_z": 0.7, "neck_lateral": 12.0, "re_x": 0.5, "re_z": -0.2})),
        cycles=(Cycle(2.4, ((0.0, {"rh_z": 0.0}), (0.15, {"rh_z": 0.02}),
                    (0.45, {"rh_z": -0.2, "rh_y": -0.1, "rh_x": 0.12}),
                    (0.7, {"rh_z": -0.45, "rh_y": -0.08, "rh_x": 0.2}),)),), cyclic=True, style={"waist_flex": 5.0},
    ),
    # ---- Catching and throwing.
    "catch_ball_front_01": gesture(seq((0.0, STAND),
            (1.2, {**CARRY_BALL, "h_x": 0.42, "h_w": 0.14, "h_z": 0.28, "z": -0.04}),
            (2.4, {**CARRY_BALL, "h_x": 0.48, "h_w": 0.12, "h_z": 0.30, "z": -0.04}),
            (2.7, {**CARRY_BALL, "h_x": 0.45, "h_w": 0.07, "h_z": 0.30, "z": -0.05}),
            (3.2, {**CARRY_BALL, "z": -0.08, "pitch": 4.0}), (4.8, CARRY_BALL), (6.4, STAND))),
    "catch_ball_step_back_01": gesture(seq((0.0, STAND), (1.0, {**CARRY_BALL, "h_x": 0.42, "h_w": 0.14, "h_z": 0.28}),
            (2.2, {**CARRY_BALL, "h_x": 0.48, "h_w": 0.07, "h_z": 0.32}),
            (2.7, {**CARRY_BALL, "rf_x": -0.12, "rf_z": 0.08, "x": -0.06, "z": -0.05}),
            (3.1, {**CARRY_BALL, "rf_x": -0.38, "x": -0.18, "z": -0.08, "pitch": 6.0}),
            (4.4, {**CARRY_BALL, "rf_x": -0.38, "x": -0.16}), (5.8, {"rf_x": -0.38, "x": -0.16}))),
    "play_catch_partner_01": gesture(repeat(seq((0.0, {**CARRY_BALL, "h_x": 0.25}), (0.9, {"r_arm": 0.0, "l_arm": 0.0,
                        "right_shoulder_abd": 85.0, "right_shoulder_twist": 75.0, "right_elbow_flex": 95.0,
                        "right_shoulder_flex": -15.0, "left_shoulder_flex": 60.0, "waist_twist": -25.0, "yaw": -10.0,
                        "lf_x": 0.15},), (1.25, {"right_shoulder_flex": 110.0, "right_shoulder_abd": 40.0,
                        "right_elbow_flex": 15.0, "waist_twist": 20.0, "waist_flex": 15.0, "left_shoulder_flex": 10.0,
                        "lf_x": 0.15, "yaw": 8.0},), (1.7, {"right_shoulder_flex": 40.0, "right_shoulder_abd": -10.0,
                        "right_elbow_flex": 30.0, "waist_flex": 18.0, "lf_x": 0.15},),
                (3.0, {**CARRY_BALL, "h_x": 0.44, "h_w": 0.14, "h_z": 0.30}),
                (4.2, {**CARRY_BALL, "h_x": 0.47, "h_w": 0.13, "h_z": 0.30}),
                (4.5, {**CARRY_BALL, "h_x": 0.42, "h_w": 0.07, "h_z": 0.28, "z": -0.05}),
                (6.0, {**CARRY_BALL, "h_x": 0.25})), 6.0, 6), cyclic=True),
    "throw_baseball_overhand_01": gesture(seq((0.0, STAND), (0.6, {**CARRY_BALL, "h_z": 0.2}), (1.3, {"lf_z": 0.22,
                    "lf_x": 0.05, "right_shoulder_abd": 70.0, "right_shoulder_flex": -35.0, "right_elbow_flex": 70.0,
                    "left_shoulder_flex": 40.0, "waist_twist": -30.0, "yaw": -20.0, "z": -0.06},), (1.8, {"lf_x": 0.6,
                    "x": 0.22, "z": -0.12, "right_shoulder_abd": 90.0, "right_shoulder_twist": 80.0,
                    "right_elbow_flex": 95.0, "left_shoulder_flex": 80.0, "left_shoulder_abd": 20.0,
                    "waist_twist": -35.0, "yaw": -15.0, "waist_lateral": -8.0},), (2.05, {"lf_x": 0.6, "x": 0.32,
                    "z": -0.12, "right_shoulder_abd": 75.0, "right_shoulder_flex": 60.0, "right_shoulder_twist": 10.0,
                    "right_elbow_flex": 25.0, "left_shoulder_flex": 20.0, "left_elbow_flex": 60.0,
                    "waist_twist": 25.0, "waist_flex": 20.0, "yaw": 10.0},), (2.45, {"lf_x": 0.6, "x": 0.4, "z": -0.1,
                    "rf_pitch": 40.0, "right_shoulder_flex": 60.0, "right_shoulder_abd": -15.0,
                    "right_elbow_flex": 30.0, "left_elbow_flex": 70.0, "waist_twist": 35.0, "waist_flex": 35.0,
                    "pitch": 10.0, "yaw": 15.0},), (3.6, {"lf_x": 0.6, "rf_x": 0.35, "x": 0.45}),
            (5.0, {"lf_x": 0.6, "rf_x": 0.35, "x": 0.45}))),
    "throw_frisbee_01": gesture(seq((0.0, STAND),
            (0.7, {"right_shoulder_flex": 50.0, "right_elbow_flex": 80.0, "right_shoulder_abd": 10.0}), (1.5, {
                    "rf_x": 0.25, "rf_y": -0.3, "x": 0.08, "y": -0.06, "z": -0.06, "right_shoulder_flex": 75.0,
                    "right_shoulder_abd": -35.0, "right_elbow_flex": 110.0, "waist_twist": 35.0, "yaw": 15.0,
                    "neck_twist": -35.0},), (1.85, {"rf_x": 0.25, "rf_y": -0.3, "x": 0.12, "y": -0.1, "z": -0.08,
                    "right_shoulder_flex": 85.0, "right_shoulder_abd": 45.0, "right_elbow_flex": 15.0,
                    "waist_twist": -20.0, "yaw": -10.0, "neck_twist": -10.0},), (2.2, {"rf_x": 0.25, "rf_y": -0.3,
                    "x": 0.12, "y": -0.1, "z": -0.06, "right_shoulder_flex": 70.0, "right_shoulder_abd": 80.0,
                    "right_elbow_flex": 10.0, "waist_twist": -35.0, "yaw": -15.0},),
            (3.6, {"rf_x": 0.25, "rf_y": -0.3, "x": 0.1, "y": -0.08}),
            (5.6, {"rf_x": 0.25, "rf_y": -0.3, "x": 0.1, "y": -0.08}))),
    # ---- Clapping and waving.
    "clap_rhythm_01": gesture(seq((0.0, _CLAP_POSE)), cycles=(_CLAP,), cyclic=True),
    "clap_once_01": gesture(
        seq((0.0, {**_CLAP_POSE, "h_w": 0.14}), (0.3, _CLAP_POSE), (0.6, {**_CLAP_POSE, "h_w": 0.14}))),
    "clap_above_head_01": gesture(seq((0.0, {**_CLAP_POSE, "h_x": 0.16, "h_z": 0.8, "neck_flex": -15.0})),
        cycles=(Cycle(0.55, _CLAP.keys),), cyclic=True),
    "applause_cheer_01": gesture(repeat(seq((0.0, _CLAP_POSE), (3.2, _CLAP_POSE), (3.7, {"shoulder_abd": 140.0,
                        "shoulder_flex": 20.0, "elbow_flex": 20.0, "neck_flex": -15.0, "f_pitch": 15.0},),
                (4.1, {"shoulder_abd": 145.0, "shoulder_flex": 20.0, "elbow_flex": 15.0, "neck_flex": -15.0}),
                (4.47, _CLAP_POSE)), 4.47, 3), cycles=(Cycle(0.45, _CLAP.keys, env=((0.0, 1.0), (3.1, 1.0),
                    (3.3, 0.0), (4.4, 0.0), (4.5, 1.0), (7.5, 1.0), (7.7, 0.0), (8.8, 0.0), (9.0, 1.0), (12.0, 1.0),
                    (12.2, 0.0), (13.3, 0.0), (13.4, 1.0),)),), osc=(Osc("z", 0.02, 0.9),), cyclic=True),
    "wave_hello_right_01": gesture(
        seq((0.0, STAND), (0.8, WAVE_UP), (5.2, WAVE_UP), (6.0, STAND)), osc=(_wave_osc(0.8, 5.2),)),
    "wave_goodbye_both_arms_01": gesture(seq((0.0, STAND),
            (1.0, {"shoulder_abd": 150.0, "elbow_flex": 15.0, "shoulder_flex": 10.0}),
            (8.6, {"shoulder_abd": 150.0, "elbow_flex": 15.0, "shoulder_flex": 10.0}), (9.6, STAND)), osc=(
            Osc("left_shoulder_abd", 18.0, 1.0, env=((1.0, 0.0), (1.4, 1.0), (8.2, 1.0), (8.6, 0.0))),
            Osc("right_shoulder_abd", -18.0, 1.0, env=((1.0, 0.0), (1.4, 1.0), (8.2, 1.0), (8.6, 0.0))),)),
    "waving_across_street_01": gesture(seq((0.0, STAND), (1.0, {"right_shoulder_abd": 155.0,
                    "right_shoulder_flex": 15.0, "right_elbow_flex": 15.0, "waist_lateral": -8.0, "f_pitch": 10.0,
                    "neck_flex": -8.0},), (10.2, {"right_shoulder_abd": 155.0, "right_shoulder_flex": 15.0,
                    "right_elbow_flex": 15.0, "waist_lateral": -8.0, "f_pitch": 10.0, "neck_flex": -8.0},),
            (11.2, STAND)),
        osc=(Osc("right_shoulder_abd", 22.0, 0.8, env=((1.0, 0.0), (1.4, 1.0), (9.8, 1.0), (10.2, 0.0))),)),
    "wave_once_01": gesture(seq((0.0, STAND), (0.25, WAVE_UP), (0.4, {**WAVE_UP, "right_elbow_flex": 55.0}),
            (0.55, {**WAVE_UP, "right_elbow_flex": 100.0}), (0.8, STAND))),
    # ---- Sports.
    "golf_full_swing_01": gesture(
        posed_arms(((0.0, STAND), *golf_swing(1.5), (7.0, _GOLF_STANCE), (8.0, STAND))), rigid=_ARM_CHANNELS),
    "golf_putt_01": gesture(seq((0.0, STAND), (1.2, {**_GOLF_STANCE, **_arc(0.0), "waist_flex": 32.0}), *(
                (1.2 + 1.3 * i + dt, {**_GOLF_STANCE, **_arc(a), "waist_flex": 32.0})
                for i, amp in enumerate((10, 10, 18)) for dt, a in ((0.5, -amp), (1.0, amp * 0.8), (1.3, 0.0))),
            (6.0, {**_GOLF_STANCE, **_arc(0.0), "waist_flex": 20.0, "neck_twist": 40.0}), (7.0, STAND))),
    "golf_chip_practice_01": gesture(posed_arms(((0.0, STAND), *golf_swing(1.0, 0.45), *golf_swing(4.3, 0.45),
                *golf_swing(8.0, 0.65), (13.6, STAND), (14.4, STAND),)), rigid=_ARM_CHANNELS),
    "kick_soccer_ball_01": gesture(seq((0.0, STAND),
            *kick(1.2, {"lf_x": 0.3, "lf_y": 0.16, "x": 0.2}, {"lf_x": 0.3, "lf_y": 0.16, "rf_x": 0.45, "x": 0.35}),
            (5.6, {"lf_x": 0.3, "lf_y": 0.16, "rf_x": 0.45, "x": 0.35}))),
    "dribble_kick_ball_01": run(cyclic=False, speed=((0.0, 2.0), (8.2, 2.0), (9.3, 0.3), (10.4, 0.0)), cadence=3.0,
        duty=0.4, lift=0.08, swing=25.0, elbow=60.0, arm_out=25.0, lean=9.0,
        keys=((0.0, STAND), *kick(9.8, {"z": 0.09})), blend=_w(9.6, 11.4, 0.3), osc=(Osc("neck_flex", 8.0, 1.5),)),
    "penalty_kick_01": run(cyclic=False, speed=((0.0, 0.0), (1.2, 0.0), (2.2, 3.0), (4.0, 3.0), (5.1, 0.0)),
        duty=None, cadence=None, keys=((0.0, STAND), *kick(5.1, {"z": 0.09})), blend=_w(4.9, 6.9, 0.3)),
    "martial_front_kick_01": gesture(seq((0.0, GUARD), (0.16, {**GUARD, "r_leg": 0.0, "right_hip_flex": 85.0,
                    "right_knee_flex": 115.0, "right_ankle_flex": -20.0, "pitch": -4.0},), (0.33, {**GUARD,
                    "r_leg": 0.0, "right_hip_flex": 88.0, "right_knee_flex": 5.0, "right_ankle_flex": 25.0,
                    "pitch": -10.0},), (0.47, {**GUARD, "r_leg": 0.0, "right_hip_flex": 80.0,
                    "right_knee_flex": 110.0, "right_ankle_flex": -20.0, "pitch": -4.0},), (0.7, GUARD))),
    "basketball_set_shot_01": gesture(seq((0.0, STAND), (1.0, _SHOT_HOLD), (2.0, _SHOT_DIP), (2.5, _SHOT_UP),
            (2.8, _SHOT_FOLLOW), (4.2, _SHOT_FOLLOW), (5.5, STAND), (7.2, STAND))),
    "basketball_jump_shot_01": Spec(family="gesture", gait=replace(HOP,
            phase_keys=((0.0, 0.2), (7.4, 0.49), (7.6, 0.52), (8.15, 0.98), (8.4, 1.05), (11.8, 1.25)), lift=0.3,
            heel_off=35.0), keys=seq((0.0, {**_DRIBBLE_POSE, "leg": 1.0}), (6.3, {**_DRIBBLE_POSE}),
            (6.8, _SHOT_HOLD), (7.35, {**_SHOT_DIP, "z": -0.18}), (7.6, {**_SHOT_UP, "z": 0.02}),
            (7.85, {**_SHOT_UP, "z": 0.3}), (8.05, {**_SHOT_FOLLOW, "z": 0.18}), (8.3, {**_SHOT_FOLLOW, "z": -0.12}),
            (9.5, STAND), (11.8, STAND)),
        cycles=(Cycle(0.6, _DRIBBLE.keys, env=((0.0, 1.0), (6.0, 1.0), (6.3, 0.0))),)),
    "basketball_free_throw_01": gesture(seq((0.0, {**_DRIBBLE_POSE, "z": -0.05}),
            (2.4, {**_DRIBBLE_POSE, "z": -0.05}), (3.2, _SHOT_HOLD), (4.3, _SHOT_DIP), (4.8, _SHOT_UP),
            (5.1, _SHOT_FOLLOW), (6.5, _SHOT_FOLLOW), (8.0, STAND)),
        cycles=(Cycle(0.8, _DRIBBLE.keys, env=((0.0, 1.0), (2.2, 1.0), (2.5, 0.0))),)),
    "dribble_basketball_01": gesture(seq((0.0, _DRIBBLE_POSE)), cycles=(_DRIBBLE,), cyclic=True,
        osc=(Osc("z", 0.015, 0.6, 0.3), Osc("neck_twist", 15.0, 4.9))),
    "baseball_swing_right_01": gesture(
        posed_arms(((0.0, STAND), *bat_swing(1.2), (4.8, _BAT_STANCE), (6.2, STAND))), rigid=_ARM_CHANNELS),
    "baseball_batting_stance_01": gesture(posed_arms(((0.0, STAND),
                (1.0, {**_BAT_STANCE, **_arc(-45, r=0.32, plane="bat"), "rh_z": 0.36, "lh_z": 0.30}), *bat_swing(4.6),
                (8.8, {**_BAT_STANCE, **_arc(58, r=0.28, plane="bat"), "lh_z": 0.45, "rh_z": 0.5, "waist_twist": 40.0,
                        "yaw": 30.0, "lf_y": 0.40},),)),
        osc=(Osc("shoulder_flex", 5.0, 0.9, env=((1.0, 0.0), (1.5, 1.0), (4.0, 1.0), (4.5, 0.0))),),
        rigid=_ARM_CHANNELS),
    "bat_practice_swings_01": gesture(posed_arms(tuple((t, mirror_posture(k)) for t, k in repeat(bat_swing(0.3)
                    + ((4.3, {**_BAT_STANCE, **_arc(-45, r=0.32, plane="bat"), "rh_z": 0.36, "lh_z": 0.30}),), 4.6, 4,
                ))), rigid=_ARM_CHANNELS),
    # ---- Archery and firearms.
    "archery_draw_release_01": gesture(
        ((0.0, STAND), *bow_draw(1.2, hold=2.0), (9.4, STAND), (10.4, STAND)), style={"waist_flex": -5.0}),
    "archery_nock_aim_01": gesture(((0.0, STAND), (1.5, {"arm": 1.0, "lh_x": 0.3, "lh_y": 0.05, "lh_z": -0.05,
                    "rh_x": 0.3, "rh_y": -0.02, "rh_z": 0.0, "neck_flex": 25.0},), (4.0, {"arm": 1.0, "lh_x": 0.3,
                    "lh_y": 0.05, "lh_z": -0.05, "rh_x": 0.28, "rh_y": 0.02, "rh_z": -0.02, "neck_flex": 25.0},),
            *bow_draw(5.2, hold=6.5, release=False), (14.8, STAND), (16.0, STAND),),
        osc=(Osc("lh_z", 0.01, 1.3, env=((8.0, 0.0), (8.5, 1.0), (13.5, 1.0), (13.8, 0.0))),)),
    "longbow_kneeling_01": posture(((0.0, HALF_KNEEL),
            *tuple((t, {**HALF_KNEEL, **k}) for t, k in bow_draw(1.0, hold=1.5)), (6.0, {**HALF_KNEEL, "arm": 1.0,
                    "lh_x": 0.35, "lh_y": 0.1, "lh_z": 0.0, "rh_x": 0.3, "rh_y": -0.1, "rh_z": 0.0},),
            *tuple((t, {**HALF_KNEEL, **k}) for t, k in bow_draw(6.8, hold=1.5)), (12.8, HALF_KNEEL),)),
    "take_a_bow_01": gesture(seq((0.0, STAND),
            (0.6, {"right_shoulder_flex": 30.0, "right_elbow_flex": 95.0, "right_shoulder_twist": -50.0}), (1.5, {
                    "pitch": 28.0, "waist_flex": 38.0, "neck_flex": 15.0, "right_shoulder_flex": 60.0,
                    "right_elbow_flex": 100.0, "right_shoulder_twist": -50.0, "left_shoulder_flex": 40.0},), (2.5, {
                    "pitch": 28.0, "waist_flex": 40.0, "neck_flex": 18.0, "right_shoulder_flex": 60.0,
                    "right_elbow_flex": 100.0, "right_shoulder_twist": -50.0, "left_shoulder_flex": 40.0},),
            (3.5, STAND), (4.4, STAND))),
    "pistol_two_hands_01": gesture(((0.0, STAND), (1.2, {**GUN, "z": -0.04, "f_w": 0.14}), *((1.2 + 1.5 * i + dt, {
                        **GUN, "z": -0.04, "f_w": 0.14, "lh_z": GUN["lh_z"] + dz, "rh_z": GUN["rh_z"] + dz,
                        "wrist_flex": -5.0 - 150 * dz},) for i in range(1, 5)
                for dt, dz in ((0.0, 0.0), (0.08, 0.06), (0.35, 0.0))), (8.0, {**GUN, "z": -0.04, "f_w": 0.14}),
            (9.0, STAND),)),
    "rifle_shoulder_standing_01": gesture(((0.0, STAND), (1.5, {"arm": 1.0, "lh_x": 0.45, "lh_y": -0.04, "lh_z": 0.18,
                    "rh_x": 0.1, "rh_y": -0.14, "rh_z": 0.3, "right_shoulder_twist": 65.0, "neck_lateral": 10.0,
                    "neck_flex": 10.0, "lf_x": 0.18, "yaw": -15.0, "waist_twist": 10.0},), *((1.5 + 2.0 * i + dt, {
                        "arm": 1.0, "lh_x": 0.45, "lh_y": -0.04, "lh_z": 0.18 + dz, "rh_x": 0.1 - dz, "rh_y": -0.14,
                        "rh_z": 0.3, "right_shoulder_twist": 65.0, "neck_lateral": 10.0, "neck_flex": 10.0,
                        "lf_x": 0.18, "yaw": -15.0, "waist_twist": 10.0, "waist_flex": -60 * dz},)
                for i in range(1, 5) for dt, dz in ((0.0, 0.0), (0.1, 0.05), (0.5, 0.0))), (11.0, {"lf_x": 0.18}),
            (12.0, {"lf_x": 0.18}),)),
    "handgun_walking_01": walk(
        speed=0.9, cadence=1.6, swing=0.0, keys=seq((0.0, GUN)), osc=(Osc("neck_twist", 10.0, 4.9),)),
    # ---- Jumping and hopping.
    "jump_forward_both_feet_01": Spec(family="cycle", gait=replace(HOP,
            phase_keys=((0.0, 0.25), (1.55, 0.49), (1.7, 0.52), (2.15, 0.98), (2.35, 1.1), (4.8, 1.3)), lift=0.22,
            px=((0.0, 0.0), (1.68, 0.0), (2.17, 1.0), (4.8, 1.0))), keys=seq((0.0, STAND),
            (1.0, {"z": -0.05, "shoulder_flex": 30.0}),
            (1.5, {"z": -0.24, "pitch": 25.0, "waist_flex": 10.0, "shoulder_flex": -45.0, "elbow_flex": 15.0}),
            (1.7, {"z": 0.0, "pitch": 15.0, "shoulder_flex": 100.0}),
            (1.93, {"z": 0.2, "pitch": 10.0, "shoulder_flex": 90.0, "hip_flex": 20.0}),
            (2.15, {"z": -0.04, "pitch": 15.0, "shoulder_flex": 70.0}),
            (2.4, {"z": -0.25, "pitch": 25.0, "waist_flex": 10.0, "shoulder_flex": 60.0}), (3.4, STAND), (4.8, STAND),
        ), guard=True),
    "jump_vertical_01": Spec(family="cycle", gait=replace(HOP, phase_keys=((0.0, 0.25), (1.75, 0.49), (1.9, 0.52),
                (2.48, 0.98), (2.7, 1.1), (3.7, 1.25), (4.15, 1.49), (4.3, 1.52), (4.88, 1.98), (5.1, 2.1),
                (6.0, 2.25),), lift=0.4), keys=repeat(seq((0.0, STAND), (0.9, {"z": -0.05, "shoulder_flex": 20.0}),
                (1.65, {"z": -0.28, "pitch": 22.0, "waist_flex": 10.0, "shoulder_flex": -40.0}),
                (1.9, {"z": 0.0, "pitch": 5.0, "shoulder_flex": 130.0}),
                (2.19, {"z": 0.4, "shoulder_flex": 170.0, "neck_flex": -15.0}),
                (2.48, {"z": -0.02, "shoulder_flex": 60.0}), (2.7, {"z": -0.22, "pitch": 15.0}), (3.4, STAND)), 2.4,
            2, 0.0) + ((6.0, STAND),), guard=True),
    "jumping_jacks_01": Spec(family="cycle",
        gait=replace(HOP, cadence=2.0, duty=0.55, lift=0.06, width=0.09, width2=0.33, loop_multiple=2),
        cycles=(_JACK_ARMS, hop_z(0.06, 0.05, 0.55)), cyclic=True, guard=True),
    "standing_long_jump_01": Spec(family="cycle", gait=replace(HOP,
            phase_keys=((0.0, 0.25), (2.15, 0.49), (2.3, 0.52), (2.95, 0.98), (3.2, 1.1), (7.6, 1.3)), lift=0.3,
            px=((0.0, 0.0), (2.27, 0.0), (2.98, 1.8), (7.6, 1.8))), keys=seq((0.0, STAND),
            (0.8, {"shoulder_flex": 60.0, "f_pitch": 15.0}),
            (1.5, {"z": -0.15, "pitch": 20.0, "shoulder_flex": -40.0}),
            (2.05, {"z": -0.3, "pitch": 35.0, "waist_flex": 15.0, "shoulder_flex": -50.0, "elbow_flex": 10.0}),
            (2.3, {"z": -0.02, "pitch": 30.0, "shoulder_flex": 100.0}),
            (2.62, {"z": 0.2, "pitch": 20.0, "shoulder_flex": 100.0, "hip_flex": 40.0}),
            (2.95, {"z": -0.1, "pitch": 25.0, "shoulder_flex": 80.0}),
            (3.3, {"z": -0.45, "pitch": 35.0, "waist_flex": 20.0, "shoulder_flex": 70.0}),
            (4.3, {"z": -0.45, "pitch": 35.0, "waist_flex": 20.0, "shoulder_flex": 40.0}), (6.0, STAND), (7.6, STAND),
        ), guard=True),
    "jump_rope_01": Spec(family="cycle", gait=replace(HOP, cadence=2.2, lift=0.07, width=0.08),
        keys=seq((0.0, {"shoulder_abd": 22.0, "elbow_flex": 70.0, "shoulder_flex": 5.0, "shoulder_twist": 20.0})),
        cycles=(_ROPE_ARMS, hop_z(0.05, 0.04)), cyclic=True, guard=True),
    "hop_one_foot_01": Spec(family="cycle",
        gait=replace(HOP, feet="right", cadence=2.0, duty=0.45, lift=0.08, width=0.02, speed=0.15), keys=seq((0.0, {
                    "l_leg": 0.0, "left_hip_flex": 30.0, "left_knee_flex": 80.0, "left_ankle_flex": -20.0, "y": -0.05,
                    "shoulder_abd": 30.0, "elbow_flex": 30.0, "roll": -3.0},)), cycles=(hop_z(0.05, 0.05, 0.45),),
        cyclic=True, guard=True),
    "hopping_left_leg_01": Spec(family="cycle",
        gait=replace(HOP, feet="left", cadence=1.9, duty=0.45, lift=0.09, width=0.02, speed=0.5), keys=seq((0.0, {
                    "r_leg": 0.0, "right_hip_flex": 20.0, "right_knee_flex": 90.0, "right_ankle_flex": -25.0,
                    "y": 0.05, "shoulder_abd": 20.0, "elbow_flex": 50.0, "roll": 3.0},)), cycles=(
            hop_z(0.06, 0.05, 0.45),
            Cycle(1.0, ((0.0, {"shoulder_flex": -15.0}), (0.5, {"shoulder_flex": 25.0})), sync=True),), cyclic=True,
        guard=True),
    "bunny_hops_01": Spec(family="cycle",
        gait=replace(HOP, speed=1.0, cadence=1.6, duty=0.45, lift=0.14, heel_off=35.0), cycles=(
            hop_z(0.1, 0.12, 0.45), Cycle(1.0, ((0.0, {"shoulder_flex": 10.0, "pitch": 10.0}),
                    (0.25, {"shoulder_flex": -35.0, "pitch": 22.0}), (0.5, {"shoulder_flex": 60.0, "pitch": 12.0}),),
                sync=True),), cyclic=True, guard=True),
    "hop_once_01": Spec(family="cycle", gait=replace(
            HOP, phase_keys=((0.0, 0.22), (0.16, 0.49), (0.19, 0.52), (0.34, 0.98), (0.38, 1.05), (0.5, 1.2)), lift=0.09
        ), keys=seq((0.0, STAND), (0.12, {"z": -0.07, "shoulder_flex": -10.0}),
            (0.19, {"z": 0.0, "shoulder_flex": 15.0}), (0.265, {"z": 0.06, "shoulder_flex": 15.0}),
            (0.34, {"z": -0.02}), (0.42, {"z": -0.05}), (0.5, STAND)), guard=True),
    "hip_hop_dance_01": walk(speed=0.0, cadence=2.0, weave=0.35, weave_period=4.0, lift=0.07, swing=0.0, crouch=-0.06,
        keys=seq((0.0, {"elbow_flex": 60.0, "shoulder_abd": 20.0, "pitch": 8.0})), cycles=(
            Cycle(0.5, ((0.0, {"z": 0.0, "neck_flex": -6.0}), (0.5, {"z": -0.05, "neck_flex": 8.0}))), Cycle(4.0, (
                    (0.0, {"left_shoulder_flex": 60.0, "right_shoulder_flex": -10.0, "waist_twist": 15.0}), (0.25, {
                            "left_shoulder_flex": 10.0, "right_shoulder_flex": 90.0, "right_elbow_flex": 30.0,
                            "waist_twist": -15.0, "waist_lateral": 10.0},),
                    (0.5, {"shoulder_abd": 60.0, "elbow_flex": 40.0, "waist_flex": 12.0}), (0.75, {
                            "left_shoulder_flex": 100.0, "left_shoulder_abd": 40.0, "right_shoulder_flex": 20.0,
                            "waist_twist": 20.0, "waist_lateral": -10.0},),)),), osc=(Osc("waist_flex", 6.0, 1.0),),
    ),
    # ---- Object manipulation.
    "push_heavy_box_01": walk(speed=0.45, cadence=1.3, lift=0.05, crouch=-0.06, lean=22.0, torso=12.0, heel_off=35.0,
        hands="heading",
        keys=seq((0.0, {"arm": 1.0, "h_x": 0.62, "h_w": 0.2, "h_z": 1.0, "neck_flex": -20.0, "shoulder_twist": -20.0})),
    ),
    "push_shopping_cart_01": walk(speed=1.0, cadence=1.6, lean=6.0, torso=5.0, hands="heading",
        keys=seq((0.0, {"arm": 1.0, "h_x": 0.46, "h_w": 0.22, "h_z": 1.0, "shoulder_twist": -15.0}))),
    "push_open_door_01": walk(cyclic=False,
        speed=((0.0, 0.9), (1.6, 0.9), (2.3, 0.15), (3.6, 0.25), (4.4, 0.9), (6.8, 0.9)), hands="heading", keys=seq(
            (0.0, {"arm": 1.0, "h_x": 0.42, "h_w": 0.18, "h_z": 1.2}),
            (2.0, {"arm": 1.0, "h_x": 0.42, "h_w": 0.18, "h_z": 1.2}),
            (3.6, {"arm": 1.0, "h_x": 0.58, "h_w": 0.18, "h_z": 1.2, "pitch": 12.0, "waist_flex": 6.0})),
        blend=_w(1.4, 3.6, 0.6)),
    "push_ups_01": cycle(keys=seq((0.0, _PLANK)), hands="heading", cyclic=True, cycles=(
            Cycle(2.0, ((0.0, {}), (0.45, {"pitch": 9.0, "neck_flex": 8.0}), (0.6, {"pitch": 9.0, "neck_flex": 8.0}))),
        )),
    "pick_up_box_01": posture(seq((0.0, STAND), (1.0, STAND),
            (2.4, {**SQUAT, "z": -0.42, "arm": 1.0, "h_x": 0.5, "h_w": 0.22, "h_z": 0.25}),
            (3.4, {**SQUAT, "z": -0.42, "arm": 1.0, "h_x": 0.5, "h_w": 0.2, "h_z": 0.25}),
            (5.0, {"arm": 1.0, "h_x": 0.38, "h_w": 0.2, "h_z": 0.95, "pitch": -4.0, "waist_flex": -4.0}),
            (8.4, {"arm": 1.0, "h_x": 0.38, "h_w": 0.2, "h_z": 0.95, "pitch": -4.0, "waist_flex": -4.0})),
        hands="heading"),
    "pick_up_object_floor_01": posture(seq((0.0, STAND), (0.8, STAND),
            (2.2, {**_PICK_LOW, "z": -0.25, "pitch": 45.0, "waist_flex": 45.0, "rf_x": -0.15}),
            (3.0, {**_PICK_LOW, "z": -0.25, "pitch": 45.0, "waist_flex": 45.0, "rf_x": -0.15, "rh_z": 0.2}),
            (4.5, {"r_arm": 1.0, "rh_x": 0.35, "rh_y": -0.2, "rh_z": 0.95, "right_wrist_flex": 20.0}),
            (6.2, {"r_arm": 1.0, "rh_x": 0.35, "rh_y": -0.2, "rh_z": 0.95, "right_wrist_flex": 20.0})),
        hands="heading"),
    "pour_water_bottle_cup_01": gesture(seq((0.0, STAND), (1.5, _POUR_BASE), (3.0, _POUR_TILT),
            (7.0, {**_POUR_TILT, "right_wrist_dev": 35.0}), (8.5, _POUR_BASE), (11.0, STAND)),
        osc=(Osc("right_wrist_flex", 6.0, 1.0, env=((3.0, 0.0), (3.5, 1.0), (7.0, 1.0), (7.5, 0.0))),)),
    "pour_from_pitcher_01": gesture(seq((0.0, _TABLE), (1.5, {**_TABLE, "arm": 1.0, "lh_x": 0.42, "lh_y": 0.08,
                    "lh_z": 0.98, "rh_x": 0.5, "rh_y": -0.22, "rh_z": 0.98, "left_shoulder_twist": -20.0},), (3.0, {
                    **_TABLE, "arm": 1.0, "lh_x": 0.42, "lh_y": 0.08, "lh_z": 0.98, "rh_x": 0.42, "rh_y": -0.08,
                    "rh_z": 1.18, "left_shoulder_twist": -20.0},), (4.5, {**_TABLE, "arm": 1.0, "lh_x": 0.42,
                    "lh_y": 0.08, "lh_z": 0.98, "rh_x": 0.42, "rh_y": -0.04, "rh_z": 1.2, "right_wrist_dev": 32.0,
                    "right_wrist_flex": 35.0, "right_shoulder_twist": -50.0, "left_shoulder_twist": -20.0},), (9.0, {
                    **_TABLE, "arm": 1.0, "lh_x": 0.42, "lh_y": 0.08, "lh_z": 0.98, "rh_x": 0.42, "rh_y": -0.04,
                    "rh_z": 1.2, "right_wrist_dev": 35.0, "right_wrist_flex": 40.0, "right_shoulder_twist": -50.0,
                    "left_shoulder_twist": -20.0},), (10.5, {**_TABLE, "arm": 1.0, "lh_x": 0.42, "lh_y": 0.08,
                    "lh_z": 0.98, "rh_x": 0.5, "rh_y": -0.22, "rh_z": 0.98},), (12.0, _TABLE), (13.6, _TABLE)),
        hands="heading"),
    "pour_cereal_bowl_01": gesture(seq((0.0, STAND), (1.3, {"arm": 1.0, "lh_x": 0.36, "lh_y": 0.1, "lh_z": 0.25,
                    "rh_x": 0.36, "rh_y": -0.1, "rh_z": 0.2, "neck_flex": 20.0, "shoulder_twist": -20.0},), (2.6, {
                    "arm": 1.0, "lh_x": 0.38, "lh_y": 0.06, "lh_z": 0.32, "rh_x": 0.38, "rh_y": -0.08, "rh_z": 0.16,
                    "wrist_dev": 25.0, "right_wrist_flex": 30.0, "neck_flex": 25.0, "shoulder_twist": -35.0},), (6.5,
                {"arm": 1.0, "lh_x": 0.38, "lh_y": 0.04, "lh_z": 0.35, "rh_x": 0.38, "rh_y": -0.08, "rh_z": 0.15,
                    "wrist_dev": 30.0, "right_wrist_flex": 35.0, "neck_flex": 25.0, "shoulder_twist": -35.0},), (7.8,
                {"arm": 1.0, "lh_x": 0.36, "lh_y": 0.1, "lh_z": 0.25, "rh_x": 0.36, "rh_y": -0.1, "rh_z": 0.2,
                    "neck_flex": 20.0, "shoulder_twist": -20.0},), (9.8, STAND)),
        osc=(Osc("lh_z", 0.02, 0.5, env=((2.6, 0.0), (3.0, 1.0), (6.2, 1.0), (6.5, 0.0))),)),
    "sweep_floor_broom_01": walk(speed=0.22, cadence=0.9, lean=12.0, torso=10.0, swing=0.0, keys=seq((0.0, {
                    "arm": 1.0, "lh_x": 0.28, "lh_y": -0.08, "lh_z": 0.12, "rh_x": 0.42, "rh_y": -0.22, "rh_z": -0.25,
                    "neck_flex": 20.0},)), cycles=(Cycle(1.6, (
                    (0.0, {"h_w": 0.0, "lh_y": 0.12, "rh_y": 0.22, "waist_twist": 15.0}),
                    (0.55, {"lh_y": -0.08, "rh_y": -0.18, "waist_twist": -15.0}),)),)),
    "prune_hedge_01": gesture(seq((0.0, {"arm": 1.0, "lh_x": 0.45, "lh_y": 0.12, "lh_z": 0.22, "rh_x": 0.45,
                    "rh_y": -0.16, "rh_z": 0.22, "neck_flex": 5.0, "f_w": 0.14, "shoulder_twist": -20.0},)),
        cycles=(Cycle(0.9, ((0.0, {"lh_y": 0.06, "rh_y": -0.06}), (0.4, {"lh_y": -0.05, "rh_y": 0.05}))),),
        osc=(Osc("waist_twist", 25.0, 8.0), Osc("h_z", 0.15, 10.7, 0.2), Osc("waist_flex", 8.0, 10.7, 0.7)),
        cyclic=True),
    # ---- On a bar or a mat.
    "pull_ups_bar_01": cycle(
        keys=seq((0.0, _HANG)), cycles=(_PULL,), hands="heading", cyclic=True, osc=(Osc("pitch", 3.0, 3.0, 0.25),)),
    "chin_ups_01": cycle(keys=seq((0.0, {**_HANG, "h_w": 0.16, "shoulder_twist": 10.0})), hands="heading",
        cyclic=True, cycles=(Cycle(28.4 / 5, ((0.0, {}), (0.25, {}),
                    (0.5, {"z": 0.45, "neck_flex": -18.0, "knee_flex": 20.0}),
                    (0.62, {"z": 0.46, "neck_flex": -18.0, "knee_flex": 20.0}), (0.9, {}),)),)),
    "hang_pull_ups_01": cycle(keys=((0.0, _HANG), *repeat(
                tuple((3.3 * f, {**_HANG, **k, "z": _HANG["z"] + k.get("z", 0.0)}) for f, k in _PULL.keys)
                + ((3.3, _HANG),), 3.3, 5, 5.0), (21.6, _HANG),), hands="heading",
        osc=(Osc("pitch", 6.0, 2.4, env=((0.0, 1.0), (4.0, 1.0), (4.9, 0.2))),)),
    "sit_ups_mat_01": cycle(keys=seq((0.0, _SUPINE)), cyclic=True, cycles=(Cycle(3.7, ((0.0, {}), (0.2, {}),
                    (0.55, {"waist_flex": 75.0, "pitch": 25.0, "neck_flex": 10.0}),
                    (0.65, {"waist_flex": 75.0, "pitch": 25.0, "neck_flex": 10.0}),)),)),
    "stretch_arms_overhead_01": gesture(seq((0.0, STAND), (1.5, {**ARMS_OVERHEAD, "shoulder_twist": 20.0}), (3.0, {
                    "shoulder_flex": 178.0, "shoulder_abd": 8.0, "elbow_flex": 3.0, "waist_flex": -12.0,
                    "neck_flex": -30.0, "f_pitch": 18.0, "pitch": -3.0},), (5.2, {"shoulder_flex": 178.0,
                    "shoulder_abd": 8.0, "elbow_flex": 3.0, "waist_flex": -12.0, "neck_flex": -35.0, "f_pitch": 18.0,
                    "pitch": -3.0},), (6.5, {"shoulder_abd": 100.0, "elbow_flex": 20.0}), (8.0, STAND))),
    "split_slide_stretch_01": posture(seq((0.0, STAND), (1.5, {"f_w": 0.45, "z": -0.08, "shoulder_abd": 30.0}),
            (4.0, {"f_w": 0.45, "y": 0.25, "z": -0.28, "shoulder_abd": 30.0, "waist_lateral": -10.0}),
            (7.0, {"f_w": 0.45, "y": -0.25, "z": -0.28, "shoulder_abd": 30.0, "waist_lateral": 10.0}),
            (9.0, {"f_w": 0.5, "z": -0.1, "shoulder_abd": 30.0}),
            (12.0, {**_SIDE_SPLIT, "hip_abd": 45.0, "z": -0.3, "leg": 0.0}), (16.0, _SIDE_SPLIT),
            (24.0, {**_SIDE_SPLIT, "waist_flex": 35.0, "shoulder_flex": 70.0}))),
    "front_split_floor_01": posture(seq(
            (0.0, HALF_KNEEL), (2.0, {**HALF_KNEEL, "lf_x": 0.6, "z": -0.5}), (5.0, _FRONT_SPLIT), (19.0, _FRONT_SPLIT)
        ), osc=(Osc("waist_flex", 10.0, 4.75, env=((5.0, 0.0), (6.0, 1.0))),)),
    "side_split_warm_up_01": posture(seq((0.0, STAND), *repeat(seq((0.0, {"f_w": 0.5, "z": -0.1}),
                    (1.5, {"f_w": 0.5, "y": 0.28, "z": -0.3, "waist_lateral": -8.0}), (3.0, {"f_w": 0.5, "z": -0.1}),
                    (4.5, {"f_w": 0.5, "y": -0.28, "z": -0.3, "waist_lateral": 8.0}), (6.0, {"f_w": 0.5, "z": -0.1}),
                ), 6.0, 2, 1.5), (17.0, {**_SIDE_SPLIT, "hip_abd": 50.0, "z": -0.35}), (20.0, _SIDE_SPLIT),
            (26.0, {**_SIDE_SPLIT, "waist_flex": 40.0, "shoulder_flex": 80.0}), (32.6, _SIDE_SPLIT))),
    "tai_chi_form_01": gesture(seq((0.0, {"f_w": 0.3, "z": -0.12, "f_out": 20.0, "arm": 1.0, "h_x": 0.35, "h_w": 0.2,
                    "h_z": 0.1, "shoulder_twist": -30.0},)), cycles=(Cycle(12.5, (
                    (0.0, {"y": 0.12, "lh_z": 0.15, "rh_z": -0.15, "lh_x": 0.1, "waist_twist": 20.0}),
                    (0.25, {"x": 0.06, "lh_z": 0.05, "rh_z": 0.1, "lh_y": -0.1, "rh_y": 0.05}),
                    (0.5, {"y": -0.12, "lh_z": -0.15, "rh_z": 0.15, "rh_x": 0.1, "waist_twist": -20.0}),
                    (0.75, {"x": -0.06, "lh_z": 0.1, "rh_z": 0.05, "lh_y": -0.05, "rh_y": 0.1}),)),), cyclic=True),
    # ---- Sitting, standing up, getting down.
    "sit_down_chair_01": posture(seq((0.0, STAND), (1.0, STAND), (2.6, SIT_LEAN), (3.7, SIT), (6.6, SIT))),
    "sit_floor_cross_legged_01": posture(seq((0.0, STAND), (1.0, STAND), (2.4, {**SQUAT, "f_out": 25.0, "f_w": 0.18}),
            (3.2, {**_DEEP_SQUAT, "hip_abd": 30.0, "hip_twist": 20.0, "pitch": 20.0}), (4.4, _CROSS), (12.0, _CROSS))
    ),
    "sit_down_stand_up_01": posture(seq((0.0, STAND), (1.0, STAND), (2.6, SIT_LEAN), (3.7, SIT), (8.0, SIT),
            (9.2, SIT_LEAN), (10.6, STAND), (13.2, STAND))),
    "stand_up_from_chair_01": posture(seq((0.0, SIT), (1.0, SIT), (2.2, SIT_LEAN), (3.6, STAND), (5.4, STAND))),
    "get_up_from_floor_01": posture(seq((0.0, _LONG_SIT), (1.0, _LONG_SIT),
            (2.4, {**_LONG_SIT, "hip_flex": 110.0, "knee_flex": 120.0, "pitch": -5.0}),
            (3.8, {**KNEEL, "pitch": 30.0, "waist_flex": 20.0, "shoulder_flex": 60.0}),
            (4.6, {**KNEEL, "pitch": 5.0}),
            (5.4, {**HALF_KNEEL, "pitch": 10.0, "l_leg": 0.0, "left_hip_flex": 80.0, "left_knee_flex": 95.0}),
            (6.0, HALF_KNEEL), (7.3, {"lf_x": 0.42, "rf_x": 0.2, "x": 0.3}),
            (8.6, {"lf_x": 0.42, "rf_x": 0.2, "x": 0.3}))),
    "rise_from_kneeling_01": posture(seq((0.0, KNEEL), (1.0, KNEEL),
            (2.0, {**HALF_KNEEL, "pitch": 8.0, "l_leg": 0.0, "left_hip_flex": 80.0, "left_knee_flex": 95.0}),
            (2.6, HALF_KNEEL), (4.0, {"lf_x": 0.42, "rf_x": 0.2, "x": 0.3}),
            (6.0, {"lf_x": 0.42, "rf_x": 0.2, "x": 0.3}))),
    "forward_roll_stand_up_01": posture(seq((0.0, _FLOOR_STAND), (0.8, _FLOOR_STAND),
            (1.8, {**_DEEP_SQUAT, "shoulder_flex": 80.0, "pitch": 45.0}), (2.4, {**_FLOOR_STAND, "pitch": 100.0,
                    "x": 0.25, "hip_flex": 120.0, "knee_flex": 140.0, "waist_flex": 30.0, "neck_flex": 60.0,
                    "shoulder_flex": 90.0, "elbow_flex": 60.0},), (3.0, {**_FLOOR_STAND, "pitch": 180.0, "x": 0.6,
                    "hip_flex": 125.0, "knee_flex": 145.0, "waist_flex": 40.0, "neck_flex": 55.0,
                    "shoulder_flex": 40.0, "elbow_flex": 60.0},), (3.6, {**_FLOOR_STAND, "pitch": 280.0, "x": 1.0,
                    "hip_flex": 125.0, "knee_flex": 145.0, "waist_flex": 40.0, "neck_flex": 40.0,
                    "shoulder_flex": 60.0, "elbow_flex": 30.0},),
            (4.3, {**_DEEP_SQUAT, "pitch": 400.0, "x": 1.15, "shoulder_flex": 90.0}),
            (6.0, {**_FLOOR_STAND, "pitch": 360.0, "x": 1.2}), (9.2, {**_FLOOR_STAND, "pitch": 360.0, "x": 1.2}))),
    "idle_standing_01": gesture(seq((0.0, ARMS_REST)), cyclic=True, osc=(Osc("y", 0.04, 7.5), Osc("roll", 2.5, 7.5),
            Osc("waist_lateral", -2.0, 7.5), Osc("neck_twist", 15.0, 10.0), Osc("z", -0.008, 3.75, 0.25),)),
    "flinch_startle_01": gesture(seq((0.0, STAND), (0.17, _FLINCH), (0.27, _FLINCH),
            (0.5, {**_FLINCH, "z": -0.05, "shoulder_flex": 35.0, "elbow_flex": 80.0}))),
    # ---- Crawling, diving, falling.
    "crawl_hands_and_knees_01": cycle(keys=seq((0.0, CRAWL)), cycles=(_CRAWL_CYCLE,), advance=0.28, cyclic=True),
    "army_crawl_01": cycle(keys=seq((0.0, _PRONE_CRAWL)), cycles=(_ARMY,), advance=0.2, cyclic=True),
    "crawling_all_fours_01": cycle(keys=seq((0.0, CRAWL)), cycles=(Cycle(1.7, _CRAWL_CYCLE.keys),), advance=0.2,
        cyclic=True, osc=(Osc("neck_twist", 45.0, 6.24), Osc("neck_lateral", 10.0, 6.24, 0.25))),
    "dive_onto_floor_artist_01": posture(seq((0.0, STAND), (0.7, STAND),
            (1.2, {"z": -0.18, "pitch": 25.0, "shoulder_flex": -35.0, "f_pitch": 10.0}),
            (1.45, {"z": -0.02, "x": 0.3, "pitch": 50.0, "shoulder_flex": 150.0, "f_pitch": 40.0}),
            (1.75, {"leg": 0.0, "z": -0.3, "x": 0.85, "pitch": 70.0, "shoulder_flex": 160.0, "hip_flex": -10.0}), (
                2.0, {**PRONE, "snap": 0.0, "z": -0.62, "x": 1.2, "pitch": 80.0, "shoulder_flex": 120.0,
                    "elbow_flex": 30.0, "shoulder_abd": 20.0},), (2.4, {**PRONE, "x": 1.35}),
            (5.2, {**PRONE, "x": 1.35}))),
    "drop_to_ground_prone_01": posture(seq((0.0, STAND), (0.8, STAND), (1.6, {**KNEEL, "pitch": 10.0}),
            (2.5, {**KNEEL, "pitch": 55.0, "x": 0.1, "shoulder_flex": 70.0, "elbow_flex": 10.0}),
            (3.4, {**PRONE, "snap": 1.0, "x": 0.15, "pitch": 75.0, "shoulder_flex": 80.0, "elbow_flex": 90.0}),
            (4.3, {**PRONE, "x": 0.2}), (7.0, {**PRONE, "x": 0.2}))),
    "fall_to_ground_01": posture(seq((0.0, STAND), (0.8, STAND),
            (1.3, {"rf_x": 0.45, "x": 0.2, "pitch": 15.0, "shoulder_flex": 40.0}), (1.75, {"rf_x": 0.45, "x": 0.5,
                    "z": -0.2, "pitch": 45.0, "shoulder_flex": 110.0, "elbow_flex": 15.0, "leg": 0.6},), (2.1, {
                    "leg": 0.0, "x": 0.8, "z": -0.55, "pitch": 72.0, "shoulder_flex": 110.0, "elbow_flex": 25.0,
                    "neck_flex": -30.0},),
            (2.5, {**PRONE, "x": 0.95, "shoulder_flex": 100.0, "elbow_flex": 110.0, "shoulder_abd": 30.0}),
            (7.4, {**PRONE, "x": 0.95, "shoulder_flex": 100.0, "elbow_flex": 110.0, "shoulder_abd": 30.0}))),
    # ---- Impaired gaits and balance.
    "limp_right_leg_01": walk(speed=0.8, cadence=1.5, limp=-0.09, stiff=0.06, stiff_lift=0.2, lift=0.08,
        swing=14.0, osc=(Osc("neck_flex", 4.0, 1.33),)),
    "stagger_drunk_01": walk(speed=0.7, cadence=1.5, width=0.14, weave=0.45, weave_period=5.8, wander=25.0,
        wander_period=9.6, sway=0.05, lift=0.06,
        keys=seq((0.0, {"shoulder_abd": 30.0, "elbow_flex": 30.0, "neck_flex": 10.0})), osc=(
            Osc("waist_lateral", 12.0, 5.8), Osc("roll", 5.0, 5.8), Osc("neck_lateral", 15.0, 3.6),
            Osc("waist_flex", 8.0, 4.8),)),
    "stumble_recover_01": walk(cyclic=False,
        speed=((0.0, 1.2), (2.4, 1.2), (3.0, 1.6), (3.8, 1.5), (4.7, 0.6), (5.6, 0.0)), cadence=None, keys=seq((0.0, {
                    "pitch": 25.0, "waist_flex": 15.0, "shoulder_flex": 70.0, "shoulder_abd": 40.0,
                    "elbow_flex": 30.0, "neck_flex": -20.0},)),
        blend=((0.0, 0.0), (2.4, 0.0), (2.7, 1.0), (3.6, 1.0), (5.2, 0.0))),
    "tightrope_walk_01": walk(speed=0.32, cadence=1.1, width=-0.01, toe_out=15.0, lift=0.06, sway=0.01, heel_off=10.0,
        swing=0.0, keys=seq((0.0, {**ARMS_OUT, "neck_flex": 25.0})), osc=(Osc("left_shoulder_abd", 12.0, 3.1),
            Osc("right_shoulder_abd", -12.0, 3.1), Osc("waist_lateral", 5.0, 3.1), Osc("roll", 2.0, 3.1),)),
    "moonwalk_artist_01": Spec(family="gait", custom="moonwalk", cyclic=True, sole_friction=0.1),
    # ---- Hands up.
    "raise_both_hands_hold_01": gesture(seq((0.0, STAND),
            (1.5, {"shoulder_abd": 165.0, "shoulder_flex": 15.0, "elbow_flex": 10.0}),
            (10.8, {"shoulder_abd": 165.0, "shoulder_flex": 15.0, "elbow_flex": 10.0}), (12.0, STAND)),
        osc=(Osc("shoulder_abd", 3.0, 1.5),)),
    "surrender_kneel_artist_01": posture(seq((0.0, STAND), (1.5, HANDS_UP), (3.5, HANDS_UP),
            (5.0, {**HALF_KNEEL, **HANDS_UP}),
            (6.5, {**HALF_KNEEL, **HANDS_UP, "l_leg": 0.0, "left_hip_flex": 60.0, "left_knee_flex": 100.0}),
            (7.5, _SURRENDER_KNEEL), (15.0, _SURRENDER_KNEEL))),
    "hands_up_behind_head_01": gesture(seq((0.0, STAND), (1.5, HANDS_UP), (4.0, HANDS_UP),
            (4.5, {**HANDS_UP, "arm": 1.0, "h_x": 0.02, "h_w": 0.5, "h_z": 0.58, "e_x": 0.15, "e_w": 1.0, "e_z": -0.1}),
            (6.0, {"arm": 1.0, "h_x": -0.06, "h_w": 0.08, "h_z": 0.6, "e_x": 0.25, "e_w": 1.0, "e_z": 0.1,
                    "neck_flex": 10.0},), (11.6, {"arm": 1.0, "h_x": -0.06, "h_w": 0.08, "h_z": 0.6, "e_x": 0.25,
                    "e_w": 1.0, "e_z": 0.1, "neck_flex": 10.0},))),
    # ---- Two people, street scenes.
    "hug_pat_back_01": gesture(seq((0.0, STAND), (1.6, {**HUG, "x": 0.08}), (7.8, {**HUG, "x": 0.08}), (9.4, STAND)),
        osc=(Osc("rh_z", 0.05, 0.55, env=((2.4, 0.0), (2.8, 1.0), (6.8, 1.0), (7.2, 0.0))),)),
    "greet_friend_hug_01": walk(cyclic=False, speed=((0.0, 0.0), (0.3, 0.0), (1.0, 0.9), (2.2, 0.9), (3.0, 0.0)),
        keys=seq((0.0, {"shoulder_abd": 45.0, "shoulder_flex": 45.0, "elbow_flex": 20.0, "neck_flex": -8.0}),
            (2.0, {"shoulder_abd": 45.0, "shoulder_flex": 45.0, "elbow_flex": 20.0}), (3.4, HUG), (5.8, HUG),
            (7.0, STAND)), blend=((0.0, 0.0), (1.0, 0.0), (1.6, 1.0), (6.0, 1.0), (7.2, 0.0)),
        osc=(Osc("rh_z", 0.04, 0.55, env=((3.6, 0.0), (4.0, 1.0), (5.4, 1.0), (5.8, 0.0))),)),
    "stroll_park_01": walk(speed=1.0, cadence=1.6, swing=32.0, elbow=10.0, lean=0.0, torso=0.0,
        osc=(Osc("neck_twist", 25.0, 10.0), Osc("neck_flex", -6.0, 13.3))),
    "holding_hands_walking_01": walk(speed=0.85, cadence=1.5, swing=14.0, keys=seq((0.0, HOLD_HAND))),
    "collide_shoulder_passerby_01": walk(cyclic=False,
        speed=((0.0, 1.3), (2.2, 1.3), (2.6, 0.4), (3.4, 0.5), (4.2, 1.2), (5.6, 1.2)),
        side=((0.0, 0.0), (2.3, 0.0), (2.55, -0.6), (2.9, 0.0)), keys=seq((0.0, {"waist_twist": 30.0, "yaw": 12.0,
                    "waist_lateral": 8.0, "left_shoulder_flex": -25.0, "right_shoulder_abd": 30.0, "neck_twist": 35.0,
                },)), blend=((0.0, 0.0), (2.2, 0.0), (2.45, 1.0), (3.0, 1.0), (4.0, 0.0))),
    "crowd_dodge_01": walk(speed=1.4, cadence=1.85, weave=0.25, weave_period=3.8, wander=8.0, wander_period=5.75,
        osc=(Osc("waist_twist", 20.0, 3.8, 0.25), Osc("neck_twist", 20.0, 2.9))),
    "cross_street_look_01": walk(cyclic=False, speed=((0.0, 0.0), (4.5, 0.0), (5.5, 1.3), (13.0, 1.3), (14.4, 0.0)),
        keys=seq((0.0, STAND), (0.8, {"neck_twist": 65.0}), (2.0, {"neck_twist": 65.0}), (2.8, {"neck_twist": -65.0}),
            (3.8, {"neck_twist": -65.0}), (4.5, {"neck_twist": 50.0}), (5.2, STAND), (8.0, STAND),
            (8.6, {"neck_twist": 55.0}), (9.4, {"neck_twist": 55.0}), (10.2, {"neck_twist": -50.0}), (11.0, STAND),
            (17.2, STAND))),
    "wait_bus_stop_01": gesture(seq(*repeat(seq((0.0, {**ARMS_REST, "neck_twist": 0.0}),
                    (4.0, {**ARMS_REST, "neck_twist": 70.0}), (7.0, {**ARMS_REST, "neck_twist": 70.0}),
                    (8.0, ARMS_REST), (11.0, ARMS_REST), (11.8, {"left_shoulder_flex": 45.0, "left_elbow_flex": 100.0,
                            "left_shoulder_twist": -60.0, "neck_flex": 30.0, "neck_twist": 15.0},), (13.0, {
                            "left_shoulder_flex": 45.0, "left_elbow_flex": 100.0, "left_shoulder_twist": -60.0,
                            "neck_flex": 30.0, "neck_twist": 15.0},), (14.0, ARMS_REST), (16.0, ARMS_REST)), 16.0, 3,
            )), osc=(Osc("y", 0.05, 12.0), Osc("roll", 3.0, 12.0), Osc("waist_lateral", -2.5, 12.0)), cyclic=True)}


# fmt: on
def _register_all() -> None:
    from phav_generator.animation import MOTION_LIBRARY

    missing = [n for n in MOTIONS.names if n not in SPECS]
    if missing:
        raise RuntimeError(f"motions without an animation: {missing}")
    for name in MOTIONS.names:
        if name in MOTION_LIBRARY:
            continue
        m = MOTIONS[name]
        spec = SPECS[name]
        stairs = spec.gait.stairs if spec.gait is not None else 0
        register_motion(
            MotionDef(name, m.length_s, _build(spec, m.length_s), m.description, spec.sole_friction, stairs)
        )


_register_all()
