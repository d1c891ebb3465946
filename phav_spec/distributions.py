"""The paper's four distribution families, built only on the bit generator's uniform doubles.

Section "Distributions": categorical, uniform, Bernoulli and the three-parameter triangular
Tr(x | a, b, c) with a = min, b = max, c = mode. Every sampler here draws ``rng.random()``
and transforms it with our own inverse CDF (DESIGN.md, random streams), so a numpy release
that changes ``Generator.triangular`` or ``Generator.choice`` cannot change a recipe. Each
family also gives its pdf and cdf, which the validators test samples against.
"""

from __future__ import annotations

import math
from bisect import bisect_right
from collections.abc import Sequence
from typing import Annotated, Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, model_validator

_FROZEN = ConfigDict(extra="forbid", frozen=True)


def cumulative(weights: Sequence[float]) -> tuple[float, ...]:
    """Running sums of non-negative weights, the table :func:`categorical_index` reads."""
    total = 0.0
    out = []
    for w in weights:
        if not (w >= 0.0 and math.isfinite(w)):
            raise ValueError(f"categorical weight {w!r} is not finite and non-negative")
        total += w
        out.append(total)
    if total <= 0.0:
        raise ValueError("categorical weights sum to zero: no value has support")
    return tuple(out)


def categorical_index(cum: Sequence[float], u: float) -> int:
    """Inverse CDF of a categorical with running sums ``cum`` at a uniform ``u`` in [0, 1).

    A zero-weight value repeats its predecessor's running sum and is never returned.
    """
    x = u * cum[-1]
    i = bisect_right(cum, x)
    if i >= len(cum):  # u * total rounded up to total: take the last value with support
        i = len(cum) - 1
        while i > 0 and cum[i] == cum[i - 1]:
            i -= 1
    return i


def sample_categorical(weights: Sequence[float], *, rng: np.random.Generator) -> int:
    """Index drawn with probability proportional to ``weights`` (one uniform double)."""
    return categorical_index(cumulative(weights), rng.random())


def sample_integer(low: int, high: int, *, rng: np.random.Generator) -> int:
    """Integer uniform on the closed range [low, high] from one uniform double."""
    if high < low:
        raise ValueError(f"empty integer range [{low}, {high}]")
    n = high - low + 1
    return low + min(int(rng.random() * n), n - 1)


def sample_subset(items: Sequence[str], k: int, *, rng: np.random.Generator) -> tuple[str, ...]:
    """``k`` distinct items, uniformly among all subsets of that size, in ``items`` order.

    Partial Fisher–Yates on indices with one uniform double per pick.
    """
    if not 0 <= k <= len(items):
        raise ValueError(f"cannot choose {k} of {len(items)} items")
    pool = list(range(len(items)))
    for j in range(k):
        r = j + min(int(rng.random() * (len(pool) - j)), len(pool) - j - 1)
        pool[j], pool[r] = pool[r], pool[j]
    return tuple(items[i] for i in sorted(pool[:k]))


def triangular_inverse_cdf(a: float, b: float, c: float, u: float) -> float:
    """The x with Tr-CDF(x | a, b, c) = u, for a ≤ c ≤ b; a = b gives the point a.

    Clamped to [a, b]: at u within an ulp of 0 or 1, rounding could step just outside.
    """
    if a == b:
        return a
    if u * (b - a) < c - a:
        x = a + math.sqrt(u * (b - a) * (c - a))
    else:
        x = b - math.sqrt((1.0 - u) * (b - a) * (b - c))
    return min(max(x, a), b)


