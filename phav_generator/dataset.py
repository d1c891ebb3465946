"""Recipes → a dataset directory: shards, metadata tables and the manifest, resumably.

Layout (DESIGN.md): ``{name}-{000000}.tar`` shards beside ``theta.yaml`` (when θ is known),
``recipes.parquet``, ``cameras.parquet``, ``people.parquet`` and ``manifest.json``.

A shard is the unit of work and of resumption. Each is a pure function of its recipes, so
the worker count and completion order cannot change a byte. A shard is finished when its
record ``.phav-work/{shard}.json`` exists (written atomically after the tar and its
metadata parts); ``write_dataset`` on a directory holding finished shards of the same run
skips them. The tables and the manifest are assembled last, then the work folder goes.
"""

from __future__ import annotations

import json
import multiprocessing
import platform
import queue
import shutil
from collections.abc import Callable, Sequence
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from dataclasses import dataclass
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path
from typing import Any

from phav_spec.canonical import canonical_json
from phav_spec.errors import PhavUserError
from phav_spec.files import atomic_write
from phav_spec.manifest import (
    MANIFEST_VERSION,
    DatasetManifest,
    RendererFingerprint,
    ShardEntry,
    VideoEntry,
    dump_manifest,
)
from phav_spec.metadata import CAMERA_COLUMNS, PEOPLE_COLUMNS, arrow_schema, frame_json
from phav_spec.recipe import RECIPE_SCHEMA_VERSION, Recipe, parse_recipe
from phav_spec.recipe_table import RecipeRows, write_recipe_table
from phav_spec.theta import Theta

WORK_DIR = ".phav-work"
RUN_FILE = "run.json"
#: Videos per shard unless told otherwise.
DEFAULT_SHARD_SIZE = 16

#: Called with (videos finished, frames finished) increments as work completes.
Progress = Callable[[int, int], None]


def _version(package: str) -> str:
    try:
        return version(package)
    except PackageNotFoundError:
        return "unknown"


def _cpu() -> tuple[str, str]:
    """CPU model name and sorted flags (Linux ``/proc/cpuinfo``; the platform elsewhere)."""
    model, flags = platform.processor() or platform.machine(), ""
    try:
        text = Path("/proc/cpuinfo").read_text(encoding="utf-8", errors="replace")
    except OSError:
        return model, flags
    for line in text.splitlines():
        key, _, value = line.partition(":")
        key = key.strip()
        if key == "model name" and model in ("", platform.machine(), platform.processor()):
            model = value.strip()
        elif key in ("flags", "Features") and not flags:
            flags = " ".join(sorted(value.split()))
    return model, flags


def renderer_fingerprint(gl: dict[str, str]) -> RendererFingerprint:
    """Everything the pixels depend on: GL strings, CPU, and the versions of the stack."""
    model, flags = _cpu()
    return RendererFingerprint(
        gl_vendor=gl["GL_VENDOR"],
        gl_renderer=gl["GL_RENDERER"],
        gl_version=gl["GL_VERSION"],
        cpu_model=model,
        cpu_flags=flags,
        versions={p: _version(p) for p in ("phav", "numpy", "mujoco", "moderngl")},
    )


def shard_name(name: str, index: int) -> str:
    return f"{name}-{index:06d}.tar"


@dataclass(frozen=True)
class ShardTask:
    """One shard to render: its name and the JSON of its recipes, in order."""

    name: str
    recipes: tuple[str, ...]


# --- worker side ---------------------------------------------------------------------------

_worker_ctx: Any = None
_worker_events: Any = None


def _init_worker(events: Any) -> None:
    global _worker_events
    _worker_events = events


def _context() -> Any:
    """This process's GL context, made on first use (one per worker process)."""
    global _worker_ctx
    if _worker_ctx is None:
        from phav_generator.render.gl import gl_context

        _worker_ctx = gl_context()
    return _worker_ctx


