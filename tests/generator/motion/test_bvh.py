"""BVH import/export: round trip through our own exporter, a hand-written CMU-style take,
parse errors as one-line PhavUserErrors, and an imported clip played as a registered motion."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from phav_generator.motion import bvh
from phav_generator.motion.animation import MotionParams, Pose, place, play
from phav_generator.motion.library import get_motion, register_motion, unregister_motion, user_motions
from phav_generator.motion.rotations import euler_zyx_matrix, matrix_to_quat, quat_to_matrix
from phav_generator.motion.skeleton import (
    BONE_INDEX,
    DOF_INDEX,
    DOFS,
    LOWER,
    N_DOFS,
    UPPER,
    body_dims,
    forward_kinematics,
    joints_from_bodies,
)
from phav_spec.errors import PhavUserError

# --------------------------------------------------------------------------------------
# Round trip through export_bvh


def _procedural_pose(n: int = 90, fps: float = 30.0) -> Pose:
    """All 30 DOFs sinusoidal within limits, root moving and turning; frame 0 faces +X.

    The middle hinge of 3-hinge joints stays below 90° (shoulder and hip abduction) so each
    rotation has one Euler decomposition within the limits: the angles are well defined.
    """
    t = np.arange(n) / fps
    lo, hi = LOWER.copy(), UPPER.copy()
    for name, (a, b) in {
        "left_shoulder_abd": (-35, 75),
        "right_shoulder_abd": (-35, 75),
        "left_hip_abd": (-30, 75),
        "right_hip_abd": (-30, 75),
    }.items():
        lo[DOF_INDEX[name]], hi[DOF_INDEX[name]] = math.radians(a), math.radians(b)
    mid, amp = (lo + hi) / 2, 0.45 * (hi - lo)
    k = np.arange(N_DOFS)
    q = mid + amp * np.sin(2 * np.pi * 0.4 * (1 + 0.13 * k) * t[:, None] + 0.7 * k)
    # Yaw and roll start at 0 so the hips' line faces +Y at frame 0 (the importer's convention).
    rot = euler_zyx_matrix(1.3 * t, 0.25 * np.sin(2.0 * t) + 0.1, 0.2 * np.sin(3.0 * t))
    root = np.stack([0.6 * t, 0.25 * np.sin(t), -0.08 * np.sin(2.0 * t)], axis=-1)
    return Pose(root, matrix_to_quat(rot), q)


def _joints(dims, pose: Pose) -> np.ndarray:
    return joints_from_bodies(forward_kinematics(dims, pose.root_pos, pose.root_quat, pose.q)[0])


@pytest.mark.parametrize("height", [1.75, 1.58])
def test_export_import_round_trip(height):
    dims = body_dims(height, 62.0, 0.38, 0.31, 1.0)
    motion_pose = _procedural_pose()
    world = place(motion_pose, dims, (0.0, 0.0, 0.0), 0.0)
    text = bvh.export_bvh(world, dims, fps=30.0)
    clip = bvh.parse_bvh(text, source="round_trip.bvh")
    assert clip.n_frames == len(world) and clip.frame_time == pytest.approx(1 / 30, rel=1e-6)

    result = bvh.retarget(clip)
    back = place(result.pose, dims, (0.0, 0.0, 0.0), 0.0)
    joint_err = float(np.abs(_joints(dims, back) - _joints(dims, world)).max())
    angle_err = np.degrees(np.abs(result.pose.q - motion_pose.q)).max(axis=0)
    print(f"round trip h={height}: max joint error {joint_err * 1000:.4f} mm, max angle error {angle_err.max():.2e}°")
    assert joint_err < 0.01
    worst = {d.name: float(e) for d, e in zip(DOFS, angle_err, strict=True) if e > 0.01}
    assert not worst, worst
    np.testing.assert_allclose(result.pose.root_pos, motion_pose.root_pos, atol=1e-5)
    assert result.clipped_fraction == 0.0
    # The 30 fps resampling of a 30 fps clip returns the same frames.
    assert len(result.pose_30fps) == len(result.pose)
    np.testing.assert_allclose(result.pose_30fps.q, result.pose.q, atol=1e-5)


def test_export_writes_documented_channels():
    dims = body_dims(1.75, 70.0, 0.40, 0.30, 1.0)
    text = bvh.export_bvh(place(_procedural_pose(3), dims, (0, 0, 0), 0), dims, fps=24)
    lines = text.splitlines()
    assert lines[0] == "HIERARCHY" and lines[1] == "ROOT pelvis"
    assert "CHANNELS 6 Xposition Yposition Zposition Zrotation Yrotation Xrotation" in text
    assert text.count("CHANNELS 3 Zrotation Yrotation Xrotation") == 14
    assert "Frames: 3" in text and "Frame Time: 0.04166667" in text
    clip = bvh.parse_bvh(text, source="x.bvh")
    assert clip.frames.shape == (3, 6 + 14 * 3)
    # Y up: the pelvis sits at its standing height along BVH +Y at rest.
    first = clip.frames[0]
    assert first[1] == pytest.approx(dims.standing_pelvis_height - 0.08 * math.sin(0.0), abs=1e-6)


def test_channel_order_is_honoured():
    """Rotations are intrinsic in channel order: R = R_c1 · R_c2 · R_c3 (here X, Y, Z)."""
    text = _minimal_bvh(
        channels="Xposition Yposition Zposition Xrotation Yrotation Zrotation",
        frames=["1 2 3 30 40 50 0 0 0", "0 0 0 -20 75 10 0 0 0"],
    )
    clip = bvh.parse_bvh(text, source="order.bvh")
    pos, rot = bvh.bvh_forward_kinematics(clip)
    for f, (a, b, c) in enumerate([(30, 40, 50), (-20, 75, 10)]):
        expected = Rotation.from_euler("XYZ", [a, b, c], degrees=True).as_matrix()
        np.testing.assert_allclose(rot[f, 0], expected, atol=1e-12)
        np.testing.assert_allclose(pos[f, 1], pos[f, 0] + expected @ np.array([0.0, 10.0, 0.0]), atol=1e-12)
    np.testing.assert_allclose(pos[0, 0], [1, 2, 3])


def _other_exporter_bvh(pose: Pose, dims, fps: float) -> str:
    """Our animated skeleton written as another exporter would: joints Hips, Spine, Chest, Neck,
    Head, LeftShoulder (clavicle), LeftArm …, an A-pose rest (arms 45° out, legs splayed 10°),
    Y up with the person facing −Z, ``Xrotation Yrotation Zrotation`` channels. Every joint
    sits on one of our bodies, so its positions are ours while its rotations differ."""
    h = dims.height_m
    off = {b: dims.offsets[BONE_INDEX[b]] for b in BONE_INDEX}
    eye = np.eye(3)
    rows = [  # (joint, parent, our body it rides on, point in that body's frame, rest rotation)
        ("Hips", None, "pelvis", np.zeros(3), eye),
        ("Spine", "Hips", "chest", np.zeros(3), eye),
        ("Chest", "Spine", "chest", 0.5 * off["head"], eye),
        ("Neck", "Chest", "chest", off["head"], eye),
        ("Head", "Neck", "head", np.zeros(3), eye),
        ("Head/End", "Head", "head", np.array([0.0, 0.0, 0.12 * h]), eye),
    ]
    for side, sign in (("Left", 1.0), ("Right", -1.0)):
        s = side.lower()
        arm, leg = _rot("X", sign * 45.0), _rot("X", sign * 10.0)
        rows += [
            (f"{side}Shoulder", "Chest", "chest", off[f"{s}_upper_arm"] * [1.0, 0.4, 0.95], eye),
            (f"{side}Arm", f"{side}Shoulder", f"{s}_upper_arm", np.zeros(3), arm),
            (f"{side}ForeArm", f"{side}Arm", f"{s}_lower_arm", np.zeros(3), arm),
            (f"{side}Hand", f"{side}ForeArm", f"{s}_hand", np.zeros(3), arm),
            (f"{side}Hand/End", f"{side}Hand", f"{s}_hand", np.array([0.0, 0.0, -0.08 * h]), arm),
            (f"{side}UpLeg", "Hips", f"{s}_upper_leg", np.zeros(3), leg),
            (f"{side}Leg", f"{side}UpLeg", f"{s}_lower_leg", np.zeros(3), leg),
            (f"{side}Foot", f"{side}Leg", f"{s}_foot", np.zeros(3), leg),
            (f"{side}Foot/End", f"{side}Foot", f"{s}_foot", np.array([0.1 * h, 0.0, -0.02 * h]), leg),
        ]
    spec = {r[0]: r for r in rows}
    body_pos, body_rot = forward_kinematics(dims, pose.root_pos, pose.root_quat, pose.q)
    k = np.array([[0.0, -1.0, 0.0], [0.0, 0.0, 1.0], [-1.0, 0.0, 0.0]])  # ours → file: X→−Z, Y→−X, Z→Y
    out, channels = ["HIERARCHY"], []

    def write(name: str, depth: int) -> None:
        _, parent, body, point, _ = spec[name]
        pad = "  " * depth
        if parent is None:
            offset = np.zeros(3)
        else:
            _, _, p_body, p_point, p_rest = spec[parent]
            here = point if body == p_body else off[body]  # this joint in the parent body's frame
            offset = k @ p_rest @ (here - p_point)
        end = name.endswith("/End")
        out.extend([pad + ("End Site" if end else ("ROOT " if parent is None else "JOINT ") + name), pad + "{"])
        out.append(pad + "  OFFSET " + " ".join(f"{v:.9f}" for v in offset))
        if not end:
            pos = "Xposition Yposition Zposition " if parent is None else ""
            out.append(f"{pad}  CHANNELS {6 if parent is None else 3} {pos}Xrotation Yrotation Zrotation")
            channels.append(name)
        for child in (r[0] for r in rows if r[1] == name):
            write(child, depth + 1)
        out.append(pad + "}")

    write("Hips", 0)
    glob = {n: body_rot[:, BONE_INDEX[b]] @ c.T for n, _, b, _, c in rows}  # G = W · C^T
    values = [body_pos[:, 0] @ k.T]
    for name in channels:
        parent = spec[name][1]
        local = glob[name] if parent is None else np.swapaxes(glob[parent], -1, -2) @ glob[name]
        values.append(Rotation.from_matrix(k @ local @ k.T).as_euler("XYZ", degrees=True))
    frames = np.concatenate(values, axis=1)
    out += ["MOTION", f"Frames: {len(frames)}", f"Frame Time: {1 / fps:.9f}"]
    out += [" ".join(f"{v:.9f}" for v in row) for row in frames]
    return "\n".join(out) + "\n"


def test_other_exporter_with_a_pose_rest_retargets_exactly():
    """Position-based retargeting ignores how the file's rest pose and axes are set up."""
    dims = body_dims(1.75, 70.0, 0.40, 0.30, 1.0)
    motion_pose = _procedural_pose(60)
    world = place(motion_pose, dims, (0.0, 0.0, 0.0), 0.0)
    clip = bvh.parse_bvh(_other_exporter_bvh(world, dims, 30.0), source="a_pose.bvh")
    assert clip.channels[0] == ("Xposition", "Yposition", "Zposition", "Xrotation", "Yrotation", "Zrotation")
    result = bvh.retarget(clip)
    angle_err = np.degrees(np.abs(result.pose.q - motion_pose.q)).max(axis=0)
    worst = {d.name: float(e) for d, e in zip(DOFS, angle_err, strict=True) if e > 0.01}
    assert not worst, worst
    joint_err = np.abs(_joints(dims, place(result.pose, dims, (0, 0, 0), 0)) - _joints(dims, world)).max()
    assert joint_err < 1e-4


