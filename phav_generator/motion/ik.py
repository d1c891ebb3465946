"""Inverse kinematics of the reference body: legs to ankle targets, arms to wrist targets.

Legs reach their foot targets by analytic two-link IK (hip flex/abd/twist, knee, ankle; the
heel rises where the ankle would over-flex); arms reach wrist targets by pole-vector IK
(hands on a pull-up bar, a cart, a rifle). Swings that hold one club or bat with both hands
are solved once per keyframe (``posed_arms``, damped least squares from the previous key's
answer) and interpolated in joint space, so the arms never flip.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from dataclasses import dataclass

import numpy as np

from phav_generator.motion.channels import DEG, Posture, default, expand
from phav_generator.motion.reference import (
    FOREARM,
    HIP_LIMITS,
    HIP_Y,
    SHIN,
    SHOULDER,
    SHOULDER_LIMITS,
    THIGH,
    TOE,
    UPPER_ARM,
)
from phav_generator.motion.rotations import rot_x, rot_y, rot_z
from phav_generator.motion.skeleton import DOF_INDEX, LOWER, UPPER


def limb_ik(
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


def limb_matrix(
    flex: np.ndarray, abd: np.ndarray, twist: np.ndarray, bend: np.ndarray, s: float, e: float
) -> np.ndarray:
    """The limb chain's rotation R_y(−flex)·R_x(s·abd)·R_z(s·twist)·R_y(−e·bend) (T, 3, 3)."""
    return rot_y(-flex) @ rot_x(s * abd) @ rot_z(s * twist) @ rot_y(-e * bend)


def terminal_angles(m: np.ndarray, s: float) -> tuple[np.ndarray, np.ndarray]:
    """(flex, deviation) of an ankle/wrist whose rotation is m = R_y(−flex)·R_x(s·dev)."""
    a = np.arctan2(-m[:, 2, 0], np.maximum(m[:, 0, 0], 0.05))  # beyond ±90°: held near the limit
    b = np.arctan2(-m[:, 1, 2], np.maximum(m[:, 1, 1], 0.05))
    return -a, s * b


