"""``phav regenerate``: rebuild videos from their recipes and compare content hashes.

The source is a dataset directory, its ``manifest.json``, a ``recipes.parquet`` or one recipe
JSON. When a manifest is found, shards keep its names and membership and every rebuilt
video's hashes are compared with it, and every rebuilt shard's sha256; a release's
``release.json`` adds the sha256 of the metadata tables the renderer wrote.
Equality is expected exactly when the renderer fingerprints are equal (DESIGN.md: same
fingerprint → identical pixels), and the report says when they are not.
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path

from phav_generator.dataset.write import DEFAULT_SHARD_SIZE, chunk
from phav_spec.errors import PhavUserError
from phav_spec.files import file_sha256, parse_json_object, read_text
from phav_spec.manifest import DatasetManifest, load_manifest, motion_unpromised, renderer_differences
from phav_spec.recipe import Recipe, load_recipe
from phav_spec.recipe_table import read_recipe_table
from phav_spec.release import METADATA_FILES, RELEASE_FILE, ReleaseIndex, load_release_index
from phav_spec.theta import Theta, load_theta


@dataclass(frozen=True)
class RegenerationPlan:
    """What to rebuild: recipes grouped in shards, and the manifest to compare with (if any)."""

    shards: list[list[Recipe]]
    shard_names: list[str] | None
    name: str
    theta: Theta | None
    dataset_seed: int
    expected: DatasetManifest | None
    #: The release's ``release.json`` when the source is a release: every file's sha256.
    release: ReleaseIndex | None = None
    #: The directory of the manifest, where its shards (the frames to compare) would lie.
    root: Path | None = None

    @property
    def n_videos(self) -> int:
        return sum(len(s) for s in self.shards)


def _locate(source: Path) -> tuple[Path | None, Path | None, Path | None]:
    """(manifest, recipes table, recipe JSON) paths for a source."""
    if source.is_dir():
        manifest = source / "manifest.json"
        table = source / "recipes.parquet"
        if not table.exists():
            raise PhavUserError("no recipes.parquet in this directory", source=str(source))
        return (manifest if manifest.exists() else None), table, None
    if not source.exists():
        raise PhavUserError("no such file or directory", source=str(source))
    if source.suffix == ".parquet":
        beside = source.parent / "manifest.json"
        return (beside if beside.exists() else None), source, None
    if source.suffix == ".json":
        data = parse_json_object(read_text(source), source=str(source))
        if "manifest_version" in data:
            table = source.parent / "recipes.parquet"
            if not table.exists():
                raise PhavUserError("no recipes.parquet beside this manifest", source=str(source))
            return source, table, None
        return None, None, source
    raise PhavUserError("expected a dataset directory, manifest.json, recipes.parquet or a recipe .json",
                        source=str(source))  # fmt: skip


def _theta_beside(table_path: Path, theta: Theta | None) -> Theta | None:
    """The dataset's ``theta.yaml`` when it is the table's θ: rewritten, it keeps its bytes
    (the table stores θ as canonical JSON, whose key order differs)."""
    path = table_path.parent / "theta.yaml"
    if theta is None or not path.exists():
        return theta
    beside = load_theta(path)
    return beside if beside.hash == theta.hash else theta


def plan_regeneration(source: str | Path, *, videos: list[str] | None = None) -> RegenerationPlan:
    """Resolve a source into shards of recipes to rebuild, optionally only some videos."""
    manifest_path, table_path, recipe_path = _locate(Path(source))
    if recipe_path is not None:
        recipe = load_recipe(recipe_path)
        if videos and recipe.video_id not in videos:
            raise PhavUserError(f"the recipe is {recipe.video_id}, not {', '.join(videos)}", field="--video")
        return RegenerationPlan([[recipe]], None, "phav", None, recipe.dataset_seed, None)
    assert table_path is not None
    table = read_recipe_table(table_path)
    ids = table.column("video_id")
    twice = sorted((v, k) for v, k in Counter(ids).items() if k > 1)
    if twice:  # which of its recipes would be the video's?
        raise PhavUserError(f"video {twice[0][0]} has {twice[0][1]} recipes in the table; run phav-validate",
                            source=str(table_path), field="video_id")  # fmt: skip
    by_id = {r.video_id: r for r in table.recipes()}
    wanted = list(by_id) if not videos else videos
    unknown = [v for v in wanted if v not in by_id]
    if unknown:
        raise PhavUserError(f"no video {unknown[0]!r} in {len(by_id)} recipes", source=str(table_path), field="--video")
    keep = set(wanted)
    theta = _theta_beside(table_path, table.theta)
    # A table of hand-made recipes has no dataset seed; its recipes carry their own seeds, so
    # the manifest records theirs where they share one, else 0 (bookkeeping only).
    seeds = {r.dataset_seed for r in by_id.values()}
    seed = table.dataset_seed if table.dataset_seed is not None else (seeds.pop() if len(seeds) == 1 else 0)
    if manifest_path is None:
        recipes = [by_id[v] for v in by_id if v in keep]
        return RegenerationPlan(chunk(recipes, DEFAULT_SHARD_SIZE), None, "phav", theta, seed, None)
    manifest = load_manifest(manifest_path)
    missing = [v.video_id for v in manifest.videos if v.video_id not in by_id]
    if missing:
        raise PhavUserError(f"video {missing[0]} is in the manifest but has no recipe", source=str(table_path))
    shards, names = [], []
    for shard in manifest.shards:
        chosen = [by_id[v] for v in shard.video_ids if v in keep]
        if chosen:
            shards.append(chosen)
            names.append(shard.name)
    release_path = manifest_path.parent / RELEASE_FILE
    release = load_release_index(release_path) if release_path.exists() else None
    return RegenerationPlan(shards, names, manifest.name, theta, seed, manifest, release, manifest_path.parent)


def check_target(source: str | Path, out: str | Path) -> None:
    """Refuse an ``--out`` whose rebuilt files would overwrite what they are compared with:
    the source's own directory, or any release."""
    src = Path(source)
    where = src if src.is_dir() else src.parent
    if Path(out).resolve() == where.resolve() or (Path(out) / RELEASE_FILE).exists():
        raise PhavUserError("must be a directory apart from the source (the rebuilt files would overwrite what "
                            "they are compared with)", source=str(out), field="--out")  # fmt: skip


