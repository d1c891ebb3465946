"""A recipe-only release under ``phav-validate``: its pixels are regenerated, then validated.

A recipe-only release (``phav release --recipes-only``) carries recipes, θ and the manifest
with every video's content hashes and every shard's sha256, but no shards. The checks that
read pixels need them, so the shards they cover are rendered from the recipes first (all of
them, or only those holding the ``--sample`` of videos), into ``--regenerate-into`` or a
temporary directory. The release's own manifest is put beside them, so the integrity check
then compares the regenerated pixels and tar bytes with the hashes the release promises.
A marker file says what was regenerated there and by which renderer: a later run reuses
the directory only for exactly the same shards of the same release.
"""

from __future__ import annotations

import contextlib
import dataclasses
import shutil
import tempfile
from collections.abc import Iterator
from pathlib import Path
from typing import TYPE_CHECKING, Any

from phav_generator.dataset.write import DONE_DIR, WORK_DIR, write_dataset
from phav_generator.pipeline import PART_TABLES
from phav_generator.regenerate import plan_regeneration
from phav_spec.canonical import pretty_json
from phav_spec.errors import PhavUserError
from phav_spec.files import WriteError, atomic_write, file_sha256, nested, parse_json_object, read_text
from phav_spec.manifest import RendererFingerprint, renderer_differences
from phav_spec.release import RECIPE_FILES, RELEASE_FILE
from phav_validators.as_is import release_file_findings, validate_as_is
from phav_validators.findings import CheckResult, ProgressFactory, Reason
from phav_validators.options import ALL_CHECKS, DatasetReport, Options, sample_videos
from phav_validators.report import flagged_pictures
from phav_validators.source import MANIFEST, RECIPES, THETA, DatasetInput

if TYPE_CHECKING:
    from phav_generator.regenerate import RegenerationPlan

#: Integrity reasons that mean "these bytes differ from the release's": expected, not a
#: failure, when the regenerating renderer is not the release's renderer of record.
_RENDERER_DEPENDENT = (Reason.HASH_MISMATCH, Reason.SHARD_BYTES_CHANGED)
#: The checks that read only a release's own files (no pixels): they run on a release too
#: broken to regenerate.
_PIXEL_FREE = ("integrity", "schema", "distribution")
#: In a ``--regenerate-into`` directory: what was regenerated there, for which release, by
#: which renderer, and the files it wrote.
MARKER = ".phav-regenerated.json"


def _shards_to_build(plan: RegenerationPlan, opts: Options) -> list[int]:
    """Indices of the plan's shards the checks read: those holding the sampled videos, or
    every shard for the checks that sample the whole dataset themselves (learnability,
    realism)."""

    if opts.sample >= 1.0 or "learnability" in opts.checks or "realism" in opts.checks:
        return list(range(len(plan.shards)))
    ids = [v.video_id for v in plan.expected.videos] if plan.expected is not None else []
    chosen = sample_videos(ids, opts.sample, opts.seed)
    return [i for i, shard in enumerate(plan.shards) if any(r.video_id in chosen for r in shard)]


def _apart(into: Path, release_root: Path) -> None:
    """Refuse the release itself, a directory inside it or holding it, and any release."""

    if nested(into, release_root) or (into / RELEASE_FILE).exists():
        raise PhavUserError("must be a directory of its own, apart from the release", source=str(into),
                            field="--regenerate-into")  # fmt: skip


def _earlier(into: Path) -> dict[str, Any] | None:
    """The marker of an earlier regeneration into ``into`` (None: there was none); a
    directory holding anything else is refused."""
    marker = into / MARKER
    if marker.exists():
        return parse_json_object(read_text(marker), source=str(marker))
    if any(into.iterdir()):
        raise PhavUserError("holds other files; choose an empty directory or one an earlier run regenerated into",
                            source=str(into), field="--regenerate-into")  # fmt: skip
    return None


def _clear(into: Path, marker: dict[str, Any]) -> None:
    """Remove the files an earlier regeneration wrote, or an interrupted one may have, and
    its work folder (its marker last)."""
    for name in marker.get("files", []):
        if isinstance(name, str) and name == Path(name).name and not name.startswith("."):
            (into / name).unlink(missing_ok=True)
    for work in (WORK_DIR, DONE_DIR):
        shutil.rmtree(into / work, ignore_errors=True)
    (into / MARKER).unlink()


