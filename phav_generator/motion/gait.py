"""The locomotion generator: a footstep plan → feet, pelvis and arm swing; and the stairs.

``Gait`` parametrises a walk, run, hop or limp. On a 60 Hz grid padded 3 s either side of
the motion, the generator integrates the path (speed, side step, turn, weaving, heading
wander) and the gait phase (cadence falling with the square root of speed, or people's
usual step frequency), plants each foot once per stance where the path is ``plant_at`` of
the way through it, and moves swing feet between plants on a lifted curve that rolls heel
to toe. Because feet in stance are IK targets that do not move, gaits do not slide; because
the root advances by the footstep plan, speed is tied to stride length and cadence.

Stairs motions snap their plants onto a staircase that starts ``STAIR_START`` ahead along +X
with ``STAIR_RISE``/``STAIR_RUN`` treads (up for the climbs, down for ``go_down_stairs_01``);
the physics builds exactly those treads. The moonwalk, the one gait whose stance foot
slides, has its own generator (``moonwalk``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from phav_generator.motion.animation import MotionParams
from phav_generator.motion.channels import DEG, Channels
from phav_generator.motion.keyframes import Keys, ease, fit_period, monotone_cubic, track
from phav_generator.motion.reference import ANKLE_H, HEEL, HIP_Y, TOE
from phav_generator.motion.rotations import rot_y, rot_z

#: Staircase of the stairs motions (the physics builds it): first riser this far ahead.
STAIR_START, STAIR_RISE, STAIR_RUN = 0.40, 0.17, 0.30

#: The gait's own time grid: its step (s) and the padding (s) either side of the motion.
_DT, _PAD = 1.0 / 60.0, 3.0


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
class GaitOut:
    """What a gait generator hands the solver, at the motion's sample times."""

    path: np.ndarray  # (T, 4): x, y, yaw (rad), ground z under the path
    ankle: np.ndarray  # (2, T, 3) ankle targets (left, right), motion frame
    foot_rot: np.ndarray  # (2, T, 3, 3)
    active: tuple[bool, bool]
    phase: np.ndarray  # (T,) gait phase in cycles
    contact: np.ndarray | None = None  # (2, T) weight of each foot in the pelvis-height constraint


