"""Furniture an action uses: the chair of sit / stand up and the pull-up bar on its posts."""

from __future__ import annotations

import math

import numpy as np

from phav_generator.motion.rotations import yaw_matrix
from phav_generator.motion.skeleton import BONE_INDEX, BodyDims
from phav_generator.physics.plan.builder import PlanBuilder, rot_to_quat
from phav_generator.physics.plan.people import body_poses
from phav_generator.physics.plan.scene_plan import Manipulation, PersonPlan, PropPlan, StaticBox
from phav_spec.vocab import OBJECTS

#: A chair's back: its height above the seat and half its thickness (m).
CHAIR_BACK_M = 0.42
CHAIR_BACK_HALF_M = 0.02
#: Half the thickness of the posts that hold a pull-up bar's ends (m).
POST_HALF_WIDTH_M = 0.04


def box_meets_bones(box: StaticBox, dims: BodyDims, rot: np.ndarray, pos: np.ndarray, bones: tuple[str, ...]) -> bool:
    """Whether any of ``bones``' capsules (ends and middle) comes inside ``box`` at any step."""
    turn = yaw_matrix(np.deg2rad(box.yaw_deg))
    half = np.array(box.half_size)
    for name in bones:
        k = BONE_INDEX[name]
        cap = dims.capsules[k]
        for local in (np.array(cap.a), np.array(cap.b), (np.array(cap.a) + np.array(cap.b)) / 2):
            point = pos[:, k] + rot[:, k] @ local
            inside = (point - np.array(box.center)) @ turn
            gap = np.linalg.norm(np.maximum(np.abs(inside) - half, 0.0), axis=-1)
            if np.any(gap < cap.radius):
                return True
    return False


def chair_under_pelvis(b: PlanBuilder, p: PersonPlan) -> None:
    """A chair whose seat is where the animated pelvis comes lowest (sit / stand up).

    Where the seat would cut through the shins or feet (a crouch rather than a seat, or
    sitting on the floor) the chair stands aside, unused and not annotated.
    """
    pos, rot = body_poses(p.dims, p.targets)
    pelvis = pos[:, 0]
    i = int(np.argmin(pelvis[:, 2]))
    ground = b.recipe.protagonist.position[2]
    heading = b.recipe.protagonist.heading_deg
    back = yaw_matrix(np.deg2rad(heading)) @ np.array([-1.0, 0.0, 0.0])
    half = 0.22

    def chair(centre: np.ndarray, seat_top: float) -> StaticBox:
        return StaticBox(
            "chair",
            (float(centre[0]), float(centre[1]), (ground + seat_top) / 2),
            (half, half, (seat_top - ground) / 2),
            heading,
        )

    seat_top = pelvis[i, 2] - p.dims.capsules[0].radius * 0.9
    box = chair(pelvis[i] + 0.05 * back, seat_top)
    legs = ("left_lower_leg", "right_lower_leg", "left_foot", "right_foot")
    if seat_top - ground < 0.25 or box_meets_bones(box, p.dims, rot, pos, legs):
        aside = pelvis[0] + 1.2 * (yaw_matrix(np.deg2rad(heading)) @ np.array([0.0, 1.0, 0.0]))
        seat = chair(aside, ground + 0.45)
        b.boxes.append(seat)
        _chair_back(b, p, seat, back, rot, pos)
        return
    b.boxes.append(box)
    _chair_back(b, p, box, back, rot, pos)
    b.manipulations.append(
        Manipulation("chair", p.person_id, "pelvis", "hold", float(b.times[i]) - 0.5, float(b.times[i]) + 0.5)
    )


def _chair_back(
    b: PlanBuilder, p: PersonPlan, seat: StaticBox, back: np.ndarray, rot: np.ndarray, pos: np.ndarray
) -> None:
    """A back on a chair seat's rear edge (``back``: the world direction behind it), where the
    person's torso, arms and head stay clear of it; none where they would meet it."""
    half, seat_top = seat.half_size[1], seat.center[2] + seat.half_size[2]
    centre = np.array(seat.center[:2]) + (half - CHAIR_BACK_HALF_M) * back[:2]
    rest = StaticBox("chair", (float(centre[0]), float(centre[1]), float(seat_top + CHAIR_BACK_M / 2)),
                     (CHAIR_BACK_HALF_M, half, CHAIR_BACK_M / 2), seat.yaw_deg)  # fmt: skip
    torso = ("pelvis", "chest", "head", "left_upper_arm", "right_upper_arm", "left_lower_arm", "right_lower_arm")
    if not box_meets_bones(rest, p.dims, rot, pos, torso):
        b.boxes.append(rest)


def pull_up_bar(b: PlanBuilder, p: PersonPlan) -> None:
    """A bar through the hands' highest point; the hands hold it while they are near it."""
    pos, _ = body_poses(p.dims, p.targets)
    hands = (pos[:, BONE_INDEX["left_hand"]] + pos[:, BONE_INDEX["right_hand"]]) / 2
    i = int(np.argmax(hands[:, 2]))
    top = hands[i]
    heading = np.deg2rad(b.recipe.protagonist.heading_deg)
    # The bar runs left–right, just above the palms.
    half_length = 0.6
    yaw = heading + math.pi / 2
    quat = rot_to_quat(yaw_matrix(yaw) @ np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]]))
    b.props.append(
        PropPlan(
            "pull_up_bar", "pull_up_bar", OBJECTS["pull_up_bar"], "capsule", (0.02, half_length), 5.0,
            top + np.array([0.0, 0.0, 0.08]), quat, dynamic=False,
        )
    )  # fmt: skip
    # Two posts carry the bar's ends down to the ground, out beside the shoulders.
    across = yaw_matrix(yaw) @ np.array([1.0, 0.0, 0.0])
    ground = b.recipe.protagonist.position[2]
    bar_z = top[2] + 0.08
    for side in (-1.0, 1.0):
        foot = top + side * (half_length + POST_HALF_WIDTH_M) * across
        b.boxes.append(
            StaticBox(OBJECTS["pull_up_bar"], (float(foot[0]), float(foot[1]), (ground + bar_z + 0.04) / 2),
                      (POST_HALF_WIDTH_M, POST_HALF_WIDTH_M, (bar_z + 0.04 - ground) / 2), math.degrees(yaw))
        )  # fmt: skip
    near = np.abs(hands[:, 2] - top[2]) < 0.15
    if near.any():
        idx = np.flatnonzero(near)
        b.manipulations.append(
            Manipulation(
                "pull_up_bar", p.person_id, "right_hand", "hold", float(b.times[idx[0]]), float(b.times[idx[-1]])
            )
        )