@contextlib.contextmanager
def _directory(opts: Options) -> Iterator[Path]:
    if opts.regenerate_into is not None:
        try:
            opts.regenerate_into.mkdir(parents=True, exist_ok=True)
        except OSError as e:
            raise WriteError(e, str(opts.regenerate_into)) from None
        yield opts.regenerate_into
        return
    if opts.engine == "ray" and opts.address:
        raise PhavUserError("a Ray cluster's workers cannot see this machine's temporary directory; name one on "
                            "storage every node mounts", field="--regenerate-into")  # fmt: skip
    path = Path(tempfile.mkdtemp(prefix="phav-validate-"))
    try:
        yield path
    finally:
        shutil.rmtree(path, ignore_errors=True)


def _regenerate(inp: DatasetInput, plan: RegenerationPlan, chosen: list[int], into: Path, options: Options,
                progress: ProgressFactory | None) -> tuple[dict[str, Any], bool]:  # fmt: skip
    """Regenerate the chosen shards into ``into``, or reuse an earlier run that made exactly
    these; returns the marker (what is there, the renderer that made it) and whether reused."""

    names = [plan.shard_names[i] for i in chosen] if plan.shard_names else []
    wanted = {"release_manifest_sha256": file_sha256(inp.root / MANIFEST), "shards": names}
    before = _earlier(into)
    same = before is not None and {k: before.get(k) for k in wanted} == wanted
    if same and not before.get("begun") and _intact(into, names, plan):
        return before, True
    if before is not None and (not same or not before.get("begun")):  # another request's, or damaged since
        _clear(into, before)
        before = None
    # Said before the first write: a run stopped half-way leaves a directory that is ours,
    # resumed by the same request (write_dataset's journal) or cleared by another.
    may_write = [*names, MANIFEST, RECIPES, THETA, *(f"{table}.parquet" for table, _ in PART_TABLES)]
    begun = wanted | {"begun": True, "files": sorted(may_write)}
    release_copy = (into / MANIFEST).is_file() and file_sha256(into / MANIFEST) == wanted["release_manifest_sha256"]
    if release_copy and before is not None and before.get("renderer") is not None:
        renderer = before["renderer"]  # stopped while the release's files were copied in: every shard is made
    else:
        if release_copy:  # not the run's own manifest: the run is made again, not taken as another's
            (into / MANIFEST).unlink()
        with atomic_write(into / MARKER) as tmp:
            tmp.write_text(pretty_json(begun) + "\n", encoding="utf-8")
        n_videos = sum(len(plan.shards[i]) for i in chosen)
        advance = progress("regenerating", n_videos) if progress is not None else None
        result = write_dataset([plan.shards[i] for i in chosen], into, name=plan.name, theta=plan.theta,
                               dataset_seed=plan.dataset_seed, workers=options.workers, shard_names=names,
                               progress=(lambda videos, frames: advance(videos)) if advance else None,
                               engine=options.engine, address=options.address)  # fmt: skip
        made = result.manifest.renderer
        renderer = made.model_dump(mode="json") if made is not None else None
        # Who made the shards, said before the subset's manifest is replaced by the release's.
        with atomic_write(into / MARKER) as tmp:
            tmp.write_text(pretty_json(begun | {"renderer": renderer}) + "\n", encoding="utf-8")
    for name in (MANIFEST, RECIPES, THETA):  # the release's, not the subset's
        with atomic_write(into / name) as tmp:
            shutil.copyfile(inp.root / name, tmp)
    marker = wanted | {
        "renderer": renderer,
        "files": sorted(p.name for p in into.iterdir() if p.is_file() and not p.name.startswith(".")),
    }
    with atomic_write(into / MARKER) as tmp:
        tmp.write_text(pretty_json(marker) + "\n", encoding="utf-8")
    return marker, False


def _name_the_release(report: DatasetReport, into: Path, release: Path) -> None:
    """Findings about the files copied from the release (its manifest, recipes, θ) name the
    release's own, not their copies where the pixels were regenerated (a temporary directory
    gone once the report is read); a regenerated shard is named by its file name."""
    for check in report.checks:
        findings = check.report.findings
        for i, f in enumerate(findings):
            if f.file is None or not Path(f.file).is_relative_to(into):
                continue
            name = Path(f.file).relative_to(into)
            where = release / name if str(name) in (MANIFEST, RECIPES, THETA) else name
            findings[i] = dataclasses.replace(f, file=str(where))


