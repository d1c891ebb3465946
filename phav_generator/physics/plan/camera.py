"""Where the camera starts: the recipe's C_xyz, moved out of the environment's walls."""

from __future__ import annotations

import numpy as np

from phav_spec.recipe import Recipe
from phav_spec.scene import ENVIRONMENT_SCENES


def _inside(colliders, point: np.ndarray, clearance: float) -> bool:
    x, y, z = (float(v) for v in point)
    return any(c.xy_distance(x, y) < clearance and c.bottom - clearance < z < c.top + clearance for c in colliders)


def clear_camera_start(recipe: Recipe, clearance: float = 0.25) -> tuple[float, float, float]:
    """The camera's start, slid towards its target until it is clear of the environment's walls.

    The sampler places C_xyz around the protagonist without looking at the geometry, so a
    start inside a building or behind a wall is moved, deterministically, to the first
    point on the segment to the target (5 cm steps) with ``clearance`` metres of room.
    """
    colliders = ENVIRONMENT_SCENES[recipe.environment.name].colliders
    start = np.array(recipe.camera.position, dtype=np.float64)
    target = np.array(recipe.camera.target, dtype=np.float64)
    length = float(np.linalg.norm(target - start))
    steps = max(1, int(length / 0.05))
    for k in range(steps + 1):
        point = start + (target - start) * (k / steps)
        if not _inside(colliders, point, clearance):
            return (float(point[0]), float(point[1]), float(point[2]))
    return tuple(float(v) for v in target)  # type: ignore[return-value]