# --------------------------------------------------------------------------------------
# A hand-written CMU-style take (Y up, CMU joint names, T-pose rest with splayed legs)

# (name, parent, offset) of the CMU BVH conversions' skeleton; End Sites as "<joint>/End".
_CMU = (
    ("Hips", None, (0, 0, 0)),
    ("LHipJoint", "Hips", (0, 0, 0)),
    ("LeftUpLeg", "LHipJoint", (1.36306, -1.79463, 0.83929)),
    ("LeftLeg", "LeftUpLeg", (2.44811, -6.72613, 0)),
    ("LeftFoot", "LeftLeg", (2.5622, -7.03959, 0)),
    ("LeftToeBase", "LeftFoot", (0.15764, -0.43311, 2.32255)),
    ("LeftToeBase/End", "LeftToeBase", (0, 0, 1.18966)),
    ("RHipJoint", "Hips", (0, 0, 0)),
    ("RightUpLeg", "RHipJoint", (-1.30552, -1.79463, 0.83929)),
    ("RightLeg", "RightUpLeg", (-2.54253, -6.98555, 0)),
    ("RightFoot", "RightLeg", (-2.56826, -7.05623, 0)),
    ("RightToeBase", "RightFoot", (-0.16473, -0.45259, 2.36315)),
    ("RightToeBase/End", "RightToeBase", (0, 0, 1.21781)),
    ("LowerBack", "Hips", (0, 0, 0)),
    ("Spine", "LowerBack", (0.02827, 2.03559, -0.19338)),
    ("Spine1", "Spine", (0.05672, 2.04885, -0.04275)),
    ("Neck", "Spine1", (0, 0, 0)),
    ("Neck1", "Neck", (-0.05417, 1.74624, 0.17202)),
    ("Head", "Neck1", (0.10407, 1.76136, -0.12397)),
    ("Head/End", "Head", (0, 0, 0)),
    ("LeftShoulder", "Spine1", (0, 0, 0)),
    ("LeftArm", "LeftShoulder", (3.36241, 1.20089, -0.31121)),
    ("LeftForeArm", "LeftArm", (4.983, 0, 0)),
    ("LeftHand", "LeftForeArm", (3.48356, 0, 0)),
    ("LeftFingerBase", "LeftHand", (0.71526, 0, 0)),
    ("LeftHandIndex1", "LeftFingerBase", (0.57666, 0, 0)),
    ("LeftHandIndex1/End", "LeftHandIndex1", (0.46495, 0, 0)),
    ("LThumb", "LeftHand", (0.58529, 0, 0.58529)),
    ("LThumb/End", "LThumb", (0.47163, 0, 0.47163)),
    ("RightShoulder", "Spine1", (0, 0, 0)),
    ("RightArm", "RightShoulder", (-3.1366, 1.37405, -0.40465)),
    ("RightForeArm", "RightArm", (-5.24946, 0, 0)),
    ("RightHand", "RightForeArm", (-3.44987, 0, 0)),
    ("RightFingerBase", "RightHand", (-0.66654, 0, 0)),
    ("RightHandIndex1", "RightFingerBase", (-0.53737, 0, 0)),
    ("RightHandIndex1/End", "RightHandIndex1", (-0.43325, 0, 0)),
    ("RThumb", "RightHand", (-0.54541, 0, 0.54541)),
    ("RThumb/End", "RThumb", (-0.4395, 0, 0.4395)),
)
# CMU's Head End Site is straight above the skull joint.
_CMU = tuple((n, p, (0, 1.7, 0.05) if n == "Head/End" else o) for n, p, o in _CMU)
_CMU_JOINTS = tuple(n for n, _, _ in _CMU if not n.endswith("/End"))


