"""Props in the hand and the kicked ball: hold, pick up, throw, catch and kick.

A handheld prop is a free body welded to the hand (a grip) while it is held; the
manipulation is annotated for the trajectory.
"""

from __future__ import annotations

import numpy as np

from phav_generator.motion.rotations import yaw_matrix
from phav_generator.motion.skeleton import BONE_INDEX
from phav_generator.physics.plan.builder import PlanBuilder, rot_to_quat, uniform
from phav_generator.physics.plan.people import body_poses
from phav_generator.physics.plan.scene_plan import Manipulation, PersonPlan, PropPlan
from phav_spec.vocab import OBJECTS

# Props held in the hand: shape, size, mass and the grip offset in the hand frame.
_HANDHELD_SHAPES: dict[str, tuple[str, tuple[float, ...], float, tuple[float, float, float]]] = {
    "ball": ("sphere", (0.11,), 0.45, (0.0, 0.0, -0.15)),
    "cup": ("capsule", (0.04, 0.04), 0.25, (0.04, 0.0, -0.09)),
    "bottle": ("capsule", (0.035, 0.1), 0.6, (0.04, 0.0, -0.09)),
    "hair_brush": ("capsule", (0.02, 0.1), 0.2, (0.0, 0.0, -0.14)),
    "gun": ("box", (0.11, 0.02, 0.06), 1.0, (0.05, 0.0, -0.08)),
    "golf_club": ("capsule", (0.015, 0.5), 0.4, (0.0, 0.0, -0.55)),
    "baseball_bat": ("capsule", (0.03, 0.42), 0.9, (0.0, 0.0, -0.45)),
    "bow": ("capsule", (0.015, 0.7), 0.8, (0.0, 0.0, -0.06)),
}


def _grip(rel: tuple[float, float, float], scale: float) -> tuple[np.ndarray, np.ndarray]:
    return np.array(rel) * np.array([1.0, 1.0, scale]), np.array([1.0, 0.0, 0.0, 0.0])


def _world_grip(body_pos: np.ndarray, body_rot: np.ndarray, rel: np.ndarray) -> np.ndarray:
    return body_pos + body_rot @ rel


def hands(motion: str, mirror: bool) -> tuple[str, str]:
    """The body's (acting, other) hand in a clip of ``motion``: a take acts with its right
    hand unless it is named for its left (``brush_hair_left_hand_01``); mirrored, with the
    other. An action's scene names the muscles of a right-handed take."""
    acting_right = ("left_hand" in motion) == mirror
    return ("right_hand", "left_hand") if acting_right else ("left_hand", "right_hand")


def free_hand(necessary: tuple[str, ...], acting: str, other: str) -> str:
    """The hand the action does not need (the objects variation's prop goes there): the
    other hand where the action needs its acting one, else the acting one."""
    return other if "right_hand" in necessary else acting


def hold(
    b: PlanBuilder,
    person: PersonPlan,
    obj: str,
    body: str,
    t0: float = 0.0,
    t1: float | None = None,
    name: str | None = None,
) -> PropPlan:
    """A handheld prop gripped by ``body`` from t0 to t1 (None: the whole clip)."""
    rel_pos, rel_quat = _grip(_HANDHELD_SHAPES[obj][3], person.dims.height_m / 1.75)
    pos, rot = body_poses(person.dims, person.targets.take(slice(0, 1)))
    k = BONE_INDEX[body]
    start = _world_grip(pos[0, k], rot[0, k], rel_pos)
    quat = rot_to_quat(rot[0, k])
    end = b.times[-1] + 1.0 if t1 is None else t1
    name = name or f"{obj}_{len(b.props)}"
    return _gripped_prop(b, person, obj, body, name, start, quat, "hold", t0, end, (rel_pos, rel_quat))


def _gripped_prop(
    b: PlanBuilder,
    person: PersonPlan,
    obj: str,
    body: str,
    name: str,
    pos: np.ndarray,
    quat: np.ndarray,
    kind: str,
    t0: float,
    t1: float,
    grip: tuple[np.ndarray, np.ndarray],
    vel: np.ndarray | None = None,
) -> PropPlan:
    """Add a handheld prop gripped by ``body`` from t0 to t1 and annotate the manipulation
    (``kind``: hold, catch, pick) from t0 to t1 or the clip's end."""
    shape, size, mass, _ = _HANDHELD_SHAPES[obj]
    prop = PropPlan(
        name=name, object=obj, pixel_class=OBJECTS[obj], shape=shape, size=size, mass=mass, pos=pos, quat=quat,
        vel=np.zeros(3) if vel is None else vel, grips=((person.person_id, body, t0, t1, grip[0], grip[1]),),
    )  # fmt: skip
    b.props.append(prop)
    b.manipulations.append(Manipulation(obj, person.person_id, body, kind, t0, min(t1, float(b.times[-1]))))
    return prop


