"""Background traffic: vehicles driving along the environment's lanes, yielding to people.

Kinematic, as the scene needs no more: no vehicle is a MuJoCo body, so nothing in the
simulation depends on the traffic, and the traffic is driven once the clip's frames are
known (``Traffic.drive``). A vehicle yields to whatever will be in its lane ahead (any body
of any person, as simulated, so a ragdoll thrown onto the road stops the traffic; a driven
prop, the car of ``car_hit`` or a pushed load; the vehicle in front; the camera where it
hangs less than ``CAMERA_HEADROOM_M`` over the
vehicle's roof) like a driver who sees it coming: it never brakes harder than
``BRAKE_MPS2``, stops ``STOP_GAP_M`` short of what comes into its way ahead and drives on
past what comes in behind it (an action's boxes too: a flight of stairs built out into a
lane). Only someone walking into its side can reach it: planned from
the recipe's background seed (``plan_traffic``), a vehicle that would meet a planned body so
is left out; the rest are driven against the simulated bodies.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Protocol

import numpy as np

from phav_spec.recipe import Recipe
from phav_spec.scene import ENVIRONMENT_SCENES, VEHICLE_HALF_SIZES, Lane
from phav_spec.seeding import stream


class Box(Protocol):
    """A box standing in the scene, as a plan's ``StaticBox`` is (traffic imports no plan)."""

    @property
    def center(self) -> tuple[float, float, float]: ...
    @property
    def half_size(self) -> tuple[float, float, float]: ...
    @property
    def yaw_deg(self) -> float: ...


#: Vehicles per lane: 0 to this many.
MAX_PER_LANE = 2
#: Cruising speed range, m/s (22–47 km/h).
CRUISE_MPS = (6.0, 13.0)
#: Acceleration, and the hardest a vehicle ever brakes (firm, short of an emergency stop), m/s².
ACCEL_MPS2 = 2.0
BRAKE_MPS2 = 6.0
#: A vehicle stops this far (m) from the obstacle ahead.
STOP_GAP_M = 3.0
#: Anything within the lane's half width plus this (m) of the centre line is in the way.
CORRIDOR_MARGIN_M = 0.8
#: Bumper-to-bumper space (m) between vehicles of one lane at the start.
START_SPACING_M = 8.0
#: The camera is in a vehicle's way when it hangs less than this (m) above the vehicle's roof.
CAMERA_HEADROOM_M = 0.5
#: Clearance reported when no vehicle is near anyone (the array stays finite).
FAR_M = 1000.0
#: A planned vehicle that would come closer than this (m) to anyone's planned body is left out.
MIN_CLEARANCE_M = 1.0
#: Speeds a vehicle weighs each frame, evenly from braking its hardest to its most
#: acceleration (and its speed now): a step of (ACCEL + BRAKE)·dt / (SPEED_STEPS − 1),
#: 0.03 m/s at 30 fps, as in the first frame's from standing to cruising.
SPEED_STEPS = 9


@dataclass(frozen=True)
class Vehicle:
    """One planned vehicle: what it is, its lane, where it starts and how fast it cruises."""

    name: str
    kind: str  # car, truck, bus (an OBJECTS name, its own pixel class)
    lane: Lane
    lane_index: int  # position of the lane in the environment's lanes
    half_size: tuple[float, float, float]  # length, width, height
    s0: float  # distance of its centre along the lane at t = 0, m
    cruise_mps: float