class Categorical:
    """A categorical distribution over indices 0 … n−1, proportional to ``weights``.

    Compiled once (running sums), sampled with one uniform double; zero-weight indices are
    never drawn.
    """

    __slots__ = ("cum", "probabilities")

    def __init__(self, weights: Sequence[float]):
        self.cum = cumulative([float(w) for w in weights])
        total = self.cum[-1]
        self.probabilities = tuple(float(w) / total for w in weights)

    def sample(self, *, rng: np.random.Generator) -> int:
        """One index (one uniform double)."""
        return categorical_index(self.cum, rng.random())

    def pmf(self, k: int) -> float:
        """P(X = k)."""
        return self.probabilities[k] if 0 <= k < len(self.probabilities) else 0.0

    def cdf(self, k: int) -> float:
        """P(X ≤ k)."""
        if k < 0:
            return 0.0
        return self.cum[min(k, len(self.cum) - 1)] / self.cum[-1]


class Uniform(BaseModel):
    """U(low, high); low == high is a point mass."""

    model_config = _FROZEN
    kind: Literal["uniform"] = "uniform"
    low: float = Field(allow_inf_nan=False, strict=True)
    high: float = Field(allow_inf_nan=False, strict=True)

    @model_validator(mode="after")
    def _ordered(self) -> Uniform:
        if self.low > self.high:
            raise ValueError(f"low ({self.low}) must not exceed high ({self.high})")
        return self

    def sample(self, *, rng: np.random.Generator) -> float:
        """One draw (one uniform double)."""
        return self.low + (self.high - self.low) * rng.random()

    def pdf(self, x: np.ndarray | float) -> np.ndarray:
        """Density; a point mass has infinite density at its point."""
        x = np.asarray(x, dtype=float)
        if self.low == self.high:
            return np.where(x == self.low, np.inf, 0.0)
        return np.where((x >= self.low) & (x <= self.high), 1.0 / (self.high - self.low), 0.0)

    def cdf(self, x: np.ndarray | float) -> np.ndarray:
        """P(X ≤ x)."""
        x = np.asarray(x, dtype=float)
        if self.low == self.high:
            return np.where(x >= self.low, 1.0, 0.0)
        return np.clip((x - self.low) / (self.high - self.low), 0.0, 1.0)

    def mean(self) -> float:
        """E[X]."""
        return 0.5 * (self.low + self.high)

    @property
    def support(self) -> tuple[float, float]:
        """(lowest, highest) value."""
        return (self.low, self.high)


class Bernoulli(BaseModel):
    """True with probability ``p``."""

    model_config = _FROZEN
    kind: Literal["bernoulli"] = "bernoulli"
    p: float = Field(ge=0.0, le=1.0, allow_inf_nan=False, strict=True)

    def sample(self, *, rng: np.random.Generator) -> bool:
        """True with probability p (one uniform double)."""
        return rng.random() < self.p

    def pmf(self, x: bool) -> float:
        """P(X = x)."""
        return self.p if x else 1.0 - self.p

    def cdf(self, x: float) -> float:
        """P(X ≤ x) with False = 0, True = 1."""
        return 0.0 if x < 0 else (1.0 - self.p if x < 1 else 1.0)


