"""What ``phav-validate`` was pointed at: a dataset directory, shards, a manifest or a table.

Paths are grouped by the directory holding their sidecar files (DESIGN.md's layout), so
``phav-validate data/phav-000003.tar data/phav-000007.tar`` checks two shards of one dataset
against its manifest, recipes and θ. A path that does not exist or is of no known kind is a
user error (exit code 2); a damaged file inside a dataset is a finding, not an error.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from phav_generator.dataset.write import WORK_DIR
from phav_spec.errors import PhavUserError
from phav_spec.release import RELEASE_FILE, load_release_index

MANIFEST = "manifest.json"
RECIPES = "recipes.parquet"
THETA = "theta.yaml"
CAMERAS = "cameras.parquet"
PEOPLE = "people.parquet"


@dataclass
class DatasetInput:
    """One dataset to validate: its directory and, optionally, the only shards to scan."""

    root: Path
    #: Shard files named on the command line (None: every shard the manifest lists).
    shards: list[Path] | None = None
    #: The recipes table when it was named directly (``phav-validate recipes.parquet``).
    recipes_path: Path | None = None
    named: list[Path] = field(default_factory=list)

    @property
    def manifest_path(self) -> Path:
        return self.root / MANIFEST

    @property
    def recipes_table(self) -> Path:
        return self.recipes_path if self.recipes_path is not None else self.root / RECIPES

    @property
    def recipes_only(self) -> bool:
        """A recipes table alone (named directly, or a directory with neither manifest nor
        shards, nor what a run of ``phav generate`` leaves): only the recipe checks (schema,
        distribution) apply. A dataset that lost its manifest and shards is not one: its
        integrity check says what is missing."""
        if self.recipes_path is not None and self.recipes_path.name != RECIPES:
            return True
        made = any((self.root / name).exists() for name in (CAMERAS, PEOPLE, WORK_DIR))
        return not made and not self.manifest_path.exists() and not any(self.root.glob("*.tar")) and self.shards is None

    @property
    def label(self) -> str:
        return ", ".join(str(p) for p in self.named) or str(self.root)


def resolve(paths: list[Path]) -> list[DatasetInput]:
    """Group command-line paths into datasets (in the order first named)."""
    if not paths:
        raise PhavUserError(
            "give a dataset directory, shard (.tar), manifest.json, release.json or recipes.parquet", field="PATH"
        )
    out: dict[Path, DatasetInput] = {}
    for path in paths:
        if not path.exists():
            raise PhavUserError("no such file or directory", source=str(path))
        if path.is_dir():
            root = path.resolve()
            inp = out.setdefault(root, DatasetInput(root))
            inp.shards = None  # the whole dataset
        elif path.suffix == ".tar":
            root = path.resolve().parent
            inp = out.setdefault(root, DatasetInput(root, shards=[]))
            if inp.shards is not None and path.resolve() not in inp.shards:  # named twice: scanned once
                inp.shards.append(path.resolve())
        elif path.name in (MANIFEST, RELEASE_FILE):
            root = path.resolve().parent
            inp = out.setdefault(root, DatasetInput(root))
            inp.shards = None  # the whole dataset the manifest lists
        elif path.suffix == ".parquet":
            root = path.resolve().parent
            inp = out.setdefault(root, DatasetInput(root, recipes_path=path.resolve()))
        else:  # another .json (a report, a recipe) would have validated the directory beside it
            raise PhavUserError(
                "expected a dataset directory, a shard .tar, a manifest.json, a release.json or a recipes.parquet",
                source=str(path),
            )
        inp.named.append(path)
    return list(out.values())


def is_recipe_release(inp: DatasetInput) -> bool:
    """True for a release directory whose ``release.json`` says it carries no pixels (an
    unreadable ``release.json`` is the integrity check's finding, not this question's)."""

    path = inp.root / RELEASE_FILE
    if inp.recipes_path is not None or not path.exists():
        return False
    try:
        return load_release_index(path).recipes_only
    except PhavUserError:
        return False