def render_shard(task: ShardTask, out: Path, report: Progress | None = None) -> dict[str, Any]:
    """Render one shard's videos into ``out/{task.name}`` and its metadata parts; returns
    the shard's record (also written to the work folder, last, as the shard's commit)."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    from phav_generator.io.shards import open_shard
    from phav_generator.render.gl import gl_strings
    from phav_generator.render.video import render_video
    from phav_spec.encoding import VideoHashes

    ctx = _context()
    work = out / WORK_DIR
    cameras: list[dict[str, Any]] = []
    people: list[dict[str, Any]] = []
    videos: list[dict[str, Any]] = []
    with open_shard(out / task.name) as (shard, digest):
        for text in task.recipes:
            recipe = parse_recipe(text, source=f"{task.name} recipe")
            hashes = VideoHashes(recipe.n_frames)
            for rf in render_video(recipe, ctx=ctx):
                hashes.add(rf.index, rf.modalities)
                shard.add_frame(recipe.video_id, rf.index, rf.modalities, frame_json(rf.camera, rf.people))
                cameras.append(rf.camera)
                people += rf.people
                if report is not None:
                    report(0, 1)
            videos.append({
                "video_id": recipe.video_id, "shard": task.name, "n_frames": recipe.n_frames,
                "content_hash": hashes.video_hash(), "modality_hashes": hashes.hexdigests(),
            })  # fmt: skip
            if report is not None:
                report(1, 0)
    stem = task.name.removesuffix(".tar")
    for table, rows, columns in (("cameras", cameras, CAMERA_COLUMNS), ("people", people, PEOPLE_COLUMNS)):
        with atomic_write(work / f"{stem}.{table}.parquet") as tmp:
            pq.write_table(pa.Table.from_pylist(rows, schema=arrow_schema(columns)), tmp, compression="zstd")
    record = {
        "shard": {"name": task.name, "sha256": digest.sha256, "bytes": digest.bytes,
                  "video_ids": [v["video_id"] for v in videos]},
        "videos": videos,
        "gl": gl_strings(ctx),
    }  # fmt: skip
    with atomic_write(work / f"{stem}.json") as tmp:
        tmp.write_text(canonical_json(record), encoding="utf-8")
    return record


def _pool_render(task: ShardTask, out: str) -> dict[str, Any]:
    def report(videos: int, frames: int) -> None:
        if _worker_events is not None:
            _worker_events.put((videos, frames))

    return render_shard(task, Path(out), report)


# --- driver side ---------------------------------------------------------------------------


@dataclass(frozen=True)
class DatasetResult:
    manifest: DatasetManifest
    rendered_shards: int
    resumed_shards: int


def _read_record(path: Path, out: Path) -> dict[str, Any] | None:
    """A finished shard's record, or None when the shard must be (re)rendered."""
    try:
        record = json.loads(path.read_text(encoding="utf-8"))
        tar = out / record["shard"]["name"]
        if tar.stat().st_size != record["shard"]["bytes"]:
            return None
        return record
    except (OSError, ValueError, KeyError, TypeError):
        return None


def _check_run(work: Path, run: dict[str, Any]) -> None:
    """Refuse to mix two different runs in one directory; remember this run otherwise."""
    path = work / RUN_FILE
    if path.exists():
        try:
            before = json.loads(path.read_text(encoding="utf-8"))
        except (OSError, ValueError):
            before = None
        if isinstance(before, dict) and before != run:
            differs = sorted(k for k in set(before) | set(run) if before.get(k) != run.get(k))
            raise PhavUserError(
                f"the directory holds an unfinished run with other settings ({', '.join(differs)} differ); "
                "use another --out, or delete the directory to start over",
                source=str(work.parent),
                field=differs[0] if differs else None,
            )
    with atomic_write(path) as tmp:
        tmp.write_text(canonical_json(run), encoding="utf-8")


