"""Background traffic: vehicles driving along the environment's lanes, yielding to people.

Kinematic, as the scene needs no more: a vehicle brakes for whatever is in its lane ahead
(any body of any person, as simulated, so a ragdoll thrown onto the road stops the
traffic, the vehicle in front, and the camera where it hangs less than
``CAMERA_HEADROOM_M`` over the vehicle's roof), so it never touches anyone and needs no
MuJoCo body. It brakes as hard as it must (no limit on its deceleration).
Planned from the recipe's background seed (``plan_traffic``), driven frame by frame inside
``simulate`` from where the people actually are (``Traffic.advance``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from phav_spec.recipe import Recipe
from phav_spec.scene import ENVIRONMENT_SCENES, VEHICLE_HALF_SIZES, Lane
from phav_spec.seeding import stream

#: Vehicles per lane: 0 to this many.
MAX_PER_LANE = 2
#: Cruising speed range, m/s (22–47 km/h).
CRUISE_MPS = (6.0, 13.0)
#: Acceleration and the braking used to stop short of an obstacle, m/s².
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


def plan_traffic(recipe: Recipe, obstacles: np.ndarray) -> tuple[Vehicle, ...]:
    """The vehicles of a recipe's scene: none where the environment has no lanes.

    ``obstacles`` (F + 1, N, 3) are the planned bodies of every person and moving prop per
    frame. Each vehicle starts far enough from its lane's end to cruise the whole clip on
    the road, clear of the vehicle ahead; driven against the planned bodies, a vehicle that
    would still come within ``MIN_CLEARANCE_M`` of someone (a walker crossing into its
    side) is left out. The draws come from the background seed's ``traffic`` stream.
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
        closest = _rehearse(vehicles, obstacles, 1.0 / recipe.video.fps)
        if closest.min() >= MIN_CLEARANCE_M:
            break
        drop = int(np.argmin(closest))
        vehicles = vehicles[:drop] + vehicles[drop + 1 :]
    return vehicles


def _rehearse(vehicles: tuple[Vehicle, ...], obstacles: np.ndarray, dt: float) -> np.ndarray:
    """Each vehicle's smallest clearance to the obstacles over the clip, driven as planned."""
    traffic = Traffic(vehicles)
    closest = traffic.clearances(obstacles[0])
    for frame in range(1, len(obstacles)):
        traffic.advance(obstacles[frame - 1], dt)
        closest = np.minimum(closest, traffic.clearances(obstacles[frame]))
    return closest


def _frame(lane: Lane) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The lane's start, unit direction and unit left normal (x, y plane)."""
    start = np.array(lane.start)
    u = np.array(lane.end) - start
    u[2] = 0.0
    u /= np.linalg.norm(u)
    return start, u, np.array([-u[1], u[0], 0.0])


class Traffic:
    """The vehicles' state while a clip is simulated: distance along the lane and speed."""

    def __init__(self, vehicles: tuple[Vehicle, ...]):
        self.vehicles = vehicles
        self.s = np.array([v.s0 for v in vehicles], dtype=np.float64)
        self.speed = np.array([v.cruise_mps for v in vehicles], dtype=np.float64)
        self._frames = [_frame(v.lane) for v in vehicles]
        # Front to back within each lane, so a follower sees where its leader went.
        self._order = sorted(range(len(vehicles)), key=lambda i: (vehicles[i].lane_index, -self.s[i]))
        # A vehicle faces along its (straight) lane all clip long.
        yaws = [math.atan2(u[1], u[0]) for _, u, _ in self._frames]
        self._quat = np.array([(math.cos(y / 2), 0.0, 0.0, math.sin(y / 2)) for y in yaws]).reshape(-1, 4)

    def poses(self) -> tuple[np.ndarray, np.ndarray]:
        """Centres (V, 3) and orientations (V, 4, w x y z) now."""
        pos = np.zeros((len(self.vehicles), 3))
        for i, (v, (start, u, _)) in enumerate(zip(self.vehicles, self._frames, strict=True)):
            pos[i] = start + u * self.s[i]
            pos[i, 2] = start[2] + v.half_size[2]
        return pos, self._quat.copy()

    def advance(self, obstacles: np.ndarray, dt: float, camera: np.ndarray | None = None) -> None:
        """Drive one frame: cruise, or brake to stop ``STOP_GAP_M`` short of the nearest
        obstacle point (N, 3), the camera (3,) where it hangs lower than the vehicle's roof
        and ``CAMERA_HEADROOM_M``, or the vehicle ahead in the lane."""
        leader: dict[int, float] = {}  # lane id → rear of the vehicle ahead, along the lane
        for i in self._order:
            v = self.vehicles[i]
            start, u, left = self._frames[i]
            lane = v.lane_index
            front = self.s[i] + v.half_size[0]
            gap = leader.get(lane, math.inf) - front
            points = obstacles
            if camera is not None and camera[2] - start[2] < 2.0 * v.half_size[2] + CAMERA_HEADROOM_M:
                points = np.concatenate([obstacles, np.asarray(camera, dtype=np.float64)[None]])
            if len(points):
                rel = points - start
                along = rel @ u - front
                across = np.abs(rel @ left)
                # In the corridor and not wholly behind the vehicle's rear.
                mask = (across < v.lane.half_width + CORRIDOR_MARGIN_M) & (along > -2.0 * v.half_size[0])
                if np.any(mask):
                    gap = min(gap, float(np.min(along[mask])))
            allowed = math.sqrt(2.0 * BRAKE_MPS2 * max(gap - STOP_GAP_M, 0.0))
            self.speed[i] = min(v.cruise_mps, self.speed[i] + ACCEL_MPS2 * dt, allowed)
            self.s[i] += self.speed[i] * dt
            leader[lane] = self.s[i] - v.half_size[0]

    def clearances(self, points: np.ndarray) -> np.ndarray:
        """Per vehicle, the smallest ground-plane distance (m) from any point (N, 3) to its
        footprint; ``FAR_M`` where there is nothing to measure."""
        out = np.full(len(self.vehicles), FAR_M)
        if not len(points):
            return out
        for i, v in enumerate(self.vehicles):
            start, u, left = self._frames[i]
            rel = points - start  # lane axes are horizontal: heights drop out
            local = np.stack([rel @ u - self.s[i], rel @ left], axis=-1)
            outside = np.maximum(np.abs(local) - np.array(v.half_size[:2]), 0.0)
            out[i] = min(FAR_M, float(np.min(np.linalg.norm(outside, axis=-1))))
        return out

    def clearance(self, points: np.ndarray) -> float:
        """Smallest distance (m, ground plane) from any point (N, 3) to any vehicle's footprint."""
        return float(self.clearances(points).min(initial=FAR_M))


def footprint_points(center: np.ndarray, yaw: float, half: tuple[float, ...]) -> np.ndarray:
    """Centre, corners and edge midpoints (..., 9, 3) of a box's footprint: how a moving
    box (the car-hit car) shows up as an obstacle."""
    c, s = math.cos(yaw), math.sin(yaw)
    local = np.array([(i * half[0], j * half[1]) for i in (-1, 0, 1) for j in (-1, 0, 1)])
    offsets = np.zeros((9, 3))
    offsets[:, 0] = c * local[:, 0] - s * local[:, 1]
    offsets[:, 1] = s * local[:, 0] + c * local[:, 1]
    return np.asarray(center)[..., None, :] + offsets
