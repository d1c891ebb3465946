"""Car hit: the car touches the protagonist, the pins let go and the ragdoll falls; the
car collides as the car drawn, bumper first, and pushes a camera in its way aside; it comes
from where its way is clear and keeps to the ground it drives on."""

from __future__ import annotations

import dataclasses
import math

import mujoco
import numpy as np
import pytest

from phav_generator.motion.skeleton import BONE_INDEX
from phav_generator.physics import Trajectory
from phav_generator.physics.control import SimulationRun
from phav_generator.physics.model import CAMERA_RADIUS_M
from phav_generator.physics.plan.car_hit import (
    CAR_ACCELERATION_MPS2,
    CAR_BRAKING_MPS2,
    CAR_CLEARANCE_M,
    CAR_LATE_TOUCH_M,
    Approach,
    _run,
)
from phav_generator.physics.plan.obstacles import clear_run
from phav_generator.physics.plan.scene import plan_scene
from phav_generator.physics.simulate import simulate, simulate_plan
from phav_generator.render.scene import drawn_vehicle
from phav_generator.sampling import RecipeSampler
from phav_spec.car_shapes import CAR_BODIES, car_profile
from phav_spec.scene import ENVIRONMENT_SCENES, Collider, support_height
from phav_spec.theta import load_theta
from phav_validators.checks.failures import BoxSet
from tests.generator.physics.support import assert_healthy, recipe_for
from tests.helpers import outside_hulls, run_measure

PELVIS = BONE_INDEX["pelvis"]


@pytest.fixture(scope="module")
def car_hit() -> Trajectory:
    # No variation: a weakened muscle is meant to lag its animation.
    return simulate(recipe_for("car_hit", seconds=3.0, variation="none"))


def test_car_hit_contact_then_fall(car_hit: Trajectory) -> None:
    assert_healthy(car_hit)
    touched = np.flatnonzero(car_hit.contacts["car_protagonist"])
    assert touched.size, "the car never touched the protagonist"
    after = car_hit.people[0].body_pos[touched[0] :, PELVIS, 2]
    ground = recipe_for("car_hit", seconds=3.0, variation="none").protagonist.position[2]
    assert np.min(after - ground) < 0.5


def test_the_car_stops_within_its_lane(car_hit: Trajectory) -> None:
    plan = plan_scene(recipe_for("car_hit", seconds=3.0, variation="none"))
    car = _car(plan)
    track = next(t for t in car_hit.props if t.name == "car")
    travelled = np.linalg.norm(track.pos[-1, :2] - car.path[0, :2])
    assert np.linalg.norm(track.pos[-1] - track.pos[-2]) < 1e-6  # it has stopped
    assert travelled <= np.linalg.norm(car.path[car.lane_end, :2] - car.path[0, :2])


def test_released_ragdoll_is_simulated(car_hit: Trajectory) -> None:
    p = car_hit.people[0]
    touched = np.flatnonzero(car_hit.contacts["car_protagonist"])[0]
    assert p.pin[-1] == 0.0 and p.pin[0] == 1.0
    divergence = np.linalg.norm(p.body_pos - p.target_pos, axis=-1).max(axis=1)
    assert divergence[: max(touched - 2, 1)].max() < 0.15
    assert divergence[touched:].max() > 0.5
    # After the release, something other than a foot rests on the ground.
    rest = [BONE_INDEX[b] for b in ("pelvis", "chest", "head", "left_hand", "right_hand")]
    ground = recipe_for("car_hit", seconds=3.0, variation="none").protagonist.position[2]
    assert (p.body_pos[-1, rest, 2] - ground).min() < 0.3


def _car(plan):
    return next(p for p in plan.props if p.object == "car")


