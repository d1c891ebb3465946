"""Recipe → trajectory: determinism, every action in every environment, the actions'
physical signatures, variations, cameras and hard cases (issue: motions, ragdoll, cameras)."""

from __future__ import annotations

import dataclasses
import subprocess
import sys

import mujoco
import numpy as np
import pytest

from phav_generator.motion.animation import blend, muscle_dof_mask
from phav_generator.motion.library import get_motion, register_motion, unregister_motion
from phav_generator.motion.rotations import quat_to_matrix
from phav_generator.motion.skeleton import (
    BONE_INDEX,
    DOF_INDEX,
    JOINT_BODIES,
    LOWER,
    UPPER,
    capsule_points,
    forward_kinematics,
    lowest_point,
)
from phav_generator.physics import Trajectory, compare
from phav_generator.physics.model import build_model
from phav_generator.physics.plan import StaticBox, plan_scene
from phav_generator.physics.simulate import intrinsics, simulate, simulate_plan
from phav_spec.errors import PhavUserError
from phav_spec.scene import ACTION_SCENES
from tests.generator.physics_support import possible_pairs, recipe_for, simulated_people

PELVIS = BONE_INDEX["pelvis"]
#: How far (joint angle) a variation may move the action's necessary muscles.
NECESSARY_TOLERANCE_RAD = 0.1


def _healthy(tr: Trajectory) -> None:
    assert tr.exploded_at is None, f"{tr.video_id}: exploded at frame {tr.exploded_at}"
    bad = {k: v for k, v in tr.warnings.items() if v}
    assert not bad, f"{tr.video_id}: MuJoCo warnings {bad}"
    for name, array in tr.arrays().items():
        assert np.all(np.isfinite(array)), f"{tr.video_id}: non-finite values in {name}"


def test_numpy_kinematics_match_mujoco() -> None:
    recipe = recipe_for("wave")
    plan = plan_scene(recipe)
    scene = build_model(plan)
    m, h = scene.model, scene.people[0]
    d = mujoco.MjData(m)
    rng = np.random.default_rng(0)
    for _ in range(5):
        q = rng.uniform(LOWER, UPPER)
        quat = rng.normal(size=4)
        quat /= np.linalg.norm(quat)
        d.qpos[h.qpos_root : h.qpos_root + 3] = rng.normal(size=3)
        d.qpos[h.qpos_root + 3 : h.qpos_root + 7] = quat
        d.qpos[h.qpos_dofs] = q
        mujoco.mj_kinematics(m, d)
        pos, rot = forward_kinematics(
            plan.people[0].dims, d.qpos[None, h.qpos_root : h.qpos_root + 3], quat[None], q[None]
        )
        np.testing.assert_allclose(pos[0], d.xpos[h.bodies], atol=1e-12)
        np.testing.assert_allclose(rot[0].reshape(-1, 9), d.xmat[h.bodies], atol=1e-12)


_HASH_SCRIPT = """
import sys
from tests.generator.physics_support import recipe_for
from phav_generator.physics.simulate import simulate
print(simulate(recipe_for(sys.argv[1], seconds=0.6)).content_hash())
"""


def test_same_recipe_same_trajectory_in_two_processes() -> None:
    hashes = [
        subprocess.run(
            [sys.executable, "-c", _HASH_SCRIPT, "car_hit"], capture_output=True, text=True, check=True
        ).stdout.strip()
        for _ in range(2)
    ]
    assert hashes[0] == hashes[1] and len(hashes[0]) == 64
    assert simulate(recipe_for("car_hit", seconds=0.6)).content_hash() == hashes[0]


def test_a_video_does_not_depend_on_the_videos_before_it() -> None:
    alone = simulate(recipe_for("walk", seconds=0.5, index=3)).content_hash()
    for i in range(3):
        simulate(recipe_for("walk", seconds=0.5, index=i))
    assert simulate(recipe_for("walk", seconds=0.5, index=3)).content_hash() == alone


