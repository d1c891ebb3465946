"""``phav release``: a dataset directory packed for publication, in full or as recipes alone.

A release holds the dataset's files (shards, ``recipes.parquet``, ``theta.yaml``,
``manifest.json``, ``cameras.parquet``, ``people.parquet``), a dataset card (``README.md``
with θ, statistics and histograms under ``histograms/``), a Croissant JSON-LD description
(``croissant.json``) and ``release.json``, which lists every file of the *full* release
with its size and sha256 and says which are included. A recipe-only release leaves out the
shards and the two metadata tables, all of which ``phav regenerate manifest.json`` rebuilds
and checks against those hashes. Everything is written atomically. The release directory
must be empty or hold this very release; a run marks it first (``.phav-release.json``) and
writes ``release.json`` last, so ``release.json`` marks a finished release, and a rerun,
even of an interrupted run, keeps the files already in place.
"""

from __future__ import annotations

import datetime as dt
import errno
import os
import re
import shutil
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from phav_app.card import RecipeFit, croissant, dataset_card, histograms
from phav_generator.dataset.fingerprint import package_version
from phav_generator.dataset.lock import remove_stale_temporaries
from phav_spec.canonical import pretty_json
from phav_spec.errors import PhavUserError
from phav_spec.files import (
    WriteError,
    atomic_write,
    check_output_dir,
    file_sha256,
    nested,
    parse_json_object,
    read_text,
)
from phav_spec.manifest import DatasetManifest, load_manifest
from phav_spec.recipe import parse_recipe
from phav_spec.recipe_table import RecipeTable, read_recipe_table
from phav_spec.release import (
    CARD_FILE,
    CROISSANT_FILE,
    HISTOGRAMS_DIR,
    IN_PROGRESS_FILE,
    METADATA_FILES,
    RECIPE_FILES,
    RELEASE_FILE,
    ReleaseFile,
    ReleaseIndex,
    load_release_index,
)
from phav_spec.theta import Theta, load_theta
from phav_validators.as_is import metadata_table_problems

__all__ = ["ReleaseResult", "make_release"]


Progress = Callable[[str, int], Callable[[int], None]]


@dataclass(frozen=True)
class ReleaseResult:
    """What ``make_release`` wrote: the index and the bytes of the whole release directory."""

    index: ReleaseIndex
    out: Path
    release_bytes: int
    kept: int  # files a previous, interrupted run had already written

    @property
    def share_of_full(self) -> float:
        """This release's bytes as a share of the full release's data files."""
        return self.release_bytes / max(self.index.full_bytes, 1)


@dataclass(frozen=True)
class _Source:
    root: Path
    manifest: DatasetManifest
    table: RecipeTable
    theta: Theta


def _load_source(root: Path) -> _Source:
    """A finished dataset directory: its manifest, recipes and θ, and every file present."""
    if not root.is_dir():
        raise PhavUserError("not a dataset directory", source=str(root))
    if not (root / "manifest.json").exists():
        unfinished = (root / ".phav-work").exists()
        raise PhavUserError("an unfinished run: finish it with phav generate" if unfinished else "no manifest.json",
                            source=str(root))  # fmt: skip
    manifest = load_manifest(root / "manifest.json")
    table = read_recipe_table(root / "recipes.parquet")
    theta_path = root / "theta.yaml"
    if not theta_path.is_file():
        raise PhavUserError("missing from the dataset; a release ships its θ", source=str(theta_path))
    theta = load_theta(theta_path)
    if manifest.theta_hash is not None and theta.hash != manifest.theta_hash:
        raise PhavUserError(f"θ hashes to {theta.hash[:12]}…, the manifest records {manifest.theta_hash[:12]}…",
                            source=str(theta_path))  # fmt: skip
    ids = table.column("video_id")
    listed = [v.video_id for v in manifest.videos]
    if sorted(ids) != sorted(listed):
        raise PhavUserError("the recipes table and the manifest list different videos", source=str(root))
    _check_recipes(root / "recipes.parquet", table, manifest)
    for name in (*(s.name for s in manifest.shards), *RECIPE_FILES, *METADATA_FILES):
        if not (root / name).is_file():
            raise PhavUserError("missing from the dataset; regenerate it before releasing", source=str(root / name))
    for name in METADATA_FILES:  # shards are checked against the manifest as they are placed
        problems, _ = metadata_table_problems(root / name, set(ids))
        if problems:
            raise PhavUserError(f"{problems[0]}; run phav-validate on the dataset", source=str(root / name))
    return _Source(root, manifest, table, theta)


