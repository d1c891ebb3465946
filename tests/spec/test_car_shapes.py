"""Car bodies: each body type's profile is a convex outline inside its box, and the hulls a
car collides as are convex solids inside it too (the drawn car's fit: tests/generator/world)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial import ConvexHull

from phav_spec.car_shapes import CAR_BODIES, car_body, car_hulls, car_profile

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
