"""The dataset manifest: ``manifest.json`` beside the shards, listing shards, videos and renderer.

A dataset directory holds shards ``{name}-{000000}.tar`` (WebDataset, one sample per frame
keyed ``{video_id}/{frame:05d}``) and this manifest (DESIGN.md row "dataset layout"). The
manifest ties every video to exactly one shard and records the renderer fingerprint that
decides whether pixels must match bit for bit (row "renderer of record").
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from typing import Annotated, Any, Literal, Self

from pydantic import (
    BaseModel,
    ConfigDict,
    Field,
    StringConstraints,
    ValidationError,
    field_validator,
    model_validator,
)
from pydantic_core import InitErrorDetails, PydanticCustomError

from phav_spec.canonical import canonical_json, pretty_json, sha256_hex
from phav_spec.encoding import MODALITIES, ModalityEncoding, video_content_hash
from phav_spec.errors import PhavUserError
from phav_spec.files import atomic_write, parse_json_object, read_text
from phav_spec.host import simd_class

__all__ = [
    "FINGERPRINT_VERSION",
    "MANIFEST_VERSION",
    "DatasetManifest",
    "RendererFingerprint",
    "ShardEntry",
    "VideoEntry",
    "dump_manifest",
    "load_manifest",
    "renderer_differences",
]

#: Version of the manifest format this code reads and writes; readers refuse newer ones.
MANIFEST_VERSION = 1
#: Version of the renderer fingerprint's fields this code writes (``RendererFingerprint``).
FINGERPRINT_VERSION = 3

VIDEO_ID_PATTERN = r"^v\d{6,}$"  # as a recipe's: v1000000 and on past a million videos
SHARD_NAME_PATTERN = r"^[A-Za-z0-9_-]+-\d{6}\.tar$"
SHA256_PATTERN = r"^[0-9a-f]{64}$"

#: ``v`` and six digits; never a dot, because WebDataset splits sample keys at the first dot.
VideoId = Annotated[str, StringConstraints(pattern=VIDEO_ID_PATTERN)]
#: ``{name}-{index:06d}.tar``.
ShardName = Annotated[str, StringConstraints(pattern=SHARD_NAME_PATTERN)]
#: A sha256 digest as 64 lowercase hex digits.
Sha256Hex = Annotated[str, StringConstraints(pattern=SHA256_PATTERN)]

_CONFIG = ConfigDict(extra="forbid", frozen=True, strict=True)


#: What a comparison of two fingerprints is for: the pixels (content hashes), or whole files
#: (shards and metadata tables, whose bytes also follow their encoders).
Scope = Literal["pixels", "files"]
#: The fingerprint keys that reach the pixels only through the GL driver: where two
#: fingerprints differ in these alone, the simulated motion and the scene handed to GL are
#: the same, and pixels differ only as two renderers draw one scene (within the
#: reproducibility check's tolerances). Any other key (numpy's and OpenBLAS's kernels, a
#: package, the body data, phav's code) can move the physics, whose contacts carry a
#: last-bit difference into a visibly other motion.
RENDERER_ONLY_KEYS = frozenset({"gl_vendor", "gl_renderer", "gl_version", "gl_settings", "cpu_class",
                                "versions.moderngl"})  # fmt: skip


class RendererFingerprint(BaseModel):
    """What a dataset's bytes depend on, as measured (docs/reproducibility.md). The pixels: the
    GL strings (Mesa, LLVM and llvmpipe's vector width), the CPU's SIMD class, numpy's SIMD
    targets and OpenBLAS's kernels (``numeric_class``: the physics carries their last bits
    into the motion), the versions of the packages whose arithmetic reaches them and the
    body data's hash. Whole files also: their encoders (``file_versions``). Equal ``key`` for
    a scope, bit-identical bytes of that scope promised.

    Version 1 recorded the CPU's model name and whole flag list and compared them too; it
    still loads and compares its class by the class its flags give, but, lacking the
    numerics, its pixels and files by its flags: equal only to a version 1 fingerprint of
    the same flags."""

    model_config = _CONFIG

    fingerprint_version: int = Field(default=1, ge=1)
    gl_vendor: str
    gl_renderer: str
    gl_version: str
    #: The CPU's SIMD class (``phav_spec.host.simd_class``); version 2 on.
    cpu_class: str | None = None
    #: numpy's SIMD targets in use and OpenBLAS's kernels; version 2 on.
    numeric_class: str | None = None
    #: The CPU's model name: recorded for the reader, compared only by version 1.
    cpu_model: str
    #: Version 1 only: the CPU's sorted flags (``/proc/cpuinfo``).
    cpu_flags: str | None = None
    #: Package versions, e.g. ``{"phav": ..., "numpy": ..., "mujoco": ..., "moderngl": ...}``.
    versions: dict[str, str]
    #: The environment's settings that change the GL driver's code without changing its
    #: strings (llvmpipe's ``GALLIVM_*``, ``LP_*`` and ``GALLIUM_*`` variables), ``NAME=value``
    #: joined by ``;``, sorted; empty: none set. Version 3 on (earlier: not recorded, read as none).
    gl_settings: str | None = None
    #: What only the files' bytes depend on, not their pixels: the PNG encoder (OpenCV and
    #: its zlib and libpng) and the Parquet writer (pyarrow). Version 3 on.
    file_versions: dict[str, str] = Field(default_factory=dict)

    @model_validator(mode="after")
    def _fields_of_its_version(self) -> Self:
        if self.fingerprint_version > FINGERPRINT_VERSION:
            raise ValueError(
                f"renderer fingerprint version {self.fingerprint_version} is newer than this phav reads "
                f"({FINGERPRINT_VERSION}); upgrade phav"
            )
        needs = {1: ("cpu_flags",), 2: ("cpu_class", "numeric_class")}.get(
            self.fingerprint_version, ("cpu_class", "numeric_class", "gl_settings")
        )
        for name in needs:
            if getattr(self, name) is None:
                raise ValueError(f"a version {self.fingerprint_version} renderer fingerprint needs {name}")
        return self

    @property
    def simd_class(self) -> str:
        """The CPU class the pixels depend on; for version 1, the one its flags give."""
        if self.cpu_class is not None:
            return self.cpu_class
        flags = self.cpu_flags or ""
        # Version 1 ran only on Linux, where x86 CPUs list sse2; ARM lists its flags as Features.
        machine = "x86_64" if "sse2" in flags.split() else "unknown"
        return simd_class(flags, machine, self.cpu_model)

    def key(self, scope: Scope = "pixels") -> dict[str, str]:
        """The fields that decide the bytes of ``scope``, flat (``versions.numpy``, …)."""
        fields = {"gl_vendor": self.gl_vendor, "gl_renderer": self.gl_renderer, "gl_version": self.gl_version,
                  "cpu_class": self.simd_class, "gl_settings": self.gl_settings or ""}  # fmt: skip
        fields |= {f"versions.{k}": v for k, v in sorted(self.versions.items())}
        # Version 1 has no numerics: its CPU's flags (the old rule) stand in.
        fields["numeric_class"] = self.numeric_class or f"CPU flags {self.cpu_flags}"
        if scope == "files":
            fields |= {f"files.{k}": v for k, v in sorted(self.file_versions.items())}
        return fields

    def differences(self, other: RendererFingerprint, scope: Scope = "pixels") -> list[str]:
        """The keys (``key``) in which ``other`` differs from this fingerprint, sorted; empty:
        bit-identical bytes of ``scope`` promised."""
        mine, theirs = self.key(scope), other.key(scope)
        return sorted(k for k in mine.keys() | theirs.keys() if mine.get(k) != theirs.get(k))

    def digest(self, scope: Scope = "pixels") -> str:
        """The sha256 hex digest of ``key``'s canonical JSON: one name for the renderer class."""
        return sha256_hex(canonical_json(self.key(scope)))