def _body_speed(person: PersonPlan, body: str) -> np.ndarray:
    """Displacement per physics step of a body's animated origin (proportional to speed)."""
    pos, _ = body_poses(person.dims, person.targets)
    return np.linalg.norm(np.gradient(pos[:, BONE_INDEX[body]], axis=0), axis=1)


def throw(b: PlanBuilder, p: PersonPlan, obj: str, body: str, kind: str) -> None:
    """Throw / shoot: held until the hand moves fastest, then released in flight."""
    speed = _body_speed(p, body)
    lo = len(b.times) // 5
    i = lo + int(np.argmax(speed[lo:])) if len(speed) > lo else len(speed) - 1
    t_release = float(b.times[i])
    hold(b, p, obj, body, 0.0, t_release)
    b.manipulations[-1] = Manipulation(obj, p.person_id, body, kind, 0.0, t_release)


def catch(b: PlanBuilder, p: PersonPlan, body: str) -> None:
    """A ball thrown from 4–6 m in front lands in the hand when it is furthest forward."""
    pos, rot = body_poses(p.dims, p.targets)
    hand = pos[:, BONE_INDEX[body]]
    forward = yaw_matrix(np.deg2rad(b.recipe.protagonist.heading_deg)) @ np.array([1.0, 0.0, 0.0])
    n = len(b.times)
    lo, hi = n // 4, max(n // 4 + 1, (3 * n) // 4)
    i = lo + int(np.argmax(hand[lo:hi] @ forward))
    t_catch = float(b.times[i])
    distance = uniform(4.0, 6.0, rng=b.rng)
    target = hand[i] + rot[i, BONE_INDEX[body]] @ np.array([0.0, 0.0, -0.15])
    start = target + distance * forward + np.array([0.0, 0.0, 0.3])
    g = np.array([0.0, 0.0, -9.81])
    vel = (target - start - 0.5 * g * t_catch**2) / max(t_catch, 1e-3)
    grip = _grip(_HANDHELD_SHAPES["ball"][3], p.dims.height_m / 1.75)
    _gripped_prop(b, p, "ball", body, "ball_catch", start, np.array([1.0, 0.0, 0.0, 0.0]), "catch", t_catch,
                  b.times[-1] + 1.0, grip, vel=vel)  # fmt: skip


#: How far over the bottle's place on the ground (m) the grip may stay at its lowest and
#: still pick it up (a hand reaching for a bottle's neck is ~0.1 m over its centre): the weld
#: closes that gap as the hand closes; a wider one would pull the bottle through the air.
PICK_REACH_M = 0.25


def pick(b: PlanBuilder, p: PersonPlan, hand: str) -> None:
    """Pick up: the object rests on the ground under the hand's lowest point; held after. A
    clip whose hand never comes down to it (its window misses the bend) holds it instead:
    the weld would have pulled it up into the hand from the ground."""
    pos, rot = body_poses(p.dims, p.targets)
    h = pos[:, BONE_INDEX[hand]]
    i = int(np.argmin(h[:, 2]))
    _, size, _, rel = _HANDHELD_SHAPES["bottle"]
    ground = b.recipe.protagonist.position[2]
    grip = _grip(rel, p.dims.height_m / 1.75)
    grip_world = _world_grip(h[i], rot[i, BONE_INDEX[hand]], grip[0])
    start = np.array([grip_world[0], grip_world[1], ground + size[0] + size[1] + 0.005])
    if grip_world[2] - start[2] > PICK_REACH_M:
        hold(b, p, "bottle", hand, name="bottle_pick")
        return
    t_pick = float(b.times[i])
    _gripped_prop(b, p, "bottle", hand, "bottle_pick", start, np.array([1.0, 0, 0, 0]), "pick", t_pick,
                  b.times[-1] + 1.0, grip)  # fmt: skip


def kick(b: PlanBuilder, p: PersonPlan) -> None:
    """A ball on the ground where a foot moves fastest: the foot's contact kicks it."""
    pos, rot = body_poses(p.dims, p.targets)
    best = None
    for foot in ("right_foot", "left_foot"):
        f = pos[:, BONE_INDEX[foot]]
        speed = np.linalg.norm(np.gradient(f, axis=0), axis=1)
        i = int(np.argmax(speed))
        if best is None or speed[i] > best[0]:
            best = (speed[i], foot, i)
    _, foot, i = best
    toe = pos[i, BONE_INDEX[foot]] + rot[i, BONE_INDEX[foot]] @ np.array([0.12 * p.dims.height_m, 0.0, 0.0])
    radius = _HANDHELD_SHAPES["ball"][1][0]
    ground = b.recipe.protagonist.position[2] + b.stand_offset_z
    ball = np.array([toe[0], toe[1], ground + radius])
    b.props.append(
        PropPlan("ball_kick", "ball", OBJECTS["ball"], "sphere", (radius,), 0.43, ball, np.array([1.0, 0, 0, 0]))
    )
    t = float(b.times[i])
    b.manipulations.append(Manipulation("ball", p.person_id, foot, "kick", max(0.0, t - 0.1), t + 0.1))
