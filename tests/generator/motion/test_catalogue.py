"""The built-in motion catalogue: every motion stays inside the skeleton's limits, stands
on the ground, does not slide its feet, moves smoothly, loops where it is a cycle, does what
its description says, and the actions it serves can be told apart from their motions alone
(a nearest-centroid classifier on pose features)."""

from __future__ import annotations

import functools
import re
from dataclasses import dataclass

import numpy as np
import pytest

from phav_generator.motion.animation import MotionParams, mirror, play
from phav_generator.motion.catalogue import SPECS
from phav_generator.motion.engine import Osc, Spec, layers
from phav_generator.motion.gait import stair_height
from phav_generator.motion.library import get_motion
from phav_generator.motion.rotations import quat_to_matrix
from phav_generator.motion.skeleton import (
    BONE_INDEX,
    DOF_INDEX,
    LOWER,
    UPPER,
    body_dims,
    capsule_points,
    forward_kinematics,
)
from phav_spec.motions import MOTIONS, theta_ab
from phav_spec.theta import load_preset
from phav_spec.vocab import ACTIONS

REF = body_dims(1.75, 70.0, 0.40, 0.34, 1.0)
NAMES = list(MOTIONS.names)
#: The default, and two recipes at the ends of the parameter ranges.
PARAMS = (
    MotionParams(),
    MotionParams(amplitude=0.85, phase=0.37, style=-1.0),
    MotionParams(amplitude=1.15, phase=0.81, style=1.0),
)
HZ = 240
REGEX = load_preset("phav-v1").theta_ab.regex
THETA_AB = theta_ab(REGEX)
STAIRS = {n: SPECS[n].gait.stairs for n in NAMES if SPECS[n].gait is not None and SPECS[n].gait.stairs}
HANGING = {n for n in NAMES if re.search(REGEX["pull_up"], MOTIONS[n].description)}
#: Motions matched by the hop and jump regexes: both feet leave the ground together.
FLIGHT = {n for n in NAMES if any(re.search(REGEX[a], MOTIONS[n].description) for a in ("hop", "jump"))}
#: Running gaits (stance shorter than half the cycle) have flight phases too.
RUNS = {n for n in NAMES if (g := SPECS[n].gait) is not None and (g.duty is None or g.duty < 0.5)}
GAITS = {n for n in NAMES if (s := SPECS[n]).gait is not None and s.gait.feet == "alt"}
RADII = np.array([c.radius for c in REF.capsules])


@functools.lru_cache(maxsize=8)  # a few motions at a time: memory stays small
def sampled(name: str, k: int) -> tuple[np.ndarray, object]:
    """The motion sampled at 240 Hz over [0, length] with PARAMS[k]."""
    m = get_motion(name)
    t = np.linspace(0.0, m.length_s, round(m.length_s * HZ) + 1)
    return t, m.fn(t, PARAMS[k])


@functools.lru_cache(maxsize=8)
def bodies(name: str, k: int, step: int = 4) -> tuple[np.ndarray, ...]:
    """Forward kinematics at 60 Hz: times, body origins, capsule bottoms (T, 15) and ends."""
    t, pose = sampled(name, k)
    sl = slice(None, None, step)
    root = pose.root_pos[sl] + np.array([0.0, 0.0, REF.standing_pelvis_height])
    pos, rot = forward_kinematics(REF, root, pose.root_quat[sl], pose.q[sl])
    wa, wb = capsule_points(REF, pos, rot)
    low = np.minimum(wa[..., 2], wb[..., 2]) - RADII
    return t[sl], pos, low, wa, wb


def ground_clearance(name: str, k: int) -> np.ndarray:
    """Lowest body point above the ground (T,), or above the staircase for stairs motions."""
    _, _, low, wa, wb = bodies(name, k)
    if name not in STAIRS:
        return low.min(axis=1)
    d = STAIRS[name]
    # each capsule's two end spheres and its middle, against the step height under them
    pts = np.stack([wa, wb, 0.5 * (wa + wb)], axis=2)  # (T, 15, 3, 3)
    h = stair_height(pts[..., 0], d)
    return (pts[..., 2] - RADII[None, :, None] - h).min(axis=(1, 2))


