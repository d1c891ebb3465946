"""The multiple-render-target pass against analytic answers: depth of known planes, flow of
a moving camera, a moving object and a rotating limb, sky and points behind the camera."""

from __future__ import annotations

import dataclasses
import math

import moderngl
import numpy as np
import pytest

from phav_generator.motion.rotations import axis_angle_matrix, look_at
from phav_generator.render.camera import project
from phav_generator.render.gl import Drawable, Frame, FrameRenderer, PostSettings
from phav_generator.render.meshes import box, capsule
from phav_generator.render.modalities import encode_frame
from phav_spec.encoding import DEPTH_MAX_CODE, decode_flow, encode_depth
from phav_spec.theta import RenderSettings

W, H = 340, 256
INTRINSICS = (260.0, 260.0, 170.0, 128.0)
SKY = 8
#: End-point error allowed against the analytic flow, pixels.
EPE_PX = 0.05


def _pose(rotation: np.ndarray | None = None, translation=(0.0, 0.0, 0.0)) -> np.ndarray:
    m = np.eye(4)
    if rotation is not None:
        m[:3, :3] = rotation
    m[:3, 3] = translation
    return m


def _look(eye, target) -> np.ndarray:
    """Camera-to-world for a camera at ``eye`` looking at ``target`` (+Z up)."""
    return _pose(look_at(np.asarray(eye, float), np.asarray(target, float)), eye)


def _render(ctx, drawables, cam0, cam1, frame=0):
    with FrameRenderer(ctx, W, H, drawables, sky_class=SKY) as r:
        return r.render(frame, cam0, cam1, INTRINSICS)


def _pixel_points(depth: np.ndarray, cam: np.ndarray) -> np.ndarray:
    """World points (H, W, 3) of every pixel centre at its rendered depth (the contract)."""
    fx, fy, cx, cy = INTRINSICS
    u, v = np.meshgrid(np.arange(W) + 0.5, np.arange(H) + 0.5)
    depth = np.where(np.isfinite(depth), depth, 0.0)  # sky: no point
    local = np.stack([(u - cx) * depth / fx, -(v - cy) * depth / fy, -depth], axis=-1)
    return local @ cam[:3, :3].T + cam[:3, 3]


def _analytic_flow(depth, cam0, cam1, motion=None) -> np.ndarray:
    """Where each pixel's surface point lands at t + 1 minus where it is, for a static world
    (or a rigid ``motion`` (4, 4) applied to it between the frames)."""
    points = _pixel_points(depth, cam0)
    if motion is not None:
        points = points @ motion[:3, :3].T + motion[:3, 3]
    u, v = np.meshgrid(np.arange(W) + 0.5, np.arange(H) + 0.5)
    return project(points, cam1, INTRINSICS) - np.stack([u, v], axis=-1)


def test_depth_of_a_plane_at_a_known_distance(ctx):
    wall = _pose(translation=(0.0, 0.0, -7.3))
    frame = _render(ctx, [Drawable(box((40, 40, 0.01)), np.stack([wall, wall]), 2)], np.eye(4), np.eye(4))
    # The front face is at 7.29 m along the axis: every pixel encodes 729 cm.
    assert np.all(encode_depth(frame.depth_m) == 729)
    assert np.all(frame.class_id == 2) and np.all(frame.instance == 0)


def test_flow_of_a_camera_translating_over_an_inclined_off_centre_plane(ctx):
    tilt = axis_angle_matrix(np.array([1.0, 0.3, 0.0]) / math.hypot(1.0, 0.3), np.array(0.6))
    plane = _pose(tilt, (1.5, -0.8, -9.0))
    cam0 = np.eye(4)
    cam1 = _pose(translation=(0.12, -0.07, 0.05))
    frame = _render(ctx, [Drawable(box((6, 6, 0.01)), np.stack([plane, plane]), 2)], cam0, cam1)
    on = frame.class_id == 2
    assert 0.2 < on.mean() < 0.99  # off-centre: sky shows too
    expected = _analytic_flow(frame.depth_m, cam0, cam1)
    epe = np.linalg.norm(frame.flow - expected, axis=-1)[on]
    assert epe.max() < EPE_PX and np.all(frame.flow_valid[on])
    depth = _pixel_points(frame.depth_m, cam0)[on]
    normal = tilt[:, 2]
    # Recovered points lie on the plane's front face.
    assert np.abs((depth - plane[:3, 3]) @ normal - 0.01).max() < 2e-3


