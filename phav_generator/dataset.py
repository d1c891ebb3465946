"""Recipes → a dataset directory: shards, metadata tables and the manifest, resumably.

Layout (DESIGN.md): ``{name}-{000000}.tar`` shards beside ``theta.yaml`` (when θ is known),
``recipes.parquet``, ``cameras.parquet``, ``people.parquet`` and ``manifest.json``.

A video is the unit of work, a pure function of its recipe, so neither the engine, the
worker count nor the completion order can change a byte. A worker renders a video into
``.phav-work/parts/`` (its tar members and metadata rows, each written atomically); the
driver journals it in ``.phav-work/journal.jsonl`` and, once a shard's videos are all in,
joins their parts into the shard's tar (atomically) and journals the shard. Rerunning on
the directory resumes from the journal: nothing it records is redone, and nothing it does
not record is trusted. The tables and the manifest are assembled last, then the work
folder goes.
"""

from __future__ import annotations

import contextlib
import json
import multiprocessing
import os
import platform
import queue
import re
import shutil
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path
from typing import Any

from phav_generator.faults import armed, crash_point, task_delay
from phav_spec.canonical import canonical_json, sha256_hex
from phav_spec.errors import PhavUserError
from phav_spec.files import WriteError, atomic_write
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
JOURNAL_FILE = "journal.jsonl"
LOCK_FILE = "lock"
PARTS_DIR = "parts"
#: Where videos are rendered: a local process pool, or a Ray cluster.
ENGINES = ("local", "ray")
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
class VideoTask:
    """One video to render: the shard it belongs to and its recipe's JSON."""

    shard: str
    video_id: str
    recipe: str
    #: The renderer (``render.context.GL_KINDS``): llvmpipe, the renderer of record, or egl-gpu.
    gl: str = "llvmpipe"


# --- worker side ---------------------------------------------------------------------------

_worker_ctx: dict[str, Any] = {}
_worker_events: Any = None


def _init_worker(events: Any) -> None:
    global _worker_events
    _worker_events = events


def _context(kind: str) -> Any:
    """This process's GL context of ``kind``, made on first use (one per worker process)."""
    if kind not in _worker_ctx:
        from phav_generator.render.context import gl_context

        _worker_ctx[kind] = gl_context(kind)
    return _worker_ctx[kind]


def _part_path(work: Path, video_id: str, what: str) -> Path:
    return work / PARTS_DIR / f"{video_id}.{what}"