def _check_recipes(path: Path, table: RecipeTable, manifest: DatasetManifest) -> None:
    """Refuse recipes that are not the ones the videos were made from: a recipe-only release
    ships them to be regenerated, and another seed's (same ids, same θ) or a blank cell would
    be published as the dataset's."""
    if table.dataset_seed is not None and table.dataset_seed != manifest.dataset_seed:
        raise PhavUserError(f"recipes of seed {table.dataset_seed}; the manifest's videos are of seed "
                            f"{manifest.dataset_seed}", source=str(path), field="phav.dataset_seed")  # fmt: skip
    frames = {v.video_id: v.n_frames for v in manifest.videos}
    for vid, cell in zip(table.column("video_id"), table.column("recipe"), strict=True):
        if cell is None:
            raise PhavUserError("no recipe", source=f"{path}[{vid}]", field="recipe")
        recipe = parse_recipe(cell, source=f"{path}[{vid}]")
        if recipe.video_id != vid or recipe.n_frames != frames[vid]:
            raise PhavUserError(f"the recipe is {recipe.video_id}'s with {recipe.n_frames} frames; the manifest's "
                                f"{vid} has {frames[vid]}", source=f"{path}[{vid}]", field="recipe")  # fmt: skip


def _same_file(path: Path, size: int, sha256: str) -> bool:
    return path.is_file() and path.stat().st_size == size and file_sha256(path) == sha256


def _place(source: Path, target: Path, size: int, sha256: str, advance: Callable[[int], None] | None) -> bool:
    """Put ``source`` at ``target`` (a hard link when the filesystem allows, else a copy),
    checking its sha256; False when ``target`` already held it."""
    if _same_file(target, size, sha256):
        return False
    tmp = target.with_name(f".{target.name}.link.tmp")
    tmp.unlink(missing_ok=True)
    try:
        os.link(source, tmp)
    except OSError as e:
        if e.errno not in (errno.EXDEV, errno.EPERM, errno.EMLINK, errno.ENOTSUP, errno.ENOSYS, errno.EACCES):
            raise
        with atomic_write(target) as t:
            shutil.copyfile(source, t)
    else:
        os.replace(tmp, target)
        tmp.unlink(missing_ok=True)  # replacing a link to the same file is a no-op that keeps tmp
    got = file_sha256(target, advance)
    if got != sha256:
        target.unlink()
        raise PhavUserError(f"sha256 {got[:12]}… differs from the recorded {sha256[:12]}… (changed since it was "
                            "generated, or while releasing); run phav-validate on the dataset",
                            source=str(source))  # fmt: skip
    return True


def _index(src: _Source, *, recipes_only: bool, about: dict[str, str | None],
           advance: Callable[[int], None] | None) -> ReleaseIndex:  # fmt: skip
    """Every data file of the full release with its size and sha256 (shards' from the manifest)."""

    files = [ReleaseFile(path=s.name, bytes=s.bytes, sha256=s.sha256, included=not recipes_only, kind="shard")
             for s in src.manifest.shards]  # fmt: skip
    for name, kind in [(n, "recipes") for n in RECIPE_FILES] + [(n, "metadata") for n in METADATA_FILES]:
        path = src.root / name
        files.append(ReleaseFile(path=name, bytes=path.stat().st_size, sha256=file_sha256(path, advance),
                                 included=kind == "recipes" or not recipes_only, kind=kind))  # fmt: skip
    return ReleaseIndex(name=src.manifest.name, recipes_only=recipes_only, phav_version=package_version("phav"),
                        files=files, **about)  # fmt: skip


#: What ``--license`` may be: an SPDX license id (the Hub's card takes it lower-cased) or
#: an http(s) URL; and what ``--url`` must be.
_SPDX_ID = r"[A-Za-z0-9][A-Za-z0-9.+-]*"
_WEB_URL = r"https?://[^\s]+"


