"""Car hit: the car that crosses the protagonist's path, and the release its touch triggers."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from phav_generator.motion.rotations import yaw_matrix
from phav_generator.physics.plan.builder import PlanBuilder, rot_to_quat, uniform
from phav_generator.physics.plan.scene_plan import Manipulation, PersonPlan, PropPlan
from phav_spec.car_shapes import car_body, car_hulls, car_profile
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


def car_hit(b: PlanBuilder, p: PersonPlan) -> PersonPlan:
    """Car hit: a car crosses the protagonist's path and hits them; contact releases the pins.

    The car collides as the body type the renderer draws in its box (``car_hulls``): its
    bumper and front meet the legs, the hood and windscreen what folds onto them."""
    rng = stream(b.recipe.seeds.physics, "car_hit")
    speed = uniform(5.0, 12.0, rng=rng)
    n = len(b.times)
    duration = b.times[-1]
    t_hit = uniform(0.35, 0.6, rng=rng) * duration
    side = 1.0 if rng.random() < 0.5 else -1.0
    i_hit = int(np.searchsorted(b.times, t_hit))
    pelvis = p.targets.root_pos[min(i_hit, n - 1)]
    heading = np.deg2rad(b.recipe.protagonist.heading_deg)
    across = yaw_matrix(heading) @ np.array([0.0, side, 0.0])
    half = np.array([2.1, 0.9, 0.7])
    ground = b.recipe.protagonist.position[2]
    # The car's front reaches the pelvis at t_hit; then it brakes once it has touched.
    centre_hit = np.array([pelvis[0], pelvis[1], ground + half[2] + CAR_CLEARANCE_M]) + across * (half[0] + 0.15)
    path = centre_hit[None, :] - across[None, :] * speed * (b.times - t_hit)[:, None]
    yaw = heading + side * math.pi / 2 + math.pi
    quat = rot_to_quat(yaw_matrix(yaw))
    # The car never passes its braking distance beyond where it first touches.
    stop_m = speed**2 / (2.0 * CAR_BRAKING_MPS2) + CAR_LATE_TOUCH_M
    lane_end = min(n - 1, int(np.searchsorted(b.times, t_hit + stop_m / speed)))
    body = car_body(stream(b.recipe.seeds.physics, CAR_LOOK_STREAM))
    hulls = car_hulls(car_profile(body, tuple(half), CAR_CLEARANCE_M))
    b.props.append(
        PropPlan("car", "car", OBJECTS["car"], "box", tuple(half), 1200.0, path[0], quat, dynamic=False, path=path,
                 hulls=hulls, lane_end=lane_end)
    )  # fmt: skip
    b.manipulations.append(Manipulation("car", p.person_id, "pelvis", "hit", t_hit, float(b.times[-1])))
    return replace(p, release_on_contact_with="car")