@pytest.mark.parametrize("index", range(4))
def test_the_car_collides_as_the_car_the_renderer_draws(index):
    recipe = recipe_for("car_hit", index=index)
    car = _car(plan_scene(recipe))
    body = drawn_vehicle(recipe, car).body
    # Its body type's glass spans the stations its greenhouse hull stands on.
    _, first, end, _ = next(part for part in body.parts if part[0] == "glass")
    glass_x = body.positions[np.unique(body.triangles[first:end]), 0]
    belt_x = [corner[0] for corner in car.hulls[1][:2]] + [corner[0] for corner in car.hulls[1][2:4]]
    assert np.isclose(glass_x.max(), max(belt_x), atol=1e-3) and np.isclose(glass_x.min(), min(belt_x), atol=1e-3)
    assert outside_hulls(body.positions.astype(np.float64), car.hulls).max() <= 0.14  # the underside, as drawn


def test_the_car_meets_the_legs_with_its_bumper_and_front(monkeypatch):
    recipe = recipe_for("car_hit", seconds=2.0, variation="none")
    plan = plan_scene(recipe)
    first: list[float] = []
    original = SimulationRun.check_contacts

    def spy(run, t):
        names = original(run, t)
        if "car_protagonist" in names and not first:
            people = set(run.scene.people[0].geoms.tolist())
            cars = run.car_geoms
            first.extend(
                float(run.d.contact[k].pos[2])
                for k in range(run.d.ncon)
                if {int(run.d.contact[k].geom1), int(run.d.contact[k].geom2)} & people
                and {int(run.d.contact[k].geom1), int(run.d.contact[k].geom2)} & cars
            )
        return names

    monkeypatch.setattr(SimulationRun, "check_contacts", spy)
    simulate_plan(plan, keep_state=False)
    car = _car(plan)
    ground = recipe.protagonist.position[2]
    outlines = [car_profile(kind, car.size, CAR_CLEARANCE_M) for kind in CAR_BODIES]
    hood = ground + max(o.hood_front - o.ground for o in outlines)  # the highest hood of any body
    assert first, "the car never touched the protagonist"
    assert max(first) < hood + 0.05, f"first touched {max(first) - ground:.2f} m up, over the hood's front edge"


def test_a_camera_in_the_car_s_way_is_pushed_aside_not_driven_through():
    recipe = recipe_for("car_hit", seconds=2.0, variation="none")
    plan = plan_scene(recipe)
    car = _car(plan)
    # Stand the camera on the car's path, 2 m short of where it hits, with no lane wall to
    # keep it out: the car must pass it.
    hit = int(np.argmin(np.linalg.norm(car.path[:, :2] - np.asarray(recipe.protagonist.position[:2]), axis=1)))
    ahead = car.path[max(hit - round(2.0 / np.linalg.norm(car.path[1] - car.path[0])), 0)]
    plan = dataclasses.replace(plan, camera_start=(float(ahead[0]), float(ahead[1]), 1.2), camera_walls=())
    trajectory = simulate_plan(plan, keep_state=False)
    track = next(t for t in trajectory.props if t.name == "car")
    eyes = trajectory.cam_to_world[:, :3, 3]
    gaps = []
    for pos, quat, eye in zip(track.pos, track.quat, eyes, strict=True):
        rot = np.empty(9)
        mujoco.mju_quat2Mat(rot, quat)
        gaps.append(float(outside_hulls((rot.reshape(3, 3).T @ (eye - pos))[None], car.hulls)[0]))
    assert min(gaps) > CAMERA_RADIUS_M / 2, f"the camera came {min(gaps):.2f} m from the car's surface"
    assert np.linalg.norm(eyes[-1] - eyes[0]) > 0.5  # it was pushed


def test_the_contact_measure_reports_air_depth_and_camera():
    out = run_measure("car_contact.py", "--recipes", "1")
    assert (
        "1 recipes" in out
        and "air (contact outside the drawn car)" in out
        and "camera inside the car in 0 frames" in out
    )


def _box(
    x: float, y: float, half: tuple[float, float, float], z_bottom: float = 0.0, yaw: float = 0.0,
    pixel_class: str = "building",
) -> Collider:  # fmt: skip
    return Collider(pixel_class, (x, y, z_bottom + half[2]), half, yaw)