def _cmu_hierarchy() -> str:
    out = ["HIERARCHY"]

    def write(name: str, depth: int) -> None:
        pad = "  " * depth
        parent, offset = next((p, o) for n, p, o in _CMU if n == name)
        end = name.endswith("/End")
        head = "End Site" if end else ("ROOT " if parent is None else "JOINT ") + name
        out.extend([pad + head, pad + "{", pad + "  OFFSET " + " ".join(f"{v:.5f}" for v in offset)])
        if not end:
            pos = "Xposition Yposition Zposition " if parent is None else ""
            out.append(f"{pad}  CHANNELS {6 if parent is None else 3} {pos}Zrotation Yrotation Xrotation")
        for child, p, _ in _CMU:
            if p == name:
                write(child, depth + 1)
        out.append(pad + "}")

    write("Hips", 0)
    return "\n".join(out)


def _rot(axis: str, degrees: float) -> np.ndarray:
    return Rotation.from_euler(axis, degrees, degrees=True).as_matrix()


def _about(axis, degrees: float) -> np.ndarray:
    axis = np.asarray(axis, dtype=float)
    return Rotation.from_rotvec(np.radians(degrees) * axis / np.linalg.norm(axis)).as_matrix()


def _cmu_leg_length() -> float:
    off = {n: np.array(o, dtype=float) for n, _, o in _CMU}
    left = np.linalg.norm(off["LeftLeg"]) + np.linalg.norm(off["LeftFoot"])
    right = np.linalg.norm(off["RightLeg"]) + np.linalg.norm(off["RightFoot"])
    return (left + right) / 2


