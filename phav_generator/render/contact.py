"""Where the skinned surfaces meet the world: how deep any person's mesh goes into the
ground or a box prop, and how high a standing foot's sole is above the floor, per frame.

The ragdoll's capsules are what MuJoCo keeps out of the ground; this measures the mesh the
camera sees, posed exactly as the renderer poses it (same weights, same level of detail).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from phav_generator.body.model import lod_body, skin
from phav_generator.motion.rotations import quat_to_matrix, yaw_matrix
from phav_generator.motion.skeleton import BONE_INDEX, capsule_points
from phav_generator.physics.trajectory import Trajectory
from phav_generator.render.people import top_bones
from phav_generator.render.scene import humans_by_id
from phav_spec.recipe import Recipe
from phav_spec.scene import ENVIRONMENT_SCENES, walkable_heights

#: A foot stands when its ragdoll capsule rests on the support (its lowest point within this
#: of it) and it barely moves: then its mesh sole should be there too.
STANDING_GAP_M = 0.01
STANDING_SPEED_MPS = 0.1


@dataclass(frozen=True)
class Contact:
    """Per (person, frame): the deepest mesh point under the walkable surface or inside a
    box prop (m, ≥ 0), and each standing foot's sole height above the support (m)."""

    depth_m: np.ndarray  # (P, F)
    standing_sole_m: np.ndarray  # (n,) one value per standing foot and frame


def _local(points: np.ndarray, centre, yaw_deg: float) -> np.ndarray:
    """Points (n, 3) in the frame of a box at ``centre`` turned by ``yaw_deg`` about +Z."""
    return (points - np.asarray(centre)) @ yaw_matrix(np.deg2rad(yaw_deg))


def _support(env: str, boxes, points: np.ndarray) -> np.ndarray:
    """The walkable surface under each point: the environment's, or a stairs tread the
    plan built (the highest top at most 0.3 m above the point)."""
    out = walkable_heights(env, points[:, 0], points[:, 1], points[:, 2] + 0.3)
    for cls, centre, half, yaw in boxes:
        if cls != "stairs":
            continue
        local = _local(points, centre, yaw)
        top = centre[2] + half[2]
        over = (np.abs(local[:, 0]) <= half[0]) & (np.abs(local[:, 1]) <= half[1]) & (top <= points[:, 2] + 0.3)
        out = np.where(over, np.maximum(out, top), out)
    return out


def _inside_boxes(points: np.ndarray, boxes) -> np.ndarray:
    """How deep each point (n, 3) is inside the nearest box face (0 outside)."""
    depth = np.zeros(len(points))
    for cls, centre, half, yaw in boxes:
        if cls == "stairs":  # a tread is support (a foot on it is ``_support``'s business)
            continue
        local = _local(points, centre, yaw)
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
        bones, weights = top_bones(body.weights)
        owner = np.argmax(body.weights, axis=1)
        rot = quat_to_matrix(track.body_quat)
        depth = np.zeros(len(track.body_pos))
        matrices = body.skinning_matrices(track.body_pos, rot)  # (F, 15, 4, 4), all frames at once
        for f in range(len(track.body_pos)):
            v = skin(body.vertices, bones, weights, matrices[f])
            support = np.maximum(_support(env, trajectory.boxes, v), ground)
            into_props = float(_inside_boxes(v, trajectory.boxes).max(initial=0.0))
            depth[f] = max(0.0, float(np.max(support - v[:, 2])), into_props)
            caps = np.stack(capsule_points(body.dims, track.body_pos[f], rot[f]), axis=1)  # (15, 2, 3)
            for foot in ("left_foot", "right_foot"):
                k = BONE_INDEX[foot]
                low = caps[k, np.argmin(caps[k, :, 2])]
                capsule_gap = low[2] - body.dims.capsules[k].radius - _support(env, trajectory.boxes, low[None])[0]
                step = track.body_pos[min(f + 1, len(depth) - 1), k] - track.body_pos[f, k]
                speed = float(np.linalg.norm(step)) * recipe.video.fps
                if abs(capsule_gap) < STANDING_GAP_M and speed < STANDING_SPEED_MPS:
                    sole = owner == k
                    soles.append(float(np.min(v[sole, 2] - support[sole])))
        depths.append(depth)
    return Contact(np.array(depths), np.array(soles))


__all__ = ["Contact", "measure_contact"]
