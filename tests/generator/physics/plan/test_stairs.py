"""Stairs: the flight a climb_stairs clip walks on, its feet on the treads."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from phav_generator.motion.library import get_motion, register_motion, unregister_motion
from phav_generator.motion.skeleton import BONE_INDEX, capsule_points, forward_kinematics, lowest_point
from phav_generator.physics.plan.scene import plan_scene
from phav_generator.sampling import sample_recipes
from phav_spec.theta import load_theta
from tests.generator.physics.support import recipe_for


def _tread_top(plan, x: float, y: float, floor: float) -> float:
    """Height of the highest built stairs box under (x, y), else ``floor``."""
    top = floor
    for box in plan.boxes:
        if box.pixel_class != "stairs":
            continue
        yaw = np.radians(box.yaw_deg)
        d = np.array([x - box.center[0], y - box.center[1]])
        along, across = d @ [np.cos(yaw), np.sin(yaw)], d @ [-np.sin(yaw), np.cos(yaw)]
        if abs(along) <= box.half_size[0] + 1e-9 and abs(across) <= box.half_size[1]:
            top = max(top, box.center[2] + box.half_size[2])
    return top


def test_stairs_feet_land_on_the_treads_the_plan_builds() -> None:
    """climb_stairs clips (up and down, cut from anywhere in a flight, any height, either
    hand) start on the waypoint or their landing, and every stance foot stands on a built
    tread: never in one, and on one for the stance share of the clip (the treads used to be
    built from the pelvis's rise, 0.4 m ahead whatever the clip, and the feet missed them)."""
    recipes = [r for r in sample_recipes(load_theta("phav-v1"), n=1500, seed=5) if r.action == "climb_stairs"]
    assert len(recipes) >= 20
    assert {r.motion.base_motion for r in recipes} >= {"go_down_stairs_01", "run_up_stairs_01", "climb_up_stairs_01"}
    late = 0
    feet = [BONE_INDEX["left_foot"], BONE_INDEX["right_foot"]]
    for r in recipes[:20]:
        plan = plan_scene(r)
        me = plan.people[0]
        t = me.targets
        s = plan.substeps
        pos, rot = forward_kinematics(me.dims, t.root_pos[::s], t.root_quat[::s], t.q[::s])
        support = r.protagonist.position[2] + plan.stand_offset_z
        a, b = capsule_points(me.dims, pos, rot)
        radius = me.dims.capsules[feet[0]].radius
        # A stance foot stands on the waypoint or landing (going down, the swing foot is lower).
        soles = [min(a[0, k, 2], b[0, k, 2]) - radius for k in feet]
        assert min(abs(z - support) for z in soles) < 0.02, (r.video_id, r.motion.base_motion, soles, support)
        gaps = []
        for f in range(len(pos)):
            for k in feet:
                low = a[f, k] if a[f, k, 2] < b[f, k, 2] else b[f, k]
                gaps.append(low[2] - radius - _tread_top(plan, low[0], low[1], r.protagonist.position[2]))
        gaps = np.array(gaps)
        # The motions are authored on the reference body; an anny foot (its own length and
        # sole) may touch a tread up to 3 cm deep at toe-off, which contacts then resolve.
        assert gaps.min() > -0.03, (r.video_id, r.motion.base_motion, gaps.min())
        # On a tread for a stance share of the clip (within 1 cm on the reference body the
        # motions are written for; within 2 cm on an anny body, its own foot length and sole).
        assert np.mean(np.abs(gaps) < 0.02) > 0.35, (r.video_id, r.motion.base_motion, np.mean(np.abs(gaps) < 0.02))
        late += r.motion.start_s > 5.0
    assert late >= 5  # the clips that used to start metres off the ground


def test_a_clip_starting_mid_stride_up_a_flight_has_the_tread_below_built() -> None:
    """phav-v1, seed 0: clips cut from part-way up a flight whose swing foot is still coming
    up from the tread below (v000520, v000956) started that foot 12–15 cm under the floor:
    the standing foot's tread was the floor, and the one below was not built."""
    recipes = {r.video_id: r for r in sample_recipes(load_theta("phav-v1"), n=960, seed=0)}
    feet = [BONE_INDEX["left_foot"], BONE_INDEX["right_foot"]]
    for video in ("v000520", "v000956"):
        r = recipes[video]
        plan = plan_scene(r)
        me = plan.people[0]
        t = me.targets
        s = plan.substeps
        pos, rot = forward_kinematics(me.dims, t.root_pos[: 3 * s : s], t.root_quat[: 3 * s : s], t.q[: 3 * s : s])
        a, b = capsule_points(me.dims, pos, rot)
        radius = me.dims.capsules[feet[0]].radius
        for f in range(len(pos)):
            for k in feet:
                low = a[f, k] if a[f, k, 2] < b[f, k, 2] else b[f, k]
                gap = low[2] - radius - _tread_top(plan, low[0], low[1], r.protagonist.position[2])
                assert gap > -0.03, (video, f, k, gap)


def test_a_stairs_motion_without_its_own_flight_gets_steps_from_its_rise() -> None:
    """An imported climb (no catalogue treads: ``MotionDef.stairs == 0``) still gets a flight,
    built from its pelvis's rise, and starts on the waypoint with the climb before the clip
    taken out."""
    climb = get_motion("climb_up_stairs_01")
    imported = dataclasses.replace(climb, name="test_imported_climb", stairs=0)
    register_motion(imported, replace=True)
    try:
        base = recipe_for("climb_stairs", "urban", seconds=2.0, variation="none")
        motion = base.motion.model_copy(update={"base_motion": imported.name, "start_s": 6.0})
        plan = plan_scene(base.model_copy(update={"motion": motion}))
    finally:
        unregister_motion(imported.name)
    steps = [box for box in plan.boxes if box.pixel_class == "stairs"]
    assert len(steps) >= 3 and plan.stand_offset_z == 0.0
    tops = [box.center[2] + box.half_size[2] - base.protagonist.position[2] for box in steps]
    assert tops == pytest.approx([0.17 * (k + 1) for k in range(len(steps))])
    me = plan.people[0]
    pos, rot = forward_kinematics(me.dims, me.targets.root_pos[:1], me.targets.root_quat[:1], me.targets.q[:1])
    assert abs(float(lowest_point(me.dims, pos, rot)[0]) - base.protagonist.position[2]) < 0.2


@pytest.mark.parametrize("action", ["run", "car_hit"])
def test_a_stairs_take_runs_on_level_ground_where_no_flight_is_built(action: str) -> None:
    """Actions other than climb_stairs whose regex admits "run up stairs" play the take's
    strides without its climb: no flight is built under them, and the climb used to lift the
    runner metres into the air (the car of car_hit passed under)."""
    base = recipe_for(action, "simple", seconds=4.0)
    recipe = base.model_copy(update={"motion": base.motion.model_copy(update={"base_motion": "run_up_stairs_01"})})
    plan = plan_scene(recipe)
    protagonist = plan.people[0]
    assert not [box for box in plan.boxes if box.pixel_class == "stairs"]
    rise = protagonist.targets.root_pos[:, 2] - protagonist.targets.root_pos[0, 2]
    assert np.abs(rise).max() < 0.15, f"the pelvis rises {rise.max():.2f} m"
    run = np.linalg.norm(protagonist.targets.root_pos[-1, :2] - protagonist.targets.root_pos[0, :2])
    assert run > 2.0  # it still runs
    # The same take climbs where the flight is built under it.
    climb = recipe_for("climb_stairs", "urban", seconds=4.0)
    climb = climb.model_copy(update={"motion": climb.motion.model_copy(update={"base_motion": "run_up_stairs_01"})})
    climber = plan_scene(climb).people[0].targets.root_pos[:, 2]
    assert climber.max() - climber[0] > 1.0
    assert get_motion("run_up_stairs_01", flight=False).stairs == 0 and get_motion("run_up_stairs_01").stairs == 1