CAR_HALF = (2.1, 0.9, 0.7)


def test_the_clear_run_ends_at_what_stands_in_the_car_s_way():
    wall_behind, wall_ahead = _box(-10.0, 0.0, (0.5, 3.0, 2.0)), _box(15.0, 0.5, (0.5, 0.5, 2.0))
    beside, kerb = _box(0.0, 3.0, (20.0, 1.0, 2.0)), _box(5.0, 0.0, (1.0, 3.0, 0.05))
    back, ahead = clear_run((wall_behind, wall_ahead, beside, kerb), (0.0, 0.0), (1.0, 0.0), CAR_HALF, 0.15, 0.0,
                            raised=False)  # fmt: skip
    # The wall's face at x = −9.5, the post's at 14.5, less the car's half length; what
    # stands beside the car's way and a kerb it rolls over do not count.
    assert math.isclose(back, 9.5 - 2.1) and math.isclose(ahead, 14.5 - 2.1)
    # Driving the other way swaps them; turned 45°, the wall meets the car's corner first.
    back, ahead = clear_run((wall_behind, wall_ahead), (0.0, 0.0), (-1.0, 0.0), CAR_HALF, 0.15, 0.0, raised=False)
    assert math.isclose(back, 14.5 - 2.1) and math.isclose(ahead, 9.5 - 2.1)
    turned = _box(-10.0, 0.0, (0.5, 3.0, 2.0), yaw=45.0)
    back, _ = clear_run((turned,), (0.0, 0.0), (1.0, 0.0), CAR_HALF, 0.15, 0.0, raised=False)
    # The turned wall's face crosses the car's side line (y = ±0.9) nearest at x = −10 + 0.5√2 + 0.9.
    assert math.isclose(back, 10.0 - 0.5 * math.sqrt(2.0) - 0.9 - 2.1, rel_tol=1e-9)
    # Where it stands it meets the wall: no way at all.
    assert clear_run((_box(1.0, 0.0, (0.5, 0.5, 2.0)),), (0.0, 0.0), (1.0, 0.0), CAR_HALF, 0.15, 0.0,
                     raised=False) == (-math.inf, -math.inf)  # fmt: skip


def test_on_raised_ground_the_car_s_way_ends_at_its_edge():
    # Two slabs of pavement, one top at 0.6 m.
    plaza = tuple(_box(x, 0.0, (h, 4.0, 0.3), pixel_class="road") for x, h in ((0.0, 5.0), (12.5, 7.5)))
    back, ahead = clear_run(plaza, (0.0, 0.0), (1.0, 0.0), CAR_HALF, 0.75, 0.6, raised=True)
    assert math.isclose(back, 5.0 - 2.1) and math.isclose(ahead, 20.0 - 2.1)
    # A car whose side overhangs the plaza's edge has no way on it.
    assert clear_run(plaza, (0.0, 3.5), (1.0, 0.0), CAR_HALF, 0.75, 0.6, raised=True) == (-math.inf, -math.inf)
    # Only walkable ground carries it: a shelf's top level with the plaza is no road.
    shelf = _box(22.5, 0.0, (2.5, 4.0, 0.3), pixel_class="shelf")
    assert clear_run((*plaza, shelf), (0.0, 0.0), (1.0, 0.0), CAR_HALF, 0.75, 0.6, raised=True)[1] == ahead


