"""Recipes → a dataset directory: shards, metadata tables and the manifest, resumably.

Layout (DESIGN.md): ``{name}-{000000}.tar`` shards beside ``theta.yaml`` (when θ is known),
``recipes.parquet``, ``cameras.parquet``, ``people.parquet`` and ``manifest.json``.

A video is the unit of work, a pure function of its recipe (``pipeline.run_task``), so
neither the engine, the worker count nor the completion order can change a byte. A worker
renders a video into ``.phav-work/parts/`` (its tar members and metadata rows, each written
atomically); this driver journals it (``journal``) and, once a shard's videos are all in,
joins their parts into the shard's tar (atomically) and journals the shard. Rerunning on the
directory resumes from the journal: nothing it records is redone, and nothing it does not
record is trusted. Each video's record names the renderer, machine and phav code that made
it (``render_task``): a run is never resumed or joined by another, and the manifest's
fingerprint is theirs. The tables and the manifest are assembled last, then the work folder
is renamed away and deleted.
"""

from __future__ import annotations

import contextlib
import functools
import os
import shutil
import tarfile
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pyarrow as pa
import pyarrow.parquet as pq

from phav_generator.body.data import body_data_path, load_body_data
from phav_generator.dataset.fingerprint import (
    BODY_DATA_KEY,
    package_version,
    renderer_fingerprint,
    source_sha256,
)
from phav_generator.dataset.journal import JOURNAL_FILE, RUN_FILE, Journal, check_run
from phav_generator.dataset.lock import exclusive, remove_stale_temporaries
from phav_generator.engines import Progress, check_engine, run_tasks
from phav_generator.faults import crash_point
from phav_generator.io.shards import assemble_shard, read_members
from phav_generator.pipeline import PART_TABLES, VideoTask, part_path, run_task
from phav_generator.render.context import check_gl_kind, is_software_renderer, require_gl
from phav_spec.canonical import canonical_json, sha256_hex
from phav_spec.errors import PhavUserError
from phav_spec.files import WriteError, atomic_write, check_output_dir, read_parquet
from phav_spec.manifest import (
    MANIFEST_VERSION,
    DatasetManifest,
    RendererFingerprint,
    ShardEntry,
    VideoEntry,
    dump_manifest,
    load_manifest,
)
from phav_spec.metadata import arrow_schema, frame_rows
from phav_spec.recipe import RECIPE_SCHEMA_VERSION, Recipe
from phav_spec.recipe_table import RecipeRows, read_recipe_table, write_recipe_table
from phav_spec.release import RELEASE_FILE
from phav_spec.theta import Theta

WORK_DIR = ".phav-work"
#: The work folder of a finished run, renamed before it is deleted: a run whose work folder is
#: gone is finished, however far the deletion got before a kill.
DONE_DIR = ".phav-work.done"
PARTS_DIR = "parts"
#: Videos per shard unless told otherwise.
DEFAULT_SHARD_SIZE = 16
#: What to do after a failed write: nothing finished is lost.
RESUME_HINT = "finished videos are kept; free space or fix the place, then rerun the same command to resume"


def shard_name(name: str, index: int) -> str:
    """The file name of shard ``index`` of dataset ``name``: ``{name}-{index:06d}.tar``."""
    return f"{name}-{index:06d}.tar"


def chunk(recipes: Sequence[Recipe], shard_size: int) -> list[list[Recipe]]:
    """Consecutive videos, ``shard_size`` per shard (the last may hold fewer)."""
    if shard_size < 1:
        raise PhavUserError(f"must be at least 1, got {shard_size}", field="--shard-size")
    return [list(recipes[i : i + shard_size]) for i in range(0, len(recipes), shard_size)]


