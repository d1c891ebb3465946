"""Background pedestrians: walkers step up onto kerbs on their way, and stop short of a
ledge they would have to climb."""

from __future__ import annotations

import numpy as np

from phav_generator.motion.skeleton import BONE_INDEX, forward_kinematics
from phav_generator.physics.plan.background import _ANKLES, STEP_M, background_people
from phav_generator.physics.plan.builder import PlanBuilder
from phav_generator.physics.plan.timestep import choose_substeps
from phav_generator.sampling import sample_recipes
from phav_spec.scene import walkable_heights
from phav_spec.theta import load_theta
from phav_validators.checks.failures import video_failures
from tests.generator.physics.support import short_recipe, simulated_people


def test_background_walkers_step_onto_kerbs() -> None:
    """A true failure of the 100-video phav-v1-short measurement: a background walker's
    front foot 19 cm inside a raised road (its pelvis stepped up only once over it).
    Walkers now rise for the highest surface within a stride."""
    walkers = short_recipe("v000027")
    assert walkers.background_actors and walkers.environment.name == "urban"
    result = video_failures(walkers, simulated_people(walkers), None)
    assert not result.failed, (walkers.video_id, result.failures)


def _feet_over_ground(recipe) -> list[tuple[float, float]]:
    """Per walker: how high both ankles stand over the surface under each (its worst frame;
    an ankle joint is ~10 cm over its sole), and its pelvis's largest rise or fall a frame."""
    plan = PlanBuilder(recipe, choose_substeps(recipe))
    out = []
    for walker in background_people(plan):
        t = walker.targets
        bodies, _ = forward_kinematics(walker.dims, t.root_pos, t.root_quat, t.q)
        ankles = bodies[:, _ANKLES]
        ground = walkable_heights(recipe.environment.name, ankles[..., 0], ankles[..., 1], ankles[..., 2] + 0.05)
        out.append((float((ankles[..., 2] - ground).min(axis=1).max()), float(np.abs(np.diff(t.root_pos[:, 2])).max())))
    return out


def test_walkers_stop_short_of_a_ledge_they_would_have_to_climb() -> None:
    """phav-v1, seed 0: walkers whose way crosses the urban plaza's 0.6 m edge hovered
    there, both feet up to 0.72 m over the ground, their pelvis leaping 0.6 m in a frame
    (the pelvis rose for any surface within half a metre). A walker now steps onto what a
    planted foot stands on, and stops short of a ledge higher than a step."""
    recipes = {r.video_id: r for r in sample_recipes(load_theta("phav-v1"), n=272, seed=0)}
    for video in ("v000185", "v000271"):
        walkers = _feet_over_ground(recipes[video])
        assert walkers
        assert max(f for f, _ in walkers) < 0.3, (video, walkers)
        assert max(j for _, j in walkers) < STEP_M, (video, walkers)


def test_a_walkers_planted_foot_stays_planted() -> None:
    """A walker's pelvis follows a straight, steady line to its destination: the gait's sway
    and surge about its own advance are kept, its speed is scaled by leg length as its
    stride is, and its way is its heading. Each took the pelvis off the planted foot, which
    slid 8–22 cm/s on these walkers (the median over the frames a foot stands, its worse
    foot)."""
    slides = []
    for recipe in sample_recipes(load_theta("phav-v1"), n=8, seed=0):
        for walker in background_people(PlanBuilder(recipe, choose_substeps(recipe))):
            t = walker.targets
            bodies, _ = forward_kinematics(walker.dims, t.root_pos, t.root_quat, t.q)
            # Walking: before it stands where it has arrived (its pose no longer changing).
            walking = np.r_[np.abs(np.diff(t.q, axis=0)).max(axis=1) > 0.0, False]
            if not walking.any():  # standing where it starts: no stride
                continue
            worse = 0.0
            for foot in ("left_foot", "right_foot"):
                z, xy = bodies[:, BONE_INDEX[foot], 2], bodies[:, BONE_INDEX[foot], :2]
                low = (z < z[walking].min() + 0.01) & walking
                stands = low[1:] & low[:-1]
                speed = np.linalg.norm(np.diff(xy, axis=0), axis=1) * recipe.video.fps
                if stands.any():  # a short walk may have no whole stance of a foot
                    worse = max(worse, float(np.median(speed[stands])))
            slides.append(worse)
    assert len(slides) >= 10 and max(slides) < 0.1 and float(np.median(slides)) < 0.06, np.round(slides, 3)


def test_a_walker_that_arrives_slows_to_a_stance_not_a_snap() -> None:
    """A walker arriving at its destination (or a ledge) was set standing on straight legs
    in one frame: some body part moved up to 16.7 m/s in that frame (2.6 m/s is a walking
    body's median). It now slows to a standstill in its last stance with both feet down."""
    fastest = []
    for recipe in sample_recipes(load_theta("phav-v1"), n=120, seed=0):
        for walker in background_people(PlanBuilder(recipe, choose_substeps(recipe))):
            t = walker.targets
            bodies, _ = forward_kinematics(walker.dims, t.root_pos, t.root_quat, t.q)
            fastest.append(float(np.linalg.norm(np.diff(bodies, axis=0), axis=-1).max()) * recipe.video.fps)
    assert len(fastest) > 100 and max(fastest) < 8.0, sorted(fastest)[-5:]


def test_a_walker_with_less_than_a_frame_to_go_stands_on_both_feet() -> None:
    """A destination 2 cm away is reached within the first frame: the walker was halted on
    that frame's pose, mid-stride, one foot in the air for the whole clip. It stands."""
    recipe = short_recipe("v000027")
    actor = recipe.background_actors[0]
    near = (actor.start[0] + 0.02, actor.start[1], actor.start[2])
    moved = recipe.model_copy(update={"background_actors": (actor.model_copy(update={"destination": near}),
                                                            *recipe.background_actors[1:])})  # fmt: skip
    (walker, *_) = background_people(PlanBuilder(moved, choose_substeps(moved)))
    t = walker.targets
    bodies, _ = forward_kinematics(walker.dims, t.root_pos, t.root_quat, t.q)
    ankles = bodies[:, _ANKLES, 2]
    assert np.abs(ankles[:, 0] - ankles[:, 1]).max() < 0.01 and np.ptp(t.root_pos, axis=0).max() < 1e-9
