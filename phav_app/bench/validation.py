"""``phav bench --sections validation``: how fast each check reads a dataset, against how
much it can miss when ``--sample`` decodes only part of it.

One phav-v1-short dataset is generated (timed: the yardstick), then validated once per check
and once with every check but reproducibility (the issue's ≥ 5× aim), all with the same
workers. For detection, a copy gets one depth pixel flipped in ``corrupted`` videos and the
integrity check runs at each ``--sample`` fraction with ``trials`` seeds; the measured
detection rate is set beside the exact hypergeometric probability that the sample holds a
corrupted video.
"""

from __future__ import annotations

import io
import math
import shutil
import tarfile
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np

from phav_generator.dataset.write import DEFAULT_SHARD_SIZE, WORK_DIR, chunk, write_dataset
from phav_generator.sampling import sample_recipes
from phav_spec.errors import PhavUserError
from phav_spec.manifest import load_manifest
from phav_spec.seeding import seeded_rng
from phav_spec.theta import Theta
from phav_validators.findings import Reason
from phav_validators.options import CHECKS, DatasetReport, Options
from phav_validators.source import resolve
from phav_validators.validate import validate_dataset

#: --sample fractions the detection table measures.
SAMPLE_FRACTIONS: tuple[float, ...] = (0.1, 0.25, 0.5, 1.0)


@dataclass(frozen=True)
class CheckSpeed:
    """One validation run: which checks, wall seconds, and what it found on clean data."""

    checks: str
    seconds: float
    frames: int
    status: str
    fails: int  # failing findings: on a clean dataset each is a false alarm

    @property
    def frames_per_s(self) -> float:
        return self.frames / self.seconds if self.seconds > 0 else math.inf


@dataclass(frozen=True)
class SampleDetection:
    """Integrity at one ``--sample`` fraction over ``trials`` seeds, ``corrupted`` bad videos."""

    fraction: float
    trials: int
    detected: int
    expected: float  # P(the sample holds a corrupted video), exact
    seconds: float  # mean wall seconds per run
    videos_decoded: float  # mean per run


@dataclass(frozen=True)
class ValidationBench:
    videos: int
    frames: int
    workers: int
    generate_s: float
    runs: list[CheckSpeed]
    combined: CheckSpeed  # every check but reproducibility
    detection: list[SampleDetection]
    corrupted: int

    @property
    def speedup(self) -> float:
        """How many times faster than generation the combined validation runs."""
        return self.generate_s / self.combined.seconds


def hypergeometric_hit(n: int, bad: int, drawn: int) -> float:
    """P(at least one of ``bad`` items among ``drawn`` drawn without replacement from ``n``)."""
    if drawn >= n or bad <= 0:
        return 1.0 if bad > 0 and drawn > 0 else 0.0
    return 1.0 - math.comb(n - bad, drawn) / math.comb(n, drawn)


