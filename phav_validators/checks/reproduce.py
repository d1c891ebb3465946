"""The reproducibility check: regenerate a seeded sample of videos from their recipes and
compare them with the shards, frame by frame, and with the manifest's content hashes.

When this machine's renderer fingerprint equals the manifest's, pixels must be identical
(DESIGN.md: same fingerprint → identical pixels). Otherwise the comparison uses tolerances
(``TOLERANCES``) and the report says so. This is the only check that catches a frame that was
changed together with its manifest entry: everything else compares the data with itself.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from phav_generator.dataset.fingerprint import renderer_fingerprint
from phav_generator.pipeline import video_frames
from phav_generator.regenerate import HashReport, RegenerationPlan
from phav_generator.render.context import gl_context, gl_strings
from phav_spec.encoding import MODALITIES, VideoHashes, decode_flow
from phav_spec.manifest import DatasetManifest, VideoEntry, motion_unpromised, renderer_differences
from phav_spec.recipe import Recipe
from phav_spec.seeding import seeded_rng
from phav_validators.checks.scan import FRAME_KEYS, decode_image, png_header
from phav_validators.checks.tarsafe import TarScan, iter_members
from phav_validators.findings import CheckResult, Finding, Reason, Report
from phav_validators.source import MANIFEST

if TYPE_CHECKING:
    import moderngl

#: Per modality, the largest difference tolerated when fingerprints differ: mean absolute
#: level difference (colour), share of differing pixels (labels, depth > 1 %, flow validity),
#: mean end-point error in px (flow).
TOLERANCES: dict[str, float] = {
    "rgb": 3.0, "raw_rgb": 3.0, "semantic": 0.01, "instance": 0.01, "depth": 0.01, "flow": 0.1,
}  # fmt: skip


def shard_video_frames(
    path: str | Path, video_id: str, size: tuple[int, int] = (340, 256)
) -> Iterator[tuple[int, dict[str, np.ndarray]]]:
    """Decoded frames of one video from a shard, in order. Incomplete frames, and frames with
    an image whose PNG header is not ``size`` (width, height), are skipped undecoded: the
    same guard against decompression bombs as the integrity scan."""
    prefix = f"{video_id}/"
    current: int | None = None
    members: dict[str, bytes] = {}

    def emit() -> dict[str, np.ndarray] | None:
        if current is None or any(k not in members for k in FRAME_KEYS[:-1]):
            return None
        if any((png_header(members[m.key]) or (0, 0))[:2] != size for m in MODALITIES):
            return None
        arrays = {m.name: decode_image(members[m.key]) for m in MODALITIES}
        return None if any(a is None for a in arrays.values()) else arrays  # type: ignore[return-value]

    for name, data in iter_members(path, TarScan()):
        if not name.startswith(prefix):
            if current is not None and name.partition("/")[0] != video_id:
                break  # a video's frames are contiguous
            continue
        frame_text, _, ext = name[len(prefix) :].partition(".")
        if not frame_text.isdigit():
            continue
        frame = int(frame_text)
        if frame != current:
            arrays = emit()
            if arrays is not None:
                yield current, arrays  # type: ignore[misc]
            current, members = frame, {}
        members[ext] = data
    arrays = emit()
    if arrays is not None:
        yield current, arrays  # type: ignore[misc]


def frame_difference(name: str, a: np.ndarray, b: np.ndarray) -> float:
    """How far two frames of one modality are apart, in ``TOLERANCES``' units."""
    if a.shape != b.shape:
        return float("inf")
    if name in ("rgb", "raw_rgb"):
        return float(np.abs(a.astype(np.int16) - b.astype(np.int16)).mean())
    if name in ("semantic", "instance"):
        return float((a != b).any(axis=-1).mean())
    if name == "depth":
        da, db = a.astype(np.float64), b.astype(np.float64)
        return float((np.abs(da - db) > 0.01 * np.maximum(da, db)).mean())
    fa, va = decode_flow(a)
    fb, vb = decode_flow(b)
    both = va & vb
    epe = float(np.linalg.norm(fa[both] - fb[both], axis=-1).mean()) if both.any() else 0.0
    return max(epe, float((va != vb).mean()) * 10.0)  # a 1 % validity disagreement counts as 0.1 px


def shards_within_tolerances(
    original: Path, rebuilt: Path, video_id: str, size: tuple[int, int], worst: dict[str, float]
) -> tuple[dict[str, int], int]:
    """One video's frames in two shards (another renderer's rebuild against the original),
    frame by frame within ``TOLERANCES``: per modality the first frame beyond them, and how
    many rebuilt frames the original lacks. ``worst`` keeps the largest difference per modality."""
    first_bad: dict[str, int] = {}
    absent = 0
    for index, frame, old in _paired(shard_video_frames(original, video_id, size),
                                     shard_video_frames(rebuilt, video_id, size)):  # fmt: skip
        if old is None:
            absent += 1
        else:
            _compare_frame(index, frame, old, False, worst, first_bad)
    return first_bad, absent


