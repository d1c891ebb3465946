"""The reference person the motion library is written for, and the lengths IK reads off it.

Motions are authored in the motion frame for one body, ``body_dims(1.75, 70, 0.40, 0.34,
1.0)``; playback scales them to each recipe's human by leg length (``animation.place``). The
gait generator, the IK solvers and the postures read their segment lengths, joint positions
and foot geometry here, so they all agree with the skeleton's proportions.
"""

from __future__ import annotations

import numpy as np

from phav_generator.motion.skeleton import BONE_INDEX, DOF_INDEX, LOWER, UPPER, body_dims

#: Height of the person the motion library is written for; motions scale with height.
REFERENCE_HEIGHT_M = 1.75

REF_BODY = body_dims(REFERENCE_HEIGHT_M, 70.0, 0.40, 0.34, 1.0)
_OFF = REF_BODY.offsets
PELVIS_H = REF_BODY.standing_pelvis_height
THIGH = float(-_OFF[BONE_INDEX["left_lower_leg"], 2])
SHIN = float(-_OFF[BONE_INDEX["left_foot"], 2])
ANKLE_H = REF_BODY.sole_height
HIP_Y = float(_OFF[BONE_INDEX["left_upper_leg"], 1])
CHEST_Z = float(_OFF[BONE_INDEX["chest"], 2])
SHOULDER = _OFF[BONE_INDEX["left_upper_arm"]].copy()  # left shoulder in the chest frame
UPPER_ARM = float(-_OFF[BONE_INDEX["left_lower_arm"], 2])
FOREARM = float(-_OFF[BONE_INDEX["left_hand"], 2])
_FOOT = REF_BODY.capsules[BONE_INDEX["left_foot"]]
TOE = np.array([_FOOT.b[0], _FOOT.b[2]])  # toe sphere centre (x, z) in the foot frame
HEEL = np.array([_FOOT.a[0], _FOOT.a[2]])
LEG = THIGH + SHIN
#: Capsule radius of every body (15,).
RADII = np.array([c.radius for c in REF_BODY.capsules])
#: (flex lower, flex upper, abduction lower, abduction upper) of the hip, radians.
HIP_LIMITS = tuple(
    float(v)
    for v in (
        LOWER[DOF_INDEX["left_hip_flex"]],
        UPPER[DOF_INDEX["left_hip_flex"]],
        LOWER[DOF_INDEX["left_hip_abd"]],
        UPPER[DOF_INDEX["left_hip_abd"]],
    )
)
#: (flex lower, flex upper, abduction lower, abduction upper) of the shoulder, radians.
SHOULDER_LIMITS = tuple(
    float(v)
    for v in (
        LOWER[DOF_INDEX["left_shoulder_flex"]],
        UPPER[DOF_INDEX["left_shoulder_flex"]],
        LOWER[DOF_INDEX["left_shoulder_abd"]],
        UPPER[DOF_INDEX["left_shoulder_abd"]],
    )
)
#: Body indices of the left arm (upper, lower, hand), then the right arm.
ARM_BODIES = [BONE_INDEX[f"{s}_{b}"] for s in ("left", "right") for b in ("upper_arm", "lower_arm", "hand")]
