"""``phav-validate`` on a dataset: the seven checks, run once each, collected into one report.

integrity · schema · encoding · distribution · failures · consistency · reproducibility,
and when named, learnability (a small TSN trained on the pixels; docs/learnability.md) and
realism (models trained on real photographs judge a sample of frames; docs/realism.md)
(docs/validation.md says what each measures and where its thresholds come from). Shards are
scanned once, in a process pool when ``workers`` > 1; integrity, encoding and consistency
read their numbers off that one pass. Every check runs even when another fails, so one
report lists everything wrong; a check whose inputs are missing is skipped, and says why.
"""

from __future__ import annotations

import dataclasses
import itertools
import math
import multiprocessing
import os
import signal
import time
from collections.abc import Callable, Iterator, Mapping, Sequence
from concurrent.futures import Future, ProcessPoolExecutor
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import cv2
import numpy as np
import pyarrow.parquet as pq

from phav_generator.engines import RayPool, exit_with_parent, worker_died
from phav_spec.errors import PhavUserError
from phav_spec.files import file_sha256, read_parquet
from phav_spec.manifest import DatasetManifest, load_manifest
from phav_spec.metadata import CAMERA_COLUMNS, METADATA_VERSION, PEOPLE_COLUMNS, ROLES, MetaColumn, arrow_schema
from phav_spec.recipe import RECIPE_SCHEMA_VERSION, Recipe
from phav_spec.recipe_table import RecipeTable, read_recipe_table
from phav_spec.release import RELEASE_FILE, load_release_index
from phav_spec.theta import Theta, load_theta
from phav_validators import tables
from phav_validators.checks.distribution import check_distributions
from phav_validators.checks.failures import check_failures
from phav_validators.checks.recipes import check_recipe_table
from phav_validators.checks.reproduce import check_reproducibility
from phav_validators.checks.scan import ShardJob, ShardScan, VideoExpect, VideoScan, scan_shard, tune_allocator
from phav_validators.checks.tarsafe import TarScan, iter_members
from phav_validators.findings import CheckResult, Finding, ProgressFactory, Reason, Report
from phav_validators.framing import FramingResult, read_framing
from phav_validators.learn.learnability import LearnOptions, check_learnability
from phav_validators.options import (
    ALL_CHECKS,
    DEFAULT_OPTIONS,
    DatasetReport,
    Options,
    sample_videos,
)
from phav_validators.realism.check import RealismOptions, realism_check, run_realism
from phav_validators.source import CAMERAS, PEOPLE, THETA, DatasetInput, is_recipe_release

if TYPE_CHECKING:
    import pyarrow as pa

    from phav_validators.checks.distribution import DistributionResult
    from phav_validators.learn.learnability import LearnOptions, LearnResult
    from phav_validators.realism.check import RealismResult

_SCAN_CHECKS = ("integrity", "encoding", "consistency")
#: Scan jobs per worker process: shards split into parts so that workers finish together
#: (a shard's first part reads the whole tar; the others seek to their own videos' members).
PARTS_PER_WORKER = 8

#: Consistency thresholds (clean datasets measure ~0.006 px mean EPE; docs/validation.md).
FLOW_MEAN_EPE_PX = 0.25
FLOW_BAD_FRACTION = 0.02
JOINT_DEPTH_OUTLIER_FRACTION = 0.02
MASK_DISAGREE_FRACTION = 0.01


# --- inputs ----------------------------------------------------------------------------------


@dataclass
class _Loaded:
    """The dataset's sidecar files as far as they could be read, and what went wrong."""

    manifest: DatasetManifest | None = None
    table: RecipeTable | None = None
    theta: Theta | None = None
    recipes: dict[str, Recipe] = field(default_factory=dict)
    integrity: Report = field(default_factory=Report)
    schema: Report = field(default_factory=Report)
    distribution: Report = field(default_factory=Report)

    @property
    def n_recipes(self) -> int:
        """Rows of the recipes table, valid or not (0 without one)."""
        return self.table.table.num_rows if self.table is not None else 0


def _named(e: PhavUserError) -> str:
    """The error's words led by the field it names (the finding names the file)."""
    return f"{e.field}: {e.detail}" if e.field else e.detail


def release_file_findings(root: Path, manifest: DatasetManifest | None) -> list[Finding]:
    """Every file the release at ``root`` says (``release.json``) it carries, against its size
    and sha256: shards against the manifest's entries (the scan hashes their bytes), the rest
    read here. None where ``root`` holds no release."""
    release = root / RELEASE_FILE
    if not release.exists():
        return []
    try:
        index = load_release_index(release)
    except PhavUserError as e:
        return [Finding(Reason.MANIFEST_INVALID, _named(e), file=str(release), numbers={"field": e.field})]
    shards = {s.name: s for s in manifest.shards} if manifest is not None else {}
    found = []
    for f in index.files:
        path = root / f.path
        if not f.included:
            continue
        if not path.is_file():
            found.append(Finding(Reason.MISSING_FILE, "listed in release.json, not in the release", file=f.path))
            continue
        if f.kind == "shard":
            listed = shards.get(f.path)
            if listed is not None and (listed.sha256, listed.bytes) != (f.sha256, f.bytes):
                found.append(Finding(Reason.RELEASE_FILE_CHANGED, "release.json and manifest.json record other "
                                     "bytes for the shard", file=f.path))  # fmt: skip
            continue
        size, digest = path.stat().st_size, file_sha256(path)
        if (size, digest) != (f.bytes, f.sha256):
            found.append(Finding(
                Reason.RELEASE_FILE_CHANGED,
                f"{size} bytes, sha256 {digest[:12]}…; release.json records {f.bytes} bytes, {f.sha256[:12]}…",
                file=f.path,
            ))  # fmt: skip
    return found


