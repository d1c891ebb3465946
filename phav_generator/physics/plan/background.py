"""Background pedestrians: kinematic walkers between the recipe's waypoints."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from phav_generator.body.model import rest_body
from phav_generator.motion.animation import MotionParams, Pose, animate, motion_params, motion_scale
from phav_generator.motion.library import get_motion
from phav_generator.motion.skeleton import JOINT_BODIES, forward_kinematics
from phav_generator.physics.plan.builder import PlanBuilder
from phav_generator.physics.plan.people import halt, planted_before
from phav_generator.physics.plan.scene_plan import PersonPlan
from phav_spec.metadata import JOINT_ORDER
from phav_spec.scene import MAX_STEP_M, walkable_heights
from phav_spec.vocab import MUSCLES

#: The highest step (m) a walker takes in its stride: a kerb, a low terrace. A higher
#: ledge on its way (a plaza, a park's terrace, up to ``MAX_STEP_M``) stops it short of it,
#: as someone stops at a wall they would have to climb.
STEP_M = 0.3
#: How far short of such a ledge (m) its pelvis stops: a stride's front foot and its toes
#: clear of it.
LEDGE_STOP_M = 0.65
#: How far to either side of its path a walker's feet reach (m): a foot's width off the
#: hip's line.
BACKGROUND_SIDE_M = 0.2
#: How far ahead of its ankle a foot's sole reaches (m): a foot stands on the highest
#: surface under its heel or its toes.
SOLE_M = 0.15
#: How fast (m/s) the pelvis moves onto a new level: a step of ``STEP_M`` over three frames.
LEVEL_RATE_MPS = 3.0
#: Heights the scenes declare in decimetres differ by a float's last bit (0.2 − (−0.1)).
_TOLERANCE_M = 1e-6
_ANKLES = [JOINT_BODIES[JOINT_ORDER.index(f"{side}_ankle")] for side in ("left", "right")]


def background_people(b: PlanBuilder) -> list[PersonPlan]:
    """Background pedestrians: kinematic walkers between waypoints, posed at frame times only."""
    r = b.recipe
    frame_times = np.arange(r.n_frames + 1) / r.video.fps
    walk = get_motion("walk_forward_01")
    ends = walk.fn(np.array([0.0, walk.length_s]), MotionParams())
    nominal = float(np.linalg.norm(ends.root_pos[1, :2] - ends.root_pos[0, :2])) / walk.length_s
    out = []
    for actor in r.background_actors:
        dims = rest_body(actor.human.phenotype).dims
        start = np.array(actor.start)
        dest = np.array(actor.destination)
        delta = dest - start
        dist = float(np.linalg.norm(delta[:2]))
        heading = math.degrees(math.atan2(delta[1], delta[0])) if dist > 1e-6 else 0.0
        speed = actor.speed_mps / max(nominal * motion_scale(dims), 1e-6)
        params = motion_params(speed, False, r.seeds.background, f"background/{actor.person_id}")
        pose = animate(walk, frame_times, params.phase * walk.length_s, params, dims, (0.0, 0.0, 0.0), heading)
        along = delta / max(dist, 1e-9)
        reach = max(start[2], dest[2]) + MAX_STEP_M
        stop = _ledge_stop(r.environment.name, start, along, dist, reach)
        # The gait's own advance is replaced by the straight segment, so the walker arrives
        # where the recipe says (or short of a ledge it would have to climb). Its sway and
        # surge about that advance are kept: they carry the pelvis over the planted foot,
        # which would slide without them.
        root = start[None, :] + (actor.speed_mps * frame_times)[:, None] * along[None, :]
        root[:, :2] += _stride_sway(pose.root_pos[:, :2])
        root[:, 2] = pose.root_pos[:, 2]  # the gait's own bob and standing height, over z = 0
        n = len(frame_times)
        walker = PersonPlan(
            person_id=actor.person_id,
            role="background",
            dims=dims,
            params=params,
            motion="walk_forward_01",
            targets=Pose(root, pose.root_quat, pose.q),
            strengths=np.ones((n, len(MUSCLES))),
            pin=np.ones(n),
            physical=False,
        )
        at = int(np.searchsorted(frame_times, stop / actor.speed_mps, side="right")) - 1  # where it arrives
        if at <= 0:  # nowhere to go (or less than a frame's walk): standing where it starts
            walker = _standing(walker)
        elif at < n - 1:  # it arrives: it slows to its last stance there
            walker = halt(walker, frame_times, float(frame_times[planted_before(walker, frame_times, at)]))
        t = walker.targets
        lift = _stance_level(r.environment.name, dims, t.root_pos, t.root_quat, t.q, along, reach, r.video.fps)
        out.append(replace(walker, targets=Pose(t.root_pos + lift[:, None] * np.array([0.0, 0.0, 1.0]),
                                                t.root_quat, t.q)))  # fmt: skip
    return out


def _stride_sway(root_xy: np.ndarray) -> np.ndarray:
    """A walk's pelvis (T, 2) about the straight, steady line from its first to its last
    sample: the sway and surge of its stride, without its advance."""
    n = len(root_xy)
    if n < 2:
        return np.zeros_like(root_xy)
    u = (np.arange(n) / (n - 1))[:, None]
    return root_xy - (root_xy[0] + u * (root_xy[-1] - root_xy[0]))


def _standing(walker: PersonPlan) -> PersonPlan:
    """A walker that has nowhere to go, standing where it starts: its legs straight (every
    angle 0), facing its way, its lower ankle as high as its gait plants one."""
    t = walker.targets
    walking, _ = forward_kinematics(walker.dims, t.root_pos, t.root_quat, t.q)
    n = len(t.root_pos)
    still = Pose(np.repeat(t.root_pos[:1], n, axis=0), np.repeat(t.root_quat[:1], n, axis=0), np.zeros_like(t.q))
    standing, _ = forward_kinematics(walker.dims, still.root_pos, still.root_quat, still.q)
    still.root_pos[:, 2] += walking[:, _ANKLES, 2].min() - standing[:, _ANKLES, 2].min(axis=1)
    return replace(walker, targets=still)


def _ledge_stop(env: str, start: np.ndarray, along: np.ndarray, dist: float, reach: float) -> float:
    """How far along its path a walker goes: to its destination, or ``LEDGE_STOP_M`` short
    of the first ledge higher than ``STEP_M`` under its feet (the surface under the path's
    line and a foot's width to either side, every 5 cm)."""
    d = np.minimum(np.arange(0.0, dist + 0.05, 0.05), dist)
    side = np.array([-along[1], along[0]])
    lines = np.array(
        [walkable_heights(env, *(start[:2] + d[:, None] * along[:2] + w * side).T, reach)
         for w in (-BACKGROUND_SIDE_M, 0.0, BACKGROUND_SIDE_M)]
    )  # fmt: skip
    # A ledge ahead, or beside the way (a path along a plaza's edge puts one foot on it).
    ahead = np.abs(np.diff(lines.max(axis=0))) > STEP_M + _TOLERANCE_M
    beside = np.ptp(lines, axis=0)[1:] > STEP_M + _TOLERANCE_M
    ledges = np.flatnonzero(ahead | beside)
    return dist if len(ledges) == 0 else max(0.0, float(d[ledges[0]]) - LEDGE_STOP_M)


def _stance_level(
    env: str,
    dims,
    root: np.ndarray,
    root_quat: np.ndarray,
    q: np.ndarray,
    along: np.ndarray,
    reach: float,
    fps: int,
) -> np.ndarray:
    """The height (T,) the walker's gait stands on: per frame, the least that keeps each
    foot over the surface under its heel or toes as far as the gait lifts it over flat
    ground (a kerb is stepped onto by the foot that lands on it, not by a pelvis that sees
    it coming), moved onto a new level at ``LEVEL_RATE_MPS``: rising before a foot needs it,
    falling once none does, so no foot sinks into a kerb and none hangs over one for more
    than a few frames."""
    bodies, _ = forward_kinematics(dims, root, root_quat, q)
    ankles = bodies[:, _ANKLES]  # (T, 2, 3) over the ground at z = 0
    toes = ankles[..., :2] + SOLE_M * along[:2]
    heels = walkable_heights(env, ankles[..., 0], ankles[..., 1], reach)
    tips = walkable_heights(env, toes[..., 0], toes[..., 1], reach)
    # The higher of heel and toes, unless they straddle a ledge no stride takes: then the
    # foot stands below it (a walker stopped at a plaza's edge, its toes over it).
    under = np.where(np.abs(tips - heels) > STEP_M + _TOLERANCE_M, np.minimum(heels, tips), np.maximum(heels, tips))
    # Each foot as high over its surface as the gait holds it over flat ground: a planted
    # foot on it, a swinging one as far above it as it is lifted. The pelvis's level is the
    # least that keeps both so (a foot swinging over a kerb's edge clears it).
    lift = ankles[..., 2] - ankles[..., 2].min(axis=0)
    level = (under - lift).max(axis=1)
    rate = LEVEL_RATE_MPS / fps
    rising, falling = level.copy(), level.copy()
    for k in range(len(level) - 2, -1, -1):  # reach a higher level by the frame a foot needs it
        rising[k] = max(rising[k], rising[k + 1] - rate)
    for k in range(1, len(level)):  # leave it only once no foot needs it
        falling[k] = max(falling[k], falling[k - 1] - rate)
    return np.maximum(rising, falling)
