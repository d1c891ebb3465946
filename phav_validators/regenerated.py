"""A recipe-only release under ``phav-validate``: its pixels are regenerated, then validated.

A recipe-only release (``phav release --recipes-only``) carries recipes, θ and the manifest
with every video's content hashes and every shard's sha256, but no shards. The checks that
read pixels need them, so the shards they cover are rendered from the recipes first (all of
them, or only those holding the ``--sample`` of videos), into ``--regenerate-into`` or a
temporary directory. The release's own manifest is put beside them, so the integrity check
then compares the regenerated pixels and tar bytes with the hashes the release promises.
"""

from __future__ import annotations

import contextlib
import dataclasses
import shutil
import tempfile
from collections.abc import Iterator
from pathlib import Path
from typing import TYPE_CHECKING

from phav_spec.errors import PhavUserError
from phav_spec.files import atomic_write
from phav_validators.findings import Reason
from phav_validators.source import MANIFEST, RECIPES, THETA, DatasetInput

if TYPE_CHECKING:
    from phav_generator.regenerate import RegenerationPlan
    from phav_spec.manifest import RendererFingerprint
    from phav_validators.validate import DatasetReport, Options, ProgressFactory

#: Checks that need pixels (shards, or the metadata tables the renderer writes).
PIXEL_CHECKS = ("integrity", "encoding", "failures", "consistency", "reproducibility", "learnability")
#: Integrity reasons that mean "these bytes differ from the release's": expected, not a
#: failure, when this machine's renderer is not the release's renderer of record.
_RENDERER_DEPENDENT = (Reason.HASH_MISMATCH, Reason.SHARD_BYTES_CHANGED)


def is_recipe_release(inp: DatasetInput) -> bool:
    """True for a release directory whose ``release.json`` says it carries no pixels."""
    from phav_generator.release import RELEASE_FILE, load_release_index

    path = inp.root / RELEASE_FILE
    return inp.recipes_path is None and path.exists() and load_release_index(path).recipes_only


def _shards_to_build(plan: RegenerationPlan, opts: Options) -> list[int]:
    """Indices of the plan's shards the checks read: those holding the sampled videos."""
    from phav_validators.validate import _sample

    if opts.sample >= 1.0 or "learnability" in opts.checks:
        return list(range(len(plan.shards)))
    ids = [v.video_id for v in plan.expected.videos] if plan.expected is not None else []
    chosen = _sample(ids, opts.sample, opts.seed)
    return [i for i, shard in enumerate(plan.shards) if any(r.video_id in chosen for r in shard)]


def _built(into: Path, release_root: Path, names: list[str], plan: RegenerationPlan) -> bool:
    """True when ``into`` already holds these shards next to the release's manifest (an
    earlier run): the integrity check verifies their hashes either way."""
    manifest = into / MANIFEST
    if not manifest.exists() or manifest.read_bytes() != (release_root / MANIFEST).read_bytes():
        return False
    sizes = {s.name: s.bytes for s in plan.expected.shards} if plan.expected is not None else {}
    return all((into / n).is_file() and (into / n).stat().st_size == sizes.get(n) for n in names)


@contextlib.contextmanager
def _directory(opts: Options) -> Iterator[Path]:
    if opts.regenerate_into is not None:
        opts.regenerate_into.mkdir(parents=True, exist_ok=True)
        yield opts.regenerate_into
        return
    path = Path(tempfile.mkdtemp(prefix="phav-validate-"))
    try:
        yield path
    finally:
        shutil.rmtree(path, ignore_errors=True)


def _fingerprint_here() -> RendererFingerprint:
    """This machine's renderer fingerprint (the one regenerated pixels were made with)."""
    from phav_generator.dataset import renderer_fingerprint
    from phav_generator.render.gl import gl_context, gl_strings

    ctx = gl_context()
    try:
        return renderer_fingerprint(gl_strings(ctx))
    finally:
        ctx.release()


def validate_release(
    inp: DatasetInput, *, theta: str | None, options: Options, progress: ProgressFactory | None
) -> DatasetReport:
    """Regenerate the shards the chosen checks read, then validate them as the release."""
    from phav_generator.dataset import write_dataset
    from phav_generator.regenerate import plan_regeneration
    from phav_validators.validate import validate_dataset

    try:
        plan = plan_regeneration(inp.manifest_path)
    except PhavUserError as e:  # a broken release: validated as it is, the checks say what is wrong
        report = validate_dataset(dataclasses.replace(inp, shards=None), theta=theta,
                                  options=dataclasses.replace(options, checks=("integrity", "schema")),
                                  progress=progress)  # fmt: skip
        report.checks[0].report.notes.append(f"cannot regenerate the release: {e}")
        return report
    chosen = _shards_to_build(plan, options)
    names = [plan.shard_names[i] for i in chosen] if plan.shard_names else []
    with _directory(options) as into:
        reused = _built(into, inp.root, names, plan)
        if not reused:
            n_videos = sum(len(plan.shards[i]) for i in chosen)
            advance = progress("regenerating", n_videos) if progress is not None else None
            write_dataset([plan.shards[i] for i in chosen], into, name=plan.name, theta=plan.theta,
                          dataset_seed=plan.dataset_seed, workers=options.workers, shard_names=names,
                          progress=(lambda videos, frames: advance(videos)) if advance else None,
                          engine=options.engine, address=options.address)  # fmt: skip
            for name in (MANIFEST, RECIPES, THETA):  # the release's, not the subset's
                with atomic_write(into / name) as tmp:
                    shutil.copyfile(inp.root / name, tmp)
        every = len(chosen) == len(plan.shards)
        built = DatasetInput(into, shards=None if every else [into / n for n in names], named=list(inp.named))
        report = validate_dataset(built, theta=theta, options=options, progress=progress)
    report.source = f"{inp.label} (recipe-only release)"
    expected = plan.expected.renderer if plan.expected is not None else None
    exact = expected is not None and expected.digest() == _fingerprint_here().digest()
    where = f"kept in {options.regenerate_into}" if options.regenerate_into is not None else "in a temporary directory"
    basis = (
        "equals the release's: every hash must match"
        if exact
        else "differs from the release's: hash differences are warnings, pixels may differ in the last bits"
    )
    verb = "reused" if reused else "regenerated"
    note = f"{verb} {len(chosen)} of {len(plan.shards)} shards from the release's recipes ({where}); "
    note += f"renderer fingerprint {basis}"
    for check in report.checks:
        if check.name != "integrity":
            continue
        check.report.notes.append(note)
        if not exact:
            check.report.findings = [dataclasses.replace(f, severity="warn") if f.reason in _RENDERER_DEPENDENT
                                     else f for f in check.report.findings]  # fmt: skip
            check.status = type(check).from_report(check.name, check.report, check.summary, check.numbers).status
    return report