@pytest.mark.parametrize(("action", "environment"), possible_pairs())
def test_every_action_simulates_in_every_environment(action: str, environment: str) -> None:
    recipe = recipe_for(action, environment, seconds=0.4)
    tr = simulate(recipe, keep_state=False)
    _healthy(tr)
    assert len(tr.times) == recipe.n_frames + 1
    assert tr.cam_to_world.shape == (recipe.n_frames + 1, 4, 4)
    assert len([p for p in tr.people if p.role != "background"]) == recipe.n_people


def test_trajectory_round_trip(tmp_path) -> None:
    tr = simulate(recipe_for("pour", seconds=0.4))
    path = tmp_path / "t.npz"
    tr.save(path)
    back = Trajectory.load(path)
    assert back.content_hash() == tr.content_hash()
    assert max(compare(tr, back).values()) == 0.0
    path.write_bytes(b"not a trajectory")
    with pytest.raises(PhavUserError, match=r"t\.npz"):
        Trajectory.load(path)


# --- what the actions are, measured on the trajectories --------------------------------


@pytest.fixture(scope="module")
def car_hit() -> Trajectory:
    # No variation: a weakened muscle is meant to lag its animation.
    return simulate(recipe_for("car_hit", seconds=3.0, variation="none"))


def test_car_hit_contact_then_fall(car_hit: Trajectory) -> None:
    _healthy(car_hit)
    touched = np.flatnonzero(car_hit.contacts["car_protagonist"])
    assert touched.size, "the car never touched the protagonist"
    after = car_hit.people[0].body_pos[touched[0] :, PELVIS, 2]
    ground = recipe_for("car_hit", seconds=3.0, variation="none").protagonist.position[2]
    assert np.min(after - ground) < 0.5


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


def test_walk_holding_hands_keeps_hands_tied() -> None:
    tr = simulate(recipe_for("walk_holding_hands", seconds=2.0))
    _healthy(tr)
    a, b = tr.people[0], tr.person(1)
    palm = np.array([0.0, 0.0, -0.08 * a.height_m / 1.75])
    pa = a.body_pos[:, BONE_INDEX["right_hand"]] + quat_to_matrix(a.body_quat[:, BONE_INDEX["right_hand"]]) @ palm
    pb = b.body_pos[:, BONE_INDEX["left_hand"]] + quat_to_matrix(b.body_quat[:, BONE_INDEX["left_hand"]]) @ palm
    gap = np.linalg.norm(pa - pb, axis=-1)
    assert gap[10:].max() < 0.05, f"palms {np.round(gap, 3)} m apart"


def test_crawl_keeps_the_torso_near_the_ground() -> None:
    recipe = recipe_for("crawl", seconds=2.0)
    tr = simulate(recipe)
    chest = tr.people[0].body_pos[:, BONE_INDEX["chest"], 2] - recipe.protagonist.position[2]
    assert np.median(chest) < 0.6


def test_hop_leaves_the_ground_with_both_feet() -> None:
    recipe = recipe_for("hop", seconds=3.0)
    tr = simulate(recipe)
    p = tr.people[0]
    dims_sole = 0.039 * p.height_m
    feet = p.body_pos[:, [BONE_INDEX["left_foot"], BONE_INDEX["right_foot"]], 2] - recipe.protagonist.position[2]
    airborne = (feet > dims_sole + 0.03).all(axis=1)
    assert airborne.any(), f"lowest foot heights {np.round(feet.min(axis=1), 3)}"


def test_limp_is_asymmetric() -> None:
    recipe = recipe_for("limp", seconds=4.0)
    tr = simulate(recipe)
    p = tr.people[0]
    knees = p.q[:, [DOF_INDEX["left_knee_flex"], DOF_INDEX["right_knee_flex"]]]
    swing = knees.max(axis=0) - knees.min(axis=0)
    assert abs(swing[0] - swing[1]) / swing.max() > 0.15, f"knee ranges {swing}"