def plan_traffic(recipe: Recipe, obstacles: np.ndarray, camera: Sequence[float] | None = None) -> tuple[Vehicle, ...]:
    """The vehicles of a recipe's scene: none where the environment has no lanes.

    ``obstacles`` (F + 1, N, 3) are the planned bodies of every person and moving prop per
    frame. Each vehicle starts far enough from its lane's end to cruise the whole clip on
    the road, clear of the vehicle ahead; driven against the planned bodies, a vehicle that
    would still come within ``MIN_CLEARANCE_M`` of someone (a walker crossing into its
    side), or would start within it of the ``camera``'s start where that hangs lower than
    the vehicle's roof and ``CAMERA_HEADROOM_M`` (a vehicle yields to a camera ahead, not
    to one it starts on, and drove through it), is left out. The draws come from the background
    seed's ``traffic`` stream.
    """
    env = ENVIRONMENT_SCENES[recipe.environment.name]
    if not env.lanes:
        return ()
    rng = stream(recipe.seeds.background, "traffic")
    duration = recipe.n_frames / recipe.video.fps
    candidates: list[Vehicle] = []
    for lane_index, lane in enumerate(env.lanes):
        placed: list[Vehicle] = []
        for _ in range(int(rng.integers(0, MAX_PER_LANE + 1))):
            kind = lane.vehicles[int(rng.integers(0, len(lane.vehicles)))]
            half = VEHICLE_HALF_SIZES[kind]
            cruise = CRUISE_MPS[0] + (CRUISE_MPS[1] - CRUISE_MPS[0]) * rng.random()
            room = lane.length - 2.0 * half[0]
            cruise = min(cruise, 0.9 * room / max(duration, 1e-9))
            s0 = half[0] + (room - cruise * duration) * rng.random()
            if any(abs(s0 - v.s0) < half[0] + v.half_size[0] + START_SPACING_M for v in placed):
                continue  # no room beside an earlier draw: this lane has one vehicle fewer
            placed.append(Vehicle(f"traffic_{lane_index}_{len(placed)}", kind, lane, lane_index, half, s0, cruise))
        candidates.extend(placed)
    vehicles = tuple(candidates)
    while vehicles:
        traffic = Traffic.drive(vehicles, obstacles, 1.0 / recipe.video.fps)
        closest = traffic.clearances(obstacles).min(axis=1)
        if camera is not None:  # its start only (the camera moves), for the vehicles it hangs low over
            start = traffic.clearances([np.asarray(camera, dtype=np.float64)[None]])[:, 0]
            low = [camera[2] - v.lane.start[2] < 2.0 * v.half_size[2] + CAMERA_HEADROOM_M for v in vehicles]
            closest = np.minimum(closest, np.where(low, start, FAR_M))
        if closest.min() >= MIN_CLEARANCE_M:
            break
        drop = int(np.argmin(closest))
        vehicles = vehicles[:drop] + vehicles[drop + 1 :]
    return vehicles


def _frame(lane: Lane) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The lane's start, unit direction and unit left normal (x, y plane)."""
    start = np.array(lane.start)
    u = np.array(lane.end) - start
    u[2] = 0.0
    u /= np.linalg.norm(u)
    return start, u, np.array([-u[1], u[0], 0.0])


@dataclass(frozen=True)
class Traffic:
    """The vehicles driven over a clip: each one's centre's distance along its lane per frame."""

    vehicles: tuple[Vehicle, ...]
    s: np.ndarray  # (V, F)

    @classmethod
    def drive(cls, vehicles: tuple[Vehicle, ...], obstacles: Sequence[np.ndarray], dt: float,
              cameras: np.ndarray | None = None) -> Traffic:  # fmt: skip
        """Drive every vehicle through the clip's frames: ``obstacles[f]`` (N_f, 3) are the
        bodies and driven props' footprints at frame f, ``cameras`` (F, 3) the camera's
        position. Each lane's vehicles front to back, so a follower sees where its leader went."""
        s = np.zeros((len(vehicles), len(obstacles)))
        order = sorted(range(len(vehicles)), key=lambda i: (vehicles[i].lane_index, -vehicles[i].s0))
        leader: dict[int, np.ndarray] = {}  # lane → the rear of the vehicle ahead, per frame
        for i in order:
            v = vehicles[i]
            ahead = _in_the_way(v, obstacles, cameras, leader.get(v.lane_index))
            s[i] = _drive_one(v, ahead, dt)
            leader[v.lane_index] = s[i] - v.half_size[0]
        return cls(vehicles, s)

    def poses(self) -> tuple[np.ndarray, np.ndarray]:
        """Centres (V, F, 3) per frame and orientations (V, 4, w x y z): a vehicle faces
        along its (straight) lane all clip long."""
        pos = np.zeros((*self.s.shape, 3))
        quat = np.zeros((len(self.vehicles), 4))
        for i, v in enumerate(self.vehicles):
            start, u, _ = _frame(v.lane)
            pos[i] = start + u * self.s[i][:, None]
            pos[i, :, 2] = start[2] + v.half_size[2]
            yaw = math.atan2(u[1], u[0])
            quat[i] = (math.cos(yaw / 2), 0.0, 0.0, math.sin(yaw / 2))
        return pos, quat

    def clearances(self, obstacles: Sequence[np.ndarray]) -> np.ndarray:
        """(V, F): per vehicle and frame, the smallest ground-plane distance (m) from any of
        the frame's points (``obstacles[f]``: (N_f, 3)) to its footprint; ``FAR_M`` where
        there is nothing to measure."""
        out = np.full(self.s.shape, FAR_M)
        for i, v in enumerate(self.vehicles):
            start, u, left = _frame(v.lane)
            half = np.array(v.half_size[:2])
            for f, points in enumerate(obstacles):
                points = points[np.isfinite(points).all(axis=-1)]  # a lost body is no clearance
                if len(points):
                    rel = points - start  # lane axes are horizontal: heights drop out
                    local = np.stack([rel @ u - self.s[i, f], rel @ left], axis=-1)
                    outside = np.maximum(np.abs(local) - half, 0.0)
                    out[i, f] = min(FAR_M, float(np.min(np.linalg.norm(outside, axis=-1))))
        return out