def test_flow_of_a_rigid_object_moving_past_a_static_camera(ctx):
    cam = _look((0.0, -8.0, 1.5), (0.0, 0.0, 1.0))
    t0 = _pose(translation=(-0.5, 0.0, 1.0))
    t1 = _pose(axis_angle_matrix(np.array([0.0, 0.0, 1.0]), np.array(0.1)), (-0.2, 0.1, 1.05))
    frame = _render(ctx, [Drawable(box((0.8, 0.5, 0.6)), np.stack([t0, t1]), 22, 3)], cam, cam)
    on = frame.instance == 3
    assert on.sum() > 2000
    expected = _analytic_flow(frame.depth_m, cam, cam, t1 @ np.linalg.inv(t0))
    assert np.linalg.norm(frame.flow - expected, axis=-1)[on].max() < EPE_PX
    assert np.all(frame.class_id[~on] == SKY) and not frame.flow_valid[~on].any()
    assert np.all(np.isinf(frame.depth_m[~on]))


def test_flow_of_a_rotating_limb(ctx):
    """A forearm-sized capsule swinging 8° about its elbow, seen by a camera that also moves."""
    cam0 = _look((0.3, -1.8, 1.2), (0.0, 0.0, 1.0))
    cam1 = _look((0.33, -1.78, 1.21), (0.0, 0.0, 1.0))
    elbow = np.array([0.0, 0.0, 1.2])
    limb = capsule((0.0, 0.0, 0.0), (0.28, 0.0, -0.05), 0.045)
    t0 = _pose(translation=elbow)
    t1 = _pose(axis_angle_matrix(np.array([0.0, 1.0, 0.0]), np.array(math.radians(8.0))), elbow)
    frame = _render(ctx, [Drawable(limb, np.stack([t0, t1]), 45, 1)], cam0, cam1)
    on = frame.instance == 1
    assert on.sum() > 300
    expected = _analytic_flow(frame.depth_m, cam0, cam1, t1 @ np.linalg.inv(t0))
    assert np.linalg.norm(frame.flow - expected, axis=-1)[on].max() < EPE_PX


def test_points_behind_the_camera_at_the_next_frame_have_no_flow(ctx):
    """The camera moves through a wall 3 m ahead: every wall point is behind it at t + 1,
    and the flow PNG encodes every pixel as invalid (0, 0, 0)."""
    wall = _pose(translation=(0.0, 0.0, -3.0))
    cam1 = _pose(translation=(0.0, 0.0, -4.0))
    frame = _render(ctx, [Drawable(box((20, 20, 0.01)), np.stack([wall, wall]), 2)], np.eye(4), cam1)
    assert not frame.flow_valid.any() and np.all(frame.flow == 0.0)
    assert np.all(encode_frame(frame)["flow"] == 0)


def test_sky_is_encoded_as_no_depth_and_no_flow(ctx):
    """A box floating in the sky: sky pixels get the depth sky code and invalid flow."""
    cam = _look((0.0, -6.0, 1.0), (0.0, 0.0, 1.0))
    t = _pose(translation=(0.0, 0.0, 1.0))
    frame = _render(ctx, [Drawable(box((0.5, 0.5, 0.5)), np.stack([t, t]), 22, 3)], cam, cam)
    out = encode_frame(frame)
    sky = frame.class_id == SKY
    assert 0.5 < sky.mean() < 0.99
    assert np.all(out["depth"][sky] == DEPTH_MAX_CODE) and np.all(out["flow"][sky] == 0)
    assert np.all(out["depth"][~sky] < DEPTH_MAX_CODE) and np.all(out["flow"][~sky][:, 2] == 1)


