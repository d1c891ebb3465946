"""The release index (``release.json``): every file of a full release with its size and
sha256, which of them this release carries, and the release's identity (name, versions,
licence, URL, date). What a release directory holds beside it is named here too, so a reader
of a release needs nothing but ``phav_spec``."""

from __future__ import annotations

from pathlib import Path

from pydantic import BaseModel, ConfigDict, Field, ValidationError

from phav_spec.errors import PhavUserError
from phav_spec.files import parse_json_object, read_text
from phav_spec.manifest import Sha256Hex

#: Version of ``release.json``'s format; readers refuse newer ones.
RELEASE_VERSION = 1
RELEASE_FILE = "release.json"
#: Marks a release being written (and by whom: the manifest's sha256 and the kind), so
#: that a rerun resumes its own release and never writes into someone else's directory.
IN_PROGRESS_FILE = ".phav-release.json"
CARD_FILE = "README.md"
CROISSANT_FILE = "croissant.json"
HISTOGRAMS_DIR = "histograms"
#: Files every release carries: what regeneration starts from and checks against.
RECIPE_FILES = ("manifest.json", "recipes.parquet", "theta.yaml")
#: Files the renderer made: in a full release, rebuilt by ``phav regenerate`` otherwise.
METADATA_FILES = ("cameras.parquet", "people.parquet")
#: The paper the dataset's generative model comes from (cited by the card and Croissant).
PHAV_CITATION = """@inproceedings{deSouza2017procedural,
  title     = {Procedural Generation of Videos to Train Deep Action Recognition Networks},
  author    = {de Souza, C{\\'e}sar Roberto and Gaidon, Adrien and Cabon, Yohann and L{\\'o}pez Pe{\\~n}a, Antonio M.},
  booktitle = {IEEE Conference on Computer Vision and Pattern Recognition (CVPR)},
  year      = {2017}
}"""


class ReleaseFile(BaseModel):
    """One file of the full release: where it is, its size and sha256, and whether this
    release carries it (a recipe-only release leaves out what regeneration rebuilds)."""

    model_config = ConfigDict(extra="forbid", frozen=True, strict=True)

    path: str = Field(pattern=r"^[A-Za-z0-9_.-]*[A-Za-z0-9_-][A-Za-z0-9_.-]*$")  # a file's name, not "." or ".."
    bytes: int = Field(ge=0)
    sha256: Sha256Hex
    included: bool
    kind: str = Field(pattern=r"^(shard|recipes|metadata)$")


class ReleaseIndex(BaseModel):
    """Contents of ``release.json``."""

    model_config = ConfigDict(extra="forbid", frozen=True, strict=True)

    release_version: int = Field(default=RELEASE_VERSION, ge=1)
    name: str
    recipes_only: bool
    phav_version: str
    dataset_version: str
    license: str
    url: str | None
    date_published: str | None
    files: list[ReleaseFile]

    @property
    def full_bytes(self) -> int:
        """Bytes of the full release's data files."""
        return sum(f.bytes for f in self.files)

    @property
    def included_bytes(self) -> int:
        return sum(f.bytes for f in self.files if f.included)

    def file(self, path: str) -> ReleaseFile | None:
        return next((f for f in self.files if f.path == path), None)


def load_release_index(path: str | Path) -> ReleaseIndex:
    """Read ``release.json``; unreadable, malformed or newer files raise PhavUserError."""
    data = parse_json_object(read_text(path), source=str(path))
    version = data.get("release_version")
    if isinstance(version, int) and version > RELEASE_VERSION:
        raise PhavUserError(f"release version {version} is newer than this phav reads ({RELEASE_VERSION}); "
                            "upgrade phav", source=str(path), field="release_version")  # fmt: skip
    try:
        return ReleaseIndex.model_validate(data)
    except ValidationError as e:
        err = e.errors()[0]
        raise PhavUserError(err["msg"], source=str(path), field=".".join(str(x) for x in err["loc"])) from None
