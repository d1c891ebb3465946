"""Held props go in the hand that uses them: the action's prop in the hand the clip acts
with (a left-handed take's left, a mirrored clip's other), the objects variation's in the
other one."""

from __future__ import annotations

import numpy as np
import pytest

from phav_generator.motion.skeleton import BONE_INDEX, forward_kinematics
from phav_generator.physics.plan.scene import plan_scene
from phav_generator.sampling import RecipeSampler
from phav_spec.theta import load_theta


@pytest.mark.parametrize("index", [79, 1504, 626, 485])
def test_the_action_s_prop_is_in_the_acting_hand_and_the_variation_s_in_the_other(index):
    """phav-v1, seed 0: `brush_hair` with the left-handed take, mirrored (79) or not (1504),
    a right-handed take mirrored (626), a mirrored `pick` (485), each with the objects
    variation. The variation's prop went into the busy hand of a mirrored clip, and the
    left-handed take's brush was always in the hand that never came near the head."""
    recipe = RecipeSampler(load_theta("phav-v1")).sample(0, index)
    assert recipe.variation.kind == "objects" and recipe.action in ("brush_hair", "pick")
    plan = plan_scene(recipe)
    held = {p.name: p.grips[0][1] for p in plan.props if p.grips}
    (action_hand,) = [hand for name, hand in held.items() if not name.endswith("_variation")]
    (other_hand,) = [hand for name, hand in held.items() if name.endswith("_variation")]
    assert {action_hand, other_hand} == {"left_hand", "right_hand"}, held
    me = plan.people[0]
    pos, _ = forward_kinematics(me.dims, me.targets.root_pos, me.targets.root_quat, me.targets.q)
    if recipe.action == "brush_hair":  # the brushing hand comes to the head; the other does not
        near = {h: float(np.linalg.norm(pos[:, BONE_INDEX[h]] - pos[:, BONE_INDEX["head"]], axis=1).min())
                for h in held.values()}  # fmt: skip
        assert near[action_hand] < 0.25 < near[other_hand], near
    else:  # the picking hand reaches lowest
        low = {h: float(pos[:, BONE_INDEX[h], 2].min()) for h in held.values()}
        assert low[action_hand] < low[other_hand], low


def test_a_pick_whose_hand_never_comes_down_holds_the_bottle_instead() -> None:
    """phav-v1, seed 0, v000032: the clip's window of `walk_pick_up_litter_01` misses the
    bend, the grip staying 0.59 m over the bottle stood on the ground under it; the weld
    then pulled the bottle up into the hand. It is held from the start instead; a clip that
    bends down to it (v000485) still picks it up."""
    sampler = RecipeSampler(load_theta("phav-v1"))
    for index, kind in ((32, "hold"), (485, "pick")):
        recipe = sampler.sample(0, index)
        assert recipe.action == "pick"
        (bottle,) = [m for m in plan_scene(recipe).manipulations if m.object == "bottle"]
        assert bottle.kind == kind and (bottle.start_s == 0.0) == (kind == "hold"), (index, bottle)
