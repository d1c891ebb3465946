"""Spring cameras start on the protagonist's actual first pose: the kite's target on the
pelvis, the close-up's on the upper chest, so that a seated brush_hair keeps its head and
hands in the frame (docs/framing.md). A rig lowered into the ground lifts its camera clear,
and the camera keeps its room from the people it films."""

from __future__ import annotations

import copy
import dataclasses

import numpy as np

from phav_generator.body.model import rest_body
from phav_generator.motion.rotations import quat_to_matrix
from phav_generator.motion.skeleton import BONE_INDEX, capsule_points, forward_kinematics
from phav_generator.physics.control import CAMERA_ROOM_M
from phav_generator.physics.plan.camera import anchor_point, clear_camera_start
from phav_generator.physics.plan.scene import plan_scene
from phav_generator.physics.simulate import simulate_plan
from phav_generator.render.camera import project
from phav_generator.sampling import RecipeSampler
from tests.generator.physics.support import recipe_for, theta_for
from tests.helpers import preset_dict


def _first_pose(plan):
    p = plan.people[0]
    pos, _ = forward_kinematics(p.dims, p.targets.root_pos[:1], p.targets.root_quat[:1], p.targets.q[:1])
    return pos[0]


def test_kite_rig_starts_on_the_pelvis() -> None:
    recipe = recipe_for("sit", "simple", seconds=0.5)
    assert recipe.camera.kind == "kite"
    plan = plan_scene(recipe)
    pelvis = _first_pose(plan)[BONE_INDEX["pelvis"]]
    np.testing.assert_allclose(plan.camera_target, pelvis, atol=1e-12)
    # Camera and target move together: the sampled placement relative to the target is kept.
    offset = np.subtract(recipe.camera.position, recipe.camera.target)
    np.testing.assert_allclose(np.subtract(plan.camera_start, plan.camera_target), offset, atol=1e-9)


def test_closeup_frames_head_and_hands_of_seated_brush_hair() -> None:
    regex = copy.deepcopy(preset_dict()["theta_ab"])
    regex["regex"]["brush_hair"] = r"brushing long hair while seated"
    theta = theta_for("brush_hair", "simple", seconds=1.5, theta_ab=regex)
    recipe = RecipeSampler(theta).sample(0, 0, force={"camera": "closeup"})
    assert recipe.camera.kind == "closeup" and recipe.motion.base_motion == "brush_long_hair_seated_01"
    plan = plan_scene(recipe)
    np.testing.assert_allclose(plan.camera_target, anchor_point("closeup", _first_pose(plan)), atol=1e-12)
    tr = simulate_plan(plan, keep_state=False)
    p = tr.people[0]
    dims = rest_body(recipe.protagonist.human.phenotype).dims
    a, b = capsule_points(dims, p.body_pos, quat_to_matrix(p.body_quat))
    parts = [BONE_INDEX[n] for n in ("head", "left_hand", "right_hand")]
    points = (a[:, parts] + b[:, parts]) / 2  # (F, 3, 3) capsule centres
    for f in range(recipe.n_frames):
        uv = project(points[f], tr.cam_to_world[f], tr.intrinsics)
        inside = np.isfinite(uv).all(axis=1) & (uv >= 0).all(axis=1)
        inside &= (uv[:, 0] < recipe.video.width) & (uv[:, 1] < recipe.video.height)
        assert inside.all(), f"frame {f}: head, left and right hand at {np.round(uv, 1)}"


def test_a_rig_lowered_into_the_ground_lifts_its_camera_clear_rather_than_onto_the_body() -> None:
    recipe = recipe_for("sit", "simple", seconds=0.5)
    down = np.array([0.0, 0.0, -recipe.camera.position[2]])  # the camera on the ground's plane
    start = np.array(clear_camera_start(recipe, 0.25, shift=down))
    wanted = np.array(recipe.camera.position) + down
    np.testing.assert_allclose(start[:2], wanted[:2], atol=1e-12)  # straight up, not slid
    assert 0.25 <= start[2] <= 0.30  # the first 5 cm step clear of the ground
    assert np.linalg.norm(start - (np.array(recipe.camera.target) + down)) > 1.0


def test_a_start_under_the_ceiling_is_never_lifted_through_it() -> None:
    """A kite start in the house within reach of the ceiling (seed 0, 673: under the lamp),
    or raised over it with the rig on a hanging body (seed 1, 621: `pull_up`), was lifted
    onto the slab and filmed its top all clip long. It now slides towards its target."""
    from phav_spec.scene import ENVIRONMENT_SCENES
    from phav_spec.theta import load_theta

    ceiling = min(c.bottom for c in ENVIRONMENT_SCENES["house_interior"].colliders if c.pixel_class == "ceiling")
    for seed, index in ((0, 673), (1, 621)):
        recipe = RecipeSampler(load_theta("phav-v1")).sample(seed, index)
        assert (recipe.environment.name, recipe.camera.kind) == ("house_interior", "kite")
        start = plan_scene(recipe).camera_start
        assert start[2] < ceiling - 0.25, (recipe.video_id, start)


def test_a_spring_camera_started_against_the_protagonist_backs_off_and_keeps_its_room() -> None:
    recipe = recipe_for("wave", "simple", seconds=1.5)
    assert recipe.camera.springs is not None
    plan = plan_scene(recipe)
    pelvis = np.array(plan.camera_target)
    # Half a metre in front of the pelvis, at its height: inside the room the camera keeps.
    plan = dataclasses.replace(plan, camera_start=tuple(pelvis + np.array([0.5, 0.0, 0.0])))
    tr = simulate_plan(plan, keep_state=False)
    cams = tr.cam_to_world[:, :3, 3]
    nearest = np.linalg.norm(np.asarray(tr.people[0].body_pos) - cams[:, None, :], axis=2).min(axis=1)
    assert nearest[0] < 0.6
    assert (nearest[15:] > 0.9 * CAMERA_ROOM_M).all(), np.round(nearest, 2)


def test_a_spring_camera_keeps_its_room_from_a_background_walker_who_walks_at_it() -> None:
    """Background people are animated, not simulated; the camera's push keeps it from them
    too. A walker sent straight through where the camera waits comes no nearer than half the
    room to it (through the camera without the push)."""
    recipe = recipe_for("wave", "simple", seconds=1.5, index=1)
    plan = plan_scene(recipe)
    [k] = [i for i, p in enumerate(plan.people) if p.role == "background"]
    walker = plan.people[k]
    n = len(walker.targets.root_pos)
    cam = np.array(plan.camera_start)
    # Along x at 1.4 m/s, the walker's pelvis passing the camera's start at its height.
    root = cam + np.outer(np.linspace(-1.0, 1.0, n) * 1.4 * recipe.duration_s / 2, [1.0, 0.0, 0.0])
    quat = np.tile([1.0, 0.0, 0.0, 0.0], (n, 1))
    targets = dataclasses.replace(walker.targets, root_pos=root, root_quat=quat)
    people = list(plan.people)
    people[k] = dataclasses.replace(walker, targets=targets)
    tr = simulate_plan(dataclasses.replace(plan, people=tuple(people)), keep_state=False)
    cams = tr.cam_to_world[:, :3, 3]
    [seen] = [p for p in tr.people if p.role == "background"]
    nearest = np.linalg.norm(np.asarray(seen.body_pos) - cams[:, None, :], axis=2).min(axis=1)
    assert nearest.min() > 0.5 * CAMERA_ROOM_M, np.round(nearest, 2)
