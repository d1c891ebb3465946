"""``phav bench``: each capability adds a section reporting speed against error."""

from __future__ import annotations

import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from phav_generator.sampling import RecipeSampler
from phav_spec.expectations import ExactTable, exact_expectations
from phav_spec.recipe_table import RecipeRows, write_recipe_table
from phav_spec.theta import Theta


@dataclass(frozen=True)
class SamplingRun:
    n: int
    recipes_per_s: float  # sampling and validating recipes, one process
    parquet_bytes: int
    camera_error: float  # max |observed − exact| over the camera marginal
    action_error: float
    duration_error: float  # |observed − exact| mean clip length, seconds
    worst_p: float  # smallest raw p-value over all goodness-of-fit tests
    rejected: int  # tests rejected after the Holm correction (0 = consistent with θ)
    n_tests: int


def _max_abs_error(column: list, table: ExactTable) -> float:
    """Largest |observed − exact| frequency over a variable's values."""
    observed = np.array([column.count(v) for v in table.values], dtype=float) / max(len(column), 1)
    return float(np.abs(observed - table.marginal()).max())


def bench_sampling(theta: Theta, *, n: int, seed: int, out_dir: Path | None = None) -> list[SamplingRun]:
    """Sample n/40, n/4 and n recipes; time the sampler and measure the distance from θ."""
    from phav_validators.distribution import check_distributions

    exact = exact_expectations(theta)
    sizes = sorted({max(100, n // 40), max(100, n // 4), n})
    runs = []
    with tempfile.TemporaryDirectory() as tmp:
        folder = out_dir or Path(tmp)
        for size in sizes:
            sampler = RecipeSampler(theta)
            rows = RecipeRows()
            start = time.perf_counter()
            for i in range(size):
                rows.add(sampler.sample(seed, i))
            elapsed = time.perf_counter() - start
            nbytes = write_recipe_table(rows.to_arrow(theta=theta, dataset_seed=seed), folder / f"bench-{size}.parquet")
            result = check_distributions(rows.columns, theta)
            runs.append(SamplingRun(
                n=size,
                recipes_per_s=size / elapsed,
                parquet_bytes=nbytes,
                camera_error=_max_abs_error(rows.columns["camera"], exact["camera"]),
                action_error=_max_abs_error(rows.columns["action"], exact["action"]),
                duration_error=abs(result.mean_duration - result.expected_mean_duration),
                worst_p=min(t.p_value for t in result.tests),
                rejected=sum(t.rejected for t in result.tests),
                n_tests=len(result.tests),
            ))  # fmt: skip
    return runs


@dataclass(frozen=True)
class PhysicsRun:
    """One physics timestep against the 1/1920 s reference, over a set of recipes."""

    hz: int
    ms_per_frame: float  # MuJoCo + control per output frame, one-person scenes
    pinned_error_m: float  # max joint deviation from the reference while pins hold the body
    released_error_m: float  # max deviation of released (falling) ragdolls: chaotic, reported apart
    pinned_clip_errors_m: tuple[float, ...] = ()  # the max deviation of each pinned clip

    def clips_within(self, tolerance_m: float) -> int:
        """Pinned clips whose joints stay within ``tolerance_m`` of the reference."""
        return sum(e < tolerance_m for e in self.pinned_clip_errors_m)


PHYSICS_RATES = (120, 240, 480, 960)
REFERENCE_HZ = 1920


def bench_physics(recipes: list, released: list, *, rates: tuple[int, ...] = PHYSICS_RATES) -> list[PhysicsRun]:
    """Timestep against error: joint positions of each rate vs a 1/1920 s reference.

    ``recipes`` are one-person scenes whose pins hold (the speed is measured on them);
    ``released`` are scenes whose ragdoll is let go (car hit), reported separately.
    """
    from phav_generator.physics.simulate import simulate
    from phav_generator.skeleton import JOINT_BODIES

    def joints(recipe, hz):
        t0 = time.perf_counter()
        tr = simulate(recipe, physics_hz=hz, keep_state=False)
        elapsed = time.perf_counter() - t0
        return tr.people[0].body_pos[:, list(JOINT_BODIES)], elapsed, tr.n_frames + 1

    refs = [joints(r, REFERENCE_HZ)[0] for r in recipes]
    refs_released = [joints(r, REFERENCE_HZ)[0] for r in released]
    out = []
    for hz in rates:
        errors = []
        seconds = 0.0
        frames = 0
        for r, ref in zip(recipes, refs, strict=True):
            j, elapsed, n = joints(r, hz)
            errors.append(float(np.linalg.norm(j - ref, axis=-1).max()))
            seconds += elapsed
            frames += n
        rel = 0.0
        for r, ref in zip(released, refs_released, strict=True):
            j, _, _ = joints(r, hz)
            rel = max(rel, float(np.linalg.norm(j - ref, axis=-1).max()))
        out.append(PhysicsRun(hz, 1000.0 * seconds / max(frames, 1), max(errors, default=0.0), rel, tuple(errors)))
    return out