def flip_depth_pixel(shard: Path, member: str) -> None:
    """Rewrite ``shard`` with one pixel of the 16-bit depth PNG ``member`` changed by one cm.

    The rewrite goes to a temporary file renamed over the shard, members kept in order."""

    with tarfile.open(shard) as tar:
        members = [(info, tar.extractfile(info).read()) for info in tar.getmembers() if info.isfile()]
    names = [info.name for info, _ in members]
    if member not in names:
        raise ValueError(f"{shard.name} has no member {member!r}")
    tmp = shard.with_name(shard.name + ".tmp")
    with tarfile.open(tmp, "w", format=tarfile.USTAR_FORMAT) as tar:
        for info, data in members:
            if info.name == member:
                image = cv2.imdecode(np.frombuffer(data, np.uint8), cv2.IMREAD_UNCHANGED)
                image[image.shape[0] // 2, image.shape[1] // 2] ^= 1
                ok, png = cv2.imencode(".png", image)
                if not ok:  # pragma: no cover - OpenCV encodes any uint16 image
                    raise RuntimeError(f"cannot re-encode {member}")
                data = png.tobytes()
                info.size = len(data)
            tar.addfile(info, io.BytesIO(data))
    tmp.replace(shard)


def _remove_earlier(folder: Path) -> None:
    """Remove what an earlier bench run wrote at ``folder`` (a dataset, finished or not);
    anything else there is refused, never deleted."""
    if not folder.exists():
        return
    if not folder.is_dir() or not any((folder / name).exists() for name in ("manifest.json", WORK_DIR)):
        raise PhavUserError("holds something the validation bench did not write; give --out-dir another folder",
                            source=str(folder), field="--out-dir")  # fmt: skip
    shutil.rmtree(folder)


def _timed(path: Path, options: Options) -> tuple[float, DatasetReport]:
    inp = resolve([path])[0]
    start = time.perf_counter()
    report = validate_dataset(inp, options=options)
    return time.perf_counter() - start, report


def bench_validation(
    theta: Theta,
    work: Path,
    *,
    videos: int,
    seed: int,
    workers: int = 2,
    trials: int = 10,
    fractions: Sequence[float] = SAMPLE_FRACTIONS,
    corrupted: int = 1,
    progress: Callable[[str], None] | None = None,
) -> ValidationBench:
    """Generate ``videos`` recipes of ``theta`` into ``work``, then time and probe validation."""

    def say(text: str) -> None:
        if progress is not None:
            progress(text)

    data = work / "clean"
    _remove_earlier(data)  # a finished earlier run would be resumed, not timed
    say(f"generating {videos} videos with {workers} workers")
    recipes = list(sample_recipes(theta, n=videos, seed=seed))
    start = time.perf_counter()
    write_dataset(chunk(recipes, DEFAULT_SHARD_SIZE), data, name="bench", theta=theta, dataset_seed=seed,
                  workers=workers)  # fmt: skip
    generate_s = time.perf_counter() - start
    manifest = load_manifest(data / "manifest.json")
    frames = sum(v.n_frames for v in manifest.videos)

    def run(checks: tuple[str, ...], regenerate: int = 1) -> tuple[CheckSpeed, DatasetReport]:
        say(f"validating: {', '.join(checks)}")
        seconds, report = _timed(data, Options(checks=checks, workers=workers, seed=seed, regenerate=regenerate))
        fails = sum(1 for c in report.checks for f in c.report.findings if f.severity == "fail")
        count = frames if checks != ("reproducibility",) else 0
        return CheckSpeed(",".join(checks), seconds, count, report.status.value, fails), report

    runs = []
    for name in CHECKS:
        speed, report = run((name,))
        if name == "reproducibility":  # frames regenerated, not frames read
            n_frames = {v.video_id: v.n_frames for v in manifest.videos}
            regenerated = sum(n_frames[v] for v in report.checks[0].numbers.get("videos", []))
            speed = CheckSpeed(speed.checks, speed.seconds, regenerated, speed.status, speed.fails)
        runs.append(speed)
    combined, _ = run(tuple(c for c in CHECKS if c != "reproducibility"))

    # Detection against --sample: the same data with ``corrupted`` videos' depth flipped.
    bad_copy = work / "corrupted"
    _remove_earlier(bad_copy)
    shutil.copytree(data, bad_copy)
    ids = [v.video_id for v in manifest.videos]
    rng = seeded_rng(seed)
    bad = sorted(ids[i] for i in rng.permutation(len(ids))[:corrupted])
    shard_of = {v.video_id: v.shard for v in manifest.videos}
    for vid in bad:
        flip_depth_pixel(bad_copy / shard_of[vid], f"{vid}/00000.depth.png")
    detection = []
    for fraction in fractions:
        hits, seconds, decoded = 0, 0.0, 0.0
        for trial in range(trials):
            say(f"detection at --sample {fraction:g}: trial {trial + 1}/{trials}")
            options = Options(checks=("integrity",), workers=workers, sample=fraction, seed=seed + trial)
            took, report = _timed(bad_copy, options)
            seconds += took
            found = {f.video_id for f in report.checks[0].report.findings if f.reason == Reason.HASH_MISMATCH}
            hits += bool(found & set(bad))
            decoded += report.checks[0].numbers.get("hashed", 0)
        drawn = len(ids) if fraction >= 1.0 else max(1, math.ceil(fraction * len(ids)))
        detection.append(SampleDetection(fraction, trials, hits, hypergeometric_hit(len(ids), len(bad), drawn),
                                         seconds / trials, decoded / trials))  # fmt: skip
    return ValidationBench(len(ids), frames, workers, generate_s, runs, combined, detection, len(bad))