def _cmu_take(arm_deg: list[float], knee_deg: list[float], heading_deg: float = 0.0, shift=(0.0, 0.0)) -> str:
    """Frames standing upright (legs straightened, arms down), the right arm raised forward
    by ``arm_deg`` and the left knee bent by ``knee_deg``; the whole take turned about +Y."""
    off = {n: np.array(o, dtype=float) for n, _, o in _CMU}
    # Standing hip-joint height for our proportions: leg · (standing pelvis / leg length).
    ref = body_dims(1.75, 70, 0.4, 0.3, 1.0)
    ref_leg = -ref.offsets[BONE_INDEX["left_lower_leg"], 2] - ref.offsets[BONE_INDEX["left_foot"], 2]
    hip_y = -off["LeftUpLeg"][1] + _cmu_leg_length() * ref.standing_pelvis_height / ref_leg
    turn = _rot("Y", heading_deg)
    rows = []
    for arm, knee in zip(arm_deg, knee_deg, strict=True):
        local = {n: np.eye(3) for n in _CMU_JOINTS}
        local["Hips"] = turn
        for side, sign in (("Left", 1.0), ("Right", -1.0)):
            thigh = off[f"{side}Leg"] / np.linalg.norm(off[f"{side}Leg"])
            tilt = math.degrees(math.atan2(abs(thigh[0]), -thigh[1]))
            local[f"{side}UpLeg"] = _rot("Z", -sign * tilt)  # straighten the splayed rest legs
            local[f"{side}Arm"] = _rot("Z", -sign * 90.0)  # T-pose → arms hanging
        # Knee: about the thigh's lateral axis (⊥ to the splayed thigh, in its X-Y plane).
        thigh = off["LeftLeg"] / np.linalg.norm(off["LeftLeg"])
        local["LeftLeg"] = _about([-thigh[1], thigh[0], 0.0], knee)
        local["RightArm"] = _rot("X", -arm) @ _rot("Z", 90.0)
        root = turn @ np.array([0.0, hip_y, 0.0]) + np.array([shift[0], 0.0, shift[1]])
        values = list(root)
        with warnings.catch_warnings():  # a 90° arm raise is a gimbal lock of Z·Y·X: still exact
            warnings.simplefilter("ignore", UserWarning)
            for name in _CMU_JOINTS:
                values += list(Rotation.from_matrix(local[name]).as_euler("ZYX", degrees=True))
        rows.append(" ".join(f"{v:.6f}" for v in values))
    return _cmu_hierarchy() + f"\nMOTION\nFrames: {len(rows)}\nFrame Time: 0.0083333\n" + "\n".join(rows) + "\n"


