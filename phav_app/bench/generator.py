"""``phav bench``: each capability adds a section reporting speed against error."""

from __future__ import annotations

import datetime
import os
import platform
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from phav_generator.dataset.fingerprint import renderer_fingerprint
from phav_generator.dataset.write import DEFAULT_SHARD_SIZE, chunk, write_dataset
from phav_generator.io.png import encode_png
from phav_generator.io.shards import open_shard
from phav_generator.motion.skeleton import JOINT_BODIES
from phav_generator.physics.simulate import simulate
from phav_generator.render.annotations import MetadataBuilder
from phav_generator.render.context import gl_context, gl_strings
from phav_generator.render.modalities import encode_frame
from phav_generator.render.video import scene_renderer
from phav_generator.sampling import RecipeSampler, sample_recipes
from phav_spec.encoding import MODALITIES, VideoHashes
from phav_spec.expectations import ExactTable, exact_expectations
from phav_spec.metadata import frame_json
from phav_spec.recipe_table import RecipeRows, write_recipe_table
from phav_spec.theta import Theta
from phav_validators.checks.distribution import check_distributions


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
                worst_p=min((t.p_value for t in result.tests if t.tested), default=1.0),
                rejected=sum(t.rejected for t in result.tests),
                n_tests=sum(t.tested for t in result.tests),
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


@dataclass(frozen=True)
class RenderRun:
    """One pass of the render bench over the scene set at one supersampling factor."""

    supersample: int
    frames: int
    seconds: dict[str, float]  # physics, render, post, encode, write
    edge_error: float | None  # mean |RGB − 4× reference| on edge pixels, 8-bit levels
    triangles_built: dict[str, float]  # per environment, mean over its videos of the scene total
    triangles_drawn: dict[str, float]  # per environment, mean per frame after culling
    hashes: dict[str, str]  # video id → content hash

    @property
    def fps(self) -> float:
        return self.frames / max(sum(self.seconds.values()), 1e-9)

    def stage_fps(self, stage: str) -> float:
        return self.frames / max(self.seconds[stage], 1e-9)


def _edges(semantic: np.ndarray, depth: np.ndarray) -> np.ndarray:
    """Pixels on a class boundary or a depth step of more than 5 %."""
    cls = semantic.astype(np.int64) @ np.array([65536, 256, 1])
    d = depth.astype(np.float64)
    edge = np.zeros(cls.shape, dtype=bool)
    for axis in (0, 1):
        step = (np.diff(cls, axis=axis) != 0) | (np.abs(np.diff(d, axis=axis)) > 0.05 * np.minimum(
            np.delete(d, -1, axis=axis), np.delete(d, 0, axis=axis)))  # fmt: skip
        lo = [slice(None), slice(None)]
        hi = [slice(None), slice(None)]
        lo[axis], hi[axis] = slice(None, -1), slice(1, None)
        edge[tuple(lo)] |= step
        edge[tuple(hi)] |= step
    return edge


@dataclass(frozen=True)
class BodyShare:
    """What the people and the world's assets cost per frame: the same frames rendered with
    everything, without the people, and with the objects drawn as their colliders' boxes."""

    frames: int
    render_s: float  # render_labels + render_rgb, with the people and the assets
    render_without_s: float  # the same without the people
    build_s: float  # the scenes' drawables, with the people (meshes cached per process)
    build_without_s: float
    render_boxes_s: float  # with the people, the objects as boxes
    build_boxes_s: float

    @property
    def share(self) -> float:
        """The people's share of the frame's render time."""
        return (self.render_s - self.render_without_s) / max(self.render_s, 1e-9)

    @property
    def asset_share(self) -> float:
        """The assets' share of the frame's render time (over drawing their boxes)."""
        return (self.render_s - self.render_boxes_s) / max(self.render_s, 1e-9)