@pytest.mark.parametrize("kind", ["random_perturbation", "action_blending"])
def test_variations_change_complementary_muscles_only(kind: str) -> None:
    base = recipe_for("wave", seconds=2.0)
    scene = ACTION_SCENES["wave"]
    muscles = scene.complementary_muscles[:6]
    if kind == "random_perturbation":
        variation = {"kind": kind, "muscles": muscles, "radius_m": 0.3, "period_s": 0.8}
    else:
        variation = {
            "kind": kind,
            "muscles": muscles,
            "blend_motion": "jumping_jacks_01",
            "blend_start_s": 1.0,
            "weight": 0.8,
        }
    varied = base.model_copy(
        update={"variation": base.model_validate({**base.model_dump(), "variation": variation}).variation}
    )
    plain = base.model_copy(
        update={"variation": base.model_validate({**base.model_dump(), "variation": {"kind": "none"}}).variation}
    )
    a, b = simulate(plain).people[0], simulate(varied).people[0]
    necessary = muscle_dof_mask(scene.necessary_muscles)
    varied_dofs = muscle_dof_mask(muscles)
    change = np.abs(a.q - b.q).max(axis=0)
    assert change[varied_dofs].max() > 0.2, f"varied muscles moved {np.round(change[varied_dofs], 3)}"
    assert change[necessary].max() < NECESSARY_TOLERANCE_RAD, (
        f"necessary muscles moved {np.round(change[necessary], 3)}"
    )


# --- cameras and hard cases -------------------------------------------------------------


def test_intrinsics_from_the_vertical_field_of_view() -> None:
    recipe = recipe_for("wave")
    _, fy, cx, cy = intrinsics(recipe)
    assert (cx, cy) == (recipe.video.width / 2, recipe.video.height / 2)
    assert np.isclose(2 * np.degrees(np.arctan(cy / fy)), recipe.camera.fov_deg)


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
    _healthy(tr)
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
    _healthy(tr)
    assert tr.camera_penetration_m.max() <= 0.01
    assert tr.cam_to_world[:, 0, 3].min() > wall_x  # never behind the wall


def test_fastest_car_keeps_the_protagonist_finite() -> None:
    recipe = recipe_for("car_hit", seconds=2.0)
    plan = plan_scene(recipe)
    car = next(p for p in plan.props if p.object == "car")
    fast_path = car.path[:1] + (car.path - car.path[:1]) * (
        20.0 / np.linalg.norm(car.path[1] - car.path[0]) * plan.timestep
    )
    plan = dataclasses.replace(
        plan, props=tuple(dataclasses.replace(p, path=fast_path) if p is car else p for p in plan.props)
    )
    _healthy(simulate_plan(plan, keep_state=False))


def test_zero_strength_muscles_do_not_explode() -> None:
    base = recipe_for("run", seconds=1.5)
    from phav_spec.vocab import MUSCLES

    weak = base.model_validate(
        {
            **base.model_dump(),
            "variation": {"kind": "muscle_weakening", "muscles": MUSCLES.names, "strengths": [0.0] * 15},
        }
    )
    tr = simulate(weak, keep_state=False)
    _healthy(tr)
    assert tr.people[0].strengths.max() == 0.0


def test_physics_bench_measures_error_against_the_reference_rate() -> None:
    from phav_generator.bench import REFERENCE_HZ, bench_physics

    pinned = [recipe_for("clap", seconds=0.5, variation="none")]
    released = [recipe_for("car_hit", seconds=0.5, variation="none")]
    same, coarse = bench_physics(pinned, released, rates=(REFERENCE_HZ, 120))
    assert same.pinned_error_m == 0.0 and same.released_error_m == 0.0  # deterministic
    assert same.clips_within(0.01) == 1 and len(coarse.pinned_clip_errors_m) == 1
    assert 0.0 < coarse.pinned_error_m < 1.0 and coarse.ms_per_frame > 0.0