def pivot_offset(pitch: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
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


def stair_plant(x: np.ndarray, direction: int) -> tuple[np.ndarray, np.ndarray]:
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


@dataclass(frozen=True)
class _Grid:
    """The walked path on the gait's own grid: times, forward speed, x, y, yaw; ``i0`` is τ = 0."""

    t: np.ndarray
    v: np.ndarray
    x: np.ndarray
    y: np.ndarray
    yaw: np.ndarray
    i0: int

    def at(self, arr: np.ndarray, tau: np.ndarray) -> np.ndarray:
        """A grid quantity ``arr`` read at the motion times ``tau`` (linear)."""
        return np.interp(tau, self.t, arr)


@dataclass(frozen=True)
class _Plants:
    """One foot's footholds, stance k of the gait cycle: when, where, which way, and the
    lift of the swing from plant k to plant k + 1."""

    ks: np.ndarray  # cycle numbers
    t: np.ndarray
    x: np.ndarray
    y: np.ndarray
    z: np.ndarray  # sole height (a stair tread)
    yaw: np.ndarray
    lift: np.ndarray  # (K − 1,)


def _path(g: Gait, p: MotionParams, length: float, amp: float) -> _Grid:
    """Integrate speed, side step and turn into the path, add jumps, wander and weaving;
    the path passes through the origin facing +X at τ = 0."""
    dt, pad = _DT, _PAD
    tg = -pad + dt * np.arange(round((length + 2 * pad) / dt) + 1)
    v = track(g.speed, tg)
    vy = track(g.side, tg)
    yaw = np.concatenate([[0.0], np.cumsum(0.5 * (track(g.turn, tg)[1:] + track(g.turn, tg)[:-1]) * dt)]) * DEG
    vx_w = v * np.cos(yaw) - vy * np.sin(yaw)
    vy_w = v * np.sin(yaw) + vy * np.cos(yaw)
    x = np.concatenate([[0.0], np.cumsum(0.5 * (vx_w[1:] + vx_w[:-1]) * dt)])
    y = np.concatenate([[0.0], np.cumsum(0.5 * (vy_w[1:] + vy_w[:-1]) * dt)])
    if g.px is not None:
        extra = track(g.px, tg) * amp
        x, y = x + np.cos(yaw) * extra, y + np.sin(yaw) * extra
    i0 = round(pad / dt)
    if g.wander:
        yaw = yaw + g.wander * DEG * np.sin(2 * np.pi * (tg / fit_period(g.wander_period, length) + p.phase))
    if g.weave:
        w = g.weave * amp * np.sin(2 * np.pi * (tg / fit_period(g.weave_period, length) + p.phase))
        x, y = x - np.sin(yaw) * w, y + np.cos(yaw) * w
    x, y, yaw = x - x[i0], y - y[i0], yaw - yaw[i0]
    return _Grid(tg, v, x, y, yaw, i0)


def _phase(g: Gait, p: MotionParams, length: float, cyclic: bool, grid: _Grid, amp: float) -> np.ndarray:
    """Gait phase in cycles on the grid: explicit keys, or integrated cadence (a whole number
    of cycles in a loop), shifted by ``p.phase``; strictly increasing, so it can be inverted."""
    tg, v, i0 = grid.t, grid.v, grid.i0
    if g.phase_keys is not None:
        phi = track(g.phase_keys, tg)
    else:
        vref = float(np.max(np.abs(track(g.speed, tg)))) if not isinstance(g.speed, (int, float)) else abs(g.speed)
        if g.cadence is None:  # human step frequency at each speed, walking then running
            steps = np.interp(
                np.abs(v), [0.0, 0.6, 1.3, 1.9, 2.3, 3.5, 5.0, 6.5], [1.3, 1.5, 1.8, 2.1, 2.6, 2.9, 3.45, 3.8]
            )
        else:
            steps = g.cadence * np.sqrt((np.abs(v) + 0.5) / (vref + 0.5))
        f = steps / amp * (0.5 if g.feet == "alt" else 1.0)
        if cyclic:
            m = g.loop_multiple
            f = np.full_like(f, max(m, m * round(f[i0] * length / m)) / length)
        phi = np.concatenate([[0.0], np.cumsum(0.5 * (f[1:] + f[:-1]) * _DT)])
        phi = phi - phi[i0] + p.phase
    return phi + 1e-7 * (tg - tg[0])  # strictly increasing for inversion


def _duty(g: Gait, grid: _Grid) -> np.ndarray:
    """Stance fraction of the cycle on the grid: the gait's, or from speed (walk → run)."""
    speed_abs = np.abs(grid.v)
    if g.duty is None:
        return np.interp(speed_abs, [0.0, 1.5, 2.4, 3.5, 5.0, 6.0], [0.6, 0.55, 0.4, 0.32, 0.27, 0.25])
    return np.full_like(grid.t, g.duty)


def _plants(g: Gait, grid: _Grid, phi_i: np.ndarray, beta_g: np.ndarray, s: float, style: float, alt: bool) -> _Plants:
    """Where one foot (side ``s``, phase ``phi_i``, duty ``beta_g`` on the grid) plants in
    each stance: beside the path where it is ``plant_at`` of the way through, on a tread for
    stairs; a swing lifts less for a short step."""
    tg = grid.t
    ks = np.arange(math.floor(phi_i[0]) - 1, math.ceil(phi_i[-1]) + 2)
    beta_k = np.interp(ks + 0.3, phi_i, beta_g)
    tk = np.interp(ks + beta_k * g.plant_at, phi_i, tg)
    yk = np.interp(tk, tg, grid.yaw)
    wk = np.full(len(ks), g.width)
    if g.width2 is not None:
        wk = np.where(ks % 2 == 0, g.width, g.width2)
    pkx = np.interp(tk, tg, grid.x) - np.sin(yk) * s * wk
    pky = np.interp(tk, tg, grid.y) + np.cos(yk) * s * wk
    pkz = np.zeros(len(ks))
    if g.stairs:
        pkx, pkz = stair_plant(pkx, g.stairs)
    yawk = yk + s * g.toe_out * DEG
    step = np.hypot(np.diff(pkx), np.diff(pky))
    liftk = np.full(len(ks) - 1, g.lift * (1.0 + 0.25 * style))
    if alt and not g.stairs:
        liftk = liftk * np.clip(step / 0.25, 0.0, 1.0)
    return _Plants(ks, tk, pkx, pky, pkz, yawk, liftk)


def _swing_progress(g: Gait, sw: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Horizontal and vertical progress (0 → 1) of a swing foot from one plant to the next,
    at swing fraction ``sw``: on stairs the foot rises before it travels (up) or after (down)."""
    if g.stairs > 0:
        return ease((sw - 0.2) / 0.8), ease(sw / 0.7)
    if g.stairs < 0:
        return ease(sw / 0.8), ease((sw - 0.35) / 0.65)
    hprog = g.swing_linear * sw + (1 - g.swing_linear) * sw * sw * (3 - 2 * sw)
    return hprog, hprog


def _lift_shape(g: Gait, sw: np.ndarray) -> np.ndarray:
    """Swing foot clearance over the swing, peaking at 1 (skewed early for runs)."""
    grid = np.linspace(0.0, 1.0, 101)
    norm = np.max(np.sin(np.pi * grid) ** g.lift_pow * (1.0 - g.lift_skew * grid))
    return np.sin(np.pi * sw) ** g.lift_pow * (1.0 - g.lift_skew * sw) / norm


def _foot_pitch(
    g: Gait,
    stance: np.ndarray,
    sig: np.ndarray,
    sw: np.ndarray,
    gw: np.ndarray,
    sg: np.ndarray,
    painful: bool,
) -> np.ndarray:
    """Foot pitch (rad, + heel up): toes up at heel strike, heel rising towards toe-off,
    rolling back flat through the swing (no push-off on a stiff leg)."""
    ho = g.heel_off * DEG * gw * sg * (g.stiff_lift if painful else 1.0)  # no push-off on a stiff leg
    hs = g.heel_strike * DEG * gw * sg
    if g.feet != "alt":
        n = len(stance)
        ho, hs = g.heel_off * DEG * np.ones(n), g.heel_strike * DEG * np.ones(n)
    h0 = g.heel_off_at
    pitch_st = -hs * (1 - ease(sig / 0.15)) + ho * ease((sig - h0) / (1 - h0))
    pitch_sw = ho * (1 - ease(sw / 0.75)) - hs * ease((sw - 0.6) / 0.4)
    return np.where(stance, pitch_st, pitch_sw)


def _foot(
    g: Gait,
    i: int,
    s: float,
    pl: _Plants,
    ph: np.ndarray,
    beta: np.ndarray,
    gw: np.ndarray,
    sg: np.ndarray,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Ankle target (T, 3), foot rotation (T, 3, 3) and contact weight (T,) of foot ``i``
    (side ``s``) at its gait phase ``ph`` and stance fraction ``beta``."""
    k = np.floor(ph).astype(int)
    j = np.clip(k - pl.ks[0], 0, len(pl.ks) - 2)
    u = ph - k
    stance = u < beta
    sig = np.clip(u / beta, 0.0, 1.0)
    sw = np.clip((u - beta) / (1.0 - beta), 0.0, 1.0)
    hprog, vprog = _swing_progress(g, sw)
    shape = np.where(sw < 0.5, np.cos(np.pi * sw) ** 2, ease((sw - 0.5) / 0.3))
    contact = np.where(stance, 1.0, 1.0 - g.release * (1.0 - shape))
    hprog = np.where(stance, 0.0, hprog)
    vprog = np.where(stance, 0.0, vprog)
    painful = g.limp != 0 and i == (0 if g.limp > 0 else 1)
    lift = np.where(stance, 0.0, pl.lift[j] * _lift_shape(g, sw) * (g.stiff_lift if painful else 1.0))
    if g.stiff and painful:
        out = np.where(stance, 0.0, g.stiff * np.sin(np.pi * sw))
    else:
        out = 0.0
    fx = pl.x[j] + hprog * (pl.x[j + 1] - pl.x[j])
    fy = pl.y[j] + hprog * (pl.y[j + 1] - pl.y[j])
    fz = pl.z[j] + vprog * (pl.z[j + 1] - pl.z[j]) + lift
    fyaw = pl.yaw[j] + hprog * (pl.yaw[j + 1] - pl.yaw[j])
    fy = fy + s * out * np.cos(fyaw)
    fx = fx - s * out * np.sin(fyaw)
    pitch = _foot_pitch(g, stance, sig, sw, gw, sg, painful)
    ox, oz = pivot_offset(pitch)
    ankle = np.stack([fx + np.cos(fyaw) * ox, fy + np.sin(fyaw) * ox, fz + ANKLE_H + oz], axis=1)
    return ankle, rot_z(fyaw) @ rot_y(pitch), contact


def _ground(g: Gait, plants: list[_Plants], tau: np.ndarray) -> np.ndarray:
    """Ground height under the path: the stance heights, smoothed through the plant times."""
    if not g.stairs:
        return np.zeros(len(tau))
    tt = np.concatenate([pl.t for pl in plants])
    zz = np.concatenate([pl.z for pl in plants])
    order = np.argsort(tt, kind="stable")
    tt, zz = tt[order], zz[order]
    keep = np.concatenate([[True], np.diff(tt) > 1e-6])
    return monotone_cubic(tt[keep], zz[keep], tau)[:, 0]


def _body_channels(
    g: Gait,
    ch: Channels,
    phase: np.ndarray,
    beta_l: np.ndarray,
    gw: np.ndarray,
    sg: np.ndarray,
    amp: float,
    style: float,
    offsets: tuple[float, float],
) -> None:
    """Pelvis and upper-body channels, phase-locked to the left foot (stance ``beta_l``):
    sway, roll, yaw and bob over the stance foot, arm swing against the legs, lean."""
    c1 = np.cos(2 * np.pi * (phase - beta_l / 2))
    arm_gain = amp * (1.0 + 0.35 * style)
    if g.feet == "alt":
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


def generate_gait(g: Gait, tau: np.ndarray, p: MotionParams, length: float, cyclic: bool, ch: Channels) -> GaitOut:
    """Footstep plan and pelvis/arm channels (written into ``ch``) of a gait, evaluated at ``tau``."""
    # amplitude: longer strides at a lower cadence (same speed), bigger jumps, wider weaving
    amp = p.amplitude if not g.stairs else 1.0
    grid = _path(g, p, length, amp)
    alt = g.feet == "alt"
    phi = _phase(g, p, length, cyclic, grid, amp)
    duty_g = _duty(g, grid)
    offsets = {"alt": (0.0, 0.5 - g.limp), "both": (0.0, 0.0), "left": (0.0, 0.0), "right": (0.0, 0.0)}[g.feet]
    active = (g.feet in ("alt", "both", "left"), g.feet in ("alt", "both", "right"))
    sgn = np.sign(grid.v + 1e-9)

    phase = grid.at(phi, tau)
    gw = np.clip(np.abs(grid.at(grid.v, tau)) / 0.6, 0.0, 1.0) if alt else np.ones_like(tau)
    gw = gw * gw * (3 - 2 * gw)
    sg = grid.at(sgn, tau)
    n = len(tau)
    ankle = np.zeros((2, n, 3))
    foot_rot = np.zeros((2, n, 3, 3))
    contact = np.ones((2, n))
    plants: list[_Plants] = []
    for i, s in enumerate((1.0, -1.0)):
        if not active[i]:
            foot_rot[i] = np.eye(3)
            continue
        beta_g = duty_g + (-g.limp if i == 0 else g.limp)
        pl = _plants(g, grid, phi - offsets[i], beta_g, s, p.style, alt)
        plants.append(pl)
        ankle[i], foot_rot[i], contact[i] = _foot(g, i, s, pl, phase - offsets[i], grid.at(beta_g, tau), gw, sg)

    ground = _ground(g, plants, tau)
    path = np.stack([grid.at(grid.x, tau), grid.at(grid.y, tau), grid.at(grid.yaw, tau), ground], axis=1)
    _body_channels(g, ch, phase, grid.at(duty_g, tau) - g.limp, gw, sg, amp, p.style, offsets)
    return GaitOut(path, ankle, foot_rot, active, phase, contact)


def moonwalk(tau: np.ndarray, p: MotionParams, length: float, ch: Channels) -> GaitOut:
    """Moonwalk: the flat foot slides back while the other stands on its toes, then they swap.

    Each foot alternates half a cycle sliding back flat at twice the body's speed and half a
    cycle standing still with the heel raised (rolled about the toe), so the body glides
    backwards with a foot always on the floor. The slide is the point: it is the one gait
    whose stance foot moves.
    """
    period = fit_period(1.1, length)
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
        pitch = (30.0 + 8.0 * p.style) * DEG * np.sin(np.pi * np.clip((f - 0.5) / 0.5, 0.0, 1.0)) ** 0.7
        ox, oz = pivot_offset(pitch)
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
    return GaitOut(path, ankle, rot, (True, True), u)