ARM = [0.0, 30.0, 60.0, 90.0, 120.0]
KNEE = [0.0, 20.0, 45.0, 70.0, 30.0]


def test_cmu_style_take_retargets():
    clip = bvh.parse_bvh(_cmu_take(ARM, KNEE), source="cmu_style.bvh")
    result = bvh.retarget(clip)
    q = np.degrees(result.pose.q)
    flex = q[:, DOF_INDEX["right_shoulder_flex"]]
    print("right_shoulder_flex", flex.round(3), "left_knee_flex", q[:, DOF_INDEX["left_knee_flex"]].round(3))
    np.testing.assert_allclose(flex, ARM, atol=0.5)
    np.testing.assert_allclose(q[:, DOF_INDEX["right_shoulder_abd"]], 0.0, atol=1.0)
    np.testing.assert_allclose(q[:, DOF_INDEX["left_knee_flex"]], KNEE, atol=0.5)
    assert np.all(q[1:, DOF_INDEX["left_knee_flex"]] > 10.0)
    # Standing frame: everything near neutral (legs straightened, arms down).
    np.testing.assert_allclose(q[0], 0.0, atol=1.5)
    # Faces +X at frame 0, pelvis at the standing height, root at the origin.
    np.testing.assert_allclose(quat_to_matrix(result.pose.root_quat[0]), np.eye(3), atol=1e-6)
    np.testing.assert_allclose(result.pose.root_pos[0], 0.0, atol=0.005)
    # Raised right hand: in front of the body (+X) and, at 120°, above the shoulder.
    dims = body_dims(1.75, 70, 0.4, 0.3, 1.0)
    placed = place(result.pose, dims, (0, 0, 0), 0)
    body_pos, body_rot = forward_kinematics(dims, placed.root_pos, placed.root_quat, placed.q)
    wrist = body_pos[:, BONE_INDEX["right_hand"]]
    shoulder = body_pos[:, BONE_INDEX["right_upper_arm"]]
    assert wrist[3, 0] - shoulder[3, 0] > 0.4 and abs(wrist[3, 2] - shoulder[3, 2]) < 0.05
    assert wrist[4, 2] > shoulder[4, 2] + 0.2
    # The toes point forward.
    assert body_rot[0, BONE_INDEX["left_foot"], 0, 0] > 0.95
    # 8.3 ms frames: the 41.7 ms take resamples to 30 fps at 0 and 33.3 ms.
    assert result.length_s == pytest.approx(5 * 0.0083333)
    assert len(result.times_30fps) == 2 and len(result.pose_30fps) == 2