@dataclass(frozen=True)
class DatasetResult:
    """What a run wrote, and how much of it an earlier, interrupted run had already done."""

    manifest: DatasetManifest
    rendered_shards: int
    resumed_shards: int
    rendered_videos: int = 0
    resumed_videos: int = 0
    #: The directory held this run finished already: no video was rendered.
    already_finished: bool = False
    #: Tables the finished run lacked, made again from its shards and θ.
    remade_tables: tuple[str, ...] = ()

    @classmethod
    def finished_before(cls, manifest: DatasetManifest, remade_tables: tuple[str, ...] = ()) -> DatasetResult:
        """The run found finished in its directory: every shard and video resumed."""
        return cls(manifest, rendered_shards=0, resumed_shards=len(manifest.shards),
                   resumed_videos=len(manifest.videos), already_finished=True,
                   remade_tables=remade_tables)  # fmt: skip


class _Run:
    """The driver's side of one run: journals finished videos, joins shards as their last
    video arrives, and knows what is left to do."""

    def __init__(self, out: Path, names: list[str], shards: Sequence[Sequence[Recipe]], progress: Progress | None,
                 *, here: bool) -> None:  # fmt: skip
        self.out, self.work = out, out / WORK_DIR
        self.parts = self.work / PARTS_DIR
        self.names = names
        self.ids = {n: [r.video_id for r in recipes] for n, recipes in zip(names, shards, strict=True)}
        self.frames = {r.video_id: r.n_frames for recipes in shards for r in recipes}
        self.progress = progress
        self.parts.mkdir(parents=True, exist_ok=True)
        self.journal = Journal(self.work / JOURNAL_FILE)
        self.resumed_shards = self.resumed_videos = self.rendered_shards = 0
        # What the journal claims must still be on disk: a missing or short file is redone.
        for name in list(self.journal.shards):
            rec = self.journal.shards[name]
            if name not in self.ids or not _has_size(out / name, rec["shard"]["bytes"]):
                del self.journal.shards[name]
        for vid in list(self.journal.videos):
            rec = self.journal.videos[vid]
            part = part_path(self.parts, vid, "tar.part")
            if vid not in self.frames or not (
                rec["shard"] in self.journal.shards or _has_size(part, rec["part_bytes"])
            ):
                del self.journal.videos[vid]
        _check_code(out, [*self.journal.videos.values(), *self.journal.shards.values()], here=here)

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
        # A Ray cluster's workers are checked as their videos arrive: one of another machine
        # stops the run now, not once its shard is joined.
        first = next(iter(self.journal.videos.values()), None) or next(iter(self.journal.shards.values()), None)
        if first is not None:
            _check_one_renderer(self.out, "the run's videos", [first, record])
        self.journal.append("video", record)
        self._maybe_join(record["shard"])

    def _maybe_join(self, name: str) -> None:
        """Join the shard's parts into its tar once every one of its videos is journalled."""
        if name in self.journal.shards or any(v not in self.journal.videos for v in self.ids[name]):
            return
        ids = self.ids[name]
        videos = [self.journal.videos[v] for v in ids]
        _check_one_renderer(self.out, name, videos)
        digest = assemble_shard([part_path(self.parts, v, "tar.part") for v in ids], self.out / name,
                                checkpoint=lambda k: crash_point(f"shard:{name}:{k}"))  # fmt: skip
        stem = name.removesuffix(".tar")
        for table, columns in PART_TABLES:
            parts = [part_path(self.parts, v, f"{table}.parquet") for v in ids]
            _concat_parquet(parts, columns, self.work / f"{stem}.{table}.parquet")
        record = {
            "name": name,
            "shard": {"name": name, "sha256": digest.sha256, "bytes": digest.bytes, "video_ids": ids},
            "videos": [{k: v[k] for k in ("video_id", "shard", "n_frames", "content_hash", "modality_hashes")}
                       for v in videos],
            "gl": videos[0]["gl"],
            "renderer": videos[0]["renderer"],
        }  # fmt: skip
        self.journal.append("shard", record)
        self.rendered_shards += 1
        for v in ids:  # the shard holds them now
            for what in ("tar.part", *(f"{table}.parquet" for table, _ in PART_TABLES)):
                with contextlib.suppress(FileNotFoundError):
                    part_path(self.parts, v, what).unlink()