def _paired(
    stored: Iterator[tuple[int, dict[str, np.ndarray]]], frames: Iterable[tuple[int, dict[str, np.ndarray]]]
) -> Iterator[tuple[int, dict[str, np.ndarray], dict[str, np.ndarray] | None]]:
    """Each (index, frame) of ``frames`` with the stored frame of that index, or None where the
    stored ones (in index order; one out of order is skipped, integrity's finding) lack it."""
    got = next(stored, None)
    for index, frame in frames:
        while got is not None and got[0] < index:
            got = next(stored, None)
        if got is None or got[0] != index:
            yield index, frame, None
            continue
        yield index, frame, got[1]
        got = next(stored, None)


def rebuilt_within_tolerances(
    report: HashReport, plan: RegenerationPlan, out: Path
) -> tuple[dict[str, float], int, list[str]]:
    """``phav regenerate`` with another renderer: each video whose content hash differs
    (``report.differing``) compared frame by frame with its original shard, where the source
    has it, within ``TOLERANCES`` as this check does. A video beyond them, or whose original
    lacks frames, is a mismatch added to ``report``; where the fingerprints differ in keys
    that can move the physics (``RENDERER_ONLY_KEYS``' complement), it is returned instead,
    as this check warns of it. Returns the largest difference per modality, how many videos
    had no original frames to compare (a recipe-only release), and those unpromised ones."""
    worst = {m.name: 0.0 for m in MODALITIES}
    if plan.expected is None or plan.root is None:
        return worst, len(report.differing), []
    motion = report.motion
    entries = {v.video_id: v for v in plan.expected.videos}
    sizes = {r.video_id: (r.video.width, r.video.height) for shard in plan.shards for r in shard}
    unchecked, unpromised = 0, []
    for vid in report.differing:
        original = plan.root / entries[vid].shard
        if not original.is_file():
            unchecked += 1
            continue
        first_bad, absent = shards_within_tolerances(original, out / entries[vid].shard, vid, sizes[vid], worst)
        beyond = [f"{k} beyond tolerance from frame {f:05d}" for k, f in first_bad.items()]
        if absent:
            beyond.append(f"{absent} frames not in {original.name}")
        if beyond:
            (unpromised if motion and not absent else report.mismatches).append(f"{vid}: {', '.join(beyond)}")
    return worst, unchecked, unpromised


def check_reproducibility(
    root: Path,
    manifest: DatasetManifest | None,
    recipes: Mapping[str, Recipe],
    candidates: Sequence[str],
    *,
    count: int,
    seed: int,
    progress: Callable[[str, int], Callable[[int], None]] | None = None,
) -> tuple[CheckResult, bool | None]:
    """Regenerate ``count`` videos chosen with ``seed`` among ``candidates``; compare them.

    Returns the check and whether the renderer fingerprints matched (None: not compared)."""
    name = "reproducibility"
    if manifest is None:
        return CheckResult.skipped(name, "no manifest: nothing to compare with"), None
    if count == 0:
        return CheckResult.skipped(name, "--regenerate 0"), None
    pool = [v for v in candidates if v in recipes]
    if not pool:
        return CheckResult.skipped(name, "no video with a valid recipe"), None
    rng = seeded_rng(seed)
    chosen = sorted(pool[i] for i in rng.permutation(len(pool))[: min(count, len(pool))])
    try:
        ctx = gl_context()
    except Exception as e:  # no EGL / GL here: say so rather than guess
        return CheckResult.skipped(name, f"cannot create a GL context to regenerate ({e})"), None
    here = renderer_fingerprint(gl_strings(ctx))
    differs = renderer_differences(manifest.renderer, here)
    exact = differs == []
    # Where the motion is not promised either, a video may leave the tolerances by physics alone.
    motion = motion_unpromised(differs)
    entries = {v.video_id: v for v in manifest.videos}
    report = Report()
    advance = progress("regenerating", len(chosen)) if progress is not None else None
    matched = 0
    uncompared: list[str] = []  # another renderer's, with no frame of theirs in the shards
    worst: dict[str, float] = {m.name: 0.0 for m in MODALITIES}
    try:
        for vid in chosen:
            entry = entries.get(vid)
            first_bad, absent = _regenerate_and_compare(ctx, vid, recipes[vid], entry, root, exact, worst)
            if absent:  # a shard missing or cut short: integrity's finding, not the renderer's
                report.notes.append(
                    f"{vid}: {absent} of {recipes[vid].n_frames} frames not in its shard (see integrity); "
                    + ("compared with the manifest's content hash" if exact else "those not compared"))  # fmt: skip
            if first_bad:
                report.add(_mismatch(vid, entry, first_bad, exact, motion))
            elif not exact and absent == recipes[vid].n_frames:  # nothing to compare within tolerances
                uncompared.append(vid)
            else:
                matched += 1
            if advance is not None:
                advance(1)
    finally:
        ctx.release()
    if manifest.renderer is None:
        report.add(Finding(
            Reason.RENDERER_UNRECORDED,
            "the manifest records no renderer fingerprint: regenerated videos compared within "
            "tolerances, as from another renderer; no pixel is promised bit for bit",
            file=MANIFEST, severity="warn",
        ))  # fmt: skip
        basis = "tolerances: the manifest records no renderer fingerprint"
    elif exact:
        basis = "bit-exact: same renderer fingerprint"
    else:
        basis = "tolerances: another renderer fingerprint"
    if differs:
        basis += f" ({', '.join(differs)} differ)"
    if motion:
        basis += "; the motion is not promised there, so a video beyond them is a warning"
    if uncompared and len(uncompared) == len(chosen) and report.ok:
        return CheckResult.skipped(name, "no regenerated video's frames are in the shards to compare "
                                   f"({basis}; the integrity check says why)"), exact  # fmt: skip
    numbers: dict[str, Any] = {"regenerated": len(chosen), "matched": matched, "exact": exact, "videos": chosen,
                               "not_compared": uncompared}  # fmt: skip
    if not exact:
        numbers["renderer_differs"] = differs
        numbers["motion_differs"] = motion
        numbers["worst_difference"] = worst
        numbers["tolerances"] = TOLERANCES
    summary = f"{matched}/{len(chosen)} regenerated videos match ({basis})"
    if uncompared:
        summary += f"; {len(uncompared)} not compared, their frames missing from the shards"
    return CheckResult.from_report(name, report, summary, numbers), exact