def test_facing_is_detected_from_the_hips():
    """The same take turned and moved in the file retargets to the same motion-frame pose."""
    plain = bvh.retarget(bvh.parse_bvh(_cmu_take(ARM, KNEE), source="a.bvh")).pose
    turned = bvh.retarget(bvh.parse_bvh(_cmu_take(ARM, KNEE, 137.0, (40.0, -12.0)), source="b.bvh")).pose
    np.testing.assert_allclose(turned.q, plain.q, atol=1e-6)
    np.testing.assert_allclose(turned.root_pos, plain.root_pos, atol=1e-6)
    np.testing.assert_allclose(quat_to_matrix(turned.root_quat), quat_to_matrix(plain.root_quat), atol=1e-6)


def test_user_mapping_and_missing_joints():
    text = _cmu_take(ARM[:2], KNEE[:2]).replace("LeftForeArm", "L_Elbow_J")
    with pytest.raises(PhavUserError) as info:
        bvh.retarget(bvh.parse_bvh(text, source="renamed.bvh"))
    assert str(info.value).startswith("renamed.bvh: mapping: no joint found for left_lower_arm")
    result = bvh.retarget(bvh.parse_bvh(text, source="renamed.bvh"), mapping={"left_lower_arm": "L_Elbow_J"})
    assert result.pose.q.shape == (2, N_DOFS)
    with pytest.raises(PhavUserError, match="'Nope' mapped to head is not in the file"):
        bvh.retarget(bvh.parse_bvh(text, source="renamed.bvh"), mapping={"head": "Nope"})
    with pytest.raises(PhavUserError, match="up axis must be"):
        bvh.retarget(bvh.parse_bvh(_cmu_take(ARM[:1], KNEE[:1]), source="c.bvh"), up="w")


# --------------------------------------------------------------------------------------
# Parse errors