def _intact(into: Path, names: list[str], plan: RegenerationPlan) -> bool:
    """Whether an earlier regeneration's shards are all in ``into`` at the sizes the release
    records, beside the release's manifest, recipes and θ (else it is made again)."""
    sizes = {s.name: s.bytes for s in plan.expected.shards} if plan.expected is not None else {}
    shards = all((into / n).is_file() and (into / n).stat().st_size == sizes.get(n) for n in names)
    return shards and all((into / n).is_file() for n in (MANIFEST, RECIPES, THETA))


def validate_release(
    inp: DatasetInput, *, theta: str | None, options: Options, progress: ProgressFactory | None
) -> DatasetReport:
    """Regenerate the shards the chosen checks read, then validate them as the release."""

    try:
        missing = [name for name in RECIPE_FILES if not (inp.root / name).is_file()]
        if missing:
            raise PhavUserError(f"{', '.join(missing)} missing", source=str(inp.root))
        plan = plan_regeneration(inp.manifest_path)
    except PhavUserError as e:  # a broken release: validated as it is, the checks say what is wrong
        why = f"cannot regenerate the release: {e}"
        # The checks asked for that need no pixels run on the release's files; integrity
        # (which says what is missing) where none was asked for; the rest are skipped, why said.
        free = tuple(c for c in options.checks if c in _PIXEL_FREE) or ("integrity",)
        report = validate_as_is(dataclasses.replace(inp, shards=None), theta=theta,
                                options=dataclasses.replace(options, checks=free), progress=progress)  # fmt: skip
        report.checks[0].report.notes.append(why)
        report.checks += [CheckResult.skipped(c, why) for c in options.checks if c not in free]
        report.checks.sort(key=lambda c: ALL_CHECKS.index(c.name))
        return report
    chosen = _shards_to_build(plan, options)
    if options.regenerate_into is not None:
        _apart(options.regenerate_into, inp.root)
    with _directory(options) as into:
        marker, reused = _regenerate(inp, plan, chosen, into, options, progress)
        shards = None if len(chosen) == len(plan.shards) else [into / n for n in marker["shards"]]
        # The sample chose the shards; every video in them is checked, not a sample drawn again.
        scanned = options if shards is None else dataclasses.replace(options, sample=1.0)
        report = validate_as_is(DatasetInput(into, shards=shards, named=list(inp.named)), theta=theta,
                                options=scanned, progress=progress)  # fmt: skip
        _name_the_release(report, into, inp.root)
        if options.regenerate_into is None:  # the shards go with the directory: the pictures are read now
            report.flagged_pictures = flagged_pictures(report)
    report.source = f"{inp.label} (recipe-only release)"
    expected = plan.expected.renderer if plan.expected is not None else None
    made_by = RendererFingerprint.model_validate(marker["renderer"]) if marker.get("renderer") else None
    differs = renderer_differences(expected, made_by)
    files_differ = renderer_differences(expected, made_by, "files")
    where = f"kept in {options.regenerate_into}" if options.regenerate_into is not None else "in a temporary directory"
    if files_differ == []:
        basis, lenient = "equals the release's: every hash must match", ()
    elif differs == []:
        encoders = ", ".join(k for k in files_differ or [] if k not in differs)
        basis = (f"equals the release's for pixels (every content hash must match); {encoders} differ, so shard "
                 "bytes may differ in their encoding (warnings)")  # fmt: skip
        lenient = (Reason.SHARD_BYTES_CHANGED,)
    else:
        basis = ("differs from the release's" + (f" ({', '.join(differs)})" if differs else "")
                 + ": hash differences are warnings, pixels may differ")  # fmt: skip
        lenient = _RENDERER_DEPENDENT
    verb = "reused" if reused else "regenerated"
    note = f"{verb} {len(chosen)} of {len(plan.shards)} shards from the release's recipes ({where}"
    if len(chosen) < len(plan.shards):
        note += f"; --sample {options.sample:g}: those holding the sampled videos, every video in them checked"
    note += f"); the renderer that made them {basis}"
    for check in report.checks:
        if check.name != "integrity":
            continue
        check.report.notes.append(note)
        if lenient:
            check.report.findings = [dataclasses.replace(f, severity="warn") if f.reason in lenient
                                     else f for f in check.report.findings]  # fmt: skip
        # The release's own files against release.json: the copy validated above has none.
        for finding in release_file_findings(inp.root, plan.expected):
            check.report.add(finding)
        check.status = type(check).from_report(check.name, check.report, check.summary, check.numbers).status
    return report