def arm_ik(
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
    f_lo, f_hi, a_lo, a_hi = SHOULDER_LIMITS
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


#: The arm's joint angles, in the order ``arm_ik`` and ``fit_arm`` give them.
ARM_DOFS = ("shoulder_flex", "shoulder_abd", "shoulder_twist", "elbow_flex")
#: Both arms' joint channels: keyframed channels amplitude must leave alone when the
#: arms hold one club together (``Spec.rigid``).
ARM_CHANNELS = tuple(f"{side}_{d}" for side in ("left", "right") for d in ARM_DOFS)


def arm_points(x: np.ndarray, s: float) -> tuple[np.ndarray, np.ndarray]:
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
    idx = [DOF_INDEX[f"{side}_{d}"] for d in ARM_DOFS]
    lo, hi = LOWER[idx], UPPER[idx]
    pole = np.asarray(pole, dtype=np.float64) / np.linalg.norm(pole)
    seed = np.clip(np.asarray(seed, dtype=np.float64), lo, hi)
    shoulder = SHOULDER * np.array([1.0, s, 1.0])

    def residuals(v: np.ndarray) -> np.ndarray:  # (N, 4) → (N, 10)
        elbow, wrist = arm_points(v, s)
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


class PosedArms(Sequence[tuple[float, Posture]]):
    """Keyframes whose hand targets (chest frame, ``arm`` weight 1) are replaced by joint angles.

    Each key's arms are fitted from the previous key's angles (``fit_arm``), so the motion
    interpolates in joint space between solved keys: hands meet at every key and the arms
    never flip configuration between them. The fits are solved on first use (a few hundred
    milliseconds for a golf swing), not when the catalogue is read.
    """

    def __init__(self, keys: tuple[tuple[float, Posture], ...]):
        self._keys = keys
        self._solved: tuple[tuple[float, Posture], ...] | None = None

    def _solve(self) -> tuple[tuple[float, Posture], ...]:
        if self._solved is None:
            self._solved = _fit_keys(self._keys)
        return self._solved

    def __len__(self) -> int:
        return len(self._keys)

    def __getitem__(self, index):  # type: ignore[override]
        return self._solve()[index]

    def __iter__(self) -> Iterator[tuple[float, Posture]]:
        return iter(self._solve())


def posed_arms(keys: tuple[tuple[float, Posture], ...]) -> PosedArms:
    """``keys`` with their hand targets solved into arm joint angles (``PosedArms``)."""
    return PosedArms(keys)


def _fit_keys(keys: tuple[tuple[float, Posture], ...]) -> tuple[tuple[float, Posture], ...]:
    """Each key's arms fitted to its hand targets, starting from the previous key's angles."""
    seeds = {side: np.array([0.5, 0.2, 0.0, 0.5]) for side in ("left", "right")}
    out = []
    for t, post in keys:
        ch = expand(post)
        new = dict(ch)
        for side, c in (("left", "l"), ("right", "r")):
            if ch.get(f"{c}_arm", 0.0) < 0.5:
                continue
            target = np.array([ch.get(f"{c}h_{a}", default(f"{c}h_{a}")) for a in "xyz"])
            pole = np.array([ch.get(f"{c}e_{a}", default(f"{c}e_{a}")) for a in "xyz"])
            x = fit_arm(side, target, pole, seeds[side])
            seeds[side] = x
            for d, v in zip(ARM_DOFS, x, strict=True):
                new[f"{side}_{d}"] = float(v / DEG)
            new[f"{c}_arm"] = 0.0
        out.append((t, new))
    return tuple(out)


@dataclass(frozen=True)
class LegGoal:
    """What one leg must reach: its ankle target and foot orientation, blended in by
    ``weight``; ``contact`` (weight × ground contact) says how firmly the foot is planted."""

    side: str  # "left" | "right"
    s: float  # +1 left, −1 right
    weight: np.ndarray  # (T,) IK weight
    ankle: np.ndarray  # (T, 3)
    foot_rot: np.ndarray  # (T, 3, 3)
    contact: np.ndarray | float


def leg_ik(q: np.ndarray, legs: list[LegGoal], root: np.ndarray, rmat: np.ndarray, yaw: np.ndarray) -> None:
    """Solve each leg for its ankle target and foot orientation, blended by its IK weight (in place).

    Where the foot would need more dorsiflexion than the ankle allows (a trailing foot far
    behind, a foot on a lower stair), the heel rises instead, rolling about the toe.
    """
    toe = np.array([TOE[0], 0.0, TOE[1]])
    hi = UPPER[DOF_INDEX["left_ankle_flex"]] - 2 * DEG
    for leg in legs:
        side, s, w, ankle, frot, wc = leg.side, leg.s, leg.weight, leg.ankle, leg.foot_rot, leg.contact
        soft = 0.985 - 0.12 * (1.0 - wc)  # a swinging foot may fall short of its target: no knee snap
        hip = root + rmat @ np.array([0.0, s * HIP_Y, 0.0])
        fyaw = np.arctan2(frot[:, 1, 0], frot[:, 0, 0])
        twist = s * np.clip(np.angle(np.exp(1j * (fyaw - yaw))), -0.7, 0.7)
        hint = (q[:, DOF_INDEX[f"{side}_hip_flex"]], q[:, DOF_INDEX[f"{side}_hip_abd"]])
        for attempt in range(3):
            d = np.einsum("tji,tj->ti", rmat, ankle - hip)
            flex, abd, knee = limb_ik(d, THIGH, SHIN, s, -1.0, twist, hint, HIP_LIMITS, soft)
            m = rmat @ limb_matrix(flex, abd, twist, knee, s, -1.0)
            af, ai = terminal_angles(np.einsum("tji,tjk->tik", m, frot), s)
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