def _minimal_bvh(channels: str = "Xposition Yposition Zposition Zrotation Yrotation Xrotation", frames=None) -> str:
    frames = frames or ["0 90 0 0 0 0 0 0 0", "1 90 0 0 10 0 0 5 0"]
    return (
        "HIERARCHY\n"
        "ROOT Hips\n"
        "{\n"
        "  OFFSET 0 0 0\n"
        f"  CHANNELS 6 {channels}\n"
        "  JOINT Spine\n"
        "  {\n"
        "    OFFSET 0 10 0\n"
        "    CHANNELS 3 Zrotation Yrotation Xrotation\n"
        "    End Site\n"
        "    {\n"
        "      OFFSET 0 5 0\n"
        "    }\n"
        "  }\n"
        "}\n"
        "MOTION\n"
        f"Frames: {len(frames)}\n"
        "Frame Time: 0.0333333\n" + "\n".join(frames) + "\n"
    )


GOOD = _minimal_bvh()
_F1, _F2 = "0 90 0 0 0 0 0 0 0", "1 90 0 0 10 0 0 5 0"
_ROOT_CH, _JOINT_CH = "Zrotation Yrotation Xrotation\n  JOINT", "CHANNELS 3 Zrotation Yrotation Xrotation"
# case: (substring of GOOD, its replacement, what the message must say)
_EDITS = {
    "short frame line": (_F2, "1 90 0 0 10 0 0 5", "line 20: frame 2 has 8 values, expected 9"),
    "long frame line": (_F1, _F1 + " 7", "line 19: frame 1 has 10 values"),
    "non-numeric": (_F2, "1 90 0 0 ten 0 0 5 0", "line 20: frame 2 has a non-numeric value 'ten'"),
    "non-finite": (_F2, "1 90 0 0 nan 0 0 5 0", "line 20: frame 2 has a non-finite value"),
    "unknown channel": (_ROOT_CH, "Zrot" + _ROOT_CH[9:], "line 5: unknown channel name 'Zrot'"),
    "too few channel names": (_JOINT_CH, _JOINT_CH[:-10], "line 9: CHANNELS declares 3 channels but names only 2"),
    "too many channel names": ("CHANNELS 3 Z", "CHANNELS 2 Z", "line 9: CHANNELS declares 2 channels but names more"),
    "repeated channel": ("3 Zrotation Y", "3 Zrotation Z", "line 9: channel Zrotation repeated"),
    "frames mismatch": ("Frames: 2", "Frames: 3", "'Frames: 3' but the file has 2 frame lines"),
    "frames not a number": ("Frames: 2", "Frames: two", "line 17: Frames must be an integer"),
    "zero frame time": ("Time: 0.0333333", "Time: 0", "line 18: Frame Time must be > 0"),
    "negative frame time": ("Time: 0.0333333", "Time: -0.01", "line 18: Frame Time must be > 0"),
    "missing frame time": ("Frame Time: 0.0333333\n", "", "expected 'Frame Time: <seconds>'"),
    "unclosed brace": ("    }\n  }\n}\n", "    }\n  }\n", "unexpected end of HIERARCHY"),
    "no OFFSET": ("    OFFSET 0 10 0\n", "", "joint 'Spine' has no OFFSET"),
    "bad OFFSET": ("OFFSET 0 10 0", "OFFSET 0 x 0", "line 8: OFFSET value must be a number, got 'x'"),
    "no hierarchy": ("HIERARCHY\n", "HIERARCHIE\n", "line 1: expected HIERARCHY"),
    "duplicate joint": ("JOINT Spine", "JOINT Hips", "line 6: duplicate joint name 'Hips'"),
}
BAD_CASES = {case: (GOOD.replace(old, new, 1), expected) for case, (old, new, expected) in _EDITS.items()}
BAD_CASES["missing MOTION"] = (GOOD[: GOOD.index("MOTION")], "no MOTION section")
BAD_CASES["no root"] = ("HIERARCHY\nMOTION\nFrames: 1\nFrame Time: 0.1\n0\n", "HIERARCHY has no ROOT joint")
BAD_CASES["empty"] = ("", "empty file")


