"""``phav bench --sections realism``: seconds per judged frame, and how wide each headline
figure's interval is at a number of judged frames — what a tighter interval costs."""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from phav_validators.realism.check import HEADLINES, Figure, RealismOptions, run_realism


@dataclass(frozen=True)
class RealismPoint:
    """One realism run: ``frames`` judged in ``seconds``, the headline figures it gave."""

    frames: int
    seconds: float
    people: int
    figures: dict[str, Figure]

    @property
    def seconds_per_frame(self) -> float:
        return self.seconds / max(self.frames, 1)


def bench_realism(root: Path, frame_counts: Sequence[int], *, seed: int = 0, threads: int = 1) -> list[RealismPoint]:
    """The realism check on ``root`` at each frame count (the same seed: each sample draws
    from the same permutation of the dataset's frames, so a larger one contains a smaller)."""
    from phav_validators.realism.judges import load_judges

    load_judges(None, threads)  # loading the models is not judging: out of the timings
    points = []
    for n in frame_counts:
        start = time.perf_counter()
        result = run_realism(root, RealismOptions(frames=n, seed=seed, threads=threads))
        seconds = time.perf_counter() - start
        figures = {name: f for name, key in HEADLINES.items() if (f := result.get(key)) is not None}
        points.append(RealismPoint(result.frames, seconds, result.people, figures))
    return points