def _concat_parquet(parts: Sequence[Path], columns: Any, target: Path) -> None:
    """Rows of ``parts``, in order, into one zstd Parquet file at ``target`` (atomically)."""
    _write_tables([read_parquet(p) for p in parts], columns, target)


def _write_tables(tables: Sequence[pa.Table], columns: Any, target: Path) -> None:
    """``tables``, in order, as one zstd Parquet file at ``target`` (atomically)."""
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
    (``render.gl.gl_context``); the manifest's fingerprint records the one that rendered.
    """
    out = Path(out)
    check_engine(engine, address)
    check_output_dir(out)
    if engine == "local":  # the workers' body data, found or built (or its cache refused) before any write
        body_data_path()
    names = list(shard_names) if shard_names is not None else [shard_name(name, i) for i in range(len(shards))]
    if len(names) != len(shards) or len(set(names)) != len(names):
        raise ValueError("shard_names must name every shard once")
    if gl != "llvmpipe":
        check_gl_kind(gl)
        if engine == "local":  # a Ray cluster's workers may have GPUs this driver lacks
            require_gl(gl)
    tasks = [VideoTask(n, r.video_id, r.model_dump_json(), gl)
             for n, recipes in zip(names, shards, strict=True) for r in recipes]  # fmt: skip
    work = out / WORK_DIR
    shutil.rmtree(out / DONE_DIR, ignore_errors=True)  # a finished run's work folder a kill left
    look = functools.partial(_finished, out, names, tasks, gl, name=name, theta=theta, dataset_seed=dataset_seed)
    if (finished := look()) is not None and not _tables_to_remake(out, theta):
        return DatasetResult.finished_before(finished)
    try:
        with exclusive(work):
            (work / PARTS_DIR).mkdir(exist_ok=True)
            remove_stale_temporaries(out, work, work / PARTS_DIR)
            # A run that held the lock may have finished since the look above (its work folder
            # moved away, this one new): look again, as the lock's holder.
            if not (work / RUN_FILE).exists():
                try:
                    finished = look(locked=True)
                except PhavUserError:  # another finished dataset: refused, leaving no work folder beside it
                    shutil.rmtree(work, ignore_errors=True)
                    raise
                if finished is not None:
                    remade = _make_tables_again(out, finished, theta)
                    if remade is not None:
                        shutil.rmtree(work, ignore_errors=True)
                        return DatasetResult.finished_before(finished, remade)
            return _write_locked(out, names, shards, tasks, name=name, theta=theta, dataset_seed=dataset_seed,
                                 workers=workers, progress=progress, engine=engine, address=address)  # fmt: skip
    except WriteError as e:
        raise e.with_hint(RESUME_HINT) from None
    except OSError as e:
        raise WriteError(e, str(e.filename or out), RESUME_HINT) from None


def check_dataset_dir(out: Path) -> None:
    """For a run the user names the directory of (``phav generate``, ``phav regenerate``):
    refuse one that holds files but no run to resume or find finished (neither a manifest nor
    a work folder), or that holds a release: the run would write over them (a θ file passed as
    --theta, a sampled table, another dataset's shards, a release's manifest)."""
    try:
        if not out.is_dir():
            return
        if (out / RELEASE_FILE).exists():
            raise PhavUserError("holds a release; write the dataset to another directory (phav-validate "
                                "--regenerate-into regenerates a release's pixels)",
                                source=str(out), field="--out")  # fmt: skip
        if (out / "manifest.json").is_file() or (out / WORK_DIR).is_dir():
            return
        if any(out.iterdir()):
            raise PhavUserError("holds other files and no run of phav generate to resume; choose an empty "
                                "directory", source=str(out), field="--out")  # fmt: skip
    except OSError:  # a place it cannot look into: the first write reports it
        return


def render_task(task: VideoTask, report: Progress | None = None, *, parts: Path) -> dict[str, Any]:
    """``run_task`` in a worker, its record carrying the fingerprint of the renderer and code
    that made the video: the manifest's is theirs, and a run is never finished by two."""
    source_sha256()  # phav's code as this process loaded it, hashed before its first video, not after
    body = load_body_data().sha256  # the data the people are made of, read before they are
    record = run_task(task, report, parts=parts)
    made = renderer_fingerprint(record["gl"])
    if made.versions[BODY_DATA_KEY] != body:  # rebuilt meanwhile: the record would name other data
        raise PhavUserError("the body data changed while the video was rendered; rerun to resume",
                            field=task.video_id)  # fmt: skip
    return {**record, "renderer": made.model_dump(mode="json")}


