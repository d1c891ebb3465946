"""What a push pushes: a box or a shopping cart driven ahead of the fingertips, or a hinged
door in its frame."""

from __future__ import annotations

import math

import numpy as np

from phav_generator.motion.rotations import yaw_matrix
from phav_generator.motion.skeleton import BONE_INDEX
from phav_generator.physics.plan.builder import PlanBuilder, rot_to_quat
from phav_generator.physics.plan.people import body_poses
from phav_generator.physics.plan.scene_plan import Manipulation, PersonPlan, PropPlan, StaticBox
from phav_spec.motions import MOTIONS
from phav_spec.vocab import OBJECTS

#: The hands that push, right first.
HANDS = ("right_hand", "left_hand")
#: Gap between the fingertips and the face of what they push (m): touching, not pressing.
PUSH_GAP_M = 0.01
#: A pushed door's leaf (m): wide enough for both hands and a walker's shoulders.
DOOR_WIDTH_M = 1.0
DOOR_HEIGHT_M = 2.0


#: A cart's basket floats this far (m) above the ground: its castors fill the gap.
CART_CLEARANCE_M = 0.15


def push_target(b: PlanBuilder, p: PersonPlan) -> None:
    """What a push motion pushes, by its description: a door, a shopping cart, else a box."""
    motion = b.recipe.motion.base_motion
    description = MOTIONS[motion].description if motion in MOTIONS else ""
    if "door" in description:
        _door(b, p)
    else:
        _pushed_load(b, p, "shopping_cart" if "cart" in description else "box")


def hand_reach(b: PlanBuilder, p: PersonPlan) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Forward axis, left axis and, per plan step, both palms' fingertip points (S, 2, 3)."""
    pos, rot = body_poses(p.dims, p.targets)
    heading = np.deg2rad(b.recipe.protagonist.heading_deg)
    fwd = yaw_matrix(heading) @ np.array([1.0, 0.0, 0.0])
    left = yaw_matrix(heading) @ np.array([0.0, 1.0, 0.0])
    tips = []
    for hand in HANDS:
        k = BONE_INDEX[hand]
        cap = p.dims.capsules[k]
        tip = pos[:, k] + rot[:, k] @ np.array(cap.b)
        tips.append(tip + cap.radius * fwd)
    return fwd, left, np.stack(tips, axis=1)


def _pushed_load(b: PlanBuilder, p: PersonPlan, obj: str) -> None:
    """A box or cart just beyond the fingertips, driven forward as far as they have pushed it."""
    fwd, left, tips = hand_reach(b, p)
    x0 = np.array(b.recipe.protagonist.position, dtype=np.float64)
    ground = x0[2] + b.stand_offset_z
    # The load never comes back towards the hands: it stays where the furthest push left it.
    reach = np.maximum.accumulate(np.max((tips - x0) @ fwd, axis=1)) + PUSH_GAP_M
    lateral = float(np.mean((tips - x0) @ left))
    hand_z = float(np.median(tips[..., 2])) - ground
    if obj == "box":  # a crate whose top stands just above the hands
        half = (0.3, 0.35, max(0.3, (hand_z + 0.1) / 2))
        bottom = 0.01
    else:  # a cart's basket, its handle end at the hands
        half = (0.45, 0.28, max(0.2, (hand_z - 0.15) / 2))
        bottom = CART_CLEARANCE_M
    path = x0 + (reach[:, None] + half[0]) * fwd + lateral * left
    path[:, 2] = ground + bottom + half[2]
    quat = rot_to_quat(yaw_matrix(np.deg2rad(b.recipe.protagonist.heading_deg)))
    b.props.append(PropPlan(obj, obj, OBJECTS[obj], "box", half, 40.0, path[0], quat, dynamic=False, path=path))
    moving = np.flatnonzero(np.diff(reach) > 1e-4)
    if moving.size:
        t0, t1 = float(b.times[moving[0]]), float(b.times[moving[-1] + 1])
        b.manipulations.append(Manipulation(obj, p.person_id, "right_hand", "push", t0, t1))


def _door(b: PlanBuilder, p: PersonPlan) -> None:
    """A hinged door in a frame across the path, where the hands first reach out; the hands
    push its leaf open (contact, no constraint) and the damped hinge resists."""
    fwd, left, tips = hand_reach(b, p)
    x0 = np.array(b.recipe.protagonist.position, dtype=np.float64)
    ground = x0[2] + b.stand_offset_z
    reach = np.max((tips - x0) @ fwd, axis=1)
    pelvis_reach = (p.targets.root_pos - x0) @ fwd
    # The door stands where the hands are furthest ahead of the pelvis (they meet the leaf).
    i = int(np.argmax(reach - pelvis_reach))
    plane = float(reach[i]) + PUSH_GAP_M
    width, height = DOOR_WIDTH_M, DOOR_HEIGHT_M
    hinge_side = 0.7  # the hinge on the person's left; the leaf spans past their right hand
    hinge = x0 + plane * fwd + hinge_side * left
    hinge[2] = ground + 0.01
    heading = b.recipe.protagonist.heading_deg
    quat = rot_to_quat(yaw_matrix(np.deg2rad(heading)))
    b.props.append(
        PropPlan("door", "door", OBJECTS["door"], "box", (0.02, width / 2, height / 2), 25.0, hinge, quat,
                 hinge=(0.0, math.radians(100.0)), offset=(0.02, -width / 2, height / 2))
    )  # fmt: skip
    # The frame: two posts beside the leaf and a lintel over it (the leaf opens away from them).
    for y in (hinge_side + 0.06, hinge_side - width - 0.06):  # the hinge post, the latch post
        c = x0 + (plane - 0.05) * fwd + y * left
        b.boxes.append(StaticBox("door", (float(c[0]), float(c[1]), ground + (height + 0.1) / 2),
                                 (0.05, 0.05, (height + 0.1) / 2), heading))  # fmt: skip
    c = x0 + (plane - 0.05) * fwd + (hinge_side - width / 2) * left
    b.boxes.append(StaticBox("door", (float(c[0]), float(c[1]), ground + height + 0.06), (0.05, width / 2 + 0.11, 0.05),
                             heading))  # fmt: skip
    b.manipulations.append(Manipulation("door", p.person_id, "right_hand", "push", float(b.times[i]),
                                        float(b.times[-1])))  # fmt: skip