def test_flow_beyond_512_px_is_encoded_invalid(ctx):
    """The camera slides 10 m sideways over a ground plane: near pixels move more than 512 px
    (encoded invalid), far ones less (encoded and decoded within the 1/64 px quantum)."""
    cam0 = _look((0.0, 0.0, 1.6), (0.0, 30.0, 0.0))
    cam1 = cam0.copy()
    cam1[:3, 3] += (10.0, 0.0, 0.0)
    plane = _pose(translation=(0.0, 40.0, -0.01))
    frame = _render(ctx, [Drawable(box((200, 40, 0.01)), np.stack([plane, plane]), 2)], cam0, cam1)
    expected = _analytic_flow(frame.depth_m, cam0, cam1)
    on = frame.class_id == 2
    speed = np.abs(expected).max(axis=-1)
    far, near = on & (speed < 500.0), on & (speed > 524.0)
    assert far.sum() > 1000 and near.sum() > 1000  # both sides of the limit are in view
    flow, valid = decode_flow(encode_frame(frame)["flow"])
    assert not valid[near].any() and np.all(encode_frame(frame)["flow"][near] == 0)
    assert valid[far].all()
    assert np.abs(flow[far] - expected[far]).max() < EPE_PX + 1.0 / 64.0


def test_rendering_is_deterministic(ctx):
    cam0 = _look((2.0, -5.0, 2.0), (0.0, 0.0, 0.5))
    cam1 = _look((2.1, -5.0, 2.0), (0.0, 0.0, 0.5))
    items = [
        Drawable(box((0.5, 0.5, 0.5)), np.stack([_pose(translation=(0, 0, 0.5))] * 2), 2, 0, (0.8, 0.2, 0.2)),
        Drawable(capsule((0, 0, 0), (0, 0, 1.0), 0.2), np.stack([_pose(translation=(1, 0, 0))] * 2), 47, 2),
    ]
    a, b = _render(ctx, items, cam0, cam1), _render(ctx, items, cam0, cam1)
    for name in ("colour", "class_id", "instance", "depth_m", "flow", "flow_valid"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name))
    # Nearer surfaces win: the box hides the capsule's lower part only where it is in front.
    assert set(np.unique(a.class_id)) == {2, 47, SKY}


def _scene() -> list[Drawable]:
    """A box on a slab: shadows, two drawables, one of them a person."""
    ground = _pose(translation=(0.0, 0.0, -0.05))
    body = _pose(translation=(0.0, 0.0, 0.5))
    return [Drawable(box((10, 10, 0.1)), np.stack([ground, ground]), 2),
            Drawable(box((0.4, 0.4, 1.0)), np.stack([body, body]), 22, 1)]  # fmt: skip


def _gl_objects(renderer: FrameRenderer) -> list:
    """The GL objects a renderer holds: programs, buffers, vertex arrays, targets."""
    kinds = (moderngl.Buffer, moderngl.Framebuffer, moderngl.Program, moderngl.Renderbuffer, moderngl.Texture,
             moderngl.VertexArray)  # fmt: skip
    return [v for v in vars(renderer).values() if isinstance(v, kinds)]


def _released(obj) -> bool:
    return isinstance(obj.mglo, moderngl.InvalidObject)


def test_render_is_the_labelled_pass_then_the_rgb_passes(ctx):
    cam0, cam1 = _look((2.0, -5.0, 2.0), (0.0, 0.0, 0.5)), _look((2.1, -5.0, 2.0), (0.0, 0.0, 0.5))
    with FrameRenderer(ctx, W, H, _scene(), sky_class=SKY) as r:
        whole = r.render(0, cam0, cam1, INTRINSICS)
        labels = r.render_labels(0, cam0, cam1, INTRINSICS)
        assert labels.rgb is None
        split = r.render_rgb(labels)
        with pytest.raises(ValueError, match="render_labels returned last"):
            r.render_rgb(whole)
    for name in ("colour", "class_id", "instance", "depth_m", "flow", "flow_valid", "rgb"):
        np.testing.assert_array_equal(getattr(whole, name), getattr(split, name))


