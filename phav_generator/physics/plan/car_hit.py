"""Car hit: the car that crosses the protagonist's path, and the release its touch triggers."""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from phav_generator.motion.rotations import yaw_matrix
from phav_generator.physics.plan.builder import PlanBuilder, rot_to_quat, uniform
from phav_generator.physics.plan.obstacles import SUPPORT_TOLERANCE_M, clear_run, first_contact
from phav_generator.physics.plan.scene_plan import Manipulation, PersonPlan, PropPlan
from phav_spec.car_shapes import car_body, car_hulls, car_profile
from phav_spec.scene import ENVIRONMENT_SCENES, MAX_STEP_M, support_height, walkable_heights
from phav_spec.seeding import stream
from phav_spec.vocab import OBJECTS

#: The car's box floats this far (m) above the ground: its wheels fill the gap.
CAR_CLEARANCE_M = 0.15
#: The stream the drawn car takes its body type from (its first draw; render/scene.py).
CAR_LOOK_STREAM = "world/car"
#: How hard (m/s²) the car brakes once it has touched the protagonist (dry asphalt).
CAR_BRAKING_MPS2 = 8.0
#: How far (m) past the planned hit the car may touch first (a body moving on ahead of it).
CAR_LATE_TOUCH_M = 1.0
#: How far (m) the car's front (its bumper) is from the pelvis at the planned hit.
CAR_HIT_GAP_M = 0.15
#: How hard (m/s²) the car may speed up from a standstill where the way behind it is too
#: short to arrive at its speed from the clip's start: a brisk car, 0–100 km/h in 8 s.
CAR_ACCELERATION_MPS2 = 3.5
#: The directions the car may come from, in degrees off square across the protagonist's
#: heading, nearest first: it takes the first whose way is clear of the environment's
#: colliders (and stays on the raised ground it drives on), so it never drives out of a
#: wall, through a tree or off a plaza's edge.
CAR_TURNS_DEG = (0.0, *(sign * 15.0 * k for k in range(1, 12) for sign in (1.0, -1.0)), 180.0)
#: How far (m) the car keeps from a background walker's pelvis, beyond its box: a body's
#: half width and a stride. Walkers are not simulated: a car driven into one passes through.
CAR_WALKER_KEEP_M = 0.5
#: Where no direction is clear at the drawn hit time (the protagonist walking into a wall
#: or a rail), the hit comes earlier, in steps of this (s)...
CAR_EARLIER_HIT_S = 0.25
#: ... but no earlier than this (s), the least time to see the car come.
CAR_EARLIEST_HIT_S = 0.5


def car_hit(b: PlanBuilder, p: PersonPlan) -> PersonPlan:
    """Car hit: a car crosses the protagonist's path and hits them; contact releases the pins.

    The car collides as the body type the renderer draws in its box (``car_hulls``): its
    bumper and front meet the legs, the hood and windscreen what folds onto them. It comes
    from where its way is clear (``_approach``) and stops short of what stands ahead."""
    rng = stream(b.recipe.seeds.physics, "car_hit")
    speed = uniform(5.0, 12.0, rng=rng)
    n = len(b.times)
    duration = b.times[-1]
    t_hit = uniform(0.35, 0.6, rng=rng) * duration
    side = 1.0 if rng.random() < 0.5 else -1.0
    heading = np.deg2rad(b.recipe.protagonist.heading_deg)
    half = np.array([2.1, 0.9, 0.7])
    ground = b.recipe.protagonist.position[2]
    way = _approach(b, p, Approach(heading, speed, speed * t_hit, t_hit, ground), side, half)
    speed, t_hit, ground = way.speed, way.t_hit, way.ground
    # The car's front reaches the pelvis at t_hit; then it brakes once it has touched.
    path = _car_path(b, p, way, side, half)
    yaw = way.heading + side * math.pi / 2 + math.pi
    quat = rot_to_quat(yaw_matrix(yaw))
    # The car has stopped by the time it has braked from a late touch (its path's end).
    lane_end = min(n - 1, int(np.searchsorted(b.times, t_hit + CAR_LATE_TOUCH_M / speed + speed / CAR_BRAKING_MPS2)))
    body = car_body(stream(b.recipe.seeds.physics, CAR_LOOK_STREAM))
    hulls = car_hulls(car_profile(body, tuple(half), CAR_CLEARANCE_M))
    b.props.append(
        PropPlan("car", "car", OBJECTS["car"], "box", tuple(half), 1200.0, path[0], quat, dynamic=False, path=path,
                 hulls=hulls, lane_end=lane_end)
    )  # fmt: skip
    b.manipulations.append(Manipulation("car", p.person_id, "pelvis", "hit", t_hit, float(b.times[-1])))
    return replace(p, release_on_contact_with="car")


