"""The reference renders: short recipes whose bytes were recorded, stage by stage, with the
renderer of record, so that any machine can tell whether it makes the same pixels and, where
it does not, the first stage that differs.

A video's stages, in data-flow order: the recipe, the simulated trajectory, the body data
the people are made of, the scene handed to GL (meshes, transforms, textures, light), then
each modality's content hash. ``reference.json`` (package data) holds the recipes, the
fingerprint of the machine that recorded them and their stage hashes; ``phav fingerprint
--check``, the golden render test and ``docs/measure/pixel_factors.py`` all compare through
``trace`` and ``compare``.
"""

from __future__ import annotations

import dataclasses
import hashlib
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import moderngl
import numpy as np

from phav_generator.body.data import load_body_data
from phav_generator.dataset.fingerprint import CODE_KEYS
from phav_generator.physics.simulate import simulate
from phav_generator.render.video import render_video, scene_inputs
from phav_spec.canonical import canonical_json, pretty_json, sha256_hex
from phav_spec.encoding import VideoHashes
from phav_spec.errors import PhavUserError, validate_user_data
from phav_spec.files import atomic_write, parse_json_object, read_text
from phav_spec.manifest import RendererFingerprint
from phav_spec.recipe import Recipe, parse_recipe

#: The recorded reference, shipped with the package.
REFERENCE_FILE = Path(__file__).with_name("reference.json")
#: Stages before GL, in data-flow order; the modalities follow, labels before colour.
CPU_STAGES = ("recipe", "trajectory", "body", "scene")
PIXEL_STAGES = ("semantic", "instance", "depth", "flow", "raw_rgb", "rgb")
STAGES = CPU_STAGES + PIXEL_STAGES


@dataclass(frozen=True)
class Reference:
    """Recorded renders: the recorder's fingerprint and, per video name, its recipe and the
    sha256 of each of its ``STAGES``."""

    fingerprint: RendererFingerprint
    recipes: dict[str, Recipe]
    stages: dict[str, dict[str, str]]

    def to_json(self) -> dict[str, Any]:
        return {
            "fingerprint": self.fingerprint.model_dump(mode="json", exclude_none=True),
            "videos": {
                name: {"recipe": self.recipes[name].model_dump(mode="json"), "stages": self.stages[name]}
                for name in sorted(self.recipes)
            },
        }


def _feed(h: Any, obj: Any) -> None:
    """Feed ``obj`` into hash ``h`` unambiguously: arrays by dtype, shape and little-endian
    bytes; dataclasses by field; mappings by sorted key; sequences in order; scalars by repr."""
    if isinstance(obj, np.ndarray):
        a = np.ascontiguousarray(obj, dtype=obj.dtype.newbyteorder("<"))
        h.update(f"array {a.dtype.str} {a.shape} {a.nbytes};".encode())
        h.update(a.tobytes())
    elif dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        h.update(f"{type(obj).__name__}{{".encode())
        for f in dataclasses.fields(obj):
            h.update(f"{f.name}=".encode())
            _feed(h, getattr(obj, f.name))
        h.update(b"}")
    elif isinstance(obj, Mapping):
        h.update(f"map {len(obj)}{{".encode())
        for key in sorted(obj):
            h.update(f"{key!r}=".encode())
            _feed(h, obj[key])
        h.update(b"}")
    elif isinstance(obj, list | tuple):
        h.update(f"seq {len(obj)}[".encode())
        for item in obj:
            _feed(h, item)
        h.update(b"]")
    elif obj is None or isinstance(obj, bool | int | float | str | np.generic):
        h.update(f"{type(obj).__name__} {obj!r};".encode())
    else:
        raise TypeError(f"cannot hash a {type(obj).__name__}")


def structure_hash(obj: Any) -> str:
    """The sha256 of nested arrays, dataclasses, mappings, sequences and scalars (``_feed``)."""
    h = hashlib.sha256()
    _feed(h, obj)
    return h.hexdigest()


def trace(recipe: Recipe, ctx: moderngl.Context) -> dict[str, str]:
    """The sha256 of each of ``STAGES`` for one recipe rendered in ``ctx``."""
    trajectory = simulate(recipe, keep_state=False)
    out = {
        "recipe": sha256_hex(canonical_json(recipe.model_dump(mode="json"))),
        "trajectory": structure_hash(trajectory.arrays()),
        "body": load_body_data().sha256,
        "scene": structure_hash(scene_inputs(recipe, trajectory)),
    }
    hashes = VideoHashes(recipe.n_frames)
    for frame in render_video(recipe, trajectory, ctx=ctx):
        hashes.add(frame.index, frame.modalities)
    pixels = hashes.hexdigests()
    return out | {stage: pixels[stage] for stage in PIXEL_STAGES}


def trace_all(recipes: Mapping[str, Recipe], ctx: moderngl.Context) -> dict[str, dict[str, str]]:
    """``trace`` of every recipe, by name."""
    return {name: trace(recipes[name], ctx) for name in sorted(recipes)}