def test_the_context_manager_releases_every_gl_object_on_exit(ctx):
    cam = _look((2.0, -5.0, 2.0), (0.0, 0.0, 0.5))
    with FrameRenderer(ctx, W, H, _scene(), sky_class=SKY, supersample=4) as r:
        r.render(0, cam, cam, INTRINSICS)
        held = _gl_objects(r)
        assert len(held) > 20 and not any(_released(o) for o in held)
    assert all(_released(o) for o in held)
    r.release()  # idempotent
    ctx.buffer(reserve=4).release()  # the context stays usable


def test_the_context_manager_releases_every_gl_object_on_an_exception(ctx):
    with pytest.raises(RuntimeError, match="mid-frame"), FrameRenderer(ctx, W, H, _scene(), sky_class=SKY) as r:
        held = _gl_objects(r)
        raise RuntimeError("mid-frame")
    assert held and all(_released(o) for o in held)


class _CountedDraws:
    """A vertex array that counts its draws."""

    def __init__(self, vao: moderngl.VertexArray):
        self.vao, self.draws = vao, 0

    def render(self, mode: int) -> None:
        self.draws += 1
        self.vao.render(mode)


def _brightness(frame: Frame) -> np.ndarray:
    return frame.colour.astype(int).sum(axis=-1)


def test_what_holds_still_is_drawn_into_its_shadow_map_once_and_shadows_every_frame(ctx):
    """A still box's shadow comes from a map drawn at the first frame rendered and is there
    at every frame; a moving box's shadow follows it; a frame is the same whichever frame
    the renderer drew first."""
    ground, still = _pose(translation=(0.0, 0.0, -0.05)), _pose(translation=(-1.5, 0.0, 0.75))
    moving = np.stack([_pose(translation=(1.5, y, 0.75)) for y in (0.0, 1.0, 2.0)])
    floor = Drawable(box((10, 10, 0.1)), np.stack([ground] * 3), 2)
    mover = Drawable(box((0.8, 0.8, 1.5)), moving, 22, 1)
    items = [floor, Drawable(box((0.8, 0.8, 1.5)), np.stack([still] * 3), 5), mover]
    cam = _look((-3.0, 5.0, 7.0), (0.0, 0.5, 0.0))
    with FrameRenderer(ctx, W, H, items, sky_class=SKY) as r:
        [still_map] = [m for m in r._shadow_maps if not m.every_frame]
        still_map.vao = counted = _CountedDraws(still_map.vao)
        frames = [r.render(f, cam, cam, INTRINSICS) for f in range(3)]
    assert counted.draws == 1
    with FrameRenderer(ctx, W, H, items, sky_class=SKY) as r:
        np.testing.assert_array_equal(r.render(2, cam, cam, INTRINSICS).rgb, frames[2].rgb)
    with FrameRenderer(ctx, W, H, [floor, mover], sky_class=SKY) as r:
        bare = [r.render(f, cam, cam, INTRINSICS) for f in range(3)]
    for with_still, without in zip(frames, bare, strict=True):
        on_ground = (with_still.class_id == 2) & (without.class_id == 2)
        assert (on_ground & (_brightness(with_still) < _brightness(without) - 60)).sum() > 300
    on_ground = (bare[0].class_id == 2) & (bare[2].class_id == 2)
    assert (on_ground & (_brightness(bare[0]) < _brightness(bare[2]) - 60)).sum() > 300  # left behind


