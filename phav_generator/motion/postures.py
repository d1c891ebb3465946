"""Postures and keyframe builders the motion catalogue is written with.

Named postures (channel values, ``channels.expand`` shorthands), the gait presets (``WALK``,
``RUN``, ``SPRINT``, ``HOP``), the ``Spec`` builders by family (``walk``, ``run``,
``gesture``, ``posture``, ``cycle``) and keyframe builders for the takes with structure
(golf and baseball swings, drawing a bow, kicks, hops, blend fades). ``catalogue.SPECS``
composes them into the 128 motions.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from phav_generator.motion.channels import DEG, Posture, expand
from phav_generator.motion.engine import Cycle, Osc, Spec
from phav_generator.motion.gait import Gait
from phav_generator.motion.keyframes import Keys
from phav_generator.motion.reference import SHOULDER

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


def gait_spec(base: Gait, cyclic: bool, kw: dict) -> Spec:
    """A gait motion from the preset ``base``: ``kw`` splits into Gait fields and Spec fields."""
    gfields = {k: v for k, v in kw.items() if k in Gait.__dataclass_fields__}
    sfields = {k: v for k, v in kw.items() if k not in gfields}
    return Spec(family="gait", gait=replace(base, **gfields), cyclic=cyclic, **sfields)


def walk(*, cyclic: bool = True, **kw: object) -> Spec:
    """A walking motion: ``kw`` are Gait fields (speed, cadence …) and Spec fields (keys …)."""
    return gait_spec(WALK, cyclic, kw)


def run(*, cyclic: bool = True, **kw: object) -> Spec:
    """A running motion (flight phases): as ``walk`` from the running defaults."""
    return gait_spec(RUN, cyclic, kw)


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


def arc(angle: float, *, r: float = 0.3, grip: float = 0.07, plane: str = "golf") -> dict[str, float]:
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
    a = angle * DEG
    for c, extra in (("l", 0.0), ("r", grip)):
        out[f"{c}h_x"], out[f"{c}h_y"] = (r + extra) * math.cos(a), (r + extra) * math.sin(a)
        out[f"{c}h_z"] = SHOULDER[2] - 0.12 - (0.06 if c == "l" else 0.0)
    return out


GOLF_STANCE: Posture = {"z": -0.06, "pitch": 18.0, "waist_flex": 24.0, "neck_flex": 20.0, "f_w": 0.22, "f_out": 10.0,
    "e_x": 0.6, "e_z": -0.8, "e_w": 0.15,  # elbows toward the ground
}  # fmt: skip


def golf_swing(t: float, scale: float = 1.0) -> tuple[tuple[float, Posture], ...]:
    """One golf swing starting at ``t``: address, backswing, impact, follow-through, recover.

    ``scale`` < 1 gives half swings and chips (shorter arc, less body turn).
    """
    s = scale
    addr = {**GOLF_STANCE, **arc(0.0)}
    return seq((t, addr),
        (t + 1.0 * s + 0.2, {**addr, **arc(-80 * s), "waist_twist": -25 * s, "yaw": -8 * s, "neck_twist": 20 * s}),
        (t + 1.5 * s + 0.3, {**addr, **arc(-120 * s), "waist_twist": -45 * s, "yaw": -15 * s, "neck_twist": 40 * s}),
        (t + 1.8 * s + 0.35, {**addr, **arc(-60 * s), "waist_twist": -15 * s, "yaw": -5 * s, "neck_twist": 15 * s}),
        (t + 1.95 * s + 0.4, {**addr, **arc(8.0), "waist_twist": 8 * s, "yaw": 8 * s}), (t + 2.15 * s + 0.45, {
                **addr, **arc(95 * s), "waist_twist": 35 * s, "yaw": 22 * s, "neck_twist": -25 * s,
                "rf_pitch": 25 * s, "waist_flex": 12.0},), (t + 2.6 * s + 0.6, {**addr, **arc(135 * s),
                "waist_twist": 50 * s, "yaw": 30 * s, "neck_twist": -45 * s, "rf_pitch": 35 * s, "waist_flex": 10.0,
                "pitch": 8.0},), (t + 3.6 * s + 1.0, {**addr, **arc(130 * s), "waist_twist": 48 * s, "yaw": 28 * s,
                "neck_twist": -45 * s, "rf_pitch": 35 * s, "waist_flex": 10.0, "pitch": 8.0},))


BAT_STANCE: Posture = {
    "z": -0.07, "pitch": 10.0, "waist_flex": 6.0, "f_w": 0.26, "f_out": 8.0, "neck_twist": 30.0, "yaw": -10.0,
    "shoulder_flex": 60.0, "e_z": -1.0, "e_x": 0.0, "e_w": 0.3}  # fmt: skip


def bat_swing(t: float) -> tuple[tuple[float, Posture], ...]:
    """One right-handed baseball swing from ``t``: load, stride, swing through, follow-through."""
    st = {**BAT_STANCE, **arc(-45, r=0.32, plane="bat"), "rh_z": 0.36, "lh_z": 0.30}
    return seq((t, st), (t + 0.7, {**st, **arc(-55, r=0.30, plane="bat"), "rh_z": 0.38, "lh_z": 0.32,
                "waist_twist": -20.0, "lf_z": 0.08, "lf_y": 0.30},), (t + 1.1,
            {**st, **arc(-55, r=0.30, plane="bat"), "rh_z": 0.36, "lh_z": 0.30, "waist_twist": -22.0, "lf_y": 0.40},
        ), (t + 1.3, {**st, **arc(-30, r=0.42, plane="bat"), "waist_twist": 10.0, "yaw": 10.0, "lf_y": 0.40}), (
            t + 1.42, {**st, **arc(20, r=0.50, plane="bat"), "waist_twist": 35.0, "yaw": 30.0, "lf_y": 0.40,
                "rf_pitch": 25.0, "neck_twist": 15.0},), (t + 1.65, {**st, **arc(55, r=0.30, plane="bat"),
                "lh_z": 0.45, "rh_z": 0.5, "waist_twist": 50.0, "yaw": 40.0, "lf_y": 0.40, "rf_pitch": 35.0,
                "neck_twist": 0.0},), (t + 2.6, {**st, **arc(58, r=0.28, plane="bat"), "lh_z": 0.45, "rh_z": 0.5,
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


def fade(t0: float, t1: float, ramp: float = 0.8) -> Keys:
    """Blend weights: 0 before t0, up to 1 over ``ramp`` s, down again from t1."""
    return ((0.0, 0.0), (t0, 0.0), (t0 + ramp, 1.0), (t1, 1.0), (t1 + ramp, 0.0))


def fade_in(t0: float, ramp: float = 0.8) -> Keys:
    """Blend weights: 0 before t0, up to 1 over ``ramp`` s, then held."""
    return ((0.0, 0.0), (t0, 0.0), (t0 + ramp, 1.0))


CLAP: Cycle = Cycle(0.5, ((0.0, {}), (0.12, {}), (0.55, {"h_w": 0.12, "elbow_flex": 8.0})))
CLAP_POSE: Posture = {"arm": 1.0, "h_x": 0.31, "h_w": 0.03, "h_z": 0.16, "shoulder_twist": -25.0, "wrist_flex": -20.0}
HAIR_R: Posture = {"r_arm": 1.0, "rh_x": 0.05, "rh_y": -0.16, "rh_z": 0.6, "right_shoulder_flex": 110.0,
    "right_shoulder_abd": 60.0, "re_x": 0.6, "re_y": -0.8, "re_z": 0.2, "neck_lateral": -6.0, "neck_flex": 6.0}
HAIR_STROKE_R = Cycle(1.6, ((0.0, {"rh_x": 0.1, "rh_z": -0.05}), (0.5, {"rh_x": -0.1, "rh_z": 0.0}),
        (0.75, {"rh_x": -0.12, "rh_z": -0.1, "rh_y": -0.03}),))
TABLE = {"z": -0.03, "pitch": 8.0, "waist_flex": 10.0, "neck_flex": 12.0}
HANG: Posture = {
    "arm": 1.0, "h_x": 0.04, "h_w": 0.28, "h_z": 2.25, "z": 0.225, "leg": 0.0, "hip_flex": 18.0, "knee_flex": 55.0,
    "ankle_flex": -30.0, "shoulder_flex": 165.0, "shoulder_abd": 20.0, "e_w": 1.0, "e_z": -0.4, "e_x": 0.3,
    "neck_flex": -8.0}  # fmt: skip
PULL = Cycle(3.0, ((0.0, {}), (0.15, {}),
        (0.5, {"z": 0.42, "neck_flex": -15.0, "knee_flex": 15.0, "hip_flex": 10.0}),
        (0.62, {"z": 0.43, "neck_flex": -15.0, "knee_flex": 15.0, "hip_flex": 10.0}),))
SUPINE: Posture = {
    "leg": 0.0, "snap": 1.0, "pitch": -88.0, "z": -0.75, "hip_flex": 55.0, "knee_flex": 105.0, "ankle_flex": 5.0,
    "hip_abd": 8.0, "shoulder_flex": 165.0, "shoulder_abd": 55.0, "elbow_flex": 135.0, "neck_flex": 15.0}  # fmt: skip
PLANK: Posture = {
    "leg": 0.0, "snap": 1.0, "pitch": 71.0, "z": -0.5, "ankle_flex": 25.0, "hip_abd": 3.0, "waist_flex": -2.0,
    "neck_flex": -25.0, "arm": 1.0, "h_x": 0.52, "h_w": 0.24, "h_z": 0.09, "wrist_flex": -60.0,
    "shoulder_twist": -10.0}  # fmt: skip
CROSS: Posture = {
    "leg": 0.0, "snap": 1.0, "z": -0.8, "pitch": -18.0, "hip_flex": 122.0, "hip_abd": 45.0, "hip_twist": 40.0,
    "knee_flex": 135.0, "ankle_flex": -20.0, "waist_flex": 24.0, "neck_flex": 4.0, "shoulder_flex": 40.0,
    "elbow_flex": 95.0, "shoulder_abd": 12.0}  # fmt: skip
SIDE_SPLIT: Posture = {
    "leg": 0.0, "snap": 1.0, "z": -0.7, "hip_abd": 86.0, "hip_twist": 20.0, "ankle_flex": 15.0, "waist_flex": 12.0,
    "shoulder_flex": 40.0, "elbow_flex": 20.0, "shoulder_abd": 15.0}  # fmt: skip
FRONT_SPLIT: Posture = {
    "leg": 0.0, "snap": 1.0, "z": -0.7, "pitch": 30.0, "waist_flex": -22.0, "left_hip_flex": 118.0,
    "right_hip_flex": -60.0, "left_ankle_flex": -5.0, "right_ankle_flex": -45.0, "shoulder_abd": 70.0,
    "elbow_flex": 10.0, "neck_flex": 5.0}  # fmt: skip
LONG_SIT: Posture = {
    "leg": 0.0, "snap": 1.0, "z": -0.75, "pitch": -12.0, "hip_flex": 95.0, "knee_flex": 8.0, "ankle_flex": -15.0,
    "waist_flex": 8.0, "shoulder_flex": -25.0, "shoulder_abd": 12.0, "elbow_flex": 5.0, "wrist_flex": -60.0,
}  # fmt: skip
CRAWL_CYCLE = Cycle(1.3, ((0.0, {"left_shoulder_flex": 14.0, "right_shoulder_flex": -14.0, "right_hip_flex": 14.0,
                "left_hip_flex": -14.0, "roll": 4.0, "waist_twist": 4.0},), (0.5, {"left_shoulder_flex": -14.0,
                "right_shoulder_flex": 14.0, "right_hip_flex": -14.0, "left_hip_flex": 14.0, "roll": -4.0,
                "waist_twist": -4.0},),))
ARMY = Cycle(2.0, ((0.0, {"left_shoulder_flex": 25.0, "left_elbow_flex": -50.0, "right_shoulder_flex": -20.0,
                "left_hip_abd": 25.0, "left_hip_flex": 45.0, "left_knee_flex": 75.0, "left_hip_twist": 30.0,
                "yaw": 6.0, "waist_lateral": -8.0},), (0.5, {"right_shoulder_flex": 25.0, "right_elbow_flex": -50.0,
                "left_shoulder_flex": -20.0, "right_hip_abd": 25.0, "right_hip_flex": 45.0, "right_knee_flex": 75.0,
                "right_hip_twist": 30.0, "yaw": -6.0, "waist_lateral": 8.0},),))
PRONE_CRAWL: Posture = {**PRONE, "shoulder_flex": 140.0, "shoulder_abd": 30.0, "elbow_flex": 100.0, "z": -0.8}
JACK_ARMS = Cycle(2.0, ((0.12, {"shoulder_abd": 0.0}), (0.6, {"shoulder_abd": 150.0, "elbow_flex": -25.0})), sync=True)
ROPE_ARMS = Cycle(1.0,
    ((0.0, {"shoulder_flex": 8.0, "shoulder_abd": -6.0}), (0.5, {"shoulder_flex": -8.0, "shoulder_abd": 6.0})),
    sync=True)
DRIBBLE = Cycle(0.6, ((0.0, {"rh_z": 0.0}), (0.45, {"rh_z": -0.32, "rh_x": 0.06, "right_wrist_flex": 50.0}),
        (0.6, {"rh_z": -0.3, "rh_x": 0.06, "right_wrist_flex": 30.0}),))
DRIBBLE_POSE: Posture = {"z": -0.1, "pitch": 12.0, "waist_flex": 12.0, "neck_flex": -8.0, "r_arm": 1.0, "rh_x": 0.3,
    "rh_y": -0.28, "rh_z": -0.05, "left_shoulder_flex": 40.0, "left_elbow_flex": 60.0, "left_shoulder_abd": 25.0,
    "f_w": 0.16}
SHOT_HOLD: Posture = {**CARRY_BALL, "h_z": 0.22, "h_x": 0.30}
SHOT_DIP: Posture = {**SHOT_HOLD, "z": -0.14, "pitch": 10.0, "h_z": 0.14, "f_w": 0.14}
SHOT_UP: Posture = {**CARRY_BALL, "h_x": 0.22, "h_w": 0.09, "h_z": 0.78, "f_pitch": 20.0, "f_w": 0.14,
    "neck_flex": -12.0, "right_shoulder_twist": 30.0}
SHOT_FOLLOW: Posture = {**SHOT_UP, "h_x": 0.38, "h_z": 0.74, "wrist_flex": 70.0, "f_pitch": 5.0}
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


FLINCH: Posture = {"z": -0.1, "x": -0.05, "pitch": 12.0, "waist_flex": 18.0, "neck_flex": 25.0,
    "shoulder_flex": 70.0, "shoulder_abd": 35.0, "elbow_flex": 125.0, "shoulder_twist": -30.0, "f_w": 0.13}
RECOIL: Posture = {"waist_flex": -12.0, "pitch": -6.0, "neck_flex": -12.0, "shoulder_flex": 45.0, "elbow_flex": 70.0,
    "shoulder_abd": 20.0}
PICK_LOW: Posture = {"z": -0.45, "pitch": 30.0, "waist_flex": 40.0, "neck_flex": -10.0, "r_arm": 1.0, "rh_x": 0.45,
    "rh_y": -0.16, "rh_z": 0.22, "left_shoulder_flex": 25.0, "left_elbow_flex": 40.0}
POUR_BASE: Posture = {"arm": 1.0, "lh_x": 0.36, "lh_y": 0.02, "lh_z": 0.02, "rh_x": 0.36, "rh_y": -0.12,
    "rh_z": 0.14, "neck_flex": 18.0, "waist_flex": 6.0, "left_shoulder_twist": -20.0}
POUR_TILT: Posture = {**POUR_BASE, "rh_y": -0.06, "rh_z": 0.2, "right_wrist_dev": 30.0, "right_wrist_flex": 40.0,
    "right_shoulder_twist": -45.0}
SURRENDER_KNEEL: Posture = {**KNEEL, **HANDS_UP, "neck_flex": 5.0}
FLOOR_STAND: Posture = {"leg": 0.0, "snap": 1.0}  # standing on directly posed legs (for rolls)
DEEP_SQUAT: Posture = {"leg": 0.0, "snap": 1.0, "hip_flex": 110.0, "knee_flex": 135.0, "ankle_flex": 30.0,
    "waist_flex": 20.0, "hip_abd": 10.0}


def wave_osc(t0: float, t1: float, amp: float = 22.0, period: float = 0.55) -> Osc:
    """The right hand waving (elbow oscillating) from ``t0`` to ``t1``."""
    return Osc("right_elbow_flex", amp, period, env=((t0, 0.0), (t0 + 0.3, 1.0), (t1 - 0.3, 1.0), (t1, 0.0)))


# fmt: on