def _load(inp: DatasetInput, theta_arg: str | None, timings: dict[str, float]) -> _Loaded:
    out = _Loaded()
    start = time.perf_counter()
    if not inp.recipes_only:
        if inp.manifest_path.exists():
            try:
                out.manifest = load_manifest(inp.manifest_path)
            except PhavUserError as e:
                out.integrity.add(Finding(Reason.MANIFEST_INVALID, _named(e), file=str(inp.manifest_path),
                                          numbers={"field": e.field}))  # fmt: skip
        else:
            out.integrity.add(Finding(Reason.MISSING_FILE, "the dataset has no manifest.json", file=str(inp.root)))
    for finding in release_file_findings(inp.root, out.manifest):  # a release's, recipe-only or not
        out.integrity.add(finding)
    timings["integrity"] = time.perf_counter() - start
    start = time.perf_counter()
    table_path = inp.recipes_table
    if inp.recipes_path is not None:  # named on the command line: unreadable is a user error
        out.table = read_recipe_table(table_path)
    elif table_path.exists():
        try:
            out.table = read_recipe_table(table_path)
        except PhavUserError as e:
            out.schema.add(Finding(Reason.RECIPE_INVALID, _named(e), file=str(table_path)))
    else:
        out.schema.add(Finding(Reason.MISSING_FILE, "no recipes table", file=str(table_path)))
    # θ: --theta (a user error when unreadable), else the dataset's theta.yaml, else the table's.
    if theta_arg is not None:
        out.theta = load_theta(theta_arg)
    elif (inp.root / THETA).exists():
        try:
            out.theta = load_theta(str(inp.root / THETA))
        except PhavUserError as e:
            out.distribution.add(Finding(Reason.THETA_MISMATCH, _named(e), file=str(inp.root / THETA)))
    elif out.table is not None and out.table.theta is not None:
        out.theta = out.table.theta
    m = out.manifest
    if (
        m is not None
        and m.theta_hash is not None
        and not (inp.root / THETA).exists()
        and not (inp.root / RELEASE_FILE).exists()
    ):  # a run made from θ writes it beside its recipes (a release's files are checked above)
        out.integrity.add(Finding(Reason.MISSING_FILE, f"the manifest records θ {m.theta_hash[:12]}…, and the "
                                  "dataset has no theta.yaml", file=THETA))  # fmt: skip
    if out.theta is not None and m is not None and m.theta_hash is not None and m.theta_hash != out.theta.hash:
        out.distribution.add(Finding(
            Reason.THETA_MISMATCH,
            f"θ {out.theta.name} hashes to {out.theta.hash[:12]}…, the manifest records {m.theta_hash[:12]}…",
            file=str(inp.manifest_path),
        ))  # fmt: skip
    if out.table is not None:
        out.recipes = check_recipe_table(out.table, out.theta, out.schema)
    timings["schema"] = time.perf_counter() - start
    return out


def _jobs(inp: DatasetInput, loaded: _Loaded, opts: Options) -> tuple[list[ShardJob], Report]:
    """One scan job per shard to read, and the integrity findings about the shard files."""
    report = Report()
    m = loaded.manifest
    recipes = loaded.recipes
    if m is not None:
        listed = {s.name: s for s in m.shards}
        entries = {v.video_id: v for v in m.videos}
        wanted = [inp.root / s.name for s in m.shards] if inp.shards is None else inp.shards
        for path in sorted(inp.root.glob("*.tar")):
            if path.name not in listed:
                report.add(Finding(Reason.UNLISTED_FILE, "shard not listed in the manifest", file=path.name))
    else:  # no usable manifest: scan what is there, expecting what the recipes say
        listed, entries = {}, {}
        wanted = sorted(inp.root.glob("*.tar")) if inp.shards is None else inp.shards
    found = []  # (path, its manifest entry, its videos) of each shard there is to read
    for path in wanted:
        shard = listed.get(path.name)
        if m is not None and shard is None:
            report.add(Finding(Reason.UNLISTED_FILE, "shard not listed in the manifest", file=path.name))
            continue
        if not path.exists():
            report.add(Finding(Reason.MISSING_FILE, "shard listed in the manifest is missing", file=path.name))
            continue
        found.append((path, shard, shard.video_ids if shard is not None else _ids_in(path, recipes)))
    if inp.shards is not None:  # named shards: the sample is drawn from their videos
        all_ids = [vid for _, _, ids in found for vid in ids]
    else:
        all_ids = sorted(recipes) if m is None else [v.video_id for v in m.videos]
    decode = sample_videos(all_ids, opts.sample, opts.seed)
    jobs = []
    for path, shard, ids in found:
        expects = []
        for vid in ids:
            recipe = recipes.get(vid)
            entry = entries.get(vid)
            n_frames = entry.n_frames if entry is not None else recipe.n_frames if recipe is not None else 0
            width, height = (recipe.video.width, recipe.video.height) if recipe is not None else (340, 256)
            hashes = dict(entry.modality_hashes) if entry is not None and entry.modality_hashes else None
            expects.append(VideoExpect(vid, n_frames, width, height, hashes, decode=vid in decode))
        parts = _parts(expects, max(1, math.ceil(PARTS_PER_WORKER * opts.workers / max(len(wanted), 1))))
        for i, part in enumerate(parts):
            others = frozenset(v.video_id for v in expects) - {v.video_id for v in part}
            jobs.append(ShardJob(str(path), part, shard.sha256 if shard else None, shard.bytes if shard else None,
                                 consistency="consistency" in opts.checks, others=others, primary=i == 0,
                                 listed_order=tuple(shard.video_ids) if shard and i == 0 else ()))  # fmt: skip
    return jobs, report