def render_part(task: VideoTask, out: Path, report: Progress | None = None) -> dict[str, Any]:
    """Render one video into the work folder: its tar members (a *part* of its shard) and
    its metadata rows, each written atomically; returns the video's record."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    from phav_generator.io.shards import open_part
    from phav_generator.physics.simulate import simulate
    from phav_generator.render.context import gl_strings
    from phav_generator.render.video import render_video
    from phav_spec.encoding import VideoHashes

    task_delay(task.video_id)
    ctx = _context(task.gl)
    work = out / WORK_DIR
    recipe = parse_recipe(task.recipe, source=f"{task.shard} recipe {task.video_id}")
    hashes = VideoHashes(recipe.n_frames)
    cameras: list[dict[str, Any]] = []
    people: list[dict[str, Any]] = []
    with open_part(_part_path(work, recipe.video_id, "tar.part")) as part:
        trajectory = simulate(recipe, keep_state=False)
        for rf in render_video(recipe, trajectory, ctx=ctx):
            hashes.add(rf.index, rf.modalities)
            part.add_frame(recipe.video_id, rf.index, rf.modalities, frame_json(rf.camera, rf.people))
            cameras.append(rf.camera)
            people += rf.people
            crash_point(f"part:{recipe.video_id}:{rf.index}")
            if report is not None:
                report(0, 1)
    for table, rows, columns in (("cameras", cameras, CAMERA_COLUMNS), ("people", people, PEOPLE_COLUMNS)):
        with atomic_write(_part_path(work, recipe.video_id, f"{table}.parquet")) as tmp:
            pq.write_table(pa.Table.from_pylist(rows, schema=arrow_schema(columns)), tmp, compression="zstd")
    crash_point(f"part-done:{recipe.video_id}")
    return {
        "video_id": recipe.video_id, "shard": task.shard, "n_frames": recipe.n_frames,
        "content_hash": hashes.video_hash(), "modality_hashes": hashes.hexdigests(),
        "part_bytes": part.size, "gl": gl_strings(ctx),
    }  # fmt: skip


def _pool_render(task: VideoTask, out: str) -> dict[str, Any]:
    def report(videos: int, frames: int) -> None:
        if _worker_events is not None:
            _worker_events.put((videos, frames))

    return render_part(task, Path(out), report)


# --- the run journal -----------------------------------------------------------------------


class Journal:
    """The run's journal: one JSON line per finished video and per finished shard.

    Appended (and fsynced) by the driver only, after the file it records is in place, so a
    line never claims work that is not on disk. A line torn by a crash is cut off when the
    journal is opened again; everything before it stands.
    """

    def __init__(self, path: Path):
        self.path = path
        self.videos: dict[str, dict[str, Any]] = {}
        self.shards: dict[str, dict[str, Any]] = {}
        self._lines = 0
        good = 0
        try:
            data = path.read_bytes()
        except FileNotFoundError:
            data = b""
        for line in data.splitlines(keepends=True):
            if not line.endswith(b"\n"):
                break
            try:
                entry = json.loads(line)
                kind, record = entry["kind"], entry["record"]
            except (ValueError, KeyError, TypeError):
                break
            self._remember(kind, record)
            good += len(line)
            self._lines += 1
        if good != len(data):
            with open(path, "r+b") as fh:
                fh.truncate(good)
                os.fsync(fh.fileno())

    def append(self, kind: str, record: dict[str, Any]) -> None:
        line = (canonical_json({"kind": kind, "record": record}) + "\n").encode("utf-8")
        self._lines += 1
        with open(self.path, "ab") as fh:
            if armed(f"journal:{self._lines}"):
                fh.write(line[: len(line) // 2])
                fh.flush()
                crash_point(f"journal:{self._lines}")
            fh.write(line)
            fh.flush()
            os.fsync(fh.fileno())
        self._remember(kind, record)

    def _remember(self, kind: str, record: dict[str, Any]) -> None:
        if kind == "video":
            self.videos[record["video_id"]] = record
        else:
            self.shards[record["name"]] = record


# --- driver side ---------------------------------------------------------------------------


@dataclass(frozen=True)
class DatasetResult:
    manifest: DatasetManifest
    rendered_shards: int
    resumed_shards: int
    rendered_videos: int = 0
    resumed_videos: int = 0


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


#: What to do after a failed write: nothing finished is lost.
RESUME_HINT = "finished videos are kept; free space or fix the place, then rerun the same command to resume"


class _Run:
    """The driver's side of one run: journals finished videos, joins shards as their last
    video arrives, and knows what is left to do."""

    def __init__(self, out: Path, names: list[str], shards: Sequence[Sequence[Recipe]], progress: Progress | None):
        self.out, self.work = out, out / WORK_DIR
        self.names = names
        self.ids = {n: [r.video_id for r in recipes] for n, recipes in zip(names, shards, strict=True)}
        self.frames = {r.video_id: r.n_frames for recipes in shards for r in recipes}
        self.progress = progress
        (self.work / PARTS_DIR).mkdir(parents=True, exist_ok=True)
        self.journal = Journal(self.work / JOURNAL_FILE)
        self.resumed_shards = self.resumed_videos = self.rendered_shards = 0
        # What the journal claims must still be on disk: a missing or short file is redone.
        for name in list(self.journal.shards):
            rec = self.journal.shards[name]
            if name not in self.ids or not _has_size(out / name, rec["shard"]["bytes"]):
                del self.journal.shards[name]
        for vid in list(self.journal.videos):
            rec = self.journal.videos[vid]
            part = _part_path(self.work, vid, "tar.part")
            if vid not in self.frames or not (
                rec["shard"] in self.journal.shards or _has_size(part, rec["part_bytes"])
            ):
                del self.journal.videos[vid]

    def todo(self, tasks: Sequence[VideoTask]) -> list[VideoTask]:
        """Videos not finished yet, in index order; reports the finished ones as progress."""
        left = []
        for t in tasks:
            if t.shard in self.journal.shards or t.video_id in self.journal.videos:
                self.resumed_videos += 1
                if self.progress is not None:
                    self.progress(1, self.frames[t.video_id])
            else:
                left.append(t)
        self.resumed_shards = sum(n in self.journal.shards for n in self.names)
        for name in self.names:  # a crash between a shard's last video and its tar
            self._maybe_join(name)
        return left

    def finished(self, record: dict[str, Any]) -> None:
        self.journal.append("video", record)
        self._maybe_join(record["shard"])

    def _maybe_join(self, name: str) -> None:
        """Join the shard's parts into its tar once every one of its videos is journalled."""
        from phav_generator.io.shards import assemble_shard

        if name in self.journal.shards or any(v not in self.journal.videos for v in self.ids[name]):
            return
        ids = self.ids[name]
        videos = [self.journal.videos[v] for v in ids]
        if len({canonical_json(v["gl"]) for v in videos}) > 1:
            raise PhavUserError(
                f"the videos of {name} were rendered by different GL renderers; use one kind of machine",
                source=str(self.out),
            )
        digest = assemble_shard([_part_path(self.work, v, "tar.part") for v in ids], self.out / name,
                                checkpoint=lambda k: crash_point(f"shard:{name}:{k}"))  # fmt: skip
        stem = name.removesuffix(".tar")
        for table, columns in (("cameras", CAMERA_COLUMNS), ("people", PEOPLE_COLUMNS)):
            parts = [_part_path(self.work, v, f"{table}.parquet") for v in ids]
            _concat_parquet(parts, columns, self.work / f"{stem}.{table}.parquet")
        record = {
            "name": name,
            "shard": {"name": name, "sha256": digest.sha256, "bytes": digest.bytes, "video_ids": ids},
            "videos": [{k: v[k] for k in ("video_id", "shard", "n_frames", "content_hash", "modality_hashes")}
                       for v in videos],
            "gl": videos[0]["gl"],
        }  # fmt: skip
        self.journal.append("shard", record)
        self.rendered_shards += 1
        for v in ids:  # the shard holds them now
            for what in ("tar.part", "cameras.parquet", "people.parquet"):
                with contextlib.suppress(FileNotFoundError):
                    _part_path(self.work, v, what).unlink()