def _regenerate_and_compare(
    ctx: moderngl.Context,
    video_id: str,
    recipe: Recipe,
    entry: VideoEntry | None,
    root: Path,
    exact: bool,
    worst: dict[str, float],
) -> tuple[dict[str, int], int]:
    """Render the video from its recipe beside its frames in the shard; returns, per thing that
    differs (a modality, the ``content hash``), the first frame it does (−1 for the hash), and
    how many frames the shard lacks (not compared). ``worst`` keeps the largest difference
    per modality."""
    shard = root / entry.shard if entry is not None else None
    size = (recipe.video.width, recipe.video.height)
    stored = shard_video_frames(shard, video_id, size) if shard is not None and shard.exists() else iter(())
    hashes = VideoHashes(recipe.n_frames)
    first_bad: dict[str, int] = {}
    absent = 0
    for index, frame, old in _paired(stored, ((rf.index, rf.modalities) for rf in video_frames(recipe, ctx))):
        hashes.add(index, frame)
        if old is None:
            absent += 1
        else:
            _compare_frame(index, frame, old, exact, worst, first_bad)
    hash_ok = entry is not None and entry.content_hash == hashes.video_hash()
    if exact and not hash_ok:
        first_bad.setdefault("content hash", -1)
    return first_bad, absent


def _compare_frame(
    index: int,
    regenerated: Mapping[str, np.ndarray],
    stored: Mapping[str, np.ndarray],
    exact: bool,
    worst: dict[str, float],
    first_bad: dict[str, int],
) -> None:
    """Each modality of one frame: equal bit for bit, or within ``TOLERANCES`` (kept in ``worst``)."""
    for m in MODALITIES:
        a, b = regenerated[m.name], stored[m.name]
        if exact:
            same = a.shape == b.shape and np.array_equal(a, b)
            if not same:
                first_bad.setdefault(m.name, index)
        else:
            diff = frame_difference(m.name, a, b)
            worst[m.name] = max(worst[m.name], diff)
            if diff > TOLERANCES[m.name]:
                first_bad.setdefault(m.name, index)


def _mismatch(
    video_id: str, entry: VideoEntry | None, first_bad: dict[str, int], exact: bool, motion: Sequence[str] = ()
) -> Finding:
    """The finding of a regenerated video that differs from its shard, naming where: a
    warning where fingerprint keys that can move the physics (``motion``) differ."""
    where = ", ".join(f"{k} (frame {f:05d})" if f >= 0 else k for k, f in first_bad.items())
    basis = "bit-exact (same renderer fingerprint)" if exact else "within tolerances (other renderer)"
    message = f"regenerated from its recipe, the video differs from the shard: {where}; expected {basis}"
    if motion:
        message += (f", but the motion is not promised ({', '.join(motion)}: the physics can go another way); "
                     "regenerate on a machine of the manifest's fingerprint to verify it")  # fmt: skip
    return Finding(
        Reason.REGENERATION_MISMATCH, message, file=entry.shard if entry is not None else None, video_id=video_id,
        numbers={"first_frames": first_bad, "exact": exact, "motion_differs": list(motion)},
        severity="warn" if motion else "fail",
    )  # fmt: skip
