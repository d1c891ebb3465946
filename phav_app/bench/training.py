"""``phav bench --sections training``: clips per second per stream on this machine, and test
accuracy against training minutes (random and held-out-actor splits), speed against error.

Each stream trains for its fixed number of epochs and is tested at evenly spaced epochs of
its own; the fused accuracy at a point combines the streams' tests of the same rank, at
the sum of their training minutes. Testing time is not counted as training time.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace

import numpy as np

from phav_validators.learn.data import Clip, ClipSet
from phav_validators.learn.learnability import binomial_p, chance_level
from phav_validators.learn.splits import make_split
from phav_validators.learn.train import TrainConfig, TrainResult, fuse, predict, stream_configs, teacher_of, train


@dataclass(frozen=True)
class Throughput:
    """Clips per second of one stream: training steps (snippets, forward, backward, update)
    and testing (``test_segments`` snippets, forward)."""

    stream: str
    train_clips_per_s: float
    test_clips_per_s: float
    parameters: int


@dataclass(frozen=True)
class CurvePoint:
    """Test accuracy after ``epochs`` epochs of each stream, at ``minutes`` of training
    (both streams' together)."""

    split: str
    epochs: dict[str, int]  # stream → epochs trained so far
    minutes: float
    accuracy: dict[str, float]  # rgb, flow, fused
    test_clips: int
    chance: float
    p_fused: float


def throughput(clips: Sequence[Clip], config: TrainConfig, *, steps: int = 8) -> Throughput:
    """Time one epoch of ``steps`` training steps (``train`` itself: snippets, forward,
    backward, update) and one pass of testing over two batches."""
    batch = config.batch
    chosen = [clips[i % len(clips)] for i in range(steps * batch)]
    result = train({"virtual": chosen}, {"virtual": 35}, replace(config, epochs=1, mix=(("virtual", batch),)))
    start = time.perf_counter()
    tested = list(clips[: 2 * batch])
    predict(result.model, tested, config, "virtual")
    test_s = time.perf_counter() - start
    n_params = sum(p.numel() for p in result.model.parameters())
    return Throughput(config.stream, len(chosen) / result.seconds, len(tested) / test_s, n_params)


def learning_curve(
    clips: ClipSet,
    split_kind: str,
    base: TrainConfig,
    streams: Sequence[str] = ("rgb", "flow"),
    *,
    points: int = 8,
    progress: Callable[[str], None] | None = None,
) -> list[CurvePoint]:
    """Test accuracy per stream and fused against training minutes on one seeded split:
    each stream is tested ``points`` times, evenly over its own epochs (the RGB stream may
    train fewer, ``rgb_epochs``), and the i-th tests of the streams are fused."""
    split = make_split(clips.clips, split_kind, seed=base.seed)
    train_clips = [clips.clips[i] for i in split.train]
    test_clips = [clips.clips[i] for i in split.test]
    labels = np.array([c.label for c in test_clips], dtype=np.int64)
    scores: dict[str, dict[int, np.ndarray]] = {s: {} for s in streams}
    minutes: dict[str, dict[int, float]] = {s: {} for s in streams}
    teacher = None
    for stream, config in stream_configs(streams, base).items():
        tested = sorted({max(1, round(k * config.epochs / points)) for k in range(1, points + 1)})

        def record(result: TrainResult, stream: str = stream, config: TrainConfig = config,
                   tested: list[int] = tested) -> None:  # fmt: skip
            epoch = len(result.history)
            if epoch in tested:
                scores[stream][epoch] = predict(result.model, test_clips, config, "virtual")
                minutes[stream][epoch] = result.seconds / 60.0
                if progress is not None:
                    acc = float((scores[stream][epoch].argmax(1) == labels).mean())
                    progress(f"{split.name}: {stream} epoch {epoch}/{config.epochs}, test accuracy {acc:.1%}")

        result = train({"virtual": train_clips}, {"virtual": len(clips.classes)}, config, after_epoch=record,
                       teacher=teacher)  # fmt: skip
        teacher = teacher_of(stream, result, base)
    out = []
    for i in range(min(len(scores[s]) for s in streams)):
        epochs = {s: sorted(scores[s])[i] for s in streams}
        probs = {s: scores[s][e] for s, e in epochs.items()}
        fused = fuse(probs)
        accuracy = {s: float((p.argmax(1) == labels).mean()) for s, p in probs.items()}
        correct = int((fused.argmax(1) == labels).sum())
        accuracy["fused"] = correct / max(len(labels), 1)
        chance = chance_level(labels, fused.argmax(1), len(clips.classes))
        out.append(CurvePoint(split.name, epochs, sum(minutes[s][e] for s, e in epochs.items()), accuracy,
                              len(labels), chance, binomial_p(correct, len(labels), chance)))  # fmt: skip
    return out