def _concat_parquet(parts: Sequence[Path], columns: Any, target: Path) -> None:
    """Rows of ``parts``, in order, into one zstd Parquet file at ``target`` (atomically)."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    tables = [pq.read_table(p) for p in parts]
    merged = pa.concat_tables(tables) if tables else arrow_schema(columns).empty_table()
    with atomic_write(target) as tmp:
        pq.write_table(merged, tmp, compression="zstd")


def _has_size(path: Path, size: int) -> bool:
    try:
        return path.stat().st_size == size
    except OSError:
        return False


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
    engine: str = "local",
    address: str | None = None,
    gl: str = "llvmpipe",
) -> DatasetResult:
    """Render ``shards`` (lists of recipes; shard i is ``{name}-{i:06d}.tar`` unless
    ``shard_names`` says otherwise) into ``out``.

    The unit of work is a video: ``engine`` ``"local"`` (a process pool of ``workers``) or
    ``"ray"`` (a Ray cluster at ``address``, else a local one) renders each into a part,
    and this process journals it and joins a shard's parts into its tar once all are in.
    Work already journalled in ``out`` for the same run is kept, not redone. Writes
    ``theta.yaml`` (when θ is given), ``recipes.parquet``, ``cameras.parquet``,
    ``people.parquet`` and, last, ``manifest.json``. ``gl`` picks the renderer
    (``render.context.gl_context``); the manifest's fingerprint records the one that rendered.
    """
    out = Path(out)
    if engine not in ENGINES:
        raise PhavUserError(f"unknown engine {engine!r}; choose one of {', '.join(ENGINES)}", field="--engine")
    if out.exists() and not out.is_dir():
        raise PhavUserError("exists and is not a directory", source=str(out), field="--out")
    names = list(shard_names) if shard_names is not None else [shard_name(name, i) for i in range(len(shards))]
    if len(names) != len(shards) or len(set(names)) != len(names):
        raise ValueError("shard_names must name every shard once")
    if gl != "llvmpipe":
        from phav_generator.render.context import check_gl_kind, require_gl

        check_gl_kind(gl)
        if engine == "local":  # a Ray cluster's workers may have GPUs this driver lacks
            require_gl(gl)
    tasks = [VideoTask(n, r.video_id, r.model_dump_json(), gl)
             for n, recipes in zip(names, shards, strict=True) for r in recipes]  # fmt: skip
    try:
        return _write(out, names, shards, tasks, name=name, theta=theta, dataset_seed=dataset_seed,
                      workers=workers, progress=progress, engine=engine, address=address)  # fmt: skip
    except WriteError as e:
        raise e.with_hint(RESUME_HINT) from None
    except OSError as e:
        raise WriteError(e, str(e.filename or out), RESUME_HINT) from None


def _write(out: Path, names: list[str], shards: Sequence[Sequence[Recipe]], tasks: list[VideoTask], *, name: str,
           theta: Theta | None, dataset_seed: int, workers: int, progress: Progress | None, engine: str,
           address: str | None) -> DatasetResult:  # fmt: skip
    work = out / WORK_DIR
    (work / PARTS_DIR).mkdir(parents=True, exist_ok=True)
    with _exclusive(work):
        _remove_stale_temporaries(out, work, work / PARTS_DIR)
        return _write_locked(out, names, shards, tasks, name=name, theta=theta, dataset_seed=dataset_seed,
                             workers=workers, progress=progress, engine=engine, address=address)  # fmt: skip


@contextlib.contextmanager
def _exclusive(work: Path) -> Iterator[None]:
    """Hold the directory's lock: two runs writing one directory would tear each other's files."""
    import fcntl

    with open(work / LOCK_FILE, "a+b") as fh:
        try:
            fcntl.flock(fh, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            raise PhavUserError("another run is writing to this directory", source=str(work.parent)) from None
        yield


#: ``atomic_write``'s temporaries: ``.{name}.{16 hex}.tmp``.
_TEMPORARY = re.compile(r"\..+\.[0-9a-f]{16}\.tmp")


def _remove_stale_temporaries(*folders: Path) -> None:
    """Temporaries a killed run left behind (a live run holds the lock, so none is in use)."""
    for folder in folders:
        for path in folder.iterdir():
            if _TEMPORARY.fullmatch(path.name) and path.is_file():
                path.unlink()


def _write_locked(out: Path, names: list[str], shards: Sequence[Sequence[Recipe]], tasks: list[VideoTask], *,
                  name: str, theta: Theta | None, dataset_seed: int, workers: int, progress: Progress | None,
                  engine: str, address: str | None) -> DatasetResult:  # fmt: skip

    work = out / WORK_DIR
    run = {
        "name": name,
        "theta_hash": theta.hash if theta is not None else None,
        "dataset_seed": dataset_seed,
        "shards": [[r.video_id for r in recipes] for recipes in shards],
        "shard_names": names,
        "recipes_hash": sha256_hex(canonical_json([t.recipe for t in tasks])),
        "gl": tasks[0].gl if tasks else None,  # a run never mixes renderers
    }
    _check_run(work, run)
    if theta is not None:
        with atomic_write(out / "theta.yaml") as tmp:
            tmp.write_text(theta.to_yaml(), encoding="utf-8")
    all_recipes = [r for recipes in shards for r in recipes]
    write_recipe_table(RecipeRows().extend(all_recipes).to_arrow(theta=theta, dataset_seed=dataset_seed),
                       out / "recipes.parquet")  # fmt: skip

    state = _Run(out, names, shards, progress)
    todo = state.todo(tasks)
    if engine == "ray":
        from phav_generator.engines import run_on_ray

        run_on_ray(todo, out, workers=workers, address=address, progress=progress, finished=state.finished)
    else:
        _run_local(todo, out, workers, progress, state.finished)

    records = state.journal.shards
    gl = {canonical_json(records[n]["gl"]) for n in names}
    if len(gl) > 1:
        raise PhavUserError(
            "shards were rendered by different GL renderers; delete the directory and regenerate on one machine",
            source=str(out),
        )
    fingerprint = renderer_fingerprint(records[names[0]]["gl"]) if names else None
    for table, columns in (("cameras", CAMERA_COLUMNS), ("people", PEOPLE_COLUMNS)):
        parts = [work / f"{n.removesuffix('.tar')}.{table}.parquet" for n in names]
        _concat_parquet(parts, columns, out / f"{table}.parquet")
    manifest = DatasetManifest(
        manifest_version=MANIFEST_VERSION,
        name=name,
        phav_version=_version("phav"),
        theta_hash=theta.hash if theta is not None else None,
        dataset_seed=dataset_seed,
        recipe_schema_version=RECIPE_SCHEMA_VERSION,
        renderer=fingerprint,
        shards=[ShardEntry.model_validate(records[n]["shard"]) for n in names],
        videos=[VideoEntry.model_validate(v) for n in names for v in records[n]["videos"]],
    )
    dump_manifest(manifest, out / "manifest.json")
    shutil.rmtree(work, ignore_errors=True)
    return DatasetResult(manifest, rendered_shards=state.rendered_shards, resumed_shards=state.resumed_shards,
                         rendered_videos=len(todo), resumed_videos=state.resumed_videos)  # fmt: skip


def _run_local(tasks: Sequence[VideoTask], out: Path, workers: int, progress: Progress | None,
               finished: Callable[[dict[str, Any]], None]) -> None:  # fmt: skip
    """Render every task in this process (one worker) or a pool of spawned processes."""
    if not tasks:
        return
    if workers <= 1 or len(tasks) == 1:
        for task in tasks:
            record = render_part(task, out, progress)
            if progress is not None:
                progress(1, 0)
            finished(record)
        return
    mp = multiprocessing.get_context("spawn")
    events = mp.Queue()
    with ProcessPoolExecutor(
        max_workers=min(workers, len(tasks)), mp_context=mp, initializer=_init_worker, initargs=(events,)
    ) as pool:
        futures: dict[Future, VideoTask] = {pool.submit(_pool_render, t, str(out)): t for t in tasks}
        pending = set(futures)
        try:
            while pending:
                done, pending = wait(pending, timeout=0.2, return_when=FIRST_COMPLETED)
                _drain(events, progress)
                # Journal in completion order: which video finishes first cannot change a byte.
                for fut in sorted(done, key=lambda f: futures[f].video_id):
                    record = fut.result()
                    if progress is not None:
                        progress(1, 0)
                    finished(record)
        except BrokenProcessPool:
            raise PhavUserError(
                "a worker process died (killed, or out of memory); finished videos are kept, rerun to resume",
                source=str(out),
            ) from None
        finally:
            for fut in pending:
                fut.cancel()
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
    "ENGINES",
    "DatasetResult",
    "Journal",
    "VideoTask",
    "chunk",
    "render_part",
    "renderer_fingerprint",
    "shard_name",
    "write_dataset",
]