def make_release(
    source: str | Path,
    out: str | Path,
    *,
    recipes_only: bool = False,
    license: str = "CC-BY-4.0",
    url: str | None = None,
    date: str | None = None,
    version: str = "1.0.0",
    progress: Progress | None = None,
) -> ReleaseResult:
    """Write the release of the finished dataset ``source`` into ``out`` (see the module doc)."""
    src = _load_source(Path(source))
    out = Path(out)
    if nested(out, src.root):
        raise PhavUserError("the release and the dataset must not contain each other", source=str(out),
                            field="--out")  # fmt: skip
    check_output_dir(out)
    if not (re.fullmatch(_SPDX_ID, license.strip()) or re.fullmatch(_WEB_URL, license.strip())):
        raise PhavUserError(f"give the data's license as an SPDX id such as CC-BY-4.0, or a URL, not {license!r}",
                            field="--license")  # fmt: skip
    if url is not None and not re.fullmatch(_WEB_URL, url):
        raise PhavUserError(f"not an http(s) URL: {url!r}", field="--url")
    if not re.fullmatch(r"\d+\.\d+\.\d+", version):
        raise PhavUserError(f"not MAJOR.MINOR.PATCH: {version!r}", field="--dataset-version")
    if date is not None:
        try:  # Python 3.11's fromisoformat also takes 20260101 and 2026-W01-1
            if not re.fullmatch(r"\d{4}-\d{2}-\d{2}", date):
                raise ValueError(date)
            dt.date.fromisoformat(date)
        except ValueError:
            raise PhavUserError(f"not a date (YYYY-MM-DD): {date!r}", field="--date") from None
    try:
        about = {"dataset_version": version, "license": license, "url": url, "date_published": date}
        return _write_release(src, out, recipes_only=recipes_only, about=about, progress=progress)
    except WriteError:
        raise
    except OSError as e:
        raise WriteError(e, str(e.filename or out), "free space or fix permissions, then rerun to resume") from None


def _claim(out: Path, src: _Source, recipes_only: bool) -> None:
    """Make ``out`` this release's: it must be empty, or hold this release (finished, or
    begun by an interrupted run, which ``IN_PROGRESS_FILE`` marks). An earlier
    ``release.json`` is removed first, so an interrupted rerun never looks finished."""
    claim = {"manifest_sha256": file_sha256(src.root / "manifest.json"), "recipes_only": recipes_only}
    marker, finished = out / IN_PROGRESS_FILE, out / RELEASE_FILE
    if marker.exists():
        ours = parse_json_object(read_text(marker), source=str(marker)) == claim
    elif finished.exists():
        old = load_release_index(finished)
        entry = old.file("manifest.json")
        ours = old.recipes_only == recipes_only and entry is not None and entry.sha256 == claim["manifest_sha256"]
    else:
        ours = not any(out.iterdir())
    if not ours:
        raise PhavUserError("holds other files or another release; choose an empty directory", source=str(out),
                            field="--out")  # fmt: skip
    with atomic_write(marker) as tmp:
        tmp.write_text(pretty_json(claim) + "\n", encoding="utf-8")
    finished.unlink(missing_ok=True)


def _write_release(src: _Source, out: Path, *, recipes_only: bool, about: dict[str, str | None],
                   progress: Progress | None) -> ReleaseResult:  # fmt: skip
    out.mkdir(parents=True, exist_ok=True)
    _claim(out, src, recipes_only)
    for stale in out.rglob(".*.link.tmp"):  # a link a killed run made and never put in place
        stale.unlink()
    # and the temporaries of its copies and writes (a release that is ours: no one else's)
    remove_stale_temporaries(*(d for d in (out, out / HISTOGRAMS_DIR) if d.is_dir()))
    small = sum((src.root / n).stat().st_size for n in RECIPE_FILES + METADATA_FILES)
    advance = progress("hashing", small) if progress is not None else None
    index = _index(src, recipes_only=recipes_only, about=about, advance=advance)
    included = [f for f in index.files if f.included]
    advance = progress("placing files", sum(f.bytes for f in included)) if progress is not None else None
    kept = sum(not _place(src.root / f.path, out / f.path, f.bytes, f.sha256, advance) for f in included)

    fit = RecipeFit.of(src.table, src.theta)
    figures = histograms(fit, src.theta)
    (out / HISTOGRAMS_DIR).mkdir(exist_ok=True)
    for name, svg in figures.items():
        with atomic_write(out / HISTOGRAMS_DIR / name) as tmp:
            tmp.write_text(svg, encoding="utf-8")
    card = dataset_card(src.manifest, fit, src.theta, index, sorted(figures))
    with atomic_write(out / CARD_FILE) as tmp:
        tmp.write_text(card, encoding="utf-8")
    jsonld = croissant(src.manifest, src.table, index)
    with atomic_write(out / CROISSANT_FILE) as tmp:
        tmp.write_text(pretty_json(jsonld) + "\n", encoding="utf-8")
    with atomic_write(out / RELEASE_FILE) as tmp:
        tmp.write_text(pretty_json(index.model_dump(mode="json")) + "\n", encoding="utf-8")
    (out / IN_PROGRESS_FILE).unlink()
    return ReleaseResult(index, out, _tree_bytes(out), kept)


def _tree_bytes(root: Path) -> int:
    return sum(p.stat().st_size for p in sorted(root.rglob("*")) if p.is_file())