def _parts(expects: list[VideoExpect], n: int) -> list[tuple[VideoExpect, ...]]:
    """Split a shard's videos into at most ``n`` consecutive runs of about equal decoding work."""
    if n <= 1 or len(expects) <= 1:
        return [tuple(expects)]
    work = np.array([v.n_frames if v.decode else 0 for v in expects], dtype=float)
    if work.sum() == 0:
        return [tuple(expects)]
    cuts = np.searchsorted(np.cumsum(work) / work.sum(), np.arange(1, n) / n, side="left") + 1
    bounds = [0, *sorted({int(c) for c in cuts if 0 < c < len(expects)}), len(expects)]
    return [tuple(expects[a:b]) for a, b in itertools.pairwise(bounds) if b > a]


def _ids_in(path: Path, recipes: Mapping[str, Recipe]) -> list[str]:
    """Video ids whose members a shard holds (without a manifest), from its member names."""

    seen: dict[str, None] = {}
    scan = TarScan()
    for name, _ in iter_members(path, scan):
        vid = name.partition("/")[0]
        if vid in recipes:
            seen.setdefault(vid)
    return list(seen)


def _init_worker(parent: int | None = None) -> None:
    """One thread per worker process: OpenCV's own pool would fight the other workers; a
    local pool's worker ends with the process that started it (``parent``), and at Ctrl-C
    (a terminal signals the whole process group) at once and silently: it writes nothing,
    and the pool's queue would print a traceback."""

    cv2.setNumThreads(1)
    tune_allocator()
    if parent is not None:
        if signal.getsignal(signal.SIGINT) is not signal.SIG_IGN:  # a run started ignoring Ctrl-C keeps doing so
            signal.signal(signal.SIGINT, lambda signum, frame: os._exit(128 + signum))
        exit_with_parent(parent)


def _ready() -> None:
    """A worker's first task: nothing, so that it starts (and imports) while the main
    process still reads the dataset's sidecar files."""


def _start_pool(workers: int, engine: str = "local", address: str | None = None) -> ProcessPoolExecutor:
    """``workers`` spawned scanning processes, started now (Ray tasks with ``engine`` ray)."""
    if engine == "ray":
        return RayPool(workers, address, initializer=_init_worker)  # type: ignore[return-value]
    mp = multiprocessing.get_context("spawn")
    pool = ProcessPoolExecutor(max_workers=workers, mp_context=mp, initializer=_init_worker, initargs=(os.getpid(),))
    for _ in range(workers):
        pool.submit(_ready)
    return pool


class _Scans:
    """The shard pass under way. With a ``pool`` every job is submitted at once, so the
    checks that need no pixels (schema, distribution, most of failures) run in this process
    meanwhile; without one, jobs run here on demand. Either way each job's result is the
    same, and results are taken in job order. The caller owns (and shuts down) the pool."""

    def __init__(self, jobs: list[ShardJob], pool: ProcessPoolExecutor | None, advance: Callable[[int], None] | None):
        self.jobs = jobs
        self._advance = advance
        self._results: dict[int, ShardScan] = {}
        self.waited = 0.0  # seconds spent here waiting for (or running) jobs
        self._job_of = {v.video_id: i for i, job in enumerate(jobs) for v in job.videos}
        self._pool = pool
        self._futures: list[Future[ShardScan]] = []
        if pool is not None:
            self._futures = [pool.submit(scan_shard, job) for job in jobs]
            if advance is not None:
                for future in self._futures:
                    future.add_done_callback(lambda _: advance(1))

    def result(self, i: int) -> ShardScan:
        if i not in self._results:
            start = time.perf_counter()
            if self._pool is not None:
                try:
                    self._results[i] = self._futures[i].result()
                except Exception as e:
                    if not worker_died(e):
                        raise
                    said = "a scanning worker process died (killed, or out of memory); nothing was written, rerun"
                    raise PhavUserError(f"{said} to validate", source=self.jobs[i].path) from None
            else:
                self._results[i] = scan_shard(self.jobs[i])
                if self._advance is not None:
                    self._advance(1)
            self.waited += time.perf_counter() - start
        return self._results[i]

    def all(self) -> list[ShardScan]:
        return [self.result(i) for i in range(len(self.jobs))]

    def video(self, video_id: str) -> VideoScan | None:
        """The video's scan (waiting for its job), None if no job covers it."""
        i = self._job_of.get(video_id)
        return None if i is None else self.result(i).videos.get(video_id)

    def video_ids(self) -> list[str]:
        return list(self._job_of)

    def cancel(self) -> None:
        """Drop the jobs not started yet (an error or ^C in this process)."""
        for future in self._futures:
            future.cancel()