def test_a_pinned_sprint_follows_its_animation_at_the_default_rate() -> None:
    """The timestep's error while pins hold: a run at the default rate stays within 1 cm of
    a 1/1920 s reference and of its own animation (it was 6.6 cm when the recorded poses lagged
    a physics step and the servos were torques the root pin never saw)."""
    from phav_generator.bench import REFERENCE_HZ

    recipe = recipe_for("run", "simple", seconds=2.0, variation="none")
    joints = list(JOINT_BODIES)
    fine = simulate(recipe, physics_hz=REFERENCE_HZ, keep_state=False).people[0]
    default = simulate(recipe, keep_state=False).people[0]
    speed = np.linalg.norm(np.diff(default.target_pos[:, PELVIS], axis=0), axis=-1).max() * 30.0
    assert speed > 2.5, f"not a run: pelvis at {speed:.1f} m/s"
    assert np.linalg.norm(default.body_pos[:, joints] - fine.body_pos[:, joints], axis=-1).max() < 0.01
    assert np.linalg.norm(default.body_pos[:, joints] - default.target_pos[:, joints], axis=-1).max() < 0.01


def test_a_running_foot_strike_is_the_same_at_every_rate() -> None:
    """A jog's foot lands at speed and stops: the animation has a corner there. The targets
    are smoothed over 5 ms on a fixed grid, so 1/120 s and 1/240 s land the foot where
    1/1920 s does. Unsmoothed, this clip (phav-v1, seed 0, v000051, its first landing) was
    1.33 cm apart at both rates: the reference slid the foot on, the coarse rates stopped it."""
    from phav_generator.bench import REFERENCE_HZ
    from phav_generator.sampling import sample_recipes
    from phav_spec.theta import load_preset

    jog = next(iter(sample_recipes(load_preset("phav-v1"), n=1, seed=0, start=51)))
    assert jog.motion.base_motion == "jog_slow_tired_01"
    recipe = jog.model_copy(update={"duration_s": 0.6, "n_frames": 18})
    joints = list(JOINT_BODIES)
    fine = simulate(recipe, physics_hz=REFERENCE_HZ, keep_state=False).people[0].body_pos[:, joints]
    for hz in (120, 240):
        coarse = simulate(recipe, physics_hz=hz, keep_state=False).people[0].body_pos[:, joints]
        assert np.linalg.norm(coarse - fine, axis=-1).max() < 0.005, f"1/{hz} s"


def test_moonwalk_sliding_foot_slides() -> None:
    """Smooth soles: friction does not hold the sliding foot back from its animation."""
    tr = simulate(recipe_for("moonwalk", "simple", seconds=2.0, variation="none"), keep_state=False)
    p = tr.people[0]
    feet = [BONE_INDEX["left_foot"], BONE_INDEX["right_foot"]]
    slide = np.linalg.norm(np.diff(p.target_pos[:, feet, :2], axis=0), axis=-1).sum(axis=0)
    assert slide.min() > 0.5, f"feet moved only {slide} m"
    assert np.linalg.norm(p.body_pos[:, feet] - p.target_pos[:, feet], axis=-1).max() < 0.05


def test_a_chair_never_cuts_through_the_legs() -> None:
    """Sit / stand recipes: the seat box stays clear of the shins and feet all clip long."""
    from phav_generator.physics.plan import _box_meets_bones

    legs = ("left_lower_leg", "right_lower_leg", "left_foot", "right_foot")
    seen = 0
    for action in ("sit", "stand"):
        for seed in range(6):
            plan = plan_scene(recipe_for(action, seconds=3.0, seed=seed, variation="none"))
            p = plan.people[0]
            pos, rot = forward_kinematics(p.dims, p.targets.root_pos, p.targets.root_quat, p.targets.q)
            for box in plan.boxes:
                if box.pixel_class == "chair":
                    seen += 1
                    assert not _box_meets_bones(box, p.dims, rot, pos, legs), f"{action} seed {seed}"
    assert seen >= 6


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
    from phav_generator.sampling import sample_recipes
    from phav_spec.theta import load_theta

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
        assert gaps.min() > -0.01, (r.video_id, r.motion.base_motion, gaps.min())
        assert np.mean(np.abs(gaps) < 0.01) > 0.4, (r.video_id, r.motion.base_motion, np.mean(np.abs(gaps) < 0.01))
        late += r.motion.start_s > 5.0
    assert late >= 5  # the clips that used to start metres off the ground


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