@dataclass(frozen=True)
class Approach:
    """How the car of ``car_hit`` comes at the protagonist: square across ``heading`` (the
    protagonist's, turned), at ``speed`` (m/s) when it hits at ``t_hit`` (s), on the ground
    at height ``ground`` there, from ``start`` metres before the hit (at a standstill until
    it must set off, where that is less than ``speed`` × ``t_hit``), on for at most
    ``ahead`` metres past the hit."""

    heading: float
    speed: float
    start: float
    t_hit: float
    ground: float
    ahead: float = math.inf


def _approach(b: PlanBuilder, p: PersonPlan, drawn: Approach, side: float, half: np.ndarray) -> Approach:
    """The way the car comes, for the drawn one: the first hit time (the drawn one, then
    earlier) and direction (``CAR_TURNS_DEG``) from which it can drive at its speed from the
    clip's start, hit and brake to a stop without meeting a collider; else the first whose
    way behind is long enough to reach its speed from a standstill; else the way that allows
    the most speed, speeding up from a standstill and braking to a stop short of what stands
    ahead at no more than the car's acceleration and braking (``_allowed``). Each of these
    first among the ways that keep clear of the background walkers (``_meets_walkers``)."""
    env = b.recipe.environment.name
    scene = ENVIRONMENT_SCENES[env]
    speed = drawn.speed
    stop_m = speed**2 / (2.0 * CAR_BRAKING_MPS2) + CAR_LATE_TOUCH_M
    reach = speed**2 / (2.0 * CAR_ACCELERATION_MPS2)
    earliest = min(CAR_EARLIEST_HIT_S, drawn.t_hit)
    # Not after the protagonist's planned way meets something it cannot pass (it would stand
    # against it, not where the car aims), then the drawn time, then earlier.
    latest = max(min(drawn.t_hit, _free_until(b, p, drawn.ground)), earliest)
    hits = [latest - k * CAR_EARLIER_HIT_S for k in range(int((latest - earliest) / CAR_EARLIER_HIT_S) + 1)]
    reach_m = half[0] + CAR_HIT_GAP_M  # from the pelvis to the car's centre at the hit
    ways = []
    for t_hit in hits:
        pelvis = _pelvis_at(b, p, t_hit)
        # The ground under the protagonist then: off a plaza they walked from, the street's.
        ground = support_height(env, float(pelvis[0]), float(pelvis[1]), reference_z=drawn.ground)
        raised = ground > scene.ground_z + SUPPORT_TOLERANCE_M
        runs = []
        for turn in CAR_TURNS_DEG:
            turned = drawn.heading + side * math.radians(turn)
            across = _across(turned, side)
            centre = (float(pelvis[0] + across[0] * reach_m), float(pelvis[1] + across[1] * reach_m))
            back, ahead = clear_run(scene.colliders, centre, (-float(across[0]), -float(across[1])), tuple(half),
                                    ground + CAR_CLEARANCE_M, ground, raised=raised)  # fmt: skip
            runs.append((turned, back, ahead))
        clear = []  # whether each way keeps clear of the walkers (a way with no room behind: no)
        for turned, back, ahead in runs:
            way = Approach(turned, speed, min(back, speed * t_hit), t_hit, ground, ahead)
            clear.append(back > 0.0 and not _meets_walkers(b, p, way, side, half))
        for (turned, back, ahead), ok in zip(runs, clear, strict=True):
            if ok and back >= speed * t_hit and ahead >= stop_m:
                return Approach(turned, speed, speed * t_hit, t_hit, ground)
        for (turned, back, ahead), ok in zip(runs, clear, strict=True):
            if ok and back >= reach and ahead >= stop_m:
                return Approach(turned, speed, back, t_hit, ground)
        ways += [(_allowed(speed, back, ahead) > 0.0, ok, _allowed(speed, back, ahead), back, -k, t_hit, turned, ahead,
                  ground) for k, ((turned, back, ahead), ok) in enumerate(zip(runs, clear, strict=True))]  # fmt: skip
    *_, v, back, _, t_hit, turned, ahead, ground = max(ways, key=lambda w: w[:6])
    if v <= 0.0:
        return drawn  # hemmed in all round: square across, as drawn
    return Approach(turned, v, min(back, v * t_hit), t_hit, ground, ahead)


def _across(heading: float, side: float) -> np.ndarray:
    """The unit direction (3,) the car drives in, from the side it comes from, for a way of
    ``heading`` (the protagonist's frame turned): the car crosses square to it."""
    return yaw_matrix(heading) @ np.array([0.0, side, 0.0])


