"""Push: what a push pushes moves ahead of the hands and stops at what stands in its way
(its pusher with it), a door swings open."""

from __future__ import annotations

import re

import mujoco
import numpy as np
import pytest

from phav_generator.motion.skeleton import BONE_INDEX
from phav_generator.physics.plan.builder import PlanBuilder
from phav_generator.physics.plan.people import HALT_RAMP_S, body_poses, halt
from phav_generator.physics.plan.push import hand_reach
from phav_generator.physics.plan.scene import plan_scene
from phav_generator.physics.simulate import simulate
from phav_generator.sampling import sample_recipes
from phav_spec.scene import ENVIRONMENT_SCENES, support_height
from phav_validators.checks.failures import BoxSet
from tests.generator.physics.support import recipe_for, theta_for
from tests.helpers import run_measure


def _push_recipes() -> dict[str, object]:
    """One 5 s push recipe per push motion of phav-v1."""
    out: dict[str, object] = {}
    for r in sample_recipes(theta_for("push", "simple", seconds=5.0, variation="none"), n=60, seed=0):
        out.setdefault(r.motion.base_motion, r)
    return out


def test_push_moves_what_it_pushes() -> None:
    """A pushed box or cart advances ahead of the fingertips without being reached through;
    a pushed door swings open on its hinge, and the pushing is annotated."""
    recipes = _push_recipes()
    assert set(recipes) == {"push_heavy_box_01", "push_shopping_cart_01", "push_open_door_01"}
    for motion, recipe in recipes.items():
        tr = simulate(recipe, keep_state=False)
        assert tr.exploded_at is None and not any(tr.warnings.values()), motion
        obj = {"push_heavy_box_01": "box", "push_shopping_cart_01": "shopping_cart"}.get(motion, "door")
        track = next(p for p in tr.props if p.name == obj)
        assert any(m[0] == obj and m[3] == "push" for m in tr.manipulations), motion
        plan = plan_scene(recipe)
        if obj == "door":
            # The leaf's yaw relative to its closed pose: opened by more than 30°.
            q0, q1 = track.quat[0], track.quat[-1]
            turn = 2 * np.degrees(np.arccos(min(1.0, abs(float(q0 @ q1)))))
            assert turn > 30.0, f"door opened only {turn:.1f}°"
            continue
        x0 = np.array(recipe.protagonist.position)
        heading = np.deg2rad(recipe.protagonist.heading_deg)
        fwd = np.array([np.cos(heading), np.sin(heading), 0.0])
        advance = (track.pos[-1] - track.pos[0]) @ fwd
        assert advance > 1.0, f"{obj} advanced only {advance:.2f} m"
        _, _, tips = hand_reach(PlanBuilder(recipe, plan.substeps), plan.people[0])
        near_face = (track.pos - x0) @ fwd - track.size[0]
        reach = ((tips[:: plan.substeps] - x0) @ fwd).max(axis=1)
        assert np.all(reach <= near_face + 1e-6), f"the hands reach into the {obj}"


def test_a_halted_motion_slows_to_the_pose_it_had_then_and_holds_it() -> None:
    recipe = recipe_for("walk", "simple", seconds=3.0)
    plan = plan_scene(recipe)
    person, times = plan.people[0], plan.step_times
    t_stop = float(times[300])
    halted = halt(person, times, t_stop).targets
    before = times < t_stop - HALT_RAMP_S / 2
    # As it was until it starts slowing down, then the pose it had at t_stop from then on.
    assert np.array_equal(halted.root_pos[before], person.targets.root_pos[before])
    assert np.array_equal(halted.q[before], person.targets.q[before])
    after = times >= t_stop + HALT_RAMP_S / 2
    assert np.abs(halted.root_pos[after] - person.targets.root_pos[300]).max() < 1e-9
    assert np.abs(halted.q[after] - person.targets.q[300]).max() < 1e-9
    # Slowing evenly: no step moves the pelvis further than the walk's own steps do.
    walked = np.linalg.norm(np.diff(person.targets.root_pos, axis=0), axis=1).max()
    assert np.linalg.norm(np.diff(halted.root_pos, axis=0), axis=1).max() <= walked * 1.001
    # A halt at the clip's start holds its first pose throughout.
    assert np.abs(halt(person, times, 0.0).targets.root_pos - person.targets.root_pos[0]).max() < 1e-12


@pytest.mark.parametrize("environment", ["house_interior", "green", "lake"])
def test_a_pushed_load_stops_at_what_stands_in_its_way_and_its_pusher_with_it(environment: str) -> None:
    """Twelve six-second push recipes: no planned load enters a collider or leaves the
    ground it slides on; where one would, its pusher's planned hands stop behind it."""
    boxes = BoxSet(ENVIRONMENT_SCENES[environment].colliders)
    grid = np.array([[x, y, z] for x in (-1, 0, 1) for y in (-1, 0, 1) for z in (-1, 0, 1)], dtype=np.float64)
    halted = 0
    for index in range(12):
        recipe = recipe_for("push", environment, seconds=6.0, index=index)
        plan = plan_scene(recipe)
        load = next((p for p in plan.props if p.path is not None), None)
        if load is None:  # a door
            continue
        half = np.asarray(load.size)
        rot = np.empty(9)
        mujoco.mju_quat2Mat(rot, np.asarray(load.quat, dtype=np.float64))
        path = load.path[:: plan.substeps]
        depth, _ = boxes.depth_inside(path[:, None, :] + (grid * half) @ rot.reshape(3, 3).T)
        assert depth.max() < 0.02, f"{recipe.video_id}: the {load.name} is {depth.max():.2f} m inside a collider"
        bottom = path[:, 2] - half[2]
        gap = bottom - [
            support_height(environment, x, y, reference_z=z) for (x, y, _), z in zip(path, bottom, strict=True)
        ]
        assert np.abs(gap - gap[0]).max() < 0.02, f"{recipe.video_id}: the {load.name} leaves its ground"
        # The hands never reach into the load, halted or not.
        x0 = np.array(recipe.protagonist.position)
        fwd, _, tips = hand_reach(PlanBuilder(recipe, plan.substeps), plan.people[0])
        near_face = (load.path - x0) @ fwd - half[0]
        assert np.all(((tips - x0) @ fwd).max(axis=1) <= near_face + 1e-6)
        root = plan.people[0].targets.root_pos
        if np.array_equal(root[-1], root[-plan.substeps * 5]):
            halted += 1
            # The pusher holds a pose that stands on both feet (a heel or a toe of each down).
            person = plan.people[0]
            pos, rot = body_poses(person.dims, person.targets.take(slice(-1, None)))
            for foot in ("left_foot", "right_foot"):
                k = BONE_INDEX[foot]
                cap = person.dims.capsules[k]
                sole = min(float((pos[0, k] + rot[0, k] @ np.array(end))[2]) for end in (cap.a, cap.b)) - cap.radius
                assert abs(sole - x0[2]) < 0.02, f"{recipe.video_id}: the halted pusher's {foot} is off the ground"
    assert halted >= 1, "no recipe met anything: the test no longer tests the stop"


def test_the_way_measure_reports_a_pushed_load_s_way():
    out = run_measure("driven_way.py", "--action", "push", "--recipes", "4", "--seed", "3")
    assert "v000000 urban   a door: nothing driven" in out and re.search(
        r"v000003 house_interior pushed \d\.\d\d m", out
    )
    assert "1 push videos with a driven load (seed 3)" in out and "the load inside a collider: 0 videos" in out