def test_background_walkers_step_onto_kerbs_and_blending_keeps_a_lying_body_above_ground() -> None:
    """Two true failures of the 100-video phav-v1-short measurement: a background walker's
    front foot 19 cm inside a raised road (its pelvis stepped up only once over it), and a
    dive clip whose blended leg (a standing one, onto a body lying on the floor) started
    71 cm into the ground. Walkers now rise for the highest surface within a stride, and
    the blend weight drops where it would sink a body."""
    from phav_generator.sampling import sample_recipes
    from phav_spec.theta import load_theta
    from phav_validators.failures import video_failures

    recipes = {r.video_id: r for r in sample_recipes(load_theta("phav-v1-short"), n=40, seed=0)}
    walkers, dive, run = recipes["v000027"], recipes["v000035"], recipes["v000005"]
    assert walkers.background_actors and walkers.environment.name == "urban"
    assert dive.action == "dive_floor" and dive.variation.kind == run.variation.kind == "action_blending"
    for recipe in (walkers, dive):
        result = video_failures(recipe, simulated_people(recipe), None)
        assert not result.failed, (recipe.video_id, result.failures)

    def targets(recipe, weight):
        variation = recipe.variation.model_copy(update={"weight": weight})
        return plan_scene(recipe.model_copy(update={"variation": variation})).people[0].targets

    # The dive's body lies on the floor all clip: its standing blended leg is never let in.
    np.testing.assert_array_equal(targets(dive, dive.variation.weight).q, targets(dive, 0.0).q)
    # A runner's blended arms sink nothing: blended at the recipe's full weight.
    weight = run.variation.weight
    full = blend(targets(run, 0.0), targets(run, 1.0), run.variation.muscles, weight)
    np.testing.assert_allclose(targets(run, weight).q, full.q, atol=1e-12)


def test_props_are_recorded_where_the_model_has_them() -> None:
    """A trajectory carries each prop's geom pose: a static bar where the plan put it, a
    driven car turned to its heading (its body only slides)."""
    for action, name in (("pull_up", "pull_up_bar"), ("car_hit", "car")):
        recipe = recipe_for(action, seconds=0.5, variation="none")
        planned = next(p for p in plan_scene(recipe).props if p.name == name)
        track = next(p for p in simulate(recipe, keep_state=False).props if p.name == name)
        np.testing.assert_allclose(track.pos[0], planned.pos, atol=1e-6)
        np.testing.assert_allclose(np.abs(track.quat[0] @ planned.quat), 1.0, atol=1e-6)


def test_a_pull_up_bar_stands_on_posts() -> None:
    plan = plan_scene(recipe_for("pull_up", seconds=1.0, variation="none"))
    bar = next(p for p in plan.props if p.name == "pull_up_bar")
    posts = [bx for bx in plan.boxes if bx.pixel_class == "misc"]
    ground = plan.recipe.protagonist.position[2]
    assert len(posts) == 2
    for post in posts:
        assert post.center[2] - post.half_size[2] == pytest.approx(ground)
        assert post.center[2] + post.half_size[2] > bar.pos[2]
        # each post stands just beyond one end of the bar
        assert np.linalg.norm(np.array(post.center[:2]) - bar.pos[:2]) == pytest.approx(bar.size[1] + post.half_size[0])


def _push_recipes() -> dict[str, object]:
    """One 5 s push recipe per push motion of phav-v1."""
    from phav_generator.sampling import sample_recipes
    from tests.generator.physics_support import theta_for

    out: dict[str, object] = {}
    for r in sample_recipes(theta_for("push", "simple", seconds=5.0, variation="none"), n=60, seed=0):
        out.setdefault(r.motion.base_motion, r)
    return out


def test_push_moves_what_it_pushes() -> None:
    """A pushed box or cart advances ahead of the fingertips without being reached through;
    a pushed door swings open on its hinge, and the pushing is annotated."""
    from phav_generator.physics.plan import _Builder, _hand_reach

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
        _, _, tips = _hand_reach(_Builder(recipe, plan.substeps), plan.people[0])
        near_face = (track.pos - x0) @ fwd - track.size[0]
        reach = ((tips[:: plan.substeps] - x0) @ fwd).max(axis=1)
        assert np.all(reach <= near_face + 1e-6), f"the hands reach into the {obj}"
