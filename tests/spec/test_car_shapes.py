"""Car bodies: each body type's profile is a convex outline inside its box, and the hulls a
car collides as are convex solids inside it too (the drawn car's fit: tests/generator/world)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial import ConvexHull

from phav_spec.car_shapes import (
    CAR_BODIES,
    CORNER_FRONT_M,
    CORNER_REAR_M,
    car_body,
    car_hulls,
    car_profile,
)

HALF = (2.1, 0.9, 0.7)


def _convex_ccw(outline) -> bool:
    p = np.asarray(outline)
    edges = np.roll(p, -1, axis=0) - p
    turns = edges[:, 0] * np.roll(edges, -1, axis=0)[:, 1] - edges[:, 1] * np.roll(edges, -1, axis=0)[:, 0]
    return bool(np.all(turns > 0))


@pytest.mark.parametrize("kind", CAR_BODIES)
@pytest.mark.parametrize("below", [0.0, 0.15])
def test_a_body_s_outlines_are_convex_and_its_hulls_fill_its_box(kind, below):
    outline = car_profile(kind, HALF, below)
    assert _convex_ccw(outline.lower()) and _convex_ccw(outline.cabin())
    assert outline.ground < outline.bottom < outline.hood_front < outline.belt < outline.roof == HALF[2]
    assert outline.rear <= outline.rear_window < outline.roof_rear < outline.roof_front < outline.windscreen
    corners = np.concatenate([np.asarray(h) for h in car_hulls(outline)])
    assert np.all(np.abs(corners) <= np.asarray(HALF) + 1e-9)
    # Together they reach the box's front, back and top, and the body's sides (5 cm inside
    # the box's, which its mirrors reach): where a person meets the car.
    assert np.allclose(corners.max(axis=0), (HALF[0], outline.side, HALF[2])) and np.isclose(
        corners[:, 0].min(), -HALF[0]
    )
    for hull in car_hulls(outline):
        assert ConvexHull(np.asarray(hull)).volume > 0.01


def test_the_body_type_is_one_draw_of_its_stream():
    kinds = {car_body(np.random.default_rng(seed)) for seed in range(40)}
    assert kinds == set(CAR_BODIES)
    # One integer draw: a stream continues after it as after any other.
    rng, twin = np.random.default_rng(3), np.random.default_rng(3)
    car_body(rng)
    twin.integers(0, len(CAR_BODIES))
    assert rng.bit_generator.state == twin.bit_generator.state


def test_an_unknown_body_is_refused_by_name():
    with pytest.raises(ValueError, match="'limousine' is not a car body"):
        car_profile("limousine", HALF)


@pytest.mark.parametrize("kind", CAR_BODIES)
@pytest.mark.parametrize("per_corner", [1, 2, 4])
def test_a_body_seen_from_above_is_a_rounded_oblong(kind, per_corner):
    """Its sections keep the side profile's span, narrow round each end along a quarter
    circle of the corner's radius (never outside it), and tuck in under the sill."""
    outline = car_profile(kind, HALF, 0.15)
    sections = [np.asarray(s) for s in outline.body_sections(per_corner)]
    xs = [s[0, 0] for s in sections]
    assert xs == sorted(xs) and np.isclose(xs[0], outline.rear) and np.isclose(xs[-1], outline.front)
    for end, r in ((outline.front, CORNER_FRONT_M), (outline.rear, CORNER_REAR_M)):
        assert np.isclose(outline.plan_half_width(end), outline.side - r)
        assert np.isclose(outline.plan_half_width(end - np.sign(end) * r), outline.side)
    for s in sections:
        x, widest = s[0, 0], np.abs(s[:, 1]).max()
        assert np.allclose(s[:4, 1], -s[:3:-1, 1]) and np.allclose(s[:4, 2], s[:3:-1, 2])  # mirrored about y = 0
        assert widest <= outline.plan_half_width(x) + 1e-12
        assert abs(s[0, 1]) <= abs(s[1, 1])
        if s[0, 2] < outline.bottom + 0.05:
            assert abs(s[0, 1]) < abs(s[1, 1])  # tucked in under the sill
    # Halfway round the front corner, the drawn side lies on the circle (a station there at 4).
    mid = outline.front - CORNER_FRONT_M * (1.0 - np.sin(np.pi / 4))
    on_arc = outline.side - CORNER_FRONT_M + CORNER_FRONT_M * np.cos(np.pi / 4)
    assert np.isclose(outline.plan_half_width(mid), on_arc)
    # A bumper reaches round its corner but not past the body's side.
    for (_, half), r in zip(outline.bumpers(), (CORNER_FRONT_M, CORNER_REAR_M), strict=True):
        assert outline.side - r < half[1] < outline.side


def test_the_side_between_a_section_s_points_is_straight_as_drawn():
    outline = car_profile("sedan", HALF)
    x = 0.3
    heights = outline.section_heights(x)
    for h in heights:
        assert np.isclose(outline.surface_half_width(x, h), outline.plan_half_width(x) * (1.0 - outline.tuck(h)))
    mid = (heights[1] + heights[2]) / 2
    ends = [outline.surface_half_width(x, h) for h in heights[1:3]]
    assert np.isclose(outline.surface_half_width(x, mid), sum(ends) / 2)