def _in_the_way(v: Vehicle, obstacles: Sequence[np.ndarray], cameras: np.ndarray | None,
                leader_rear: np.ndarray | None) -> np.ndarray:  # fmt: skip
    """(F, K) distances along the lane of what stands in its corridor per frame, padded with
    +inf: the obstacles, the camera where it hangs lower than the vehicle's roof and
    ``CAMERA_HEADROOM_M``, and the rear of the vehicle ahead in the lane."""
    start, u, left = _frame(v.lane)
    rows = []
    for f, points in enumerate(obstacles):
        points = np.asarray(points, dtype=np.float64).reshape(-1, 3)
        if cameras is not None and cameras[f][2] - start[2] < 2.0 * v.half_size[2] + CAMERA_HEADROOM_M:
            points = np.concatenate([points, np.asarray(cameras[f], dtype=np.float64)[None]])
        rel = points - start
        along = rel @ u
        row = along[np.abs(rel @ left) < v.lane.half_width + CORRIDOR_MARGIN_M]
        rows.append(row if leader_rear is None else np.append(row, leader_rear[f]))
    out = np.full((len(rows), max((len(r) for r in rows), default=0) or 1), np.inf)
    for f, row in enumerate(rows):
        out[f, : len(row)] = row
    return out


def _drive_one(v: Vehicle, ahead: np.ndarray, dt: float) -> np.ndarray:
    """A vehicle's centre along its lane per frame, given what is in its way (``_in_the_way``).

    Each frame it takes the fastest speed within its braking and acceleration (and cruise)
    that is safe: from which some way on keeps ``STOP_GAP_M`` short of everything ahead in
    every later frame to the clip's end, a way on being to hold the speed until a frame
    (at once, never, or one of every ``HOLD_EVERY``) and then brake its hardest. The next
    frame can go on the same way (its hardest braking, or the same speed, is among the
    speeds it tries, and the frames are the same), so a vehicle never needs to brake harder,
    and it drives on past someone who steps into the lane behind it. Where no speed is safe
    (someone walks into its side) it takes the slowest of those that meet the fewest frames
    in the way. The first frame's speed is free up to the cruise, finely: the clip may start
    as it slows.
    """
    half = v.half_size[0]
    s = np.empty(len(ahead))
    s[0] = v.s0
    speed = v.cruise_mps
    for f in range(len(ahead) - 1):
        if f == 0:
            tried = np.linspace(0.0, v.cruise_mps, 1 + math.ceil(v.cruise_mps / _speed_step(dt)))
        else:
            lo, hi = max(speed - BRAKE_MPS2 * dt, 0.0), min(v.cruise_mps, speed + ACCEL_MPS2 * dt)
            tried = np.unique(np.append(lo + (hi - lo) * np.arange(SPEED_STEPS) / (SPEED_STEPS - 1), speed))
        if _blocked_frames(s[f], tried[-1:], ahead, f + 1, half, dt)[0] == 0:  # most frames: the fastest
            speed = float(tried[-1])
        else:
            blocked = _blocked_frames(s[f], tried, ahead, f + 1, half, dt)
            safe = np.nonzero(blocked == 0)[0]
            speed = float(tried[safe[-1]] if len(safe) else tried[np.argmin(blocked)])  # else the slowest of the fewest
        s[f + 1] = s[f] + speed * dt
    return s