class _InstancePixels(Mapping[str, Mapping[int, Sequence[int]]]):
    """Per decoded video, its people's instance pixels per frame, each taken from the scan
    when the failures check first asks for it (so that check overlaps the shard pass)."""

    def __init__(self, scans: _Scans):
        self._scans = scans

    def __getitem__(self, video_id: str) -> Mapping[int, Sequence[int]]:
        scan = self._scans.video(video_id)
        if scan is None or not scan.decoded:
            raise KeyError(video_id)
        return scan.instance_pixels

    def __iter__(self) -> Iterator[str]:
        return iter(self._scans.video_ids())

    def __len__(self) -> int:
        return len(self._scans.video_ids())


# --- checks on the scan ----------------------------------------------------------------------


def _consistency(videos: Mapping[str, VideoScan], shard_of: Mapping[str, str], report: Report) -> dict[str, Any]:
    """Per video: flow against depth + camera, joints against projection and depth, masks."""
    worst_epe, worst_bad, worst_joint, worst_mask, compared = 0.0, 0.0, 0.0, 0.0, 0
    for vid, v in sorted(videos.items()):
        if not v.decoded:
            continue
        file = shard_of.get(vid)
        compared += 1
        if v.flow_epe:
            t, n, epe, _ = max(v.flow_epe, key=lambda x: (x[2], x[0]))
            tb, _, _, badf = max(v.flow_epe, key=lambda x: (x[3], x[0]))
            worst_epe, worst_bad = max(worst_epe, epe), max(worst_bad, badf)
            if epe > FLOW_MEAN_EPE_PX or badf > FLOW_BAD_FRACTION:
                report.add(Finding(
                    Reason.FLOW_DEPTH_MISMATCH,
                    f"flow disagrees with depth + camera motion on static pixels: mean end-point error "
                    f"{epe:.3f} px at frame {t:05d} (limit {FLOW_MEAN_EPE_PX}), {badf:.1%} of pixels off by > 1 px "
                    f"at frame {tb:05d}",
                    file=file, video_id=vid,
                    numbers={"frame": t, "mean_epe_px": epe, "bad_fraction": badf, "pixels": n},
                ))  # fmt: skip
        if v.joint_2d_error_px > 0.01:
            report.add(Finding(Reason.JOINT_PROJECTION,
                               f"2-D joints are {v.joint_2d_error_px:.3g} px from the projected 3-D joints",
                               file=file, video_id=vid, numbers={"error_px": v.joint_2d_error_px}))  # fmt: skip
        share = v.joint_depth_outliers / max(v.joints_checked, 1)
        worst_joint = max(worst_joint, share)
        if share > JOINT_DEPTH_OUTLIER_FRACTION:
            report.add(Finding(Reason.JOINT_PROJECTION,
                               f"{v.joint_depth_outliers} of {v.joints_checked} joints disagree with the depth image "
                               "(visible but behind a surface, or hidden with nothing in front)",
                               file=file, video_id=vid, numbers={"outliers": v.joint_depth_outliers}))  # fmt: skip
        mask = v.mask_disagree / max(v.person_pixels, 1)
        worst_mask = max(worst_mask, mask)
        if mask > MASK_DISAGREE_FRACTION:
            report.add(Finding(Reason.MASK_MISMATCH,
                               f"{v.mask_disagree} pixels are a person in one of instance / semantic but not the "
                               f"other ({mask:.1%} of {v.person_pixels} person pixels)",
                               file=file, video_id=vid, numbers={"pixels": v.mask_disagree}))  # fmt: skip
    return {
        "videos": compared, "worst_flow_mean_epe_px": worst_epe, "worst_flow_bad_fraction": worst_bad,
        "worst_joint_depth_outliers": worst_joint, "worst_mask_disagreement": worst_mask,
    }  # fmt: skip


def _schema_links(loaded: _Loaded, inp: DatasetInput) -> None:
    """Videos and recipes one to one; versions this phav knows; metadata tables' columns,
    their types and the values the contract rules out."""

    report, m = loaded.schema, loaded.manifest
    if m is None and not inp.recipes_only:  # nothing to pair the recipes with: not a pass
        missing = not inp.manifest_path.exists()
        why = "missing" if missing else "invalid"
        report.add(
            Finding(
                Reason.MISSING_FILE if missing else Reason.MANIFEST_INVALID,
                f"videos and recipes cannot be paired: the manifest is {why}",
                file="manifest.json",
            )
        )
    if m is not None and loaded.table is not None:
        table_ids = set(loaded.table.column("video_id"))
        for v in m.videos:
            recipe = loaded.recipes.get(v.video_id)
            if v.video_id not in table_ids:
                report.add(Finding(Reason.VIDEO_RECIPE_MISMATCH, "video in the manifest has no recipe",
                                   file="manifest.json", video_id=v.video_id))  # fmt: skip
            elif recipe is not None and recipe.n_frames != v.n_frames:
                report.add(Finding(Reason.VIDEO_RECIPE_MISMATCH,
                                   f"manifest says {v.n_frames} frames, the recipe {recipe.n_frames}",
                                   file="manifest.json", video_id=v.video_id))  # fmt: skip
        seeds = {r.dataset_seed for r in loaded.recipes.values()}
        if len(seeds) == 1 and seeds != {m.dataset_seed}:  # one draw's recipes (mixed ones have no one seed)
            report.add(Finding(Reason.VIDEO_RECIPE_MISMATCH, f"dataset seed {m.dataset_seed}, the recipes' "
                               f"{seeds.pop()}", file="manifest.json"))  # fmt: skip
        listed = {v.video_id for v in m.videos}
        for vid in sorted(table_ids - listed):
            report.add(Finding(Reason.VIDEO_RECIPE_MISMATCH, "recipe has no video in the manifest",
                               file=str(loaded.table.path.name), video_id=vid))  # fmt: skip
        if m.recipe_schema_version > RECIPE_SCHEMA_VERSION:
            report.add(Finding(Reason.VERSION_UNKNOWN, f"recipe schema version {m.recipe_schema_version} is newer "
                               f"than this phav knows ({RECIPE_SCHEMA_VERSION})", file="manifest.json"))  # fmt: skip
    if inp.recipes_only or is_recipe_release(inp):  # a recipe-only release regenerates its tables
        return
    known = set(loaded.table.column("video_id")) if loaded.table is not None else None
    for name in (CAMERAS, PEOPLE):
        path = inp.root / name
        if not path.exists():
            report.add(Finding(Reason.MISSING_FILE, "metadata table missing", file=name))
            continue
        problems, version = metadata_table_problems(path, known)
        for problem in problems:
            report.add(Finding(Reason.METADATA_INVALID, problem, file=name))
        if version is not None and (not version.isdigit() or int(version) > METADATA_VERSION):
            report.add(Finding(Reason.VERSION_UNKNOWN, f"metadata version {version!r}; this phav reads ≤ "
                               f"{METADATA_VERSION}", file=name))  # fmt: skip