def bench_bodies(recipes: list, trajectories: list, ctx, *, supersample: int = 2,
                 max_frames: int | None = None) -> BodyShare:  # fmt: skip
    """Render every recipe's frames three times in one context: as generated, without its
    people, and with its objects drawn as their colliders' boxes."""
    times = dict.fromkeys(("render", "render_without", "render_boxes", "build", "build_without", "build_boxes"), 0.0)
    frames = 0
    for r, tr in zip(recipes, trajectories, strict=True):
        n = min(r.n_frames, max_frames or r.n_frames)
        frames += n
        for people, assets, key in ((True, True, ""), (False, True, "_without"), (True, False, "_boxes")):
            t0 = time.perf_counter()
            renderer = scene_renderer(r, tr, ctx, supersample=supersample, people=people, assets=assets)
            times["build" + key] += time.perf_counter() - t0
            with renderer:
                t0 = time.perf_counter()
                for f in range(n):
                    renderer.render(f, tr.cam_to_world[f], tr.cam_to_world[f + 1], tr.intrinsics)
                times["render" + key] += time.perf_counter() - t0
    return BodyShare(frames, times["render"], times["render_without"], times["build"], times["build_without"],
                     times["render_boxes"], times["build_boxes"])  # fmt: skip


def bench_render(
    recipes: list,
    *,
    factors: tuple[int, ...] = (1, 2),
    reference: int = 4,
    max_frames: int | None = None,
    gl: str = "llvmpipe",
) -> tuple[list[RenderRun], float, BodyShare]:
    """Each supersampling factor over the recipes, stage by stage, with the edge error of its
    RGB against ``reference``× supersampling; the encode-only rate (six PNGs, frames/s); and
    the people's share of a 2× frame."""

    ctx = gl_context(gl)
    trajectories, physics_s = [], 0.0
    for r in recipes:
        t0 = time.perf_counter()
        trajectories.append(simulate(r, keep_state=False))
        physics_s += time.perf_counter() - t0
    n_frames = [min(r.n_frames, max_frames or r.n_frames) for r in recipes]
    references: dict[tuple[int, int], np.ndarray] = {}
    runs, encode_only = [], 0.0
    tmp = Path(tempfile.mkdtemp(prefix="phav-bench-"))
    try:
        for factor in (reference, *factors):
            seconds = {"physics": physics_s * sum(n_frames) / sum(r.n_frames for r in recipes),
                       "render": 0.0, "post": 0.0, "encode": 0.0, "write": 0.0}  # fmt: skip
            errors, built, drawn, hashes = [], {}, {}, {}
            png_s = 0.0
            for vi, (r, tr, n) in enumerate(zip(recipes, trajectories, n_frames, strict=True)):
                renderer = scene_renderer(r, tr, ctx, supersample=factor)
                meta = MetadataBuilder(r, tr)
                h = VideoHashes(n)
                env = r.environment.name
                with open_shard(tmp / f"bench-{vi:06d}.tar") as (shard, _):
                    for f in range(n):
                        # The labelled pass and read-back ("render"), then supersampling and post.
                        t0 = time.perf_counter()
                        labels = renderer.render_labels(f, tr.cam_to_world[f], tr.cam_to_world[f + 1], tr.intrinsics)
                        t1 = time.perf_counter()
                        frame = renderer.render_rgb(labels)
                        seconds["render"] += t1 - t0
                        seconds["post"] += time.perf_counter() - t1
                        modalities = encode_frame(frame)
                        h.add(f, modalities)
                        t0 = time.perf_counter()
                        pngs = [encode_png(modalities[m.name], m) for m in MODALITIES]
                        png_s += time.perf_counter() - t0
                        js = frame_json(meta.camera_row(f), meta.people_rows(f, frame))
                        t1 = time.perf_counter()
                        for m, data in zip(MODALITIES, pngs, strict=True):
                            shard.add(f"{r.video_id}/{f:05d}.{m.key}", data)
                        shard.add(f"{r.video_id}/{f:05d}.json", js)
                        seconds["encode"] += t1 - t0
                        seconds["write"] += time.perf_counter() - t1
                        if factor == reference:
                            references[(vi, f)] = modalities["rgb"].astype(np.int16)
                        else:
                            edge = _edges(modalities["semantic"], modalities["depth"])
                            diff = np.abs(modalities["rgb"].astype(np.int16) - references[(vi, f)]).mean(axis=-1)
                            errors.append(float(diff[edge].mean()) if edge.any() else 0.0)
                built.setdefault(env, []).append(renderer.triangles_built)
                drawn.setdefault(env, []).append(renderer.triangles_drawn / max(n, 1))
                renderer.release()
                hashes[r.video_id] = h.video_hash()
            if factor == reference:
                encode_only = sum(n_frames) / max(png_s, 1e-9)
                continue
            runs.append(RenderRun(factor, sum(n_frames), seconds, float(np.mean(errors)) if errors else None,
                                  {e: float(np.mean(v)) for e, v in built.items()},
                                  {e: float(np.mean(v)) for e, v in drawn.items()}, hashes))  # fmt: skip
        bodies = bench_bodies(recipes, trajectories, ctx, supersample=2, max_frames=max_frames)
    finally:
        ctx.release()
        for p in tmp.glob("*"):
            p.unlink()
        tmp.rmdir()
    return runs, encode_only, bodies