@pytest.mark.parametrize("case", sorted(BAD_CASES))
def test_parse_errors_are_one_line_user_errors(case):
    text, expected = BAD_CASES[case]
    assert text != GOOD
    with pytest.raises(PhavUserError) as info:
        bvh.parse_bvh(text, source="bad.bvh")
    message = str(info.value)
    assert info.value.source == "bad.bvh"
    assert message.startswith("bad.bvh: ") and "\n" not in message
    assert expected in message, message
    assert info.value.__cause__ is None or info.value.__suppress_context__


def test_good_minimal_file_parses_and_load_reports_missing(tmp_path):
    clip = bvh.parse_bvh(GOOD, source="good.bvh")
    assert clip.names == ("Hips", "Spine", "Spine/End Site")
    assert clip.parents == (-1, 0, 1) and clip.frames.shape == (2, 9)
    path = tmp_path / "take.bvh"
    path.write_text(GOOD, encoding="utf-8")
    assert bvh.load_bvh(path).n_frames == 2
    with pytest.raises(PhavUserError, match=r"nothere\.bvh: no such file"):
        bvh.load_bvh(tmp_path / "nothere.bvh")


# --------------------------------------------------------------------------------------
# Imported clip as a registered motion


def test_bvh_motion_registers_and_plays(tmp_path):
    path = tmp_path / "raise_arm.bvh"
    path.write_text(_cmu_take(ARM, KNEE), encoding="utf-8")
    motion = bvh.bvh_motion(path, name="bvh_raise_arm_test", description="raise right arm forward, bend left knee")
    assert motion.length_s == pytest.approx(5 * 0.0083333)
    register_motion(motion)
    try:
        assert get_motion("bvh_raise_arm_test") is motion
        times = np.linspace(0.0, 0.1, 13)  # past the end: playback wraps with root carry-over
        pose = play(motion, times, 0.0, MotionParams())
        assert len(pose) == 13 and np.all(np.isfinite(pose.q)) and np.all(np.isfinite(pose.root_quat))
        # Interpolation midway between frames 2 and 3.
        mid = motion.fn(np.array([2.5 * 0.0083333]), MotionParams())
        assert np.degrees(mid.q[0, DOF_INDEX["right_shoulder_flex"]]) == pytest.approx(75.0, abs=0.6)
        dims = body_dims(1.6, 55.0, 0.36, 0.30, 0.9)
        placed = place(pose, dims, (2.0, -1.0, 0.0), 90.0)
        assert placed.root_pos[0, :2] == pytest.approx([2.0, -1.0], abs=1e-6)
        assert placed.root_pos[0, 2] == pytest.approx(dims.standing_pelvis_height, abs=0.01)
        assert np.all(placed.q >= LOWER - 1e-12) and np.all(placed.q <= UPPER + 1e-12)
        # Amplitude scales excursions around the clip's mean pose.
        half = motion.fn(np.array([0.0]), MotionParams(amplitude=0.5)).q
        full = motion.fn(np.array([0.0]), MotionParams()).q
        mean = bvh.retarget(bvh.load_bvh(path)).pose.q.mean(axis=0)
        np.testing.assert_allclose(half - mean, np.clip(0.5 * (full - mean) + mean, LOWER, UPPER) - mean, atol=1e-9)
    finally:
        unregister_motion("bvh_raise_arm_test")
    assert "bvh_raise_arm_test" not in user_motions()


def test_bvh_motion_validates_name_and_description():
    clip = bvh.parse_bvh(_cmu_take(ARM[:2], KNEE[:2]), source="take.bvh")
    with pytest.raises(PhavUserError, match=r"take\.bvh: description: .*must be non-empty lowercase"):
        bvh.bvh_motion(clip, name="bvh_take", description="Raise Arm")
    with pytest.raises(PhavUserError, match=r"take\.bvh: name: .*snake_case"):
        bvh.bvh_motion(clip, name="Bvh Take", description="raise arm")
