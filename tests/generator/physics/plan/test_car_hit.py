"""Car hit: the car touches the protagonist, the pins let go and the ragdoll falls; the
car collides as the car drawn, bumper first, and pushes a camera in its way aside."""

from __future__ import annotations

import dataclasses
import subprocess
import sys
from pathlib import Path

import mujoco
import numpy as np
import pytest

from phav_generator.motion.skeleton import BONE_INDEX
from phav_generator.physics import Trajectory
from phav_generator.physics.control import SimulationRun
from phav_generator.physics.model import CAMERA_RADIUS_M
from phav_generator.physics.plan.car_hit import CAR_CLEARANCE_M
from phav_generator.physics.plan.scene import plan_scene
from phav_generator.physics.simulate import simulate, simulate_plan
from phav_generator.render.scene import drawn_vehicle
from phav_spec.car_shapes import CAR_BODIES, car_profile
from tests.generator.physics.support import assert_healthy, recipe_for
from tests.helpers import cli_env, outside_hulls

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
    script = Path(__file__).parents[4] / "docs" / "measure" / "car_contact.py"
    out = subprocess.run(
        [sys.executable, str(script), "--recipes", "1"], capture_output=True, text=True, check=True, env=cli_env()
    ).stdout
    assert (
        "1 recipes" in out
        and "air (contact outside the drawn car)" in out
        and "camera inside the car in 0 frames" in out
    )