def _check_one_renderer(out: Path, what: str, records: Sequence[dict[str, Any]]) -> None:
    """Refuse to join videos (or shards) that different renderers, machines or phav code made:
    the manifest promises one fingerprint for every byte."""
    made = [RendererFingerprint.model_validate(r["renderer"]) for r in records]
    differ = sorted({k for m in made[1:] for k in made[0].differences(m, "files")})
    if differ:
        raise PhavUserError(
            f"{what} were made by different renderers, machines or phav code ({', '.join(differ)} differ); "
            "delete the directory and regenerate with one phav on one kind of machine",
            source=str(out),
            field=differ[0],
        )


def _check_code(out: Path, records: Sequence[dict[str, Any]], *, here: bool) -> None:
    """Refuse to resume a run that another phav, package set or llvmpipe setting began (its
    finished videos' code, versions, encoders and GL settings against this process's): the
    rest would be made otherwise. ``here``: this machine renders the rest (the local engine),
    so its renderer and CPU class must be the run's too; a Ray cluster's workers may be other
    machines than its driver, whose videos are checked as they arrive (``_Run.finished``)."""
    made_here: dict[str, RendererFingerprint] = {}
    seen: set[str] = set()
    for record in records:
        if "renderer" not in record:
            differ = ["renderer"]
        else:
            made = canonical_json(record["renderer"])
            if made in seen:
                continue
            seen.add(made)
            gl = canonical_json(record["gl"])
            if gl not in made_here:
                made_here[gl] = renderer_fingerprint(record["gl"])
            theirs = RendererFingerprint.model_validate(record["renderer"])
            differ = [k for k in theirs.differences(made_here[gl], "files")  # the packages, encoders and GL settings
                      if here or k.startswith(("versions.", "files.")) or k == "gl_settings"]  # fmt: skip
        if differ:
            raise PhavUserError(
                f"the run was begun by another phav, package set, llvmpipe setting or machine ({', '.join(differ)} "
                "differ); finish it as it began, or delete the directory to start over",
                source=str(out),
                field=differ[0],
            )


def _finished(out: Path, names: list[str], tasks: list[VideoTask], gl: str, *, name: str, theta: Theta | None,
              dataset_seed: int, locked: bool = False) -> DatasetManifest | None:  # fmt: skip
    """The manifest of this very run if ``out`` holds it finished (every shard in place at
    its size, and its recipes; a metadata table or θ it lacks is made again from the shards,
    ``_make_tables_again``), None if ``out`` holds no finished run, or one short of a shard or
    of ``recipes.parquet``: rendered again, as nothing else records which recipes made the
    shards. A finished run with other settings is refused: running over it would replace
    another dataset's files. A work folder means the run is unfinished, unless ``locked``:
    the caller holds the lock of a work folder it has just made."""
    if not (out / "manifest.json").is_file() or (not locked and (out / WORK_DIR).exists()):
        return None
    manifest = load_manifest(out / "manifest.json")
    recipes = [t.recipe for t in tasks]  # the table gone: made again from these
    if (out / "recipes.parquet").is_file():
        recipes = [r.model_dump_json() for r in read_recipe_table(out / "recipes.parquet").recipes()]
    differs = [field for field, same in (
        ("name", manifest.name == name),
        ("theta_hash", manifest.theta_hash == (theta.hash if theta is not None else None)),
        ("dataset_seed", manifest.dataset_seed == dataset_seed),
        ("shard_names", [sh.name for sh in manifest.shards] == names),
        ("shards", [sh.video_ids for sh in manifest.shards] == [[t.video_id for t in tasks if t.shard == n]
                                                                for n in names]),
        ("recipes", recipes == [t.recipe for t in tasks]),
        ("gl", manifest.renderer is None or is_software_renderer(manifest.renderer.gl_renderer) == (gl == "llvmpipe")),
    ) if not same]  # fmt: skip
    if differs:
        raise PhavUserError(
            f"the directory holds a finished dataset with other settings ({', '.join(differs)} differ); "
            "use another --out, or delete the directory to make this one",
            source=str(out),
            field=differs[0],
        )
    if not (out / "recipes.parquet").is_file() or not all(_has_size(out / sh.name, sh.bytes) for sh in manifest.shards):
        return None
    return manifest


