"""Annotations measured on the rendered frame: a joint called visible is seen on its own
class or a body part that meets at it."""

from __future__ import annotations

import numpy as np

from phav_spec.metadata import JOINT_ORDER
from phav_spec.vocab import PIXEL_CLASSES
from tests.generator.physics.support import recipe_for
from tests.generator.render.support import render_recipe


def _adjacent(joint: str) -> set[str]:
    """The joint's own class and the parts that meet at it."""
    side, _, kind = joint.partition("_")
    parts = {
        "shoulder": ("chest", f"{side}_upper_arm"),
        "elbow": (f"{side}_upper_arm", f"{side}_lower_arm"),
        "wrist": (f"{side}_lower_arm", f"{side}_hand"),
        "hip": (f"{side}_upper_leg", f"{side}_hip", "chest"),
        "knee": (f"{side}_upper_leg", f"{side}_lower_leg"),
        "ankle": (f"{side}_lower_leg", f"{side}_foot"),
    }
    return {joint, *(("head", "chest") if joint == "neck" else parts[kind])}


def test_visible_2d_joints_land_on_their_joint_or_an_adjacent_part(ctx):
    by_colour = {PIXEL_CLASSES[n].rgb: n for n in PIXEL_CLASSES.names}
    visible = 0
    for action, env in (("walk", "urban"), ("wave", "green"), ("sit", "house_interior")):
        for rf in render_recipe(recipe_for(action, env, seconds=0.3, variation="none"), ctx):
            semantic = rf.modalities["semantic"]
            for person in rf.people:
                uv = np.array(person["joints2d"]).reshape(13, 2)
                for j, name in enumerate(JOINT_ORDER):
                    if not person["visible"][j]:
                        continue
                    visible += 1
                    seen = by_colour[tuple(int(c) for c in semantic[int(uv[j, 1]), int(uv[j, 0])])]
                    assert seen in _adjacent(name), (action, rf.index, person["person_id"], name, seen)
    assert visible > 100