def write_dataset(
    shards: Sequence[Sequence[Recipe]],
    out: str | Path,
    *,
    name: str,
    theta: Theta | None,
    dataset_seed: int,
    workers: int = 1,
    progress: Progress | None = None,
    shard_names: Sequence[str] | None = None,
) -> DatasetResult:
    """Render ``shards`` (lists of recipes; shard i is ``{name}-{i:06d}.tar`` unless
    ``shard_names`` says otherwise) into ``out``.

    Finished shards of the same run found in ``out`` are kept, not redone. Writes
    ``theta.yaml`` (when θ is given), ``recipes.parquet``, ``cameras.parquet``,
    ``people.parquet`` and, last, ``manifest.json``.
    """
    import pyarrow as pa
    import pyarrow.parquet as pq

    out = Path(out)
    if out.exists() and not out.is_dir():
        raise PhavUserError("exists and is not a directory", source=str(out), field="--out")
    work = out / WORK_DIR
    try:
        work.mkdir(parents=True, exist_ok=True)
    except OSError as e:
        raise PhavUserError(f"cannot create the output directory: {e.strerror or e}", source=str(out)) from None
    names = list(shard_names) if shard_names is not None else [shard_name(name, i) for i in range(len(shards))]
    if len(names) != len(shards) or len(set(names)) != len(names):
        raise ValueError("shard_names must name every shard once")
    tasks = [
        ShardTask(n, tuple(r.model_dump_json() for r in recipes)) for n, recipes in zip(names, shards, strict=True)
    ]
    run = {
        "name": name,
        "theta_hash": theta.hash if theta is not None else None,
        "dataset_seed": dataset_seed,
        "shards": [[r.video_id for r in recipes] for recipes in shards],
        "recipes_hash": _recipes_digest(tasks),
    }
    _check_run(work, run)
    if theta is not None:
        with atomic_write(out / "theta.yaml") as tmp:
            tmp.write_text(theta.to_yaml(), encoding="utf-8")
    all_recipes = [r for recipes in shards for r in recipes]
    write_recipe_table(RecipeRows().extend(all_recipes).to_arrow(theta=theta, dataset_seed=dataset_seed),
                       out / "recipes.parquet")  # fmt: skip

    records: dict[str, dict[str, Any]] = {}
    todo = []
    for task, recipes in zip(tasks, shards, strict=True):
        record = _read_record(work / f"{task.name.removesuffix('.tar')}.json", out)
        if record is not None:
            records[task.name] = record
            if progress is not None:
                progress(len(recipes), sum(r.n_frames for r in recipes))
        else:
            todo.append(task)
    resumed = len(records)
    _render_all(todo, out, workers, progress, records)

    gl = {json.dumps(records[t.name]["gl"], sort_keys=True) for t in tasks}
    if len(gl) > 1:
        raise PhavUserError(
            "shards were rendered by different GL renderers; delete the directory and regenerate on one machine",
            source=str(out),
        )
    fingerprint = renderer_fingerprint(records[tasks[0].name]["gl"]) if tasks else None
    for table, columns in (("cameras", CAMERA_COLUMNS), ("people", PEOPLE_COLUMNS)):
        parts = [pq.read_table(work / f"{t.name.removesuffix('.tar')}.{table}.parquet") for t in tasks]
        merged = pa.concat_tables(parts) if parts else arrow_schema(columns).empty_table()
        with atomic_write(out / f"{table}.parquet") as tmp:
            pq.write_table(merged, tmp, compression="zstd")
    manifest = DatasetManifest(
        manifest_version=MANIFEST_VERSION,
        name=name,
        phav_version=_version("phav"),
        theta_hash=theta.hash if theta is not None else None,
        dataset_seed=dataset_seed,
        recipe_schema_version=RECIPE_SCHEMA_VERSION,
        renderer=fingerprint,
        shards=[ShardEntry.model_validate(records[t.name]["shard"]) for t in tasks],
        videos=[VideoEntry.model_validate(v) for t in tasks for v in records[t.name]["videos"]],
    )
    dump_manifest(manifest, out / "manifest.json")
    shutil.rmtree(work, ignore_errors=True)
    return DatasetResult(manifest, rendered_shards=len(todo), resumed_shards=resumed)


def _recipes_digest(tasks: Sequence[ShardTask]) -> str:
    from phav_spec.canonical import sha256_hex

    return sha256_hex(canonical_json([list(t.recipes) for t in tasks]))


def _render_all(
    tasks: Sequence[ShardTask], out: Path, workers: int, progress: Progress | None, records: dict[str, Any]
) -> None:
    """Render every task, in this process (one worker) or a pool of spawned processes."""
    if not tasks:
        return
    if workers <= 1 or len(tasks) == 1:
        for task in tasks:
            records[task.name] = render_shard(task, out, progress)
        return
    mp = multiprocessing.get_context("spawn")
    events = mp.Queue()
    with ProcessPoolExecutor(
        max_workers=min(workers, len(tasks)), mp_context=mp, initializer=_init_worker, initargs=(events,)
    ) as pool:
        futures: dict[Future, ShardTask] = {pool.submit(_pool_render, t, str(out)): t for t in tasks}
        pending = set(futures)
        while pending:
            done, pending = wait(pending, timeout=0.2, return_when=FIRST_COMPLETED)
            _drain(events, progress)
            for fut in done:
                records[futures[fut].name] = fut.result()
        _drain(events, progress)


def _drain(events: Any, progress: Progress | None) -> None:
    while True:
        try:
            videos, frames = events.get_nowait()
        except (queue.Empty, OSError, ValueError):
            return
        if progress is not None:
            progress(videos, frames)


def chunk(recipes: Sequence[Recipe], shard_size: int) -> list[list[Recipe]]:
    """Consecutive videos, ``shard_size`` per shard (the last may hold fewer)."""
    if shard_size < 1:
        raise PhavUserError(f"must be at least 1, got {shard_size}", field="--shard-size")
    return [list(recipes[i : i + shard_size]) for i in range(0, len(recipes), shard_size)]


__all__ = [
    "DEFAULT_SHARD_SIZE",
    "DatasetResult",
    "ShardTask",
    "chunk",
    "render_shard",
    "renderer_fingerprint",
    "shard_name",
    "write_dataset",
]