class Triangular(BaseModel):
    """The paper's Tr(x | a, b, c): a = ``min``, b = ``max``, c = ``mode``.

    With a ``period`` (24 for clock hours) an interval may wrap: ``min`` > ``max`` means
    the support runs from ``min`` up through the period's end and on to ``max`` (night,
    20h → 7h with mode 0h). Samples and pdf/cdf arguments then live in [0, period).
    Degenerate cases are defined: a = c (decreasing), c = b (increasing), a = b (a point).
    """

    model_config = _FROZEN
    kind: Literal["triangular"] = "triangular"
    min: float = Field(allow_inf_nan=False, strict=True)
    max: float = Field(allow_inf_nan=False, strict=True)
    mode: float = Field(allow_inf_nan=False, strict=True)
    period: float | None = Field(default=None, gt=0.0, allow_inf_nan=False, strict=True)

    @model_validator(mode="after")
    def _ordered(self) -> Triangular:
        a, b, c = self.unwrapped()
        if self.period is not None:
            for name in ("min", "max", "mode"):
                v = getattr(self, name)
                if not 0.0 <= v < self.period:
                    raise ValueError(f"{name} ({v}) must lie in [0, period={self.period})")
        elif self.min > self.max:
            raise ValueError(f"min ({self.min}) must not exceed max ({self.max})")
        if not a <= c <= b:
            raise ValueError(f"mode ({self.mode}) must lie between min ({self.min}) and max ({self.max})")
        return self

    @property
    def wraps(self) -> bool:
        """Whether the interval runs past the end of the period (night: 20h → 7h)."""
        return self.period is not None and self.min > self.max

    def unwrapped(self) -> tuple[float, float, float]:
        """(a, b, c) on the real line: a wrapped interval is shifted past the period."""
        a, b, c = self.min, self.max, self.mode
        if self.period is not None and a > b:
            b += self.period
            if c < a:
                c += self.period
        return a, b, c

    def sample(self, *, rng: np.random.Generator) -> float:
        """One draw by inverse CDF (one uniform double), wrapped into [0, period) if needed."""
        x = triangular_inverse_cdf(*self.unwrapped(), rng.random())
        if self.wraps:
            x = math.fmod(x, self.period)
        return x

    def _cdf_unwrapped(self, x: np.ndarray) -> np.ndarray:
        a, b, c = self.unwrapped()
        if a == b:
            return np.where(x >= a, 1.0, 0.0)
        left = np.where(c > a, (x - a) ** 2 / ((b - a) * max(c - a, 1e-300)), 0.0)
        right = np.where(c < b, 1.0 - (b - x) ** 2 / ((b - a) * max(b - c, 1e-300)), 1.0)
        return np.where(x <= a, 0.0, np.where(x >= b, 1.0, np.where(x <= c, left, right)))

    def _pdf_unwrapped(self, x: np.ndarray) -> np.ndarray:
        a, b, c = self.unwrapped()
        if a == b:
            return np.where(x == a, np.inf, 0.0)
        up = np.where(c > a, 2.0 * (x - a) / ((b - a) * max(c - a, 1e-300)), 0.0)
        down = np.where(c < b, 2.0 * (b - x) / ((b - a) * max(b - c, 1e-300)), 0.0)
        peak = 2.0 / (b - a)
        inside = (x >= a) & (x <= b)
        return np.where(inside, np.where(x < c, up, np.where(x == c, peak, down)), 0.0)

    def cdf(self, x: np.ndarray | float) -> np.ndarray:
        """P(X <= x); for a wrapped interval, x is a time of the period in [0, period)."""
        x = np.asarray(x, dtype=float)
        if not self.wraps:
            return self._cdf_unwrapped(x)
        p = self.period
        # X mod p <= x  ⇔  X ∈ [a, x] (when x ≥ a)  or  X ∈ [p, p + x].
        head = np.where(x >= self.min, self._cdf_unwrapped(x), 0.0)
        tail = self._cdf_unwrapped(x + p) - self._cdf_unwrapped(np.asarray(p))
        return np.clip(head + tail, 0.0, 1.0)

    def pdf(self, x: np.ndarray | float) -> np.ndarray:
        """The paper's Tr(x | a, b, c); for a wrapped interval, x is a time of the period."""
        x = np.asarray(x, dtype=float)
        if not self.wraps:
            return self._pdf_unwrapped(x)
        return np.where(x >= self.min, self._pdf_unwrapped(x), self._pdf_unwrapped(x + self.period))

    def mean(self) -> float:
        """Mean on the real line (for a wrapped interval: of the unwrapped variable)."""
        return sum(self.unwrapped()) / 3.0

    @property
    def support(self) -> tuple[float, float]:
        """(min, max); for a wrapped interval min > max."""
        return (self.min, self.max)


#: A continuous parameter in θ: ``kind`` selects the family.
Continuous = Annotated[Uniform | Triangular, Field(discriminator="kind")]