def foot_stance_speeds(name: str, k: int) -> list[np.ndarray]:
    """Horizontal speed of each foot's contact point over the samples it is on the ground.

    The contact point is the foot capsule's lower end sphere (heel or toe): a foot rolling
    from heel to toe does not slide, a foot dragged along the floor does.
    """
    t, _, _, wa, wb = bodies(name, k)
    out = []
    for foot in ("left_foot", "right_foot"):
        b = BONE_INDEX[foot]
        ends = np.stack([wa[:, b], wb[:, b]], axis=1)  # (T, 2, 3) sphere centres
        floor = stair_height(ends[..., 0], STAIRS[name]) if name in STAIRS else 0.0
        clearance = ends[..., 2] - RADII[b] - floor
        low_end = (clearance[:, 1] < clearance[:, 0] - 0.005).astype(int)  # the heel unless the toe is lower
        on = clearance.min(axis=1) <= 0.02
        idx = np.arange(len(t) - 1)
        same = on[1:] & on[:-1] & (low_end[1:] == low_end[:-1])
        p0 = ends[idx, low_end[:-1], :2]
        p1 = ends[idx + 1, low_end[:-1], :2]
        v = np.linalg.norm(p1 - p0, axis=1) / np.diff(t)
        out.append(v[same])
    return out


@dataclass(frozen=True)
class Summary:
    """What the per-motion tests check, measured once per (motion, params)."""

    in_limits: bool
    max_step: float  # largest joint change between 240 Hz samples, rad
    step_at: float
    max_root_speed: float
    max_root_turn: float  # largest root rotation between samples, rad
    clearance_min: float
    clearance_max: float
    touching: float  # fraction of the time something touches the ground (or stair)
    slide: tuple[float, ...]  # median contact-point speed of each foot in stance, m/s
    slide_mean: tuple[float, ...]
    loop_q: float  # joint mismatch between τ = 0 and τ = length
    loop_z: float
    loop_tilt: float
    q_coarse: np.ndarray  # joint angles at 10 Hz, to tell recipes apart


