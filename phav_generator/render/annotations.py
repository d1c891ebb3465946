"""Per-frame annotations: a rendered frame + its trajectory → the camera row and people rows
of the metadata contract.

Column meanings are ``phav_spec.metadata``'s. Boxes and visibility are measured on the
rendered frame itself (instance mask, linear depth), so metadata and pixels always agree:
that is why they belong to the render stage (``io`` only turns the rows into bytes).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from phav_generator.body.model import rest_body
from phav_generator.motion.rotations import quat_to_matrix
from phav_generator.motion.skeleton import DOF_BODY, JOINT_BODIES, PARENTS, BodyDims, capsule_points
from phav_generator.physics.trajectory import PersonTrack, Trajectory
from phav_generator.render.camera import project, view
from phav_generator.render.gl import Frame
from phav_generator.render.people import JOINT_SURFACES, visibility_reach
from phav_generator.render.scene import humans_by_id
from phav_spec.encoding import instance_rgb
from phav_spec.recipe import Recipe

#: A joint counts as visible when nothing at its pixel is in front of it, or when what is in
#: front is this person's surface around the joint (its class or a part meeting there,
#: ``render.people.JOINT_SURFACES``) no nearer than the joint's depth under the body's
#: surface (``render.people.visibility_reach``) plus this (m).
VISIBILITY_SLACK_M = 0.003


def _box3d(dims: BodyDims, pos: np.ndarray, quat: np.ndarray) -> np.ndarray:
    """8 world corners (8, 3) of the body's box aligned with the pelvis heading."""
    rot = quat_to_matrix(quat)
    a, b = capsule_points(dims, pos, rot)
    radius = np.array([c.radius for c in dims.capsules])
    forward = rot[0, :, 0]
    heading = np.arctan2(forward[1], forward[0])
    axes = np.array(
        [[np.cos(heading), np.sin(heading), 0.0], [-np.sin(heading), np.cos(heading), 0.0], [0.0, 0.0, 1.0]]
    )
    ends = np.concatenate([a, b]) @ axes.T  # (30, 3) in box coordinates
    r = np.concatenate([radius, radius])[:, None]
    lo, hi = (ends - r).min(axis=0), (ends + r).max(axis=0)
    corners = np.array([[(hi if k >> i & 1 else lo)[i] for i in range(3)] for k in range(8)])
    return corners @ axes


def _bbox2d(mask: np.ndarray) -> tuple[list[float], int]:
    rows = np.flatnonzero(mask.any(axis=1))
    if rows.size == 0:
        return [float("nan")] * 4, 0
    cols = np.flatnonzero(mask.any(axis=0))
    return [float(cols[0]), float(rows[0]), float(cols[-1] + 1), float(rows[-1] + 1)], int(mask.sum())


def _muscle_limits(track: PersonTrack) -> list[list[float]]:
    out: list[list[float]] = [[] for _ in range(len(PARENTS))]
    for j, body in enumerate(DOF_BODY):
        out[int(body)] += [float(track.lower[j]), float(track.upper[j])]
    return out


class MetadataBuilder:
    """Per-frame metadata rows of one video (person shapes resolved once)."""

    def __init__(self, recipe: Recipe, trajectory: Trajectory) -> None:
        self.recipe = recipe
        self.trajectory = trajectory
        humans = humans_by_id(recipe)
        self._people = [
            (track, humans[track.person_id], rest_body(humans[track.person_id].phenotype).dims)
            for track in trajectory.people
        ]
        self._radii = {track.person_id: visibility_reach(dims) for track, _, dims in self._people}
        self._limits = {track.person_id: _muscle_limits(track) for track, _, _ in self._people}

    def camera_row(self, f: int) -> dict[str, Any]:
        """Frame ``f``'s camera: time, intrinsics and pose."""
        tr = self.trajectory
        fx, fy, cx, cy = tr.intrinsics
        return {
            "video_id": self.recipe.video_id,
            "frame": f,
            "time_s": float(tr.times[f]),
            "fx": float(fx), "fy": float(fy), "cx": float(cx), "cy": float(cy),
            "cam_to_world": [float(x) for x in tr.cam_to_world[f].reshape(16)],
        }  # fmt: skip

    def people_rows(self, f: int, frame: Frame) -> list[dict[str, Any]]:
        """One row per person of frame ``f``: boxes, joints and visibility measured on ``frame``."""
        tr = self.trajectory
        height, width = frame.depth_m.shape
        world_to_cam = view(tr.cam_to_world[f])
        rows = []
        for track, human, dims in self._people:
            joints = track.body_pos[f][list(JOINT_BODIES)]  # (13, 3)
            uv = project(joints, tr.cam_to_world[f], tr.intrinsics)  # pixel-centre convention
            z = -(joints @ world_to_cam[:3, :3].T + world_to_cam[:3, 3])[:, 2]
            visible = np.zeros(len(joints), dtype=bool)
            inside = np.isfinite(uv).all(axis=1) & (uv[:, 0] >= 0) & (uv[:, 0] < width)
            inside &= (uv[:, 1] >= 0) & (uv[:, 1] < height)
            for j in np.flatnonzero(inside):
                v, u = int(uv[j, 1]), int(uv[j, 0])
                seen = frame.depth_m[v, u]
                if seen >= z[j]:  # nothing in front of the joint
                    visible[j] = True
                    continue
                on_it = frame.instance[v, u] == track.person_id + 1 and frame.class_id[v, u] in JOINT_SURFACES[j]
                visible[j] = on_it and seen >= z[j] - self._radii[track.person_id][j] - VISIBILITY_SLACK_M
            bbox, pixels = _bbox2d(frame.instance == track.person_id + 1)
            pin = [0.0] * len(PARENTS)
            pin[0] = float(track.pin[f])
            rows.append({
                "video_id": self.recipe.video_id,
                "frame": f,
                "person_id": track.person_id,
                "instance_rgb": list(instance_rgb(track.person_id)),
                "role": track.role,
                "human_model": human.model,
                "pixels": pixels,
                "bbox2d": bbox,
                "bbox3d": [float(x) for x in _box3d(dims, track.body_pos[f], track.body_quat[f]).reshape(24)],
                "joints3d": [float(x) for x in joints.reshape(39)],
                "joints2d": [float(x) for x in uv.reshape(26)],
                "visible": [bool(v) for v in visible],
                "muscle_strength": [float(x) for x in track.strengths[f]],
                "muscle_limits": self._limits[track.person_id],
                "pin_weight": pin,
                "penetration_m": float(track.penetration_m[f]),
                "joint_limit_excess": float(track.limit_excess_rad[f]),
            })  # fmt: skip
        return rows