#: A PHAV-sized run: the paper's 39,982 videos (about 6 million frames).
PHAV_VIDEOS = 39_982


@dataclass(frozen=True)
class GenerationRun:
    """``write_dataset`` of the same recipes with one worker count, timed end to end."""

    workers: int
    engine: str
    videos: int
    frames: int
    seconds: float
    identical: bool  # every file equals the first run's, byte for byte

    @property
    def fps(self) -> float:
        return self.frames / self.seconds


def bench_generation(
    recipes: list,
    theta: Theta,
    *,
    seed: int,
    workers: tuple[int, ...] = (1, 2),
    engine: str = "local",
    gl: str = "llvmpipe",
) -> list[GenerationRun]:
    """Frames per second of whole-dataset generation (render, encode, shards, tables,
    manifest) for each worker count; every run must give the first run's bytes."""

    frames = sum(r.n_frames for r in recipes)
    runs: list[GenerationRun] = []
    first: dict[str, bytes] | None = None
    with tempfile.TemporaryDirectory() as tmp:
        for w in workers:
            out = Path(tmp) / f"w{w}"
            start = time.perf_counter()
            write_dataset(chunk(recipes, DEFAULT_SHARD_SIZE), out, name="bench", theta=theta, dataset_seed=seed,
                          workers=w, engine=engine, gl=gl)  # fmt: skip
            seconds = time.perf_counter() - start
            files = {p.name: p.read_bytes() for p in sorted(out.iterdir()) if p.is_file()}
            first = files if first is None else first
            runs.append(GenerationRun(w, engine, len(recipes), frames, seconds, files == first))
    return runs


def mean_frames_per_video(theta: Theta, *, seed: int, n: int = 4000) -> float:
    """Mean clip length in frames of ``n`` recipes sampled from θ."""

    return float(np.mean([r.n_frames for r in sample_recipes(theta, n=n, seed=seed)]))


def machine_lines(gl: str = "llvmpipe") -> list[str]:
    """Markdown rows naming the machine and renderer (``gl``) the numbers were measured on."""

    ctx = gl_context(gl)
    try:
        fp = renderer_fingerprint(gl_strings(ctx))
    finally:
        ctx.release()
    memory = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES") / 1024**3
    versions = ", ".join(f"{k} {v}" for k, v in sorted(fp.versions.items()))
    return [
        "| | |",
        "|---|---|",
        f"| CPU | {fp.cpu_model} (SIMD class {fp.simd_class}), {os.cpu_count()} logical cores |",
        f"| memory | {memory:.0f} GiB |",
        f"| system | {platform.system()} {platform.release()}, Python {platform.python_version()} |",
        f"| GL | {fp.gl_vendor}; {fp.gl_renderer}; {fp.gl_version} |",
        f"| versions | {versions} |",
        f"| renderer fingerprint | `{fp.digest()}` |",
    ]


def benchmark_report(sections: dict[str, str], *, command: str, gl: str = "llvmpipe") -> str:
    """One Markdown page: the machine and renderer, then each bench section's tables as text."""

    lines = ["# Benchmarks", "", f"Made by `{command}` on {datetime.date.today().isoformat()}.", "",
             "Numbers depend on the machine and renderer below (the fingerprint names everything the pixels",
             "depend on: same fingerprint, same pixels). Rerun the command to measure yours.", "",
             *machine_lines(gl)]  # fmt: skip
    for name, text in sections.items():
        lines += ["", f"## {name}", "", "```", *(line.rstrip() for line in text.rstrip().splitlines()), "```"]
    return "\n".join(lines) + "\n"
