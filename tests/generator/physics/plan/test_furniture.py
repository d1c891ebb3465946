"""Furniture: a chair clear of the legs with a back clear of the torso, a pull-up bar on
its posts."""

from __future__ import annotations

import numpy as np
import pytest

from phav_generator.motion.skeleton import forward_kinematics
from phav_generator.physics.plan.furniture import box_meets_bones
from phav_generator.physics.plan.scene import plan_scene
from tests.generator.physics.support import recipe_for


def _sit_and_stand():
    """(action, seed, plan, body positions, rotations) of six sit and six stand recipes."""
    for action in ("sit", "stand"):
        for seed in range(6):
            plan = plan_scene(recipe_for(action, seconds=3.0, seed=seed, variation="none"))
            p = plan.people[0]
            pos, rot = forward_kinematics(p.dims, p.targets.root_pos, p.targets.root_quat, p.targets.q)
            yield action, seed, plan, pos, rot


def test_a_chair_never_cuts_through_the_legs() -> None:
    """Sit / stand recipes: the seat box stays clear of the shins and feet all clip long."""
    legs = ("left_lower_leg", "right_lower_leg", "left_foot", "right_foot")
    seen = 0
    for action, seed, plan, pos, rot in _sit_and_stand():
        for box in plan.boxes:
            if box.pixel_class == "chair":
                seen += 1
                assert not box_meets_bones(box, plan.people[0].dims, rot, pos, legs), f"{action} seed {seed}"
    assert seen >= 6


def test_a_chair_back_stands_on_its_seats_rear_edge_clear_of_the_sitter() -> None:
    torso = ("pelvis", "chest", "head", "left_upper_arm", "right_upper_arm", "left_lower_arm", "right_lower_arm")
    backs = 0
    for action, seed, plan, pos, rot in _sit_and_stand():
        chairs = [bx for bx in plan.boxes if bx.pixel_class == "chair"]
        seat, rest = chairs[0], chairs[1:]
        for back in rest:
            backs += 1
            assert not box_meets_bones(back, plan.people[0].dims, rot, pos, torso), f"{action} seed {seed}"
            assert back.center[2] - back.half_size[2] == pytest.approx(seat.center[2] + seat.half_size[2])
            assert back.yaw_deg == seat.yaw_deg and back.half_size[0] < 0.05
            gap = np.linalg.norm(np.array(back.center[:2]) - np.array(seat.center[:2]))
            assert gap == pytest.approx(seat.half_size[0] - back.half_size[0])
    assert backs >= 4


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