def compare(recorded: Mapping[str, Mapping[str, str]], traced: Mapping[str, Mapping[str, str]]) -> dict[str, list[str]]:
    """Per video, the stages (in ``STAGES`` order) whose hashes differ; empty lists: identical."""
    return {name: [s for s in STAGES if recorded[name].get(s) != traced[name].get(s)] for name in sorted(recorded)}


def first_difference(differing: Mapping[str, list[str]]) -> str | None:
    """The earliest stage that differs in any video, or None when every stage matches."""
    stages = {s for found in differing.values() for s in found}
    return next((s for s in STAGES if s in stages), None)


def without_code(fingerprint: RendererFingerprint) -> RendererFingerprint:
    """``fingerprint`` without the versions of phav's own code (``CODE_KEYS``): the machine alone.
    The package's reference is recorded so, since the golden render test holds it to the code
    it ships with; another machine's ``phav fingerprint --json`` keeps them."""
    versions = {k: v for k, v in fingerprint.versions.items() if k not in CODE_KEYS}
    return fingerprint.model_copy(update={"versions": versions})


def as_recorded(recorded: RendererFingerprint, here: RendererFingerprint) -> RendererFingerprint:
    """``here`` as ``recorded`` can be compared with it: without the code's versions when
    ``recorded`` names none of them (the package's reference, ``without_code``), and without
    the files' encoders when it names none (a reference holds no shard or table bytes)."""
    here = here if any(k in recorded.versions for k in CODE_KEYS) else without_code(here)
    return here if recorded.file_versions else here.model_copy(update={"file_versions": {}})


#: Fingerprint keys in which a machine may differ from a reference's and still owe its
#: pixels: the reference clips are 0.2 s, too short for the physics to carry the numerics'
#: last bits into a pixel (measured: docs/reproducibility.md, every numeric factor gives
#: every pixel stage equal), though a whole clip's motion may part (so datasets compare them).
SHORT_CLIP_KEYS = ("numeric_class",)


def promised_stages(recorded: RendererFingerprint, here: RendererFingerprint) -> tuple[str, ...]:
    """The stages whose bytes must equal the recorded ones here: every stage where the
    fingerprints agree for pixels (the stages' hashes are of arrays, not of encoded files,
    so the encoders do not count); where they differ in the numerics alone, the recipe, the
    body data and the pixels (``SHORT_CLIP_KEYS``); none else. A reference without the
    code's versions is compared on the machine alone (``as_recorded``)."""
    differs = recorded.differences(as_recorded(recorded, here), "pixels")
    if not differs:
        return STAGES
    if all(k in SHORT_CLIP_KEYS for k in differs):
        return ("recipe", "body", *PIXEL_STAGES)
    return ()


def broken_promise(differing: Mapping[str, list[str]], promised: tuple[str, ...]) -> list[str]:
    """The promised stages that differ in some video, in ``STAGES`` order."""
    found = {s for stages in differing.values() for s in stages}
    return [s for s in STAGES if s in found and s in promised]


def load_reference(path: Path = REFERENCE_FILE) -> Reference:
    """Read a recorded reference; a malformed file is a one-line error naming it."""
    source = str(path)
    data = parse_json_object(read_text(path), source=source)
    videos = data.get("videos")
    if "fingerprint" not in data or not isinstance(videos, dict) or not videos:
        raise PhavUserError("a reference holds 'fingerprint' and a non-empty 'videos' object", source=source)
    fingerprint = validate_user_data(RendererFingerprint, data["fingerprint"], source=source)
    recipes: dict[str, Recipe] = {}
    stages: dict[str, dict[str, str]] = {}
    for name, video in sorted(videos.items()):
        if not isinstance(video, dict) or "recipe" not in video or not isinstance(video.get("stages"), dict):
            raise PhavUserError("each video holds 'recipe' and 'stages'", source=source, field=f"videos.{name}")
        missing = [s for s in STAGES if s not in video["stages"]]
        if missing:
            raise PhavUserError(f"stages {missing} missing", source=source, field=f"videos.{name}.stages")
        recipes[name] = parse_recipe(video["recipe"], source=f"{source}: videos.{name}.recipe")
        stages[name] = {s: str(video["stages"][s]) for s in STAGES}
    return Reference(fingerprint, recipes, stages)


def record(
    recipes: Mapping[str, Recipe], fingerprint: RendererFingerprint, ctx: moderngl.Context, path: Path
) -> Reference:
    """Trace ``recipes`` here and write them with ``fingerprint`` to ``path`` (atomically)."""
    reference = Reference(fingerprint, dict(recipes), trace_all(recipes, ctx))
    with atomic_write(path) as tmp:
        tmp.write_text(pretty_json(reference.to_json()), encoding="utf-8")
    return reference


def stage_table(names: Iterable[str], differing: Mapping[str, list[str]]) -> list[list[str]]:
    """Rows (video, then ``=`` or ``≠`` per stage) for a report."""
    return [[name] + ["≠" if s in differing[name] else "=" for s in STAGES] for name in names]