def motion_unpromised(differs: Sequence[str] | None) -> list[str]:
    """The fingerprint keys among ``differs`` (``renderer_differences``) that can move the
    simulated motion, all but ``RENDERER_ONLY_KEYS``; empty: the same scene is drawn and
    pixels differ as renderers do. An unrecorded fingerprint (None) promises no motion."""
    if differs is None:
        return ["renderer fingerprint (not recorded)"]
    return [k for k in differs if k not in RENDERER_ONLY_KEYS]


def renderer_differences(
    recorded: RendererFingerprint | None, here: RendererFingerprint | None, scope: Scope = "pixels"
) -> list[str] | None:
    """The fingerprint keys in which ``here`` differs from ``recorded`` for ``scope`` (empty:
    bit-identical bytes promised); None when either is unknown."""
    if recorded is None or here is None:
        return None
    return recorded.differences(here, scope)


class ShardEntry(BaseModel):
    """One WebDataset tar file: its name, sha256 and size, and the videos it holds."""

    model_config = _CONFIG

    name: ShardName
    sha256: Sha256Hex
    bytes: int = Field(ge=0)
    video_ids: list[VideoId]


class VideoEntry(BaseModel):
    """One video: the shard holding all of its frames, its length and its content hash."""

    model_config = _CONFIG

    video_id: VideoId
    shard: ShardName
    n_frames: int = Field(ge=1)
    #: ``phav_spec.encoding.video_content_hash`` of ``modality_hashes``: one digest of every pixel.
    content_hash: Sha256Hex
    #: Per modality name, ``phav_spec.encoding.content_hash`` over that modality's decoded
    #: frames named ``00000``, ``00001``, … (empty: not recorded).
    modality_hashes: dict[str, Sha256Hex] = Field(default_factory=dict)

    @model_validator(mode="after")
    def _hashes_agree(self) -> Self:
        if self.modality_hashes and video_content_hash(self.modality_hashes) != self.content_hash:
            raise ValueError(f"video {self.video_id!r}: content_hash is not the digest of its modality_hashes")
        return self


