"""Supporting characters: tied hands stay together while the two walk."""

from __future__ import annotations

import numpy as np

from phav_generator.motion.rotations import quat_to_matrix
from phav_generator.motion.skeleton import BONE_INDEX
from phav_generator.physics.plan.scene import plan_scene
from phav_generator.physics.simulate import simulate
from phav_generator.sampling import RecipeSampler
from phav_spec.motions import meeting_start
from phav_spec.theta import load_theta
from tests.generator.physics.support import assert_healthy, recipe_for


def test_walk_holding_hands_keeps_hands_tied() -> None:
    tr = simulate(recipe_for("walk_holding_hands", seconds=2.0))
    assert_healthy(tr)
    a, b = tr.people[0], tr.person(1)
    palm = np.array([0.0, 0.0, -0.08 * a.height_m / 1.75])
    pa = a.body_pos[:, BONE_INDEX["right_hand"]] + quat_to_matrix(a.body_quat[:, BONE_INDEX["right_hand"]]) @ palm
    pb = b.body_pos[:, BONE_INDEX["left_hand"]] + quat_to_matrix(b.body_quat[:, BONE_INDEX["left_hand"]]) @ palm
    gap = np.linalg.norm(pa - pb, axis=-1)
    assert gap[10:].max() < 0.05, f"palms {np.round(gap, 3)} m apart"


def test_a_partner_keeps_pace_whatever_its_legs_and_stride() -> None:
    """phav-v1, seed 0: walking hand in hand with a 1.50 m partner, a 1.95 m protagonist
    (1804) walked away from them by 1.6 m over the clip, the partner's pelvis 0.79 → 1.82 m
    from theirs: the same motion at the same speed travels in proportion to leg length and
    stride. The partner now walks at the cadence that keeps pace."""
    sampler = RecipeSampler(load_theta("phav-v1"))
    for index in (1804, 3697):
        recipe = sampler.sample(0, index)
        assert recipe.action == "walk_holding_hands"
        plan = plan_scene(recipe)
        a, b = plan.people[0].targets.root_pos, plan.people[1].targets.root_pos
        apart = np.linalg.norm((a - b)[:, :2], axis=1)
        assert abs(apart[-1] - apart[0]) < 0.1, (index, np.round(apart[[0, -1]], 2))


def test_people_walking_into_each_other_stop_before_their_chests_meet() -> None:
    """phav-v1, seed 0: in `bump_into_each_other` both walk the same motion towards each
    other from θ's distance, pinned to their plans; the pelvises of 119, 182 and 249 came
    within 0.00–0.04 m, the two walking through each other. Each now halts at a stance
    before, the chests no nearer than touching, and the physics keeps them apart."""
    sampler = RecipeSampler(load_theta("phav-v1"))
    for index in (119, 182, 249):
        recipe = sampler.sample(0, index)
        assert recipe.action == "bump_into_each_other"
        plan = plan_scene(recipe)
        a, b = plan.people[0], plan.people[1]
        touching = sum(p.dims.capsules[BONE_INDEX["chest"]].radius for p in (a, b))
        apart = np.linalg.norm((a.targets.root_pos - b.targets.root_pos)[:, :2], axis=1)
        assert apart.min() >= touching, (index, round(float(apart.min()), 3), round(touching, 3))
        assert apart.min() < touching + 1.5, (index, round(float(apart.min()), 3))  # they did walk up
        assert np.ptp(a.targets.root_pos[-10:, :2], axis=0).max() < 1e-6  # standing still
    tr = simulate(recipe, keep_state=False)
    gap = np.linalg.norm((tr.people[0].body_pos[:, 0] - tr.person(1).body_pos[:, 0])[:, :2], axis=1)
    assert gap.min() >= 0.9 * touching, round(float(gap.min()), 3)


def test_people_walking_into_each_other_on_a_take_that_stops_them_meet():
    """phav-v1, seed 0: on the walk and bump (a walk that stops at 4.6 s, then steps back),
    the clip started anywhere θ put it, mostly past the point where two people 4–8 m apart
    could meet before the take stopped them: the pelvises ended 2–7 m beyond touching. The
    clip now starts where they meet as the take stops; of the first eight such clips, the
    five long enough to reach that point end within a few tenths of touching (the others,
    1.6–2.4 s long, cannot cover 7–8 m, and keep θ's start)."""
    sampler = RecipeSampler(load_theta("phav-v1"))
    gaps, seen = [], 0
    for index in range(3000):
        recipe = sampler.sample(0, index)
        if recipe.action != "bump_into_each_other" or recipe.motion.base_motion != "walk_bump_into_someone_01":
            continue
        seen += 1
        m = recipe.motion
        if meeting_start(m.base_motion, m.base_motion_length_s, recipe.duration_s * m.speed,
                         recipe.supporting_characters[0].distance_m) == m.start_s:  # fmt: skip
            plan = plan_scene(recipe)
            a, b = plan.people[0], plan.people[1]
            touching = sum(p.dims.capsules[BONE_INDEX["chest"]].radius for p in (a, b))
            apart = np.linalg.norm((a.targets.root_pos - b.targets.root_pos)[:, :2], axis=1)
            gaps.append(float(apart.min() - touching))
        if seen == 8:
            break
    assert len(gaps) >= 4 and max(gaps) < 1.0 and np.median(gaps) < 0.5, np.round(gaps, 2)