@functools.cache
def summary(name: str, k: int) -> Summary:
    t, pose = sampled(name, k)
    q = pose.q
    dq = np.abs(np.diff(q, axis=0))
    r = quat_to_matrix(pose.root_quat)
    cos = (np.einsum("tij,tij->t", r[1:], r[:-1]) - 1.0) / 2.0
    clearance = ground_clearance(name, k)
    speeds = foot_stance_speeds(name, k) if name in GAITS or name == "moonwalk_artist_01" else []
    return Summary(
        in_limits=bool(np.all(q >= LOWER - 1e-9) and np.all(q <= UPPER + 1e-9)),
        max_step=float(dq.max()),
        step_at=float(t[dq.max(axis=1).argmax()]),
        max_root_speed=float((np.linalg.norm(np.diff(pose.root_pos, axis=0), axis=1) * HZ).max()),
        max_root_turn=float(np.arccos(np.clip(cos, -1, 1)).max()),
        clearance_min=float(clearance.min()),
        clearance_max=float(clearance.max()),
        touching=float(np.mean(clearance <= 0.03)),
        slide=tuple(float(np.median(v)) if len(v) else float("nan") for v in speeds),
        slide_mean=tuple(float(np.mean(v)) if len(v) else float("nan") for v in speeds),
        loop_q=float(np.abs(q[0] - q[-1]).max()),
        loop_z=float(abs(pose.root_pos[0, 2] - pose.root_pos[-1, 2])),
        loop_tilt=float(abs(r[0, :, 2] @ r[-1, :, 2] - 1.0)),
        q_coarse=q[:: HZ // 10].copy(),
    )


@pytest.mark.parametrize("name", NAMES)
def test_shapes_finite_and_deterministic(name):
    m = get_motion(name)
    t = np.concatenate([[0.0, m.length_s], np.random.default_rng(0).uniform(0, m.length_s, 37)])
    for p in PARAMS:
        a, b = m.fn(t, p), m.fn(t.copy(), p)
        assert a.root_pos.shape == (len(t), 3) and a.root_quat.shape == (len(t), 4) and a.q.shape == (len(t), 30)
        for x, y in ((a.root_pos, b.root_pos), (a.root_quat, b.root_quat), (a.q, b.q)):
            assert np.all(np.isfinite(x)) and np.array_equal(x, y)
        assert np.allclose(np.linalg.norm(a.root_quat, axis=1), 1.0)
        # a sample does not depend on the other samples it is evaluated with
        single = m.fn(t[5:6], p)
        assert np.allclose(single.q, a.q[5:6], atol=1e-9) and np.allclose(single.root_pos, a.root_pos[5:6], atol=1e-9)


@pytest.mark.parametrize("k", range(len(PARAMS)))
@pytest.mark.parametrize("name", NAMES)
def test_inside_limits_smooth_and_on_the_ground(name, k):
    s = summary(name, k)
    assert s.in_limits, "joint limits"
    assert s.max_step < 0.15, f"jump of {s.max_step:.3f} rad at {s.step_at:.2f}s"
    assert s.max_step * HZ < 25.0, f"angular velocity {s.max_step * HZ:.1f} rad/s at {s.step_at:.2f}s"
    assert s.max_root_speed < 10.0, f"root speed {s.max_root_speed:.1f} m/s"
    assert s.max_root_turn < 0.15, "root orientation jump"
    assert s.clearance_min > -0.02, f"{s.clearance_min:.3f} m below the ground"
    if name in HANGING:
        assert s.clearance_min > 0.03  # hanging from the bar
    else:
        flight = name in FLIGHT or name in RUNS
        assert s.touching >= (0.45 if flight else 0.85), f"on the ground {s.touching:.0%} of the time"


@pytest.mark.parametrize("name", sorted(GAITS))
def test_gaits_do_not_slide_their_feet(name):
    for k in range(len(PARAMS)):
        slide = summary(name, k).slide
        assert all(v < 0.15 for v in slide), f"stance feet move at {slide} m/s"


def test_moonwalk_slides_backwards():
    for k in range(len(PARAMS)):
        _, pose = sampled("moonwalk_artist_01", k)
        assert pose.root_pos[-1, 0] < -3.0
        assert min(summary("moonwalk_artist_01", k).slide_mean) > 0.15


@pytest.mark.parametrize("name", [n for n in NAMES if SPECS[n].cyclic])
def test_cycles_loop_seamlessly(name):
    for k in range(len(PARAMS)):
        s = summary(name, k)
        assert s.loop_q < 0.02 and s.loop_z < 0.01 and s.loop_tilt < 1e-3  # same pose, height, pitch and roll


@pytest.mark.parametrize("name", NAMES)
def test_recipes_with_different_params_differ(name):
    a, b = summary(name, 1).q_coarse, summary(name, 2).q_coarse
    assert np.abs(a - b).max() > 0.02


@pytest.mark.parametrize("name", sorted(FLIGHT))
def test_hops_and_jumps_leave_the_ground_with_both_feet(name):
    for k in range(len(PARAMS)):
        assert summary(name, k).clearance_max > 0.03


def test_every_sub_hmdb_action_has_three_motions():
    sub = "brush_hair catch clap climb_stairs golf jump kick_ball push pick pour pull_up run shoot_ball shoot_bow "
    sub += "shoot_gun sit stand swing_baseball throw walk wave"
    for action in sub.split():
        assert THETA_AB[ACTIONS.index(action)].sum() >= 3, action


# ---- What the descriptions promise, measured.


def end_state(name: str, k: int = 0) -> tuple[np.ndarray, np.ndarray]:
    _, pos, _, _, _ = bodies(name, k)
    return pos[-1], pos


def test_walks_and_runs_advance_at_their_speed_and_runs_fly():
    for name, lo, hi in (
        ("walk_forward_01", 1.1, 1.5),
        ("run_forward_01", 3.0, 4.0),
        ("walk_backwards_01", -0.8, -0.4),
    ):
        t, pose = sampled(name, 0)
        v = (pose.root_pos[-1, 0] - pose.root_pos[0, 0]) / t[-1]
        assert lo < v < hi, (name, v)
    for name in ("run_forward_01", "sprint_away_01", "jog_circle_01"):
        assert np.mean(ground_clearance(name, 0) > 0.01) > 0.1


def test_turns_circles_and_stops():
    _, pose = sampled("walk_forward_turn_left_01", 0)
    yaw = np.degrees(np.arctan2(*quat_to_matrix(pose.root_quat[[-1]])[0, [1, 0], 0]))
    assert 80 < yaw < 100
    assert np.linalg.norm(pose.root_pos[-1] - pose.root_pos[-HZ]) < 0.02  # stopped for the last second
    _, pose = sampled("walk_circle_01", 0)
    assert np.linalg.norm(pose.root_pos[-1, :2] - pose.root_pos[0, :2]) < 0.3  # back where it started


def test_stairs_rise_one_step_per_stride():
    for name, sign in (("climb_up_stairs_01", 1), ("go_down_stairs_01", -1), ("run_up_stairs_01", 1)):
        _, pos, _, wa, wb = bodies(name, 0)
        feet = [BONE_INDEX["left_foot"], BONE_INDEX["right_foot"]]
        ends = np.stack([wa[:, feet], wb[:, feet]], axis=2)  # heel and toe spheres (T, 2, 2, 3)
        above = ends[..., 2] - RADII[feet[0]] - stair_height(ends[..., 0], sign)
        assert np.mean(np.abs(above).min(axis=(1, 2)) < 0.02) > 0.8  # a foot stands on a tread
        assert sign * stair_height(pos[-1, feet, 0], sign).min() > 1.0  # metres up (down) the stairs


def test_sitting_lowers_the_pelvis_onto_a_chair_seat():
    for name in ("sit_down_chair_01", "stand_up_from_chair_01"):
        _, pose = sampled(name, 0)
        seated = pose.root_pos[-1 if name.startswith("sit") else 0]
        assert -0.5 < seated[2] < -0.4 and seated[0] < -0.3
    _, pose = sampled("stand_up_from_chair_01", 0)
    assert abs(pose.root_pos[-1, 2]) < 0.03


def test_pull_ups_hang_from_a_bar():
    for name in sorted(HANGING):
        _, pos, _, _, _ = bodies(name, 0)
        hands = pos[:, [BONE_INDEX["left_hand"], BONE_INDEX["right_hand"]], 2]
        assert np.all(np.abs(hands - 2.25) < 0.06)
        head = pos[:, BONE_INDEX["head"], 2]
        assert head.max() - head.min() > 0.3  # pulls up


def test_crawls_dives_and_falls_are_low_and_prone():
    for name in ("crawl_hands_and_knees_01", "crawling_all_fours_01", "army_crawl_01"):
        _, pos = end_state(name)
        assert pos[:, BONE_INDEX["chest"], 2].max() < 0.6
        _, pose = sampled(name, 0)
        pitch = np.degrees(np.arccos(np.clip(quat_to_matrix(pose.root_quat)[:, 2, 2], -1, 1)))
        assert np.all((pitch > 70) & (pitch < 95)), name
    for name in ("dive_onto_floor_artist_01", "drop_to_ground_prone_01", "fall_to_ground_01"):
        last, pos = end_state(name)
        assert pos[0, BONE_INDEX["head"], 2] > 1.4 and last[BONE_INDEX["head"], 2] < 0.4
        assert last[BONE_INDEX["chest"], 2] < 0.35


def test_splits_spread_the_legs_low():
    for name in ("split_slide_stretch_01", "front_split_floor_01", "side_split_warm_up_01"):
        last, _ = end_state(name)
        spread = np.linalg.norm(last[BONE_INDEX["left_foot"]] - last[BONE_INDEX["right_foot"]])
        assert spread > 1.2 and last[BONE_INDEX["pelvis"], 2] < 0.35, name


def test_hand_gestures():
    hands = [BONE_INDEX["left_hand"], BONE_INDEX["right_hand"]]
    _, pos = end_state("clap_rhythm_01")
    gap = np.linalg.norm(pos[:, hands[0]] - pos[:, hands[1]], axis=1)
    assert gap.min() < 0.08 and gap.max() > 0.15 and np.sum(np.diff((gap < 0.1).astype(int)) == 1) > 20
    _, pos = end_state("wave_hello_right_01")
    mid = slice(len(pos) // 4, 3 * len(pos) // 4)
    rh = pos[mid, hands[1]]
    assert np.all(rh[:, 2] > pos[mid, BONE_INDEX["head"], 2] - 0.1) and np.ptp(rh[:, 1]) > 0.08
    for name, t0, t1 in (
        ("golf_full_swing_01", 2, 6),
        ("baseball_swing_right_01", 1.5, 4),
        ("pistol_two_hands_01", 2, 7),
    ):
        t, pos, _, _, _ = bodies(name, 0)
        sel = (t > t0) & (t < t1)
        gap = np.linalg.norm(pos[sel, hands[0]] - pos[sel, hands[1]], axis=1)
        assert np.percentile(gap, 90) < 0.16, name  # both hands on the club, bat, gun
    _, pos = end_state("raise_both_hands_hold_01")
    assert np.all(pos[len(pos) // 2, hands, 2] > pos[len(pos) // 2, BONE_INDEX["head"], 2])


def at_time(name: str, seconds: float) -> np.ndarray:
    """Body origins (15, 3) of a motion at one time (default params)."""
    t, pos, _, _, _ = bodies(name, 0)
    return pos[np.abs(t - seconds).argmin()]


def test_more_gestures_and_postures():
    b = BONE_INDEX
    # hair: the brushing hand works around the head
    for name, hand in (("comb_hair_right_hand_01", "right_hand"), ("brush_hair_left_hand_01", "left_hand")):
        t, pos, _, _, _ = bodies(name, 0)
        mid = slice(len(t) // 5, 4 * len(t) // 5)
        head = pos[mid, b["head"]] + np.array([0.0, 0.0, 0.13])  # the skull's centre, above the neck
        assert np.median(np.linalg.norm(pos[mid, b[hand]] - head, axis=1)) < 0.25, name
    # bow: the left arm straight ahead, the right hand drawn back to the chin
    p = at_time("archery_draw_release_01", 4.5)
    assert p[b["left_hand"], 0] - p[b["chest"], 0] > 0.5
    assert np.linalg.norm(p[b["right_hand"]] - p[b["head"]]) < 0.2
    # gun: both hands ahead at shoulder height
    p = at_time("pistol_two_hands_01", 4.0)
    ahead = p[[b["left_hand"], b["right_hand"]], 0] - p[b["chest"], 0]
    assert np.all(ahead > 0.4) and np.all(
        np.abs(p[[b["left_hand"], b["right_hand"]], 2] - p[b["right_upper_arm"], 2]) < 0.15
    )
    # surrender kneeling: hands above the head, pelvis down at knee height
    p = at_time("surrender_kneel_artist_01", 12.0)
    assert np.all(p[[b["left_hand"], b["right_hand"]], 2] > p[b["head"], 2]) and p[b["pelvis"], 2] < 0.6
    # golf: the torso turns through the swing
    _, pose = sampled("golf_full_swing_01", 0)
    twist = pose.q[:, DOF_INDEX["waist_twist"]]
    assert np.ptp(twist) > np.radians(60)


def test_kicks_swing_a_leg_and_limps_are_asymmetric():
    for name in ("kick_soccer_ball_01", "penalty_kick_01", "martial_front_kick_01", "dribble_kick_ball_01"):
        _, pose = sampled(name, 0)
        assert pose.q[:, DOF_INDEX["right_hip_flex"]].max() > np.radians(60), name
    knees = [DOF_INDEX["left_knee_flex"], DOF_INDEX["right_knee_flex"]]
    for name in ("walk_injured_knee_01", "walk_with_limp_01", "limp_right_leg_01"):
        _, pose = sampled(name, 0)
        swing = np.ptp(pose.q[:, knees], axis=0)
        assert abs(swing[0] - swing[1]) / swing.max() > 0.3, name


# ---- The actions can be told apart from their motions.


def window_features(name: str, params: MotionParams, start: float) -> np.ndarray:
    """Pose features of a 3 s window at 30 fps: joint angles, root height, pitch, planar speed."""
    t = np.arange(90) / 30.0
    pose = play(get_motion(name), t, start, params)
    if params.mirror:
        pose = mirror(pose)
    r = quat_to_matrix(pose.root_quat)
    pitch = np.arccos(np.clip(r[:, 2, 2], -1.0, 1.0))  # trunk tilt from upright
    speed = np.linalg.norm(np.gradient(pose.root_pos[:, :2], 1 / 30.0, axis=0), axis=1)
    x = np.concatenate([pose.q, pose.root_pos[:, 2:3], pitch[:, None], speed[:, None]], axis=1)[::3]
    d = np.abs(np.diff(x, axis=0))
    return np.concatenate([x.mean(0), x.std(0), x.min(0), x.max(0), d.mean(0)])


def excluded_actions() -> dict[str, str]:
    """Actions whose motions all serve another action (or that contain another's): not separable."""
    sets = {a: frozenset(np.flatnonzero(THETA_AB[i])) for i, a in enumerate(ACTIONS.names) if THETA_AB[i].any()}
    out = {}
    for a, ma in sets.items():
        for b, mb in sets.items():
            if a != b and ma <= mb:
                out[a] = f"its motions are a subset of {b}'s"
                out.setdefault(b, f"contains every motion of {a}")
    return out


def sample_set(actions: list[str], seed: int, per_action: int) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    xs, ys = [], []
    for label, action in enumerate(actions):
        motions = [MOTIONS.names[j] for j in np.flatnonzero(THETA_AB[ACTIONS.index(action)])]
        for _ in range(per_action):
            name = motions[rng.integers(len(motions))]
            length = MOTIONS[name].length_s
            params = MotionParams(
                speed=rng.uniform(0.85, 1.15),
                amplitude=rng.uniform(0.85, 1.15),
                phase=rng.random(),
                style=rng.uniform(-1, 1),
                mirror=bool(rng.random() < 0.5),
            )
            xs.append(window_features(name, params, rng.uniform(0.0, max(length - 3.0, 0.0))))
            ys.append(label)
    return np.array(xs), np.array(ys)


def test_actions_are_distinguishable_by_a_nearest_centroid_classifier():
    excluded = excluded_actions()
    assert set(excluded) == {"walk", "run", "car_hit"}
    actions = [a for a in ACTIONS.names if THETA_AB[ACTIONS.index(a)].any() and a not in excluded]
    xtr, ytr = sample_set(actions, seed=1, per_action=24)
    xte, yte = sample_set(actions, seed=2, per_action=12)
    mu, sd = xtr.mean(0), xtr.std(0) + 1e-6
    ztr, zte = (xtr - mu) / sd, (xte - mu) / sd
    centroids = np.stack([ztr[ytr == c].mean(0) for c in range(len(actions))])
    pred = np.argmin(((zte[:, None, :] - centroids[None]) ** 2).sum(-1), axis=1)
    acc = float(np.mean(pred == yte))
    per_action = {a: float(np.mean(pred[yte == c] == c)) for c, a in enumerate(actions)}
    confusions = {
        a: actions[int(np.bincount(pred[yte == c], minlength=len(actions)).argmax())]
        for c, a in enumerate(actions)
        if per_action[a] < 0.5
    }
    summary = f"accuracy {acc:.1%}; weakest: " + ", ".join(
        f"{a} {per_action[a]:.0%}→{confusions.get(a, a)}" for a in sorted(per_action, key=per_action.get)[:8]
    )
    print(summary)
    assert acc >= 0.6, summary


@pytest.mark.parametrize(
    ("spec", "left", "right"),
    [
        (Spec("gesture", style={"h_w": 0.1}), "lh_y", "rh_y"),  # hands apart: left +y, right −y
        (Spec("gesture", osc=(Osc("f_out", 8.0, 2.0),)), "lf_yaw", "rf_yaw"),  # toes out: yaws opposite
        (Spec("gesture", style={"rh_y": -0.1}), None, "rh_y"),  # a right-side channel as written
    ],
)
def test_a_shorthand_moves_the_two_sides_as_mirror_images(spec, left, right):
    """The style and oscillator layers give a shorthand's two sides as ``expand`` does (the
    right side mirrored once, not twice), and a channel written for one side as written."""
    tau = np.linspace(0.0, 2.0, 9)
    params = MotionParams(style=1.0, phase=0.1)
    ch, _ = layers(spec, tau, params, 2.0)
    plain, _ = layers(Spec("gesture"), tau, params, 2.0)
    r = ch[right] - plain[right]
    assert np.abs(r).max() > 1e-3
    if left is None:
        np.testing.assert_allclose(r, -0.1)
    else:
        np.testing.assert_allclose(ch[left] - plain[left], -r, atol=1e-12)