def _located(loc: tuple[str | int, ...], message: str, value: Any) -> InitErrorDetails:
    """Build one pydantic line error at ``loc`` so that load errors name the exact field."""
    return InitErrorDetails(
        type=PydanticCustomError("manifest_consistency", "{reason}", {"reason": message}),
        loc=loc,
        input=value,
    )


class DatasetManifest(BaseModel):
    """Contents of a dataset's ``manifest.json``: provenance, modalities, shards and videos."""

    model_config = _CONFIG

    manifest_version: int = Field(default=MANIFEST_VERSION, ge=1)
    name: str = Field(pattern=r"^[A-Za-z0-9_-]+$")
    phav_version: str
    #: ``Theta.hash`` of the θ the recipes were sampled from (None: videos made from recipes alone).
    theta_hash: Sha256Hex | None
    dataset_seed: int = Field(ge=0)
    recipe_schema_version: int = Field(ge=1)
    modalities: list[ModalityEncoding] = Field(default_factory=lambda: list(MODALITIES))
    renderer: RendererFingerprint | None = None
    shards: list[ShardEntry]
    videos: list[VideoEntry]

    @field_validator("manifest_version")
    @classmethod
    def _not_newer(cls, version: int) -> int:
        if version > MANIFEST_VERSION:
            raise ValueError(
                f"manifest version {version} is newer than this phav reads ({MANIFEST_VERSION}); upgrade phav"
            )
        return version

    @model_validator(mode="after")
    def _consistent(self) -> Self:
        """Check uniqueness and that every video lives in exactly the one shard naming it."""
        errors: list[InitErrorDetails] = []

        def once(values: list[str], field: str, attr: str, what: str) -> None:
            first: dict[str, int] = {}
            for i, value in enumerate(values):
                if value in first:
                    reason = f"duplicate {what} {value!r} (first at {field}.{first[value]})"
                    errors.append(_located((field, i, attr), reason, value))
                else:
                    first[value] = i

        once([m.name for m in self.modalities], "modalities", "name", "modality")
        once([s.name for s in self.shards], "shards", "name", "shard name")
        once([v.video_id for v in self.videos], "videos", "video_id", "video id")

        listed_in: dict[str, str] = {}
        for si, shard in enumerate(self.shards):
            for j, video_id in enumerate(shard.video_ids):
                if video_id in listed_in:
                    where = listed_in[video_id]
                    reason = (
                        f"video {video_id!r} is listed twice in shard {where!r}"
                        if where == shard.name
                        else f"video {video_id!r} is also listed in shard {where!r}; a video never spans shards"
                    )
                    errors.append(_located(("shards", si, "video_ids", j), reason, video_id))
                else:
                    listed_in[video_id] = shard.name

        modality_names = sorted(m.name for m in self.modalities)
        for vi, video in enumerate(self.videos):
            if video.modality_hashes and sorted(video.modality_hashes) != modality_names:
                reason = f"video {video.video_id!r} has hashes for {sorted(video.modality_hashes)}, "
                reason += f"the manifest's modalities are {modality_names}"
                errors.append(_located(("videos", vi, "modality_hashes"), reason, video.modality_hashes))

        shard_names = {s.name for s in self.shards}
        for vi, video in enumerate(self.videos):
            if video.shard not in shard_names:
                reason = f"video {video.video_id!r} names shard {video.shard!r}, which is not "
                reason += "in the shard list"
            elif listed_in.get(video.video_id) != video.shard:
                reason = f"video {video.video_id!r} names shard {video.shard!r}, but that "
                reason += "shard does not list it in video_ids"
            else:
                continue
            errors.append(_located(("videos", vi, "shard"), reason, video.shard))

        video_ids = {v.video_id for v in self.videos}
        for si, shard in enumerate(self.shards):
            for j, video_id in enumerate(shard.video_ids):
                if video_id not in video_ids:
                    reason = f"shard {shard.name!r} lists video {video_id!r}, which has no "
                    reason += "entry in videos"
                    errors.append(_located(("shards", si, "video_ids", j), reason, video_id))

        if errors:
            raise ValidationError.from_exception_data(type(self).__name__, errors)
        return self