def test_post_settings_follow_the_recipes_render_switches():
    """θ's defaults switch every effect on at its default strength; each switch turns off
    only its own effect."""
    assert PostSettings.from_render(RenderSettings()) == PostSettings()
    off = PostSettings.from_render(RenderSettings(bloom=False, color_grading=False))
    assert (off.bloom, off.grading) == (0.0, False)
    assert off.motion_blur == PostSettings().motion_blur and off.reflections and off.vignette > 0.0


def _ao_darkening(ctx, drawables, cam) -> tuple[np.ndarray, Frame]:
    """How much ambient occlusion alone darkens each pixel (0..1), the other effects off, and
    the frame without it."""
    quiet = PostSettings(motion_blur=0.0, bloom=0.0, vignette=0.0, grading=False)
    frames = []
    for post in (quiet, dataclasses.replace(quiet, ambient_occlusion=0.0)):
        with FrameRenderer(ctx, W, H, drawables, sky_class=SKY, post=post) as r:
            frames.append(r.render(0, cam, cam, INTRINSICS))
    with_ao, without = (f.rgb.astype(float).mean(axis=-1) for f in frames)
    return 1.0 - with_ao / np.maximum(without, 1.0), frames[1]


def test_occlusion_darkens_a_corner_and_a_foot_but_leaves_no_copy_of_a_thin_post(ctx):
    """A wall meeting the floor darkens the floor beside it, and a 4 cm post the floor at its
    foot; floor more than 0.4 m from either keeps its light, however the post's silhouette
    lies over it on screen: a thin thing prints no shifted copies of itself."""
    floor, wall = _pose(translation=(0.0, 0.0, -0.05)), _pose(translation=(0.0, 4.0, 1.5))
    post = _pose(translation=(0.0, 1.0, 0.5))
    items = [Drawable(box((10, 10, 0.05)), np.stack([floor, floor]), 2),
             Drawable(box((10, 0.05, 1.5)), np.stack([wall, wall]), 3),
             Drawable(box((0.02, 0.02, 0.5)), np.stack([post, post]), 5)]  # fmt: skip
    cam = _look((0.4, -2.5, 1.6), (0.0, 2.0, 0.3))
    dark, frame = _ao_darkening(ctx, items, cam)
    points = _pixel_points(frame.depth_m, cam)
    on_floor = frame.class_id == 2
    from_post = np.hypot(points[..., 0], points[..., 1] - 1.0)
    from_wall = 3.95 - points[..., 1]
    assert dark[on_floor & (from_wall < 0.1)].mean() > 0.05  # the corner
    assert dark[on_floor & (from_post < 0.1) & (from_post > 0.02)].mean() > 0.005  # the foot
    away = on_floor & (from_post > 0.4) & (from_wall > 0.4)
    behind_post = away & (np.abs(points[..., 0]) < 0.3)  # floor the post's silhouette crosses on screen
    assert behind_post.sum() > 500
    assert np.percentile(dark[away], 99.5) < 0.01


def test_material_coordinates_follow_the_world_where_a_drawable_stands_still():
    """A still drawable's pattern coordinates are the world's turned into its axes: a point's
    are the same whichever pose puts it there; a moving or skinned drawable keeps its own."""
    from phav_generator.render.gl import material_coordinates

    rng = np.random.default_rng(0)
    local = rng.normal(size=(6, 3))
    pose = np.eye(4)
    pose[:3, :3] = axis_angle_matrix(np.array([0.0, 0.0, 1.0]), 0.7)
    pose[:3, 3] = (4.0, -2.0, 0.5)
    still = np.broadcast_to(pose, (3, 4, 4))
    world = local @ pose[:3, :3].T + pose[:3, 3]
    np.testing.assert_allclose(material_coordinates(local, still), world @ pose[:3, :3], atol=1e-12)
    moving = np.stack([pose, pose, pose])
    moving[1, 0, 3] += 0.1  # it moves in one frame
    assert material_coordinates(local, moving) is local
    assert material_coordinates(local, np.broadcast_to(pose, (3, 2, 4, 4))) is local  # skinned: bones
