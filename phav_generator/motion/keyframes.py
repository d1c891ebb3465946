"""Keyframe curves for the procedural motion library.

Motions are written as keyframes (time, value) and periodic cycles; these helpers turn them
into smooth curves. Interpolation is a monotone cubic (Fritsch–Carlson, the PCHIP scheme):
C1-continuous, it passes through every key, never overshoots between two keys (a joint
never swings past where the animator put it) and has zero velocity at the first and last
key and at every local extremum, so a posture held between two equal keys stays still.
The periodic variant wraps around, for cycles that must loop seamlessly.

Everything is vectorised over the sample axis and pure: the same keys and times always
give the same values.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

#: Keys of a scalar curve: (time s, value) pairs, times increasing.
Keys = tuple[tuple[float, float], ...]


def ease(u: np.ndarray | float) -> np.ndarray:
    """Quintic smootherstep on [0, 1] (clipped): zero velocity and acceleration at both ends."""
    u = np.clip(np.asarray(u, dtype=np.float64), 0.0, 1.0)
    return u * u * u * (u * (u * 6.0 - 15.0) + 10.0)


def bump(u: np.ndarray | float) -> np.ndarray:
    """A smooth 0 → 1 → 0 hump on [0, 1] (sin², zero outside), for lifts and pulses."""
    u = np.clip(np.asarray(u, dtype=np.float64), 0.0, 1.0)
    return np.sin(np.pi * u) ** 2


def window(t: np.ndarray, t0: float, t1: float, ramp: float) -> np.ndarray:
    """1 inside [t0, t1], 0 outside, with smooth ramps of ``ramp`` seconds on either side."""
    r = max(ramp, 1e-6)
    return ease((t - (t0 - r)) / r) * (1.0 - ease((t - t1) / r))


def _fc_slopes(h: np.ndarray, delta: np.ndarray) -> np.ndarray:
    """Fritsch–Carlson interior slopes (K−2, C) from knot gaps (K−1,) and secants (K−1, C)."""
    d0, d1 = delta[:-1], delta[1:]
    h0, h1 = h[:-1, None], h[1:, None]
    w1 = 2.0 * h1 + h0
    w2 = h1 + 2.0 * h0
    same = d0 * d1 > 0.0
    safe0 = np.where(same, d0, 1.0)
    safe1 = np.where(same, d1, 1.0)
    return np.where(same, (w1 + w2) / (w1 / safe0 + w2 / safe1), 0.0)


def hermite(xk: np.ndarray, yk: np.ndarray, mk: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Cubic Hermite curve through knots xk (K,) with values yk (K, C) and slopes mk (K, C),
    at x (T,) → (T, C); held at the end knots outside [xk[0], xk[-1]]."""
    i = np.clip(np.searchsorted(xk, x, side="right") - 1, 0, len(xk) - 2)
    h = xk[i + 1] - xk[i]
    t = np.clip((x - xk[i]) / h, 0.0, 1.0)[:, None]
    h = h[:, None]
    t2 = t * t
    t3 = t2 * t
    return (
        (2 * t3 - 3 * t2 + 1) * yk[i]
        + (t3 - 2 * t2 + t) * h * mk[i]
        + (-2 * t3 + 3 * t2) * yk[i + 1]
        + (t3 - t2) * h * mk[i + 1]
    )


def monotone_cubic(xk: Sequence[float], yk: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Monotone cubic through knots (xk (K,) increasing, yk (K, C)) at x (T,) → (T, C).

    Zero slope at the end knots; held constant outside [xk[0], xk[-1]].
    """
    xk = np.asarray(xk, dtype=np.float64)
    yk = np.asarray(yk, dtype=np.float64).reshape(len(xk), -1)
    x = np.asarray(x, dtype=np.float64)
    if len(xk) == 1:
        return np.broadcast_to(yk[0], (x.shape[0], yk.shape[1])).copy()
    h = np.diff(xk)
    if np.any(h <= 0):
        raise ValueError("keyframe times must increase")
    delta = np.diff(yk, axis=0) / h[:, None]
    mk = np.zeros_like(yk)
    mk[1:-1] = _fc_slopes(h, delta)
    return hermite(xk, yk, mk, x)


def periodic_cubic(xk: Sequence[float], yk: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Periodic monotone cubic with period 1: knots xk (K,) in [0, 1), values yk (K, C).

    The curve wraps from the last knot back to the first, C1 across the wrap, so a cycle
    sampled at x and x + 1 gives the same value.
    """
    xk = np.asarray(xk, dtype=np.float64)
    yk = np.asarray(yk, dtype=np.float64).reshape(len(xk), -1)
    x = np.asarray(x, dtype=np.float64)
    if len(xk) == 1:
        return np.broadcast_to(yk[0], (x.shape[0], yk.shape[1])).copy()
    ext_x = np.concatenate([[xk[-1] - 1.0], xk, [xk[0] + 1.0, xk[1] + 1.0]])
    ext_y = np.concatenate([yk[-1:], yk, yk[:2]])
    h = np.diff(ext_x)
    if np.any(h <= 0):
        raise ValueError("cycle keys must increase within one period")
    delta = np.diff(ext_y, axis=0) / h[:, None]
    m = _fc_slopes(h, delta)  # slopes at ext_x[1:-1] = xk and xk[0] + 1
    knots = ext_x[1:-1]
    u = xk[0] + np.mod(x - xk[0], 1.0)
    return hermite(knots, ext_y[1:-1], m, u)


def track(keys: float | Keys, t: np.ndarray) -> np.ndarray:
    """A constant, or keys (time, value) through a monotone cubic, sampled at ``t`` (T,) → (T,)."""
    if isinstance(keys, (int, float)):
        return np.full(t.shape, float(keys))
    ks = np.array(keys, dtype=np.float64)
    return monotone_cubic(ks[:, 0], ks[:, 1], t)[:, 0]


def fit_period(period: float, length: float) -> float:
    """``period`` rounded so a whole number of cycles (at least one) fills ``length``: seamless loops."""
    return length / max(1, round(length / period))