_HINTS = {
    "missing": "add the field",
    "extra_forbidden": "remove the key (misspelt?)",
    "string_pattern_mismatch": "fix the value",
    "manifest_consistency": "regenerate the manifest or fix the shard/video lists",
}


_PATTERN_HINTS = {
    "video_id": "video ids look like v000123 (v and six digits, never a dot)",
    "video_ids": "video ids look like v000123 (v and six digits, never a dot)",
    "shard": "shard names look like {name}-000000.tar",
    "sha256": "write 64 lowercase hex digits",
    "content_hash": "write 64 lowercase hex digits",
    "theta_hash": "write 64 lowercase hex digits",
}


def _user_error(source: str, error: ValidationError) -> PhavUserError:
    """Turn the first pydantic error into a one-line user error naming the field and a fix."""
    first = error.errors(include_url=False)[0]
    field = ".".join(str(part) for part in first["loc"]) or None
    message = first["msg"].removeprefix("Value error, ").removeprefix("Assertion failed, ")  # pydantic's wrapping
    hint = _HINTS.get(first["type"], "fix the value or regenerate the manifest")
    if first["type"] == "string_pattern_mismatch":
        names = [part for part in first["loc"] if isinstance(part, str)]
        key = names[-1] if names else ""
        if names == ["shards", "name"]:
            key = "shard"
        hint = _PATTERN_HINTS.get(key, hint)
    more = error.error_count() - 1
    text = f"{message}; {hint}" + (f" ({more} more error(s))" if more else "")
    return PhavUserError(" ".join(text.split()), source=source, field=field)


def load_manifest(path: str | os.PathLike[str]) -> DatasetManifest:
    """Read and validate a ``manifest.json``.

    Raises:
        PhavUserError: a missing or unreadable file, invalid JSON, a manifest written by a
            newer phav, or a validation failure; the message names the file and the dotted
            field of the first problem (e.g. ``videos.3.video_id``).
    """
    source = str(path)
    text = read_text(path, hint="pass the dataset's manifest.json")
    data = parse_json_object(text, source=source)
    version = data.get("manifest_version")
    if isinstance(version, int) and not isinstance(version, bool) and version > MANIFEST_VERSION:
        raise PhavUserError(
            f"manifest version {version} is newer than this phav reads ({MANIFEST_VERSION}); upgrade phav",
            source=source,
            field="manifest_version",
        )
    try:
        return DatasetManifest.model_validate(data)
    except ValidationError as exc:
        raise _user_error(source, exc) from None


def dump_manifest(manifest: DatasetManifest, path: str | os.PathLike[str]) -> None:
    """Write ``manifest`` as canonical JSON (sorted keys, indent 2) atomically."""
    text = pretty_json(manifest.model_dump(mode="json")) + "\n"
    with atomic_write(path) as tmp:
        tmp.write_text(text, encoding="utf-8", newline="\n")