def _speed_step(dt: float) -> float:
    """The step (m/s) between the speeds a vehicle tries in a frame."""
    return (ACCEL_MPS2 + BRAKE_MPS2) * dt / (SPEED_STEPS - 1)


#: The frames a vehicle's ways on may start braking at, besides at once: every this many.
HOLD_EVERY = 10


def _blocked_frames(s: float, speeds: np.ndarray, ahead: np.ndarray, first: int, half: float,
                    dt: float) -> np.ndarray:  # fmt: skip
    """Per speed tried (J,): in how many frames from ``first`` on (``ahead``: (F, K)) the
    vehicle moving on at that speed has something in its way, the fewest over its ways on.
    Braking at once and holding the speed to the end are tried first, for every speed;
    braking later (from a frame of every ``HOLD_EVERY``) only where neither is safe for any."""
    later = ahead[first:]
    m = np.arange(len(later))[None, :]
    grid = range(-(-(first + 1) // HOLD_EVERY) * HOLD_EVERY, first + len(later) - 1, HOLD_EVERY)
    holds = [1, len(later), *(last - first + 1 for last in grid)]  # moves made at the speed first
    blocked = np.full(len(speeds), len(later) + 1)
    for n, k in enumerate(holds):
        if n == 2 and np.any(blocked == 0):
            break
        open_ = np.nonzero(blocked > 0)[0]
        c = speeds[open_, None]
        way = np.where(m < k, c, np.maximum(c - BRAKE_MPS2 * dt * (m - k + 1), 0.0))
        blocked[open_] = np.minimum(blocked[open_], _frames_in_the_way(s, way, later, half, dt))
    return blocked


def _frames_in_the_way(s: float, speeds: np.ndarray, later: np.ndarray, half: float, dt: float) -> np.ndarray:
    """Per row of speeds (J, M) it moves at from ``s``: the frames with something between its
    rear and ``STOP_GAP_M`` beyond its front."""
    centre = (s + dt * np.cumsum(speeds, axis=1))[:, :, None]  # semi-implicit, as each frame moves
    inside = (later[None] > centre - half) & (later[None] < centre + half + STOP_GAP_M)
    return np.sum(np.any(inside, axis=2), axis=1)


def box_footprints(boxes: Sequence[Box]) -> np.ndarray:
    """The footprint points (9 per box, (N, 3)) of an action's static boxes (a flight of
    stairs, a door's frame, a chair): traffic stops short of them as of a body, where a
    flight built out into a lane was driven through."""
    if not boxes:
        return np.zeros((0, 3))
    return np.concatenate([footprint_points(np.asarray(b.center), math.radians(b.yaw_deg), b.half_size) for b in boxes])


def footprint_points(center: np.ndarray, yaw: float, half: tuple[float, ...]) -> np.ndarray:
    """Centre, corners and edge midpoints (..., 9, 3) of a box's footprint: how a moving
    box (the car-hit car) shows up as an obstacle."""
    c, s = math.cos(yaw), math.sin(yaw)
    local = np.array([(i * half[0], j * half[1]) for i in (-1, 0, 1) for j in (-1, 0, 1)])
    offsets = np.zeros((9, 3))
    offsets[:, 0] = c * local[:, 0] - s * local[:, 1]
    offsets[:, 1] = s * local[:, 0] + c * local[:, 1]
    return np.asarray(center)[..., None, :] + offsets
