"""Keyframe curves: through every key, no overshoot, still at the ends; cycles wrap seamlessly."""

from __future__ import annotations

import numpy as np
import pytest

from phav_generator.motion.keyframes import ease, fit_period, monotone_cubic, periodic_cubic, track


def test_monotone_cubic_passes_through_its_keys_without_overshoot() -> None:
    xk = [0.0, 1.0, 1.5, 3.0]
    yk = np.array([0.0, 2.0, 2.0, -1.0])
    np.testing.assert_allclose(monotone_cubic(xk, yk, np.array(xk))[:, 0], yk, atol=1e-12)
    x = np.linspace(-1.0, 4.0, 501)
    y = monotone_cubic(xk, yk, x)[:, 0]
    assert y.min() >= -1.0 - 1e-12 and y.max() <= 2.0 + 1e-12
    np.testing.assert_allclose(y[(x > 1.0) & (x < 1.5)], 2.0, atol=1e-12)  # a held posture stays still
    assert y[0] == 0.0 and y[-1] == -1.0  # held outside the keys
    with pytest.raises(ValueError, match="keyframe times must increase"):
        monotone_cubic([0.0, 0.0], np.array([1.0, 2.0]), x)


def test_periodic_cubic_wraps_with_its_period() -> None:
    xk = [0.1, 0.4, 0.8]
    yk = np.array([[1.0, 0.0], [-1.0, 2.0], [0.5, 1.0]])
    x = np.linspace(0.0, 1.0, 97)
    np.testing.assert_allclose(periodic_cubic(xk, yk, x), periodic_cubic(xk, yk, x + 1.0), atol=1e-12)
    np.testing.assert_allclose(periodic_cubic(xk, yk, np.array(xk)), yk, atol=1e-12)


def test_ease_track_and_fit_period() -> None:
    u = np.linspace(-0.5, 1.5, 41)
    e = ease(u)
    assert e[0] == 0.0 and e[-1] == 1.0 and np.all(np.diff(e) >= 0.0)
    t = np.linspace(0.0, 2.0, 5)
    np.testing.assert_array_equal(track(1.5, t), np.full(5, 1.5))
    np.testing.assert_allclose(track(((0.0, 0.0), (2.0, 4.0)), t)[[0, -1]], [0.0, 4.0])
    assert fit_period(1.1, 10.0) == pytest.approx(10.0 / 9) and fit_period(30.0, 10.0) == 10.0
