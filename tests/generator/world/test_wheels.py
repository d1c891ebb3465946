"""A vehicle's wheels turn as it drives, and their forward flow follows the turning: the
next frame warped back along the flow matches the frame, where the flow of a wheel that
only slid along with the car would not. A bus shows its wheels in arches."""

from __future__ import annotations

import numpy as np
import pytest

from phav_generator.render.assets import wheel_spin, wheels_drawable
from phav_generator.render.gl import FrameRenderer
from phav_generator.world.vehicles import bus, car
from phav_spec.seeding import stream
from phav_spec.vocab import PIXEL_CLASSES

STEP_M = 0.12  # per frame: 13 km/h at 30 fps


def _moving(n: int, step: float) -> np.ndarray:
    t = np.tile(np.eye(4), (n, 1, 1))
    t[:, 0, 3] = step * np.arange(n)
    t[:, 2, 3] = 0.75
    return t


def test_wheels_turn_by_the_distance_rolled():
    spin = wheel_spin(_moving(4, STEP_M), 0.3)
    assert np.allclose(spin, STEP_M * np.arange(4) / 0.3)
    assert np.allclose(wheel_spin(_moving(3, -STEP_M), 0.3), -STEP_M * np.arange(3) / 0.3)


def _bilinear(image: np.ndarray, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    x0, y0 = np.floor(x).astype(int), np.floor(y).astype(int)
    fx, fy = (x - x0)[:, None], (y - y0)[:, None]
    img = image.astype(np.float64)
    return ((1 - fx) * (1 - fy) * img[y0, x0] + fx * (1 - fy) * img[y0, x0 + 1]
            + (1 - fx) * fy * img[y0 + 1, x0] + fx * fy * img[y0 + 1, x0 + 1])  # fmt: skip


def test_the_forward_flow_of_a_turning_wheel_warps_the_next_frame_onto_this_one(ctx):
    vehicle = car((2.2, 0.9, 0.75), stream(1, "wheel-flow"), 0, body="sedan")
    transforms = _moving(3, STEP_M)
    width, height = 320, 240
    eye = np.array([0.3, -4.5, 0.45])  # beside the car, level with its wheels
    c2w = np.eye(4)
    c2w[:3, :3] = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]]).T  # looking along +y
    c2w[:3, 3] = eye
    intrinsics = (300.0, 300.0, width / 2, height / 2)
    sky = PIXEL_CLASSES["sky"].class_id
    with FrameRenderer(ctx, width, height, [wheels_drawable(vehicle, transforms)], sky_class=sky, supersample=1) as r:
        now = r.render_labels(0, c2w, c2w, intrinsics)
        later = r.render_labels(1, c2w, c2w, intrinsics)
    wheel = (now.class_id != sky) & now.flow_valid
    ys, xs = np.nonzero(wheel)
    u, v = now.flow[ys, xs, 0], now.flow[ys, xs, 1]
    # Where the flow says each wheel pixel goes, and where it would go if the wheel only slid.
    slide = 300.0 * STEP_M / now.depth_m[ys, xs]
    tx, ty = xs + 0.5 + u - 0.5, ys + 0.5 + v - 0.5
    sx, sy = xs + slide, ys.astype(np.float64)
    inside = (tx > 1) & (tx < width - 2) & (ty > 1) & (ty < height - 2) & (sx < width - 2)
    lands = np.zeros_like(inside)
    lands[inside] = later.class_id[np.round(ty[inside]).astype(int), np.round(tx[inside]).astype(int)] != sky
    keep = inside & lands
    assert keep.sum() > 500, "the wheels fill too little of the frame"
    source = now.colour[ys[keep], xs[keep]].astype(np.float64)
    # Judge where the two readings disagree (spokes and rims passing): the flow's warp should
    # find the pixel's own colour there, the slide's should not. Per pixel, the largest channel.
    along_flow = _bilinear(later.colour, tx[keep], ty[keep])
    along_slide = _bilinear(later.colour, sx[keep], sy[keep])
    telling = np.abs(along_flow - along_slide).max(axis=1) > 16.0
    assert telling.sum() > 100
    exact = np.abs(along_flow - source).max(axis=1)[telling]
    slid = np.abs(along_slide - source).max(axis=1)[telling]
    assert np.median(exact) < 0.25 * np.median(slid), f"warped: {np.median(exact):.1f}, slid: {np.median(slid):.1f}"
    assert np.median(np.hypot(u, v) - slide) != 0.0  # the flow is not the sliding one


def _first_hit_y(asset, origin: np.ndarray) -> float:
    """The y of the first triangle of ``asset`` a ray from ``origin`` along −y meets."""
    p = asset.positions.astype(np.float64)[asset.triangles]
    a, e1, e2 = p[:, 0], p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]
    d = np.array([0.0, -1.0, 0.0])
    h = np.cross(d, e2)
    det = np.einsum("ij,ij->i", e1, h)
    ok = np.abs(det) > 1e-12
    s = origin - a
    u = np.einsum("ij,ij->i", s, h) / np.where(ok, det, 1.0)
    q = np.cross(s, e1)
    v = (q @ d) / np.where(ok, det, 1.0)
    t = np.einsum("ij,ij->i", e2, q) / np.where(ok, det, 1.0)
    hit = ok & (u >= 0) & (v >= 0) & (u + v <= 1) & (t > 0)
    return float(origin[1] - t[hit].min())


@pytest.mark.parametrize("seed", range(3))
def test_a_bus_shows_its_wheels_in_arches(seed):
    # Seen from the side at a hub's height, the first thing of the body is behind the tyre's
    # outer face (the dark wheel well), not a panel in front of it.
    bus_ = bus((6.0, 1.2, 1.5), stream(seed, "bus-arches"), 0)
    for x, y, z in bus_.axles[bus_.axles[:, 1] > 0]:
        tyre_face = y + 0.15
        assert _first_hit_y(bus_.body, np.array([x, 5.0, z])) < tyre_face - 0.05


def test_the_rear_wheels_are_drawn_with_the_front_ones_out_of_view(ctx):
    """The renderer culls a skinned mesh by its first bone's bounding sphere: the wheels'
    must hold all of them, not only the front wheel's (which dropped the rear wheels of a
    bus or a parked car cut by the frame's edge)."""
    vehicle = bus((6.0, 1.2, 1.5), stream(0, "cull"), 0)
    rear = vehicle.axles[np.argmin(vehicle.axles[:, 0])]
    assert np.argmin(vehicle.axles[:, 0]) != 0  # the first wheel is a front one
    c2w = np.eye(4)
    c2w[:3, :3] = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]]).T  # looking along +y
    c2w[:3, 3] = (rear[0], -6.0, rear[2])  # beside the rear axle: the front wheels far out of view
    sky = PIXEL_CLASSES["sky"].class_id
    still = np.tile(np.eye(4), (2, 1, 1))
    with FrameRenderer(ctx, 320, 240, [wheels_drawable(vehicle, still)], sky_class=sky, supersample=1) as r:
        frame = r.render_labels(0, c2w, c2w, (300.0, 300.0, 160.0, 120.0))
    assert (frame.class_id != sky).sum() > 1000