def _tables_to_remake(out: Path, theta: Theta | None) -> list[str]:
    """The metadata tables and θ beside a finished run's shards that ``out`` lacks, or holds
    unreadable (a Parquet file without its footer or columns) or changed (``theta.yaml``)."""
    remake = []
    for table, columns in PART_TABLES:
        try:
            with pq.ParquetFile(out / f"{table}.parquet") as f:
                readable = f.schema_arrow.names == [c.name for c in columns]
        except (OSError, pa.ArrowException):
            readable = False
        if not readable:
            remake.append(f"{table}.parquet")
    if theta is not None:
        try:
            same = (out / "theta.yaml").read_text(encoding="utf-8") == theta.to_yaml()
        except (OSError, UnicodeDecodeError):
            same = False
        if not same:
            remake.append("theta.yaml")
    return remake


def _make_tables_again(out: Path, manifest: DatasetManifest, theta: Theta | None) -> tuple[str, ...] | None:
    """Write the tables a finished run lacks without rendering (``_tables_to_remake``): θ from
    this run's (its hash the manifest's), the metadata tables from the frames' json in its
    shards (the rows the videos' parts held), each shard read whole and its bytes checked
    against the manifest first. None, and nothing written, where a shard differs from the
    manifest or its json is not this contract's: the run is then rendered again."""
    missing = _tables_to_remake(out, theta)
    wanted = [(t, columns) for t, columns in PART_TABLES if f"{t}.parquet" in missing]
    per_shard: dict[str, list[pa.Table]] = {t: [] for t, _ in wanted}
    if wanted:
        schemas = {t: arrow_schema(columns) for t, columns in wanted}
        for entry in manifest.shards:
            try:
                members, digest = read_members(out / entry.name, lambda n: n.endswith(".json"))
                if (digest.sha256, digest.bytes) != (entry.sha256, entry.bytes):
                    return None
                rows: dict[str, dict[str, list[dict[str, Any]]]] = {v: {"cameras": [], "people": []}
                                                                    for v in entry.video_ids}  # fmt: skip
                for member, data in members:  # frames in order, as the parts were written
                    camera, people = frame_rows(data)
                    rows[member.partition("/")[0]]["cameras"].append(camera)
                    rows[member.partition("/")[0]]["people"] += people
                # Each shard's table through Parquet, as the run's shard tables went (Parquet names a
                # list's items `element`, and reads one chunk back): the joined file is the run's.
                for t, _ in wanted:
                    videos = [pa.Table.from_pylist(rows[vid][t], schema=schemas[t]) for vid in entry.video_ids]
                    per_shard[t].append(_read_back(pa.concat_tables(videos)))
            except (OSError, tarfile.TarError, ValueError, KeyError, pa.ArrowException):
                return None
    if theta is not None and "theta.yaml" in missing:
        _write_theta(out, theta)
    for t, columns in wanted:
        _write_tables(per_shard[t], columns, out / f"{t}.parquet")
    return tuple(missing)