@dataclass
class HashReport:
    """How rebuilt videos compare with the manifest they came from."""

    compared: int = 0
    matched: int = 0
    exact: bool = True  # the fingerprints agree for pixels: equal content hashes are expected
    #: The fingerprint keys for pixels in which the rebuilding renderer differs.
    renderer_differs: list[str] = field(default_factory=list)
    #: The fingerprints agree for whole files (numpy and OpenBLAS too): equal sha256 expected.
    files_exact: bool = True
    files_differ_in: list[str] = field(default_factory=list)
    #: Whether both fingerprints are recorded (``renderer_differs`` is then the whole difference).
    renderer_known: bool = True
    mismatches: list[str] = field(default_factory=list)
    #: Videos whose content hash differs where another renderer made them (not a mismatch:
    #: their frames are compared within tolerances where the originals are at hand).
    differing: list[str] = field(default_factory=list)
    #: Whole files (shards, and a release's other files) compared by sha256, and matched.
    files_compared: int = 0
    files_matched: int = 0
    #: Files whose sha256 differs where the fingerprints do not promise it (not a mismatch).
    files_unpromised: list[str] = field(default_factory=list)

    @property
    def motion(self) -> list[str]:
        """The fingerprint keys that differ and can move the physics (``motion_unpromised``)."""
        return motion_unpromised(self.renderer_differs if self.renderer_known else None)

    def summary(self) -> str:
        basis = (
            "same renderer fingerprint: bit-exact equality expected"
            if self.exact
            else "another renderer fingerprint"
            + (f" ({', '.join(self.renderer_differs)})" if self.renderer_differs else "")
            + ": equal pixels not promised"
        )
        files = f"; files: {self.files_matched}/{self.files_compared} sha256 match" if self.files_compared else ""
        if self.files_unpromised:
            why = f"where {', '.join(self.files_differ_in)} differ: their encoding" if self.exact else "not promised"
            files += f" ({len(self.files_unpromised)} differ {why})"
        return f"content hashes: {self.matched}/{self.compared} videos match{files} ({basis})"

    def _file(self, name: str, expected: str, got: str) -> None:
        self.files_compared += 1
        if expected == got:
            self.files_matched += 1
        elif self.files_exact:
            self.mismatches.append(f"{name}: sha256 {got[:12]}…, expected {expected[:12]}…")
        else:  # not promised: other floats in the metadata, or another renderer's pixels
            self.files_unpromised.append(name)


def compare_hashes(
    expected: DatasetManifest | None,
    rebuilt: DatasetManifest,
    *,
    out: Path | None = None,
    release: ReleaseIndex | None = None,
) -> HashReport:
    """Per video and modality, which rebuilt content hashes differ from the expected ones;
    then the sha256 of every rebuilt shard holding the same videos as the expected one and,
    when every video was rebuilt into ``out``, of the metadata tables ``release`` lists."""
    report = HashReport()
    if expected is None:
        return report
    differs = renderer_differences(expected.renderer, rebuilt.renderer)
    report.exact = differs == []
    report.renderer_differs = differs or []
    report.renderer_known = differs is not None
    files_differ = renderer_differences(expected.renderer, rebuilt.renderer, "files")
    report.files_exact = files_differ == []
    report.files_differ_in = [k for k in files_differ or [] if k not in report.renderer_differs]
    before = {v.video_id: v for v in expected.videos}
    for video in rebuilt.videos:
        old = before[video.video_id]
        report.compared += 1
        if old.content_hash == video.content_hash:
            report.matched += 1
            continue
        if not report.exact:
            report.differing.append(video.video_id)
            continue
        differ = [m for m in sorted(video.modality_hashes) if old.modality_hashes.get(m) != video.modality_hashes[m]]
        report.mismatches.append(f"{video.video_id}: {', '.join(differ) or 'content hash'}")
    shards = {s.name: s for s in expected.shards}
    for shard in rebuilt.shards:
        old_shard = shards.get(shard.name)
        if old_shard is not None and old_shard.video_ids == shard.video_ids:
            report._file(shard.name, old_shard.sha256, shard.sha256)
    if release is not None and out is not None and len(rebuilt.videos) == len(expected.videos):
        for f in release.files:
            if f.kind != "metadata":  # renderer outputs (recipes and θ are the inputs)
                continue
            if f.path in METADATA_FILES:
                report._file(f.path, f.sha256, file_sha256(out / f.path))
            else:  # a file a run does not write: the release lists what phav did not make
                report.files_compared += 1
                report.mismatches.append(f"{f.path}: listed as metadata by release.json, not made by phav")
    return report