def metadata_table_problems(path: Path, videos: set[str] | None) -> tuple[list[str], str | None]:
    """What breaks the contract in the metadata table at ``path`` (``cameras.parquet`` or
    ``people.parquet``, by its name), one line each: not Parquet, columns other than the
    contract's, of another type or holding nulls, values it rules out, rows of a video not in
    ``videos`` (None: not checked); and the contract version its schema records (None when
    unreadable)."""
    name = path.name
    columns = PEOPLE_COLUMNS if name == PEOPLE else CAMERA_COLUMNS
    try:
        schema = pq.read_schema(path)
    except Exception as e:  # pyarrow raises several types for damaged files
        return [f"not a readable Parquet file ({e})"], None
    problems = [] if schema.names == [c.name for c in columns] else [f"columns {schema.names} are not the contract's"]
    problems += _column_problems(path, schema, columns)
    if not problems:
        try:
            problems = _value_problems(path, name, videos)
        except PhavUserError as e:  # a null the Parquet statistics did not count
            problems = [e.detail if e.field is None else f"{e.field}: {e.detail}"]
    meta = {k.decode(): v.decode() for k, v in (schema.metadata or {}).items()}
    return problems, meta.get("phav.metadata_version", "")


def _column_problems(path: Path, schema: pa.Schema, columns: Sequence[MetaColumn]) -> list[str]:
    """Each contract column of a metadata table whose type is not the contract's, or which
    holds nulls (none may: a number is NaN where unknown), one line each: from the schema
    and the Parquet statistics, no row read."""
    import pyarrow as pa

    expected = arrow_schema(columns)
    problems = [
        f"column {f.name!r} is {schema.field(f.name).type}, the contract's is {f.type}"
        for f in expected
        if f.name in schema.names and not schema.field(f.name).type.equals(f.type)
    ]
    nulls: dict[str, int] = {}
    try:
        meta = pq.ParquetFile(path).metadata
    except Exception:  # pyarrow raises several types for damaged files: read_schema said
        return problems
    for g in range(meta.num_row_groups):
        group = meta.row_group(g)
        for j in range(group.num_columns):
            chunk = group.column(j)
            stats = chunk.statistics
            if stats is not None and stats.has_null_count and stats.null_count:
                top = chunk.path_in_schema.split(".")[0]
                nulls[top] = nulls.get(top, 0) + stats.null_count
    # A variable list's empty entries count as leaf nulls in the statistics: only a scalar
    # or fixed-size list column's nulls are nulls.
    exact = {f.name for f in expected if not pa.types.is_list(f.type)}
    problems += [f"column {n!r} holds {k:,} null{'s' if k != 1 else ''}" for n, k in nulls.items() if n in exact]
    return problems


#: Off a rigid pose by more than this: a camera's rotation (RᵀR − I, det R − 1) or bottom row.
RIGID_TOLERANCE = 1e-3


def _value_problems(path: Path, name: str, videos: set[str] | None) -> list[str]:
    """Values of a well-typed metadata table the contract rules out, one line each: rows of
    a video without a recipe; people with a negative id or pixel count or a role not in
    ``ROLES``; cameras whose focal lengths are not positive or whose pose is not rigid."""
    people = name == PEOPLE
    columns = ["video_id", "person_id", "role", "pixels"] if people else ["video_id", "fx", "fy", "cam_to_world"]
    try:
        table = read_parquet(path, columns=columns)
    except Exception:  # pyarrow raises several types for damaged files: read_schema said
        return []
    out = []
    vids = tables.keys(table, "video_id", name)
    if videos is not None:
        foreign = sorted(set(vids.tolist()) - videos)
        if foreign:
            out.append(f"rows of {len(foreign)} videos without a recipe (first {foreign[0]})")

    def ruled_out(bad: np.ndarray, what: str) -> None:
        if bad.any():
            out.append(f"{what} in {int(bad.sum()):,} rows (first {vids[bad][0]})")

    if people:
        ruled_out(tables.numbers(table, "person_id", name) < 0, "a negative person_id")
        ruled_out(tables.numbers(table, "pixels", name) < 0, "a negative pixel count")
        roles = tables.keys(table, "role", name)
        ruled_out(~np.isin(roles, ROLES), f"a role not one of {', '.join(ROLES)}")
    else:
        focal = np.stack([tables.numbers(table, c, name) for c in ("fx", "fy")], axis=1)
        ruled_out(~(focal > 0.0).all(axis=1), "a focal length that is not positive")
        pose = tables.fixed_lists(table, "cam_to_world", 16, name).reshape(-1, 4, 4)
        rot = pose[:, :3, :3]
        with np.errstate(invalid="ignore"):
            off = np.abs(np.einsum("nji,njk->nik", rot, rot) - np.eye(3)).max(axis=(1, 2))
            off = np.maximum(off, np.abs(np.linalg.det(rot) - 1.0))
            off = np.maximum(off, np.abs(pose[:, 3] - [0.0, 0.0, 0.0, 1.0]).max(axis=1))
        ruled_out(np.isfinite(off) & (off > RIGID_TOLERANCE), "a cam_to_world that is not a rigid pose")
    return out