def _read_back(table: pa.Table) -> pa.Table:
    """``table`` written as a zstd Parquet file and read again, in memory."""
    sink = pa.BufferOutputStream()
    pq.write_table(table, sink, compression="zstd")
    with pq.ParquetFile(pa.BufferReader(sink.getvalue())) as f:  # as read_parquet reads
        return f.read()


def _write_theta(out: Path, theta: Theta) -> None:
    with atomic_write(out / "theta.yaml") as tmp:
        tmp.write_text(theta.to_yaml(), encoding="utf-8")


def _write_locked(out: Path, names: list[str], shards: Sequence[Sequence[Recipe]], tasks: list[VideoTask], *,
                  name: str, theta: Theta | None, dataset_seed: int, workers: int, progress: Progress | None,
                  engine: str, address: str | None) -> DatasetResult:  # fmt: skip
    """The run, holding the directory's lock: sidecars first, then the videos, then the manifest."""
    work = out / WORK_DIR
    check_run(work, {
        "name": name,
        "theta_hash": theta.hash if theta is not None else None,
        "dataset_seed": dataset_seed,
        "shards": [[r.video_id for r in recipes] for recipes in shards],
        "shard_names": names,
        "recipes_hash": sha256_hex(canonical_json([t.recipe for t in tasks])),
        "gl": tasks[0].gl if tasks else None,  # a run never mixes renderers
    })  # fmt: skip
    if theta is not None:
        _write_theta(out, theta)
    all_recipes = [r for recipes in shards for r in recipes]
    write_recipe_table(RecipeRows().extend(all_recipes).to_arrow(theta=theta, dataset_seed=dataset_seed),
                       out / "recipes.parquet")  # fmt: skip

    state = _Run(out, names, shards, progress, here=engine == "local")
    # Longest videos first: workers that pick the next task as they finish then end close
    # together (no worker rendering one long video alone at the end). Which order the videos
    # are rendered in cannot change a byte.
    todo = sorted(state.todo(tasks), key=lambda t: -state.frames[t.video_id])
    stage = functools.partial(render_task, parts=state.parts)
    run_tasks(stage, todo, engine=engine, workers=workers, address=address, out=out, progress=progress,
              finished=state.finished)  # fmt: skip
    manifest = _finish(out, names, state.journal.shards, name=name, theta=theta, dataset_seed=dataset_seed)
    os.replace(work, out / DONE_DIR)  # finished: a kill while it is deleted leaves no work folder
    shutil.rmtree(out / DONE_DIR, ignore_errors=True)
    return DatasetResult(manifest, rendered_shards=state.rendered_shards, resumed_shards=state.resumed_shards,
                         rendered_videos=len(todo), resumed_videos=state.resumed_videos)  # fmt: skip


def _finish(out: Path, names: list[str], records: dict[str, dict[str, Any]], *, name: str, theta: Theta | None,
            dataset_seed: int) -> DatasetManifest:  # fmt: skip
    """Every shard is in: join the metadata tables and write the manifest, last."""
    _check_one_renderer(out, "the shards", [records[n] for n in names])
    fingerprint = RendererFingerprint.model_validate(records[names[0]]["renderer"]) if names else None
    for table, columns in PART_TABLES:
        parts = [out / WORK_DIR / f"{n.removesuffix('.tar')}.{table}.parquet" for n in names]
        _concat_parquet(parts, columns, out / f"{table}.parquet")
    manifest = DatasetManifest(
        manifest_version=MANIFEST_VERSION,
        name=name,
        phav_version=package_version("phav"),
        theta_hash=theta.hash if theta is not None else None,
        dataset_seed=dataset_seed,
        recipe_schema_version=RECIPE_SCHEMA_VERSION,
        renderer=fingerprint,
        shards=[ShardEntry.model_validate(records[n]["shard"]) for n in names],
        videos=[VideoEntry.model_validate(v) for n in names for v in records[n]["videos"]],
    )
    dump_manifest(manifest, out / "manifest.json")
    return manifest
