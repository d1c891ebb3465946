"""The paper's protocol as options (``phav train``): TSN on PHAV over random or held-out
splits; TSN, TSN-FT and Cool-TSN on a real dataset, over a sweep of the fraction of real
training data. Every run is checkpointed under one output folder, so a rerun resumes."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np

from phav_spec.errors import PhavUserError
from phav_spec.seeding import seeded_rng
from phav_validators.findings import ProgressFactory
from phav_validators.learn.data import Clip, ClipSet
from phav_validators.learn.splits import make_split, verdict_clips
from phav_validators.learn.train import TrainConfig, fuse, predict, stream_configs, teacher_of, train

#: ``tsn``: one source; ``cool``: PHAV mixed into every real mini-batch; ``ft``: real
#: training started from a PHAV checkpoint's backbone.
MODES = ("tsn", "cool", "ft")


@dataclass
class RunResult:
    """One trained-and-tested configuration: accuracy per stream and fused."""

    name: str
    split: int
    fraction: float
    train_clips: int
    test_clips: int
    accuracy: dict[str, float]
    minutes: dict[str, float]
    labels: list[int] = field(default_factory=list)  # test labels
    predicted: list[int] = field(default_factory=list)  # fused (or the one stream's) answers

    def to_json(self) -> dict[str, Any]:
        out = asdict(self)
        del out["labels"], out["predicted"]
        return out


def _accuracy(probs: np.ndarray, labels: np.ndarray) -> float:
    return float((probs.argmax(1) == labels).mean()) if len(labels) else 0.0


def train_and_test(
    name: str,
    data: dict[str, Sequence[Clip]],
    heads: dict[str, int],
    test: Sequence[Clip],
    test_head: str,
    base: TrainConfig,
    streams: Sequence[str],
    out: Path,
    *,
    split: int = 1,
    fraction: float = 1.0,
    init: Path | None = None,
    device: str = "cpu",
    progress: ProgressFactory | None = None,
) -> RunResult:
    """Train each stream (checkpoint ``out/{name}-{stream}.pt``), test, fuse."""
    scores: dict[str, np.ndarray] = {}
    minutes: dict[str, float] = {}
    teacher = None
    for stream, config in stream_configs(streams, base).items():
        advance = progress(f"{name}: {stream}", config.epochs) if progress is not None else None
        start = None
        if init is not None:
            start = init / f"split1-{stream}.pt" if init.is_dir() else init
        result = train(data, heads, config, checkpoint=out / f"{name}-{stream}.pt", init=start, device=device,
                       progress=(lambda e, n, a=advance: a(1)) if advance is not None else None,
                       teacher=teacher)  # fmt: skip
        teacher = teacher_of(stream, result, base)
        scores[stream] = predict(result.model, test, config, test_head, device=device)
        minutes[stream] = result.seconds / 60.0
    labels = np.array([c.label for c in test], dtype=np.int64)
    accuracy = {s: _accuracy(p, labels) for s, p in scores.items()}
    fused = fuse(scores)
    if len(streams) > 1:
        accuracy["fused"] = _accuracy(fused, labels)
    n_train = sum(len(v) for v in data.values())
    return RunResult(name, split, fraction, n_train, len(test), accuracy, minutes, labels.tolist(),
                     fused.argmax(1).tolist())  # fmt: skip


def phav_runs(
    clips: ClipSet,
    base: TrainConfig,
    streams: Sequence[str],
    out: Path,
    *,
    split_kind: str = "random",
    splits: int = 3,
    device: str = "cpu",
    progress: ProgressFactory | None = None,
) -> list[RunResult]:
    """TSN on PHAV alone: ``splits`` seeded 80/20 splits of ``split_kind`` (the paper: three random).
    Split ``k`` (from 0) splits and trains with seed ``base.seed + k``, so that held-out-actor
    split ``k`` is the learnability check run with ``--seed`` that number, checkpoints and all."""
    runs = []
    for k in range(splits):
        split = make_split(clips.clips, split_kind, seed=base.seed + k)
        train_clips = [clips.clips[i] for i in split.train]
        test = [clips.clips[i] for i in verdict_clips(split)[0]]  # the clips the check's verdict is on
        config = replace(base, mix=(("virtual", base.batch),), seed=base.seed + k)
        runs.append(train_and_test(f"split{k + 1}", {"virtual": train_clips}, {"virtual": len(clips.classes)}, test,
                                   "virtual", config, streams, out, split=k + 1, device=device,
                                   progress=progress))  # fmt: skip
    return runs


def subsample(clips: Sequence[Clip], fraction: float, seed: int) -> list[Clip]:
    """A seeded, class-stratified ``fraction`` of ``clips``: ``ceil`` per class, at least one."""
    if not 0.0 < fraction <= 1.0:
        raise PhavUserError(f"fractions must be in (0, 1], got {fraction}", field="--real-fraction")
    if fraction == 1.0:
        return list(clips)
    rng = seeded_rng(seed, 0xF2AC)
    chosen: list[int] = []
    for label in sorted({c.label for c in clips}):
        mine = [i for i, c in enumerate(clips) if c.label == label]
        k = max(1, int(np.ceil(fraction * len(mine))))
        chosen += [mine[int(i)] for i in rng.permutation(len(mine))[:k]]
    return [clips[i] for i in sorted(chosen)]


def real_runs(
    mode: str,
    real_train: Sequence[Clip],
    real_test: Sequence[Clip],
    real_classes: int,
    base: TrainConfig,
    streams: Sequence[str],
    out: Path,
    *,
    virtual: ClipSet | None = None,
    mix: tuple[int, int] = (10, 22),
    fractions: Sequence[float] = (1.0,),
    split: int = 1,
    init: Path | None = None,
    device: str = "cpu",
    progress: ProgressFactory | None = None,
) -> list[RunResult]:
    """TSN, TSN-FT or Cool-TSN on a real dataset's split, once per fraction of its training data."""
    if mode not in MODES:
        raise PhavUserError(f"unknown mode {mode!r}; choose from {', '.join(MODES)}", field="--mode")
    if mode == "cool" and (virtual is None or not len(virtual)):
        raise PhavUserError("Cool-TSN mixes PHAV clips into every batch: give a PHAV dataset", field="--mode")
    if mode == "ft" and init is None:
        raise PhavUserError("TSN-FT starts from a PHAV run: give --init (a phav train output folder)", field="--mode")
    runs = []
    for fraction in fractions:
        chosen = subsample(real_train, fraction, base.seed)
        data: dict[str, Sequence[Clip]] = {"real": chosen}
        heads = {"real": real_classes}
        config = replace(base, mix=(("real", base.batch),))
        if mode == "cool" and virtual is not None:
            data["virtual"] = virtual.clips
            heads["virtual"] = len(virtual.classes)
            config = replace(base, mix=(("virtual", mix[0]), ("real", mix[1])))
        name = f"{mode}-split{split}-{fraction:g}"
        runs.append(train_and_test(name, data, heads, real_test, "real", config, streams, out, split=split,
                                   fraction=fraction, init=init if mode == "ft" else None, device=device,
                                   progress=progress))  # fmt: skip
    return runs


def summarise(runs: Sequence[RunResult]) -> list[dict[str, Any]]:
    """Mean accuracy per (fraction, stream) over splits, in the order first seen."""
    rows: dict[tuple[float, str], list[float]] = {}
    for run in runs:
        for stream, acc in run.accuracy.items():
            rows.setdefault((run.fraction, stream), []).append(acc)
    return [{"fraction": f, "stream": s, "splits": len(v), "mean_accuracy": float(np.mean(v)),
             "min": float(min(v)), "max": float(max(v))} for (f, s), v in rows.items()]  # fmt: skip