def _read_tables(inp: DatasetInput) -> tuple[pa.Table | None, pa.Table | None]:
    """``people.parquet`` and ``cameras.parquet``, each None where it cannot be read."""

    def read(name: str) -> pa.Table | None:
        try:
            return read_parquet(inp.root / name)
        except Exception:  # pyarrow raises several types for damaged files
            return None

    return read(PEOPLE), read(CAMERAS)


def validate_as_is(
    inp: DatasetInput,
    *,
    theta: str | None = None,
    options: Options = DEFAULT_OPTIONS,
    progress: ProgressFactory | None = None,
) -> DatasetReport:
    """Run the chosen checks on the files the directory holds (nothing is regenerated)."""
    opts = options
    want = set(opts.checks)
    scanning = not inp.recipes_only and bool(want & set(_SCAN_CHECKS))
    # Workers start first, so that their start-up overlaps reading the sidecar files.
    parallel = opts.workers > 1 or opts.engine == "ray"
    pool = _start_pool(opts.workers, opts.engine, opts.address) if scanning and parallel else None
    try:
        return _validate(inp, theta, opts, progress, scanning, pool)
    finally:
        if pool is not None:
            pool.shutdown(wait=True, cancel_futures=True)


def _validate(
    inp: DatasetInput,
    theta: str | None,
    opts: Options,
    progress: ProgressFactory | None,
    scanning: bool,
    pool: ProcessPoolExecutor | None,
) -> DatasetReport:
    """Read the sidecar files, start the shard pass, run the checks beside it and after it."""
    timings: dict[str, float] = {}
    loaded = _load(inp, theta, timings)
    want = set(opts.checks)

    # The shard pass (integrity, encoding, consistency) starts first: with workers it runs
    # beside schema, distribution and failures, which need no pixels until failures asks.
    scan_start = time.perf_counter()
    jobs, scan_report = _jobs(inp, loaded, opts) if scanning else ([], Report())
    advance = progress("scanning shards", len(jobs)) if progress is not None and jobs else None
    scans = _Scans(jobs, pool if len(jobs) > 1 else None, advance)
    try:
        selected = _selected_videos(inp, loaded, scans)
        results, dist_result = _checks_beside_the_scan(inp, loaded, selected, scans, opts, progress, timings)
        shard_scans = scans.all()
        timings["scan"] = time.perf_counter() - scan_start
    except BaseException:
        scans.cancel()
        raise
    shard_of = {vid: Path(s.path).name for s in shard_scans for vid in s.videos}
    if inp.recipes_only:
        for name in ("integrity", "encoding", "failures", "consistency", "reproducibility"):
            results[name] = CheckResult.skipped(name, "a recipes table alone: no shards or metadata to read")
    else:
        results.update(_scan_results(shard_scans, shard_of, loaded.integrity, scan_report, opts))

    fingerprint_match = None
    if not inp.recipes_only and "reproducibility" in want:
        with _timed(timings, "reproducibility"):
            results["reproducibility"], fingerprint_match = check_reproducibility(
                inp.root, loaded.manifest, loaded.recipes, sorted(selected), count=opts.regenerate, seed=opts.seed,
                progress=progress,
            )  # fmt: skip
    learn_result = None
    if "learnability" in want:
        with _timed(timings, "learnability"):
            results["learnability"], learn_result = _learnability(inp, loaded, opts, progress)
    realism_result = None
    if "realism" in want:
        with _timed(timings, "realism"):
            results["realism"], realism_result = _realism(inp, loaded, opts, progress)

    framing = None if inp.recipes_only else _framing(inp, loaded, selected)
    m = loaded.manifest
    covered = [v for v in m.videos if v.video_id in selected] if m is not None else []  # named shards' only
    report = DatasetReport(
        source=inp.label,
        root=str(inp.root),
        checks=_timed_checks(results, want, timings),
        n_videos=len(covered) if m is not None else loaded.n_recipes,
        n_frames=sum(v.n_frames for v in covered) if m is not None else 0,
        theta={"name": loaded.theta.name, "hash": loaded.theta.hash} if loaded.theta is not None else None,
        fingerprint_match=fingerprint_match,
        distribution=dist_result,
        learnability=learn_result,
        realism=realism_result,
        framing=framing,
    )
    _flag_frames(report, shard_of, inp.root)
    return report


@contextmanager
def _timed(timings: dict[str, float], name: str) -> Iterator[None]:
    """Add the seconds the block takes to ``timings[name]``."""
    start = time.perf_counter()
    yield
    timings[name] = timings.get(name, 0.0) + time.perf_counter() - start


