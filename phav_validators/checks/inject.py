"""Physics failure cases injected into a clean video's poses and cameras, to measure what
the failures check catches (docs/measure/false_alarms.py, tests). Each injection copies the
series it changes; the recipe is never touched.

- wall: the protagonist's path bent so that the hips end at the centre of the nearest
  collision box at least 1 m tall (scenes without one: not applicable);
- knee: both knees put 15 cm behind the middle of the hip–ankle line in every frame;
- nan: one joint of the middle frame set to NaN;
- explosion: every joint of the middle frame thrown 1.5 m (45 m/s at 30 fps);
- off-screen: the camera turned 180° about the vertical in every frame;
- camera-inside: the camera moved into the nearest box's centre (else 50 cm under the
  ground) for the middle third of the clip;
- perturbation: (random-perturbation videos) the necessary muscles' joints other than the
  hips moved 40 cm;
- sliding: the whole body drifting sideways at 1.5 m/s, planted feet included.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from phav_spec.metadata import JOINT_ORDER
from phav_spec.recipe import Recipe
from phav_spec.scene import ENVIRONMENT_SCENES
from phav_validators.checks.failures import CameraSeries, PersonSeries, boxes, necessary_joints
from phav_validators.findings import Reason

#: Each injection and the reason the failures check should give it.
INJECTIONS: dict[str, Reason] = {
    "wall": Reason.INTERPENETRATION,
    "knee": Reason.JOINT_LIMIT,
    "nan": Reason.NAN_POSE,
    "explosion": Reason.ENERGY_EXPLOSION,
    "off-screen": Reason.OFF_SCREEN,
    "camera-inside": Reason.CAMERA_IN_GEOMETRY,
    "perturbation": Reason.PERTURBATION_TOO_STRONG,
    "sliding": Reason.FOOT_SLIDING,
}
_J = {name: i for i, name in enumerate(JOINT_ORDER)}


def _nearest_box(env: str, point: np.ndarray) -> np.ndarray | None:
    box = boxes(env)
    solid = [i for i, c in enumerate(box.colliders) if not c.hulls]  # solid to its centre
    tall = [i for i in solid if 2 * box.half[i, 2] >= 1.0 and min(box.half[i, :2]) >= 0.3]
    if not tall:
        return None
    d = np.linalg.norm(box.center[tall, :2] - point[:2], axis=1)
    return box.center[tall[int(np.argmin(d))]]


def inject(
    kind: str, recipe: Recipe, people: list[PersonSeries], cams: CameraSeries
) -> tuple[list[PersonSeries], CameraSeries] | None:
    """A copy of (people, cams) with failure ``kind`` injected, None where not applicable."""
    if kind not in INJECTIONS:
        raise ValueError(f"unknown injection {kind!r}; choose from {', '.join(INJECTIONS)}")
    pid = recipe.protagonist.person_id
    people = [dataclasses.replace(p, joints=p.joints.copy()) for p in people]
    cams = dataclasses.replace(cams, poses=cams.poses.copy())
    me = next(p for p in people if p.person_id == pid)
    j = me.joints
    t = len(j)
    mid = t // 2
    hips = 0.5 * (j[:, _J["left_hip"]] + j[:, _J["right_hip"]])
    env = recipe.environment.name
    if kind == "wall":
        centre = _nearest_box(env, hips[0])
        if centre is None:
            return None
        ramp = np.linspace(0.0, 1.0, t)[:, None]
        j += (ramp * (centre - hips[-1]))[:, None, :]
    elif kind == "knee":
        up = j[:, _J["neck"]] - hips
        right = j[:, _J["right_hip"]] - j[:, _J["left_hip"]]
        forward = np.cross(up, right)
        forward /= np.linalg.norm(forward, axis=-1, keepdims=True)
        for side in ("left", "right"):
            hip, ankle = j[:, _J[f"{side}_hip"]], j[:, _J[f"{side}_ankle"]]
            axis = (ankle - hip) / np.linalg.norm(ankle - hip, axis=-1, keepdims=True)
            back = forward - np.sum(forward * axis, axis=-1, keepdims=True) * axis
            back /= np.linalg.norm(back, axis=-1, keepdims=True)
            j[:, _J[f"{side}_knee"]] = 0.5 * (hip + ankle) - 0.15 * back  # bent backwards
    elif kind == "nan":
        j[mid, _J["left_wrist"]] = np.nan
    elif kind == "explosion":
        j[mid] += np.array([1.5, 0.0, 0.0])
    elif kind == "off-screen":
        turn = np.diag([-1.0, -1.0, 1.0])  # 180° about world z, about the camera's own position
        cams.poses[:, :3, :3] = turn @ cams.poses[:, :3, :3]
    elif kind == "camera-inside":
        third = slice(len(cams.poses) // 3, 2 * len(cams.poses) // 3)
        centre = _nearest_box(env, cams.poses[len(cams.poses) // 2, :3, 3])
        if centre is None:
            centre = cams.poses[third, :3, 3].copy()
            centre[:, 2] = ENVIRONMENT_SCENES[env].ground_z - 0.5
        cams.poses[third, :3, 3] = centre
    elif kind == "perturbation":
        if recipe.variation.kind != "random_perturbation":
            return None
        # Relative to the pelvis (as the check measures): the hips themselves stay.
        moved = [i for i in necessary_joints(recipe.action) if i not in (_J["left_hip"], _J["right_hip"])]
        if not moved:
            return None
        j[:, moved] += np.array([0.4, 0.0, 0.0])
    elif kind == "sliding":
        j += (np.arange(t) / recipe.video.fps * 1.5)[:, None, None] * np.array([1.0, 0.0, 0.0])
    return people, cams
