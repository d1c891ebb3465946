"""Where the skinned surfaces meet the world: how deep any person's mesh goes into the
ground or a box prop, and how high a standing foot's sole is above the floor, per frame.

The ragdoll's capsules are what MuJoCo keeps out of the ground; this measures the mesh the
camera sees, posed exactly as the renderer poses it (same weights, same level of detail).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from phav_generator.body.model import lod_body, skin
from phav_generator.motion.rotations import quat_to_matrix
from phav_generator.motion.skeleton import BONE_INDEX
from phav_generator.physics.trajectory import Trajectory
from phav_generator.render.people import _top_bones
from phav_generator.render.scene import humans_by_id
from phav_spec.recipe import Recipe
from phav_spec.scene import ENVIRONMENT_SCENES, walkable_heights

#: A foot stands when its lowest mesh point is this close to the support and it barely moves.
STANDING_GAP_M = 0.05
STANDING_SPEED_MPS = 0.1


@dataclass(frozen=True)
class Contact:
    """Per (person, frame): the deepest mesh point under the walkable surface or inside a
    box prop (m, ≥ 0), and each standing foot's sole height above the support (m)."""

    depth_m: np.ndarray  # (P, F)
    standing_sole_m: np.ndarray  # (n,) one value per standing foot and frame


def _inside_boxes(points: np.ndarray, boxes) -> np.ndarray:
    """How deep each point (n, 3) is inside the nearest box face (0 outside)."""
    depth = np.zeros(len(points))
    for _, centre, half, yaw in boxes:
        c, s = np.cos(np.deg2rad(yaw)), np.sin(np.deg2rad(yaw))
        d = points - np.asarray(centre)
        local = np.stack([c * d[:, 0] + s * d[:, 1], -s * d[:, 0] + c * d[:, 1], d[:, 2]], axis=1)
        inside = np.min(np.asarray(half) - np.abs(local), axis=1)
        depth = np.maximum(depth, inside)
    return depth


def measure_contact(recipe: Recipe, trajectory: Trajectory, *, level: int = 1) -> Contact:
    """Mesh depth into the ground and box props, and standing soles' heights, of every
    simulated person of a video."""
    env = recipe.environment.name
    ground = ENVIRONMENT_SCENES[env].ground_z
    humans = humans_by_id(recipe)
    depths, soles = [], []
    for track in trajectory.people:
        body = lod_body(humans[track.person_id].phenotype, level)
        bones, weights = _top_bones(body.weights)
        owner = np.argmax(body.weights, axis=1)
        rot = quat_to_matrix(track.body_quat)
        depth = np.zeros(len(track.body_pos))
        for f in range(len(track.body_pos)):
            v = skin(body.vertices, bones, weights, body.skinning_matrices(track.body_pos[f], rot[f]))
            support = walkable_heights(env, v[:, 0], v[:, 1], v[:, 2] + 0.3)
            support = np.maximum(support, ground)
            into_props = float(_inside_boxes(v, trajectory.boxes).max(initial=0.0))
            depth[f] = max(0.0, float(np.max(support - v[:, 2])), into_props)
            for foot in ("left_foot", "right_foot"):
                k = BONE_INDEX[foot]
                sole = v[owner == k]
                gap = float(np.min(sole[:, 2] - support[owner == k]))
                step = track.body_pos[min(f + 1, len(depth) - 1), k] - track.body_pos[f, k]
                speed = float(np.linalg.norm(step)) * recipe.video.fps
                if gap < STANDING_GAP_M and speed < STANDING_SPEED_MPS:
                    soles.append(gap)
        depths.append(depth)
    return Contact(np.array(depths), np.array(soles))


__all__ = ["Contact", "measure_contact"]
