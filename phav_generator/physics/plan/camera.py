"""Where the camera starts: the recipe's C_xyz and T_xyz, put on the protagonist's actual
first pose and moved out of the environment's walls; what a spring camera's target holds on to."""

from __future__ import annotations

import numpy as np

from phav_generator.motion.skeleton import BONE_INDEX
from phav_spec.recipe import Recipe
from phav_spec.scene import ENVIRONMENT_SCENES

#: Where on the protagonist a spring camera's target is tied, per camera, as weights of body
#: origins: the kite films the whole body around the pelvis; the close-up aims two thirds of
#: the way from the chest's origin to the head's (the neck), about 0.77 of the body's height
#: standing, so that the head, the hand brushing it and the hand hanging by the hip share the frame.
ANCHOR_WEIGHTS: dict[str, dict[str, float]] = {"kite": {"pelvis": 1.0}, "closeup": {"chest": 1 / 3, "head": 2 / 3}}


def anchor_point(kind: str, body_pos: np.ndarray) -> np.ndarray:
    """The point a ``kind`` camera's target spring holds on to, from world body origins (…, 15, 3)."""
    weights = ANCHOR_WEIGHTS[kind]
    body_pos = np.asarray(body_pos)
    return sum(w * body_pos[..., BONE_INDEX[b], :] for b, w in weights.items())


#: How far (m) a camera start inside something is first lifted to clear it.
LIFT_M = 1.0


def _inside(colliders, point: np.ndarray, clearance: float, floor: float = -np.inf) -> bool:
    x, y, z = (float(v) for v in point)
    return z < floor + clearance or any(
        c.xy_distance(x, y) < clearance and c.bottom - clearance < z < c.top + clearance for c in colliders
    )


def clear_camera_start(
    recipe: Recipe, clearance: float = 0.25, *, shift: np.ndarray | None = None
) -> tuple[float, float, float]:
    """The camera's start, moved clear of the environment's geometry: lifted, or slid
    towards its target.

    The sampler places C_xyz around the protagonist without looking at the geometry, so a
    start inside something is moved, deterministically, up to ``LIFT_M`` straight up (over
    the ground, a bench or a car) or else to the first point on the segment to the target
    (through a wall), in 5 cm steps, to the first with ``clearance`` metres of room.
    ``shift`` moves camera and target together first (a spring camera's rig put on the
    protagonist's actual first pose): a rig lowered onto a seated or lying body can put the
    camera into the ground, where the slide would end on the body itself.
    """
    env = ENVIRONMENT_SCENES[recipe.environment.name]
    colliders, floor = env.colliders, float(getattr(env, "ground_z", 0.0))
    offset = np.zeros(3) if shift is None else np.asarray(shift, dtype=np.float64)
    start = np.array(recipe.camera.position, dtype=np.float64) + offset
    target = np.array(recipe.camera.target, dtype=np.float64) + offset
    for j in range(round(LIFT_M / 0.05) + 1):
        lifted = start + np.array([0.0, 0.0, 0.05 * j])
        if not _inside(colliders, lifted, clearance, floor):
            return (float(lifted[0]), float(lifted[1]), float(lifted[2]))
    length = float(np.linalg.norm(target - start))
    steps = max(1, int(length / 0.05))
    for k in range(steps + 1):
        point = start + (target - start) * (k / steps)
        if not _inside(colliders, point, clearance, floor):
            return (float(point[0]), float(point[1]), float(point[2]))
    return tuple(float(v) for v in target)  # type: ignore[return-value]