def _checks_beside_the_scan(
    inp: DatasetInput,
    loaded: _Loaded,
    selected: set[str],
    scans: _Scans,
    opts: Options,
    progress: ProgressFactory | None,
    timings: dict[str, float],
) -> tuple[dict[str, CheckResult], DistributionResult | None]:
    """Schema, and distribution and failures when asked for, while the shard pass runs;
    failures waits for a video's instance pixels only when it reaches that video (its waits
    are not its time)."""
    results: dict[str, CheckResult] = {}
    with _timed(timings, "schema"):
        _schema_links(loaded, inp)
        results["schema"] = CheckResult.from_report(
            "schema", loaded.schema,
            f"{len(loaded.recipes)}/{loaded.n_recipes} recipes valid (schema ≤ {RECIPE_SCHEMA_VERSION})",
            {"recipes": loaded.n_recipes, "valid": len(loaded.recipes)},
        )  # fmt: skip
    dist_result = None
    if "distribution" in opts.checks:  # its tests and scipy's import take most of a second
        with _timed(timings, "distribution"):
            results["distribution"], dist_result = _distribution(loaded, opts)
    if not inp.recipes_only and "failures" in opts.checks:
        start = time.perf_counter()
        waited = scans.waited
        results["failures"] = _failures(inp, loaded, selected, _InstancePixels(scans), opts, progress)
        timings["failures"] = time.perf_counter() - start - (scans.waited - waited)
    return results, dist_result


def _timed_checks(results: Mapping[str, CheckResult], want: set[str], timings: dict[str, float]) -> list[CheckResult]:
    """The chosen checks in report order, each with its seconds (a check that did not apply
    says so). The shard pass's time is shared by the checks that read it (it overlaps the others)."""
    share = timings.pop("scan", 0.0) / max(len(want & set(_SCAN_CHECKS)), 1)
    for name in _SCAN_CHECKS:
        timings[name] = timings.get(name, 0.0) + share
    checks = []
    for name in ALL_CHECKS:
        if name not in want:
            continue
        result = results.get(name) or CheckResult.skipped(name, "not applicable")
        result.seconds = timings.get(name, 0.0)
        checks.append(result)
    return checks


def _flag_frames(report: DatasetReport, shard_of: Mapping[str, str], root: Path) -> None:
    """Per video a finding names, its shard and the finding's frame (the first finding's)."""
    for check in report.checks:
        for f in check.report.findings:
            if f.video_id is not None and f.video_id in shard_of and f.video_id not in report.flagged_frames:
                frame = f.numbers.get("frame", 0) if isinstance(f.numbers.get("frame"), int) else 0
                report.flagged_frames[f.video_id] = (str(root / shard_of[f.video_id]), frame)


def _scan_results(
    scans: list[ShardScan],
    shard_of: Mapping[str, str],
    integrity: Report,
    scan_report: Report,
    opts: Options,
) -> dict[str, CheckResult]:
    """integrity, encoding and consistency from the shard pass."""
    videos = {vid: v for s in scans for vid, v in s.videos.items()}
    for f in scan_report.findings:
        integrity.add(f)
    for s in scans:
        for f in s.findings["integrity"]:
            integrity.add(f)
    hashed = sum(1 for v in videos.values() if v.content_hash is not None)
    members = sum(len(v.frames) for v in videos.values())
    n_shards = len({s.path for s in scans})
    frames_decoded = sum(s.frames_decoded for s in scans)
    out = {}
    out["integrity"] = CheckResult.from_report(
        "integrity", integrity,
        f"{n_shards} shards read, {hashed}/{len(videos)} videos' pixel hashes recomputed",
        {"shards": n_shards, "videos": len(videos), "hashed": hashed, "complete_frames": members,
         "refused_members": sum(len(s.tar.refused) for s in scans),
         "truncated_shards": sum(s.tar.truncated is not None for s in scans)},
    )  # fmt: skip
    encoding = Report()
    for s in scans:
        for f in s.findings["encoding"]:
            encoding.add(f)
    if frames_decoded == 0 and not encoding.findings:  # every shard missing or unreadable: nothing checked
        why = "no frame could be read (the integrity check says why)"
        out["encoding"], out["consistency"] = (
            CheckResult.skipped("encoding", why),
            CheckResult.skipped("consistency", why),
        )
        return out
    out["encoding"] = CheckResult.from_report(
        "encoding", encoding, f"{frames_decoded} frames decoded and checked ({opts.sample:.0%} sample)",
        {"frames_decoded": frames_decoded, "sample": opts.sample},
    )  # fmt: skip
    consistency = Report()
    numbers = _consistency(videos, shard_of, consistency)
    out["consistency"] = CheckResult.from_report(
        "consistency", consistency,
        f"{numbers['videos']} videos; worst mean flow EPE {numbers['worst_flow_mean_epe_px']:.3f} px",
        numbers,
    )  # fmt: skip
    return out