@pytest.mark.parametrize("start", [30.0, 20.0, 12.0, 6.0])
def test_the_car_arrives_at_its_speed_from_where_it_starts(start: float) -> None:
    speed, t_hit = 10.0, 3.0
    times = np.arange(0, 181) / 30.0
    run = _run(Approach(0.0, speed, start, t_hit, 0.0), times)
    v = np.diff(run) * 30.0
    assert math.isclose(run[0], -start) and abs(run[90]) < 1e-9  # from its start to the hit at t_hit
    assert np.all(v >= -1e-9)  # never backwards
    assert math.isclose(v[89], speed, rel_tol=0.02)  # at its speed when it hits
    # Then it brakes, hit or miss, to a stop where a late touch's braking would end it...
    assert math.isclose(run[-1], CAR_LATE_TOUCH_M + speed**2 / (2 * CAR_BRAKING_MPS2)) and v[-1] == 0.0
    assert np.diff(v[95:]).min() * 30.0 >= -CAR_BRAKING_MPS2 - 1e-6
    # ... and goes no further than its way does.
    assert _run(Approach(0.0, speed, start, t_hit, 0.0, ahead=5.0), times).max() == 5.0
    if start < speed * t_hit:
        assert np.diff(v[:89]).max() * 30.0 <= speed**2 / (2.0 * min(start, speed * t_hit / 2)) + 1e-6


@pytest.mark.parametrize("environment", ["simple", "urban", "middle"])
def test_the_car_never_drives_through_a_collider_or_off_its_ground(environment: str) -> None:
    boxes = BoxSet(ENVIRONMENT_SCENES[environment].colliders)
    grid = np.array([[x, y, z] for x in (-1, -0.5, 0, 0.5, 1) for y in (-1, 0, 1) for z in (-0.7, 0, 1)]) * CAR_HALF
    for index in range(10):
        recipe = recipe_for("car_hit", environment, seconds=6.0, index=index)
        plan = plan_scene(recipe)
        car = _car(plan)
        path = car.path[: car.lane_end + 1 : plan.substeps]
        rot = np.empty(9)
        mujoco.mju_quat2Mat(rot, np.asarray(car.quat, dtype=np.float64))
        points = path[:, None, :] + grid @ rot.reshape(3, 3).T
        depth, _ = boxes.depth_inside(points)
        assert depth.max() < 0.02, f"{recipe.video_id}: the car is {depth.max():.2f} m inside a collider"
        wheels = path[:, 2] - CAR_HALF[2] - CAR_CLEARANCE_M
        under = [support_height(environment, x, y, reference_z=w) for (x, y, _), w in zip(path, wheels, strict=True)]
        assert np.abs(wheels - under).max() < 0.02, f"{recipe.video_id}: the car leaves the ground it drives on"
        # ... and it never speeds up or brakes harder than a car can, however short its way.
        speed = np.linalg.norm(np.diff(car.path, axis=0), axis=1) / plan.timestep
        change = np.diff(speed) / plan.timestep
        assert change.min() > -CAR_BRAKING_MPS2 - 0.5, f"{recipe.video_id}: the car stops dead"
        assert change.max() < CAR_ACCELERATION_MPS2 + 0.5, f"{recipe.video_id}: the car leaps"


def test_the_way_measure_reports_the_car_s_way():
    out = run_measure("driven_way.py", "--recipes", "2")
    assert (
        "2 car_hit videos with a driven car (seed 7)" in out and "the car inside a collider: 0 videos, 0 frames" in out
    )


def test_the_car_keeps_clear_of_the_background_walkers() -> None:
    """phav-v1, seed 1: the car of 128, 273, 297 and 675 drove through a background walker
    (kinematic, on its way whatever comes), most of its body inside the car's box for up to
    19 frames: the walkers start on the road the car comes along. It now comes from a
    direction whose way keeps clear of them."""
    sampler = RecipeSampler(load_theta("phav-v1"))
    for index in (128, 273, 297, 675):
        recipe = sampler.sample(1, index)
        assert recipe.action == "car_hit" and recipe.background_actors
        plan = plan_scene(recipe)
        car = _car(plan)
        rot = np.empty(9)
        mujoco.mju_quat2Mat(rot, np.asarray(car.quat, dtype=np.float64))
        centre = car.path[:: plan.substeps]
        for walker in (p for p in plan.people if p.role == "background"):
            local = np.abs((walker.targets.root_pos - centre) @ rot.reshape(3, 3))
            inside = np.all(local[:, :2] <= np.array(CAR_HALF[:2]) + 0.3, axis=1)
            assert not inside.any(), (index, walker.person_id, np.flatnonzero(inside))
