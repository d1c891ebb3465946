"""What a push pushes: a box or a shopping cart driven ahead of the fingertips, stopping
(and its pusher with it) at what stands in its way, or a hinged door in its frame."""

from __future__ import annotations

import math

import numpy as np

from phav_generator.motion.rotations import yaw_matrix
from phav_generator.motion.skeleton import BONE_INDEX
from phav_generator.physics.plan.builder import PlanBuilder, rot_to_quat
from phav_generator.physics.plan.obstacles import SUPPORT_TOLERANCE_M, clear_run
from phav_generator.physics.plan.people import body_poses, halt, planted_before
from phav_generator.physics.plan.scene_plan import Manipulation, PersonPlan, PropPlan, StaticBox
from phav_spec.motions import MOTIONS
from phav_spec.scene import ENVIRONMENT_SCENES, Collider
from phav_spec.vocab import OBJECTS

#: The hands that push, right first.
HANDS = ("right_hand", "left_hand")
#: Gap between the fingertips and the face of what they push (m): touching, not pressing.
PUSH_GAP_M = 0.01
#: A pushed door's leaf (m): wide enough for both hands and a walker's shoulders.
DOOR_WIDTH_M = 1.0
DOOR_HEIGHT_M = 2.0


#: How far (m) short of what stands in its way a pushed load stops: touching, not pressing.
LOAD_STOP_GAP_M = 0.02
#: A cart's basket floats this far (m) above the ground: its castors fill the gap.
CART_CLEARANCE_M = 0.15


def push_target(b: PlanBuilder, p: PersonPlan) -> PersonPlan:
    """What a push motion pushes, by its description: a door, a shopping cart, else a box;
    the pusher as planned, halted where a load meets something it cannot pass."""
    motion = b.recipe.motion.base_motion
    description = MOTIONS[motion].description if motion in MOTIONS else ""
    if "door" in description:
        _door(b, p)
        return p
    return _pushed_load(b, p, "shopping_cart" if "cart" in description else "box")


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


def _pushed_load(b: PlanBuilder, p: PersonPlan, obj: str) -> PersonPlan:
    """A box or cart just beyond the fingertips, driven forward as far as they have pushed
    it. Where that would drive it into a collider (or off the raised ground it stands on),
    the pusher's motion halts at the last moment before, both feet down, and the load stops
    where the hands then leave it (a load that starts against something is not pushed)."""
    fwd, left, tips = hand_reach(b, p)
    x0 = np.array(b.recipe.protagonist.position, dtype=np.float64)
    ground = x0[2] + b.stand_offset_z
    reach = _reach(tips, x0, fwd)
    lateral = float(np.mean((tips - x0) @ left))
    hand_z = float(np.median(tips[..., 2])) - ground
    if obj == "box":  # a crate whose top stands just above the hands
        half = (0.3, 0.35, max(0.3, (hand_z + 0.1) / 2))
        bottom = 0.01
    else:  # a cart's basket, its handle end at the hands
        half = (0.45, 0.28, max(0.2, (hand_z - 0.15) / 2))
        bottom = CART_CLEARANCE_M
    start = x0 + (reach[0] + half[0]) * fwd + lateral * left
    room = load_room(b, (float(start[0]), float(start[1])), (float(fwd[0]), float(fwd[1])), half[:2],
                     ground + bottom + 2.0 * half[2], ground)  # fmt: skip
    blocked = np.flatnonzero(reach - reach[0] > room)
    if blocked.size:
        p = halt(p, b.times, float(b.times[planted_before(p, b.times, max(int(blocked[0]) - 1, 0))]))
        reach = np.minimum(_reach(hand_reach(b, p)[2], x0, fwd), reach[0] + max(room, 0.0))
    path = x0 + (reach[:, None] + half[0]) * fwd + lateral * left
    path[:, 2] = ground + bottom + half[2]
    quat = rot_to_quat(yaw_matrix(np.deg2rad(b.recipe.protagonist.heading_deg)))
    b.props.append(PropPlan(obj, obj, OBJECTS[obj], "box", half, 40.0, path[0], quat, dynamic=False, path=path))
    moving = np.flatnonzero(np.diff(reach) > 1e-4)
    if moving.size:
        t0, t1 = float(b.times[moving[0]]), float(b.times[moving[-1] + 1])
        b.manipulations.append(Manipulation(obj, p.person_id, "right_hand", "push", t0, t1))
    return p


def _reach(tips: np.ndarray, x0: np.ndarray, fwd: np.ndarray) -> np.ndarray:
    """How far ahead of ``x0`` (m) the load's near face is at each step: just beyond the
    furthest the fingertips have pushed so far (it never comes back towards the hands)."""
    return np.maximum.accumulate(np.max((tips - x0) @ fwd, axis=1)) + PUSH_GAP_M


def load_room(
    b: PlanBuilder, centre: tuple[float, float], travel: tuple[float, float], half: tuple[float, float],
    top: float, ground: float,
) -> float:  # fmt: skip
    """How far (m) a load of ``half`` extents seen from above, centred on ``centre`` and
    standing on the ground at height ``ground`` (its wheels on it, a cart's) up to ``top``,
    can be pushed along ``travel`` before it comes within ``LOAD_STOP_GAP_M`` of a collider
    of the environment or a box the action built (a kerb too: it slides, it does not
    climb), or leaves the raised ground it stands on (inf where nothing is in its way;
    negative where it starts against one)."""
    scene = ENVIRONMENT_SCENES[b.recipe.environment.name]
    built = tuple(Collider(s.pixel_class, s.center, s.half_size, s.yaw_deg) for s in b.boxes)
    raised = ground > scene.ground_z + SUPPORT_TOLERANCE_M
    bottom = ground + SUPPORT_TOLERANCE_M
    extent = (float(half[0]), float(half[1]), (top - bottom) / 2.0)
    _, ahead = clear_run((*scene.colliders, *built), centre, travel, extent, bottom, ground, raised=raised)
    return ahead - LOAD_STOP_GAP_M


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