def _distribution(loaded: _Loaded, opts: Options) -> tuple[CheckResult, DistributionResult | None]:
    """The recipes table against θ's exact expectations."""
    if loaded.table is None or loaded.theta is None:
        why = "no readable recipes table" if loaded.table is None else "no θ: pass --theta or ship theta.yaml"
        if loaded.table is not None and loaded.distribution.findings:  # theta.yaml there, and invalid
            why = "theta.yaml is not a valid θ: pass --theta or mend it"
        if loaded.distribution.findings:
            return CheckResult.from_report("distribution", loaded.distribution, why, {}), None
        return CheckResult.skipped("distribution", why), None

    rt = loaded.table
    if rt.table.num_rows == 0:
        return CheckResult.skipped("distribution", "the recipes table has no rows: nothing to test"), None
    result = check_distributions(
        {name: rt.column(name) for name in rt.table.column_names}, loaded.theta, alpha=opts.alpha,
        source=str(rt.path.name),
    )  # fmt: skip
    for f in result.report.findings:
        loaded.distribution.add(f)
    rejected = sum(t.rejected for t in result.tests)
    tested = sum(t.tested for t in result.tests)
    untested = len(result.tests) - tested
    check = CheckResult.from_report(
        "distribution", loaded.distribution,
        f"{tested} tests against θ {loaded.theta.name}, {rejected} rejected (Holm, α = {opts.alpha:g}); "
        f"{untested} rows too small to test",
        {"tests": tested, "untested_rows": untested, "rejected": rejected, "videos": result.n_videos,
         "mean_duration_s": result.mean_duration, "expected_mean_duration_s": result.expected_mean_duration},
    )  # fmt: skip
    return check, result


def _failures(
    inp: DatasetInput,
    loaded: _Loaded,
    selected: set[str],
    pixels: Mapping[str, Mapping[int, Sequence[int]]],
    opts: Options,
    progress: ProgressFactory | None,
) -> CheckResult:
    """Failure cases recomputed from the metadata tables, the recipes and instance pixels."""
    missing = [name for name in (PEOPLE, CAMERAS) if not (inp.root / name).is_file()]
    if missing:  # the schema check reports a missing table
        return CheckResult.skipped("failures", f"no {' or '.join(missing)}")
    people, cameras = _read_tables(inp)
    if people is None or cameras is None:  # there but damaged: a finding, whichever checks run
        report = Report()
        for name, table in ((PEOPLE, people), (CAMERAS, cameras)):
            if table is None:
                report.add(Finding(Reason.METADATA_INVALID, "not a readable Parquet table", file=name))
        return CheckResult.from_report("failures", report, "the metadata tables cannot be read", {})

    chosen = {vid: loaded.recipes[vid] for vid in selected if vid in loaded.recipes}
    if not chosen:  # nothing was checked: not a pass
        return CheckResult.skipped("failures", "no video has a valid recipe (the schema check says why)")
    advance = progress("failure cases", len(chosen)) if progress is not None else None
    result, _ = check_failures(chosen, people, cameras, instance_pixels=pixels, budget=opts.budget, progress=advance)
    return result


def _framing(inp: DatasetInput, loaded: _Loaded, selected: set[str]) -> FramingResult | None:
    """The protagonist's framing in the selected videos, from people.parquet; None when it is
    missing or unreadable (the schema check says why) or no video has a valid recipe."""
    path = inp.root / PEOPLE
    recipes = [loaded.recipes[vid] for vid in sorted(selected) if vid in loaded.recipes]
    if not recipes or not path.exists():
        return None
    try:
        return read_framing(path, recipes)
    except PhavUserError:
        return None


def _selected_videos(inp: DatasetInput, loaded: _Loaded, scans: _Scans) -> set[str]:
    """The videos this run covers: those of the named shards (by the manifest, else by their
    members), whichever checks run; else every video."""
    m = loaded.manifest
    if inp.shards is not None:
        if m is not None:
            names = {p.name for p in inp.shards}
            return {v.video_id for v in m.videos if v.shard in names}
        if scans.jobs:
            return set(scans.video_ids())
        return {vid for p in inp.shards if p.exists() for vid in _ids_in(p, loaded.recipes)}
    if m is not None:
        return {v.video_id for v in m.videos}
    return set(loaded.recipes)


def _learnability(
    inp: DatasetInput, loaded: _Loaded, opts: Options, progress: ProgressFactory | None
) -> tuple[CheckResult, LearnResult | None]:
    """A small TSN trained on a held-out-actor split of the dataset's pixels."""
    if inp.recipes_only or loaded.manifest is None or loaded.table is None:
        return CheckResult.skipped("learnability", "needs shards, a manifest and the recipes table"), None
    if inp.shards is not None:
        return CheckResult.skipped("learnability", "trains on the whole dataset: name its directory"), None

    learn = opts.learn if opts.learn is not None else LearnOptions()
    if learn.workers != opts.workers:
        learn = dataclasses.replace(learn, workers=opts.workers)
    try:
        return check_learnability(inp.root, learn, progress=progress, manifest=loaded.manifest, table=loaded.table)
    except PhavUserError as e:
        if e.field != "--split":
            raise
        # Data the split cannot divide (one performer): nothing to measure, not a user's error.
        return CheckResult.skipped("learnability", f"cannot split the data: {e.detail}"), None


def _realism(
    inp: DatasetInput, loaded: _Loaded, opts: Options, progress: ProgressFactory | None
) -> tuple[CheckResult, RealismResult | None]:
    """Models trained on real photographs judge a seeded sample of the dataset's frames."""
    if inp.recipes_only or loaded.manifest is None or loaded.table is None:
        return CheckResult.skipped("realism", "needs shards, a manifest and the recipes table"), None
    if inp.shards is not None:
        return CheckResult.skipped("realism", "samples the whole dataset: name its directory"), None
    realism = opts.realism if opts.realism is not None else RealismOptions(seed=opts.seed)
    result = run_realism(inp.root, realism, progress=progress)
    return realism_check(result, realism), result