def _car_path(b: PlanBuilder, p: PersonPlan, way: Approach, side: float, half: np.ndarray) -> np.ndarray:
    """The car's centre at every plan step along ``way``: its front reaching the protagonist's
    pelvis at the hit, then braking once it has touched."""
    pelvis = _pelvis_at(b, p, way.t_hit)
    across = _across(way.heading, side)
    centre_hit = np.array([pelvis[0], pelvis[1], way.ground + half[2] + CAR_CLEARANCE_M]) + across * (
        half[0] + CAR_HIT_GAP_M
    )
    return centre_hit[None, :] - across[None, :] * _run(way, b.times)[:, None]


def _meets_walkers(b: PlanBuilder, p: PersonPlan, way: Approach, side: float, half: np.ndarray) -> bool:
    """Whether the car driven along ``way`` comes within ``CAR_WALKER_KEEP_M`` of a background
    walker's pelvis at any frame (in the car's frame, elementwise: no BLAS summation order)."""
    if not b.walkers:
        return False
    centre = _car_path(b, p, way, side, half)[:: b.substeps, :2]
    across = _across(way.heading, side)
    along, lateral = (float(across[0]), float(across[1])), (-float(across[1]), float(across[0]))
    for walker in b.walkers:
        d = walker.targets.root_pos[:, :2] - centre
        ahead = np.abs(d[:, 0] * along[0] + d[:, 1] * along[1]) <= half[0] + CAR_WALKER_KEEP_M
        beside = np.abs(d[:, 0] * lateral[0] + d[:, 1] * lateral[1]) <= half[1] + CAR_WALKER_KEEP_M
        if bool(np.any(ahead & beside)):
            return True
    return False


def _allowed(speed: float, back: float, ahead: float) -> float:
    """The most speed (m/s, at most ``speed``) a car can hit at with ``back`` metres behind the
    hit to speed up in from a standstill and ``ahead`` metres past it to run on after a late
    touch and brake to a stop in (0 where either is too short)."""
    room = min(2.0 * CAR_ACCELERATION_MPS2 * back, 2.0 * CAR_BRAKING_MPS2 * (ahead - CAR_LATE_TOUCH_M))
    return min(speed, math.sqrt(room)) if room > 0.0 else 0.0


def _pelvis_at(b: PlanBuilder, p: PersonPlan, t: float) -> np.ndarray:
    """Where ``p``'s planned pelvis is at time ``t`` (the first plan step at or after it)."""
    return p.targets.root_pos[min(int(np.searchsorted(b.times, t)), len(b.times) - 1)]


def _free_until(b: PlanBuilder, p: PersonPlan, ground: float) -> float:
    """Until when (s) the protagonist's planned body keeps clear of the obstacles it would
    run into (``obstacles.first_contact``) and over ground at the height it started on, less
    ``CAR_EARLIER_HIT_S``; the clip's end where it always does."""
    root = p.targets.root_pos
    heights = walkable_heights(b.recipe.environment.name, root[:, 0], root[:, 1], ground + MAX_STEP_M)
    off = np.flatnonzero(np.abs(heights - ground) > SUPPORT_TOLERANCE_M)
    steps = [int(k) for k in (first_contact(b, p), off[0] if off.size else None) if k is not None]
    return float(b.times[min(steps)]) - CAR_EARLIER_HIT_S if steps else float(b.times[-1])


def _run(way: Approach, times: np.ndarray) -> np.ndarray:
    """How far (m) the car is along its way at each time, 0 at the hit (negative before):
    at its speed throughout, or from a standstill ``way.start`` metres back, speeding up
    evenly to arrive at its speed; after the hit on at that speed for ``CAR_LATE_TOUCH_M``,
    then braking to a stop, hit or miss (a touch brakes it sooner, in the simulation), and
    never further than ``way.ahead``."""
    v, s0, t_hit = way.speed, way.start, way.t_hit
    late = CAR_LATE_TOUCH_M / v
    braking = np.clip(times - t_hit - late, 0.0, v / CAR_BRAKING_MPS2)
    after = v * np.minimum(times - t_hit, late) + v * braking - 0.5 * CAR_BRAKING_MPS2 * braking**2
    after = np.minimum(after, way.ahead)
    if s0 >= v * t_hit:
        return np.where(times < t_hit, v * (times - t_hit), after)
    if s0 <= v * t_hit / 2.0:  # stands, then sets off as late as it can
        t0 = t_hit - 2.0 * s0 / v
        u, a = 0.0, v * v / (2.0 * s0)
    else:  # already rolling at the start
        t0 = 0.0
        u = 2.0 * s0 / t_hit - v
        a = (v - u) / t_hit
    dt = np.clip(times - t0, 0.0, None)
    return np.where(times < t_hit, -s0 + u * dt + 0.5 * a * dt**2, after)
