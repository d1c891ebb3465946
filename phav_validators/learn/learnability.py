"""``phav-validate --checks learnability``: can a small TSN learn the actions from the pixels?

A seeded held-out-actor split (no training clip's protagonist or supporting person is a
held-out human model: ``splits``), both streams trained on a fixed schedule, late fusion,
and a one-sided binomial test of the fused test accuracy against chance. The model sees
RGB frames and flow (the dataset's ground truth, or estimated from the frames) only;
labels and groups are used for the loss and the split, never as input. Chance is the
accuracy of answers independent of the input: 1/classes for uniform guessing, or, when
higher, the agreement expected from the test labels' and the predictions' frequencies
alone (Cohen's p_e), so that a model answering one common class does not count as learning.

The verdict is a property of the data and the arithmetic, not of the machine's speed: a
time budget that stops training before the schedule ends makes a failing result
inconclusive (``warn``), never a failure.
"""

from __future__ import annotations

import dataclasses
import json
import math
import tempfile
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import cv2
import numpy as np

from phav_spec.errors import PhavUserError
from phav_spec.files import atomic_write
from phav_spec.manifest import load_manifest
from phav_spec.seeding import seeded_rng
from phav_validators.findings import CheckResult, Finding, ProgressFactory, Reason, Report
from phav_validators.learn.data import DEFAULT_SIZE, ClipSet, load_phav
from phav_validators.learn.splits import BACKGROUND, Split, make_split, verdict_clips
from phav_validators.learn.train import (
    PRECISIONS,
    RECOMMENDED,
    TrainConfig,
    default_threads,
    fuse,
    predict,
    recommended_config,
    stream_configs,
    teacher_of,
    train,
)

if TYPE_CHECKING:
    from phav_spec.manifest import DatasetManifest
    from phav_spec.recipe_table import RecipeTable

#: The flow the check's flow stream reads, by ``--learn-flow``, as the report names it.
FLOW_NAMES = {"gt": "ground-truth flow", "farneback": "Farneback flow estimated from the frames"}


@dataclass(frozen=True)
class LearnOptions:
    """How the learnability check trains and what it demands."""

    split: str = "actor"
    streams: tuple[str, ...] = ("rgb", "flow")
    epochs: int = RECOMMENDED.epochs
    #: The RGB stream's epochs (None: in ``RECOMMENDED``'s proportion to ``epochs``).
    rgb_epochs: int | None = None
    #: A ceiling on the minutes of training, all streams together, shared by their expected
    #: seconds (``epoch_cost``): high enough that the default schedule ends on a 2-core CPU
    #: in float32 as in bfloat16 (docs/learnability.md, "The verdict and the budget"), so
    #: that only a slower machine is stopped by it, and then the verdict is inconclusive.
    budget_minutes: float = 30.0
    size: tuple[int, int] = DEFAULT_SIZE
    #: ``gt`` (the dataset's flow) or ``farneback`` (estimated from the RGB frames, as a
    #: real video's must be); TV-L1 is ``phav train``'s (it needs opencv-contrib).
    flow: str = "gt"
    #: Training clips that show a held-out model among the background people: ``keep``
    #: (counted in the report) or ``exclude`` (``splits.BACKGROUND``).
    background: str = "keep"
    seed: int = 0
    threads: int | None = None
    #: ``fp32`` or ``bf16``; None: what this machine computes fastest (``default_precision``).
    precision: str | None = None
    #: Max-pool after the stem (``TrainConfig.stem_pool``), as ``RECOMMENDED`` on a CPU:
    #: the epochs take less time for the same accuracy (docs/experiments/learnability.md,
    #: "The defaults and why").
    stem_pool: bool = RECOMMENDED.stem_pool
    alpha: float = 1e-3
    #: The fused accuracy must also be at least this many times chance.
    min_over_chance: float = 2.0
    #: Control run: labels permuted across clips before splitting (must fail).
    shuffle_labels: bool = False
    #: Checkpoints and the confusion image; None: a temporary folder (no resume).
    out_dir: Path | None = None
    workers: int = 1

    def config(self, threads: int) -> TrainConfig:
        """The training settings: ``RECOMMENDED`` with these epochs, seed, threads, precision and stem."""
        more = {"precision": self.precision} if self.precision is not None else {}
        return recommended_config(self.streams, epochs=self.epochs, rgb_epochs=self.rgb_epochs, seed=self.seed,
                                  threads=threads, stem_pool=self.stem_pool, **more)  # fmt: skip

    def __post_init__(self) -> None:
        if not self.budget_minutes > 0 or not math.isfinite(self.budget_minutes):  # nan passes a <= 0 test
            raise PhavUserError(
                f"must be a positive, finite number, got {self.budget_minutes}", field="--learn-minutes"
            )
        if self.precision is not None and self.precision not in PRECISIONS:
            raise PhavUserError(f"choose {' or '.join(PRECISIONS)}, got {self.precision!r}", field="--learn-precision")
        if not self.streams or any(s not in ("rgb", "flow") for s in self.streams):
            raise PhavUserError(f"streams are rgb and flow, got {self.streams}", field="--streams")
        if self.flow not in FLOW_NAMES:
            raise PhavUserError(f"choose {' or '.join(FLOW_NAMES)}, got {self.flow!r}", field="--learn-flow")
        if self.background not in BACKGROUND:
            raise PhavUserError(f"choose {' or '.join(BACKGROUND)}, got {self.background!r}",
                                field="--learn-background")  # fmt: skip


@dataclass
class LearnResult:
    """Test accuracies per stream and fused, against chance, with the confusion matrix."""

    classes: list[str]
    labels: np.ndarray  # (N,) test labels
    scores: dict[str, np.ndarray]  # stream → (N, classes) probabilities
    fused: np.ndarray
    chance: float
    p_value: float
    train_clips: int
    minutes: float
    stopped_on_time: bool
    held_out: dict[str, list[str]] = field(default_factory=dict)
    keys: list[str] = field(default_factory=list)  # the test clips' video ids, in ``labels`` order
    settings: dict[str, Any] = field(default_factory=dict)  # the base TrainConfig, as JSON
    epochs: dict[str, int] = field(default_factory=dict)  # stream → epochs trained
    schedule: dict[str, int] = field(default_factory=dict)  # stream → epochs of its schedule
    epoch_seconds: dict[str, float] = field(default_factory=dict)  # stream → mean seconds an epoch here
    #: The split as video ids: ``train``, ``mixed`` (test clips with a member seen in training,
    #: scored apart and left out of the verdict), ``background_seen`` (training clips showing a
    #: held-out model in the background). The verdict's test clips are ``keys``.
    videos: dict[str, list[str]] = field(default_factory=dict)
    dropped: int = 0  # clips on neither side
    background_dropped: int = 0  # training clips excluded for a held-out model in the background
    #: The fused accuracy on the ``mixed`` test clips, scored apart (None: there are none, or
    #: every test clip is mixed and the verdict is on them: ``mixed_in_verdict``).
    mixed_accuracy: float | None = None
    mixed_in_verdict: bool = False

    def full_minutes(self) -> float:
        """Minutes the streams' whole schedules take at the epoch times measured here."""
        return sum(self.schedule[s] * self.epoch_seconds[s] for s in self.schedule) / 60.0

    def minutes_needed(self) -> int:
        """A budget that finishes the schedules here: their measured minutes and a tenth more,
        as epoch times vary from run to run."""
        return math.ceil(self.full_minutes() * 1.1)

    def budget_note(self, budget_minutes: float) -> str:
        """What a stop at the budget cost, and the budget that would finish the schedules here."""
        reached = ", ".join(f"{s} {self.epochs[s]} of {self.schedule[s]} epochs" for s in self.schedule)
        note = (f"training stopped at the {budget_minutes:g}-minute budget before its schedule ended ({reached}); "
                f"the whole schedule would take {self.full_minutes():.1f} minutes here: rerun with "
                f"--learn-minutes {self.minutes_needed()}")  # fmt: skip
        if not self.settings.get("stem_pool", False):
            note += ", or less with --learn-stem-pool (the default)"
        return note

    def accuracy(self, stream: str | None = None) -> float:
        """Test accuracy of ``stream`` (None: fused) over the verdict's test clips."""
        probs = self.fused if stream is None else self.scores[stream]
        right = probs.argmax(1) == self.labels
        return float(right.mean()) if len(right) else 0.0

    def test_clips_per_class(self) -> dict[str, int]:
        """Test clips of every class, none left out (a class with none shows 0)."""
        counts = np.bincount(self.labels, minlength=len(self.classes))
        return {name: int(n) for name, n in zip(self.classes, counts, strict=True)}

    def split_json(self, split: str, background: str) -> dict[str, Any]:
        """The split as a reader checks it against recipes.parquet: what was held out and
        every video on each side."""
        return {
            "split": split, "held_out": self.held_out, "background": background,
            "train_videos": self.videos.get("train", []), "test_videos": self.keys,
            "mixed_test_videos": self.videos.get("mixed", []), "mixed_in_verdict": self.mixed_in_verdict,
            "dropped_clips": self.dropped,
            "train_videos_with_held_out_background": self.videos.get("background_seen", []),
            "train_clips_dropped_for_background": self.background_dropped,
        }  # fmt: skip

    def interval(self, stream: str | None = None) -> tuple[float, float]:
        """The 95 % Wilson interval of ``accuracy(stream)`` over the test clips."""
        return wilson_interval(round(self.accuracy(stream) * len(self.labels)), len(self.labels))

    def confusion(self) -> np.ndarray:
        return confusion_matrix(self.labels, self.fused.argmax(1), len(self.classes))

    def per_class(self) -> list[dict[str, Any]]:
        """Per tested class: clips, fused accuracy and the commonest wrong answer, worst first."""
        matrix = self.confusion()
        rows = []
        for c, name in enumerate(self.classes):
            n = int(matrix[c].sum())
            if n == 0:
                continue
            wrong = matrix[c].copy()
            wrong[c] = 0
            mistaken = self.classes[int(wrong.argmax())] if wrong.any() else None
            rows.append({"class": name, "clips": n, "accuracy": float(matrix[c, c]) / n, "mistaken_for": mistaken,
                         "mistakes": int(wrong.max())})  # fmt: skip
        return sorted(rows, key=lambda r: (r["accuracy"], r["class"]))

    def confused_pairs(self, limit: int = 5) -> list[tuple[str, str, int]]:
        """The pairs of classes most often answered for each other (both directions summed),
        most first: (a, b, clips)."""
        matrix = self.confusion()
        both = matrix + matrix.T
        pairs = [(int(both[a, b]), a, b) for a in range(len(self.classes)) for b in range(a + 1, len(self.classes))]
        pairs = sorted((p for p in pairs if p[0] > 0), key=lambda p: (-p[0], p[1], p[2]))[:limit]
        return [(self.classes[a], self.classes[b], n) for n, a, b in pairs]

    def example(self, true: str, predicted: str) -> str | None:
        """A test clip of class ``true`` answered as ``predicted`` (the first by key), if any."""
        t, p = self.classes.index(true), self.classes.index(predicted)
        answers = self.fused.argmax(1)
        hits = sorted(k for k, label, a in zip(self.keys, self.labels, answers, strict=True) if label == t and a == p)
        return hits[0] if hits else None


def confusion_matrix(labels: Sequence[int] | np.ndarray, predicted: Sequence[int] | np.ndarray, n: int) -> np.ndarray:
    """Counts (n, n): row = true class, column = predicted class."""
    matrix = np.zeros((n, n), dtype=np.int64)
    np.add.at(matrix, (np.asarray(labels, dtype=np.int64), np.asarray(predicted, dtype=np.int64)), 1)
    return matrix


def chance_level(labels: np.ndarray, predicted: np.ndarray, n_classes: int) -> float:
    """Accuracy expected of answers independent of the input: ``max(1/C, Σ_c p(c) q(c))``
    with p the test labels' and q the predictions' class frequencies."""
    if len(labels) == 0:
        return 1.0 / n_classes
    p = np.bincount(labels, minlength=n_classes) / len(labels)
    q = np.bincount(predicted, minlength=n_classes) / len(predicted)
    return max(1.0 / n_classes, float(p @ q))


def could_pass(labels: np.ndarray, n_classes: int, alpha: float, min_over_chance: float) -> tuple[bool, float]:
    """Whether any answers to this test set could pass (p < ``alpha`` at ``min_over_chance``
    times chance), and the smallest p-value any reach. Chance follows the answers (``chance_level``),
    so the best answers for c right are those right on the c clips of the rarest classes, every
    other answer a class the test set lacks: chance is then as low as c right allows."""
    labels = np.asarray(labels, dtype=np.int64)
    n = len(labels)
    if n == 0:
        return False, 1.0
    counts = np.bincount(labels, minlength=n_classes)
    share = counts / n
    # The c right answers, taken from the rarest classes first: the class of each in turn.
    rarest = np.argsort(counts, kind="stable")
    order = np.repeat(rarest, counts[rarest])
    overlap = np.cumsum(share[order]) / n  # Σ_k p_k q_k after c = 1 … n right answers
    best = 1.0
    for c in range(1, n + 1):
        chance = max(1.0 / n_classes, float(overlap[c - 1]))
        p = binomial_p(c, n, chance)
        best = min(best, p)
        if p < alpha and c / n >= min_over_chance * chance:
            return True, p
    return False, best


def wilson_interval(correct: int, n: int, z: float = 1.959964) -> tuple[float, float]:
    """The Wilson score interval of a proportion ``correct / n`` (95 % for the default z)."""
    if n == 0:
        return 0.0, 1.0
    p = correct / n
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z * np.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / (1 + z * z / n)
    return float(centre - half), float(centre + half)


def binomial_p(correct: int, n: int, chance: float) -> float:
    """One-sided p of ≥ ``correct`` right answers out of ``n`` when each is right with ``chance``."""

    if n == 0:
        return 1.0
    from scipy.stats import binomtest  # 0.4 s to import: only this test needs it, not every phav process

    return float(binomtest(correct, n, chance, alternative="greater").pvalue)


#: An epoch of the distilled RGB stream in flow epochs, an estimate: it cuts its snippets
#: and the teacher's and runs the teacher's forward pass too. Only a run stopped by the
#: budget depends on it (its source: docs/experiments/learnability.md, "On an AMD EPYC").
DISTILLED_RGB_EPOCH = 1.5


def epoch_cost(config: TrainConfig) -> float:
    """A stream's training time in flow epochs, by which the check shares its budget, so
    that a stopped stream is stopped at the same share of its schedule as the other."""
    per_epoch = DISTILLED_RGB_EPOCH if config.stream == "rgb" and config.distill > 0 else 1.0
    return config.epochs * per_epoch


def shuffled(clips: ClipSet, seed: int) -> ClipSet:
    """The same clips with labels permuted among them (the control that must not learn)."""
    rng = seeded_rng(seed, 0x5EED)
    labels = [clips.clips[int(i)].label for i in rng.permutation(len(clips))]
    out = [dataclasses.replace(c, label=label) for c, label in zip(clips.clips, labels, strict=True)]
    return ClipSet(clips.source, clips.classes, out)


def _estimate_unmeasured(epoch_seconds: dict[str, float], configs: dict[str, TrainConfig]) -> None:
    """A stream the budget stopped before its first epoch: its epoch time from a measured
    stream's, in proportion to their ``epoch_cost`` an epoch."""
    measured = [s for s in configs if s in epoch_seconds]
    if not measured:
        return
    unit = {s: epoch_cost(c) / c.epochs for s, c in configs.items()}
    per_unit = epoch_seconds[measured[0]] / unit[measured[0]]
    for stream in configs:
        epoch_seconds.setdefault(stream, per_unit * unit[stream])


def run_learnability(
    clips: ClipSet, opts: LearnOptions, *, progress: ProgressFactory | None = None, split: Split | None = None
) -> LearnResult:
    """Split (unless a ``split`` of ``clips`` is given), train every stream within the
    budget, test, fuse and test against chance."""
    if opts.shuffle_labels:
        clips = shuffled(clips, opts.seed)
    if split is None:
        split = make_split(clips.clips, opts.split, seed=opts.seed, background=opts.background)
    train_clips = [clips.clips[i] for i in split.train]
    test_clips = [clips.clips[i] for i in split.test]
    threads = opts.threads if opts.threads is not None else default_threads()
    scores: dict[str, np.ndarray] = {}
    seconds, stopped, epochs, schedule, epoch_seconds = 0.0, False, {}, {}, {}
    with tempfile.TemporaryDirectory(prefix="phav-learn-") as tmp:
        out = opts.out_dir if opts.out_dir is not None else Path(tmp)
        base = opts.config(threads)
        teacher = None
        configs = stream_configs(opts.streams, base)
        costs = [epoch_cost(config) for config in configs.values()]
        for i, (stream, config) in enumerate(configs.items()):
            # Each stream may use what the streams before it left, less the later streams'
            # shares: the time is shared in proportion to the streams' expected seconds.
            budget = (opts.budget_minutes * 60.0 - seconds) * costs[i] / sum(costs[i:])
            advance = progress(f"learnability: training {stream}", config.epochs) if progress is not None else None
            result = train({"virtual": train_clips}, {"virtual": len(clips.classes)}, config,
                           checkpoint=out / f"{stream}.pt", max_seconds=budget,
                           progress=(lambda e, n, a=advance: a(1)) if advance is not None else None,
                           teacher=teacher)  # fmt: skip
            teacher = teacher_of(stream, result, base)
            seconds += result.seconds
            stopped = stopped or result.stopped_on_time
            epochs[stream], schedule[stream] = len(result.history), config.epochs
            if result.history:
                epoch_seconds[stream] = sum(e.seconds for e in result.history) / len(result.history)
            scores[stream] = predict(result.model, test_clips, config, "virtual")
    _estimate_unmeasured(epoch_seconds, configs)
    labels = np.array([c.label for c in test_clips], dtype=np.int64)
    fused = fuse(scores)
    # The verdict is on the test clips whose every performer (or motion) training never saw;
    # those with a partner seen in training are scored apart.
    chosen, mixed_in_verdict = verdict_clips(split)
    verdict = np.isin(split.test, chosen)
    apart = ~verdict
    mixed_accuracy = float((fused[apart].argmax(1) == labels[apart]).mean()) if apart.any() else None
    labels, fused, scores = labels[verdict], fused[verdict], {s: v[verdict] for s, v in scores.items()}
    chance = chance_level(labels, fused.argmax(1), len(clips.classes))
    p = binomial_p(int((fused.argmax(1) == labels).sum()), len(labels), chance)
    keyed = {name: [clips.clips[i].key for i in idx] for name, idx in
             (("train", split.train), ("mixed", split.mixed), ("background_seen", split.background_seen))}  # fmt: skip
    return LearnResult(clips.classes, labels, scores, fused, chance, p, len(train_clips), seconds / 60.0, stopped,
                       split.held_out, [c.key for c, v in zip(test_clips, verdict, strict=True) if v], base.to_json(),
                       epochs, schedule, epoch_seconds, keyed, split.dropped, split.background_dropped,
                       mixed_accuracy, mixed_in_verdict)  # fmt: skip


def check_learnability(
    root: Path,
    opts: LearnOptions,
    *,
    progress: ProgressFactory | None = None,
    manifest: DatasetManifest | None = None,
    table: RecipeTable | None = None,
) -> tuple[CheckResult, LearnResult]:
    """The learnability check on a dataset directory, and the numbers behind it (its
    manifest and recipes table are read unless given)."""

    if manifest is None:
        manifest = load_manifest(root / "manifest.json")
    load_bar = progress("learnability: reading clips", len(manifest.videos)) if progress is not None else None
    clips = load_phav(root, size=opts.size, flow=opts.flow, workers=opts.workers, progress=load_bar,
                      manifest=manifest, table=table)  # fmt: skip
    result = run_learnability(clips, opts, progress=progress)
    return learnability_check(result, opts, root), result


def learnability_check(result: LearnResult, opts: LearnOptions, root: Path) -> CheckResult:
    """The check's verdict, summary and numbers from a result (and, with ``opts.out_dir``,
    its confusion image and split.json there): ``fail`` when the fused accuracy does not
    beat chance after the whole schedule, ``warn`` (inconclusive) when the budget stopped
    training first and the partial result does not pass either."""
    report = Report()
    fused = result.accuracy()
    ratio = fused / result.chance
    n = len(result.labels)
    flow = FLOW_NAMES[opts.flow]
    passes = result.p_value < opts.alpha and ratio >= opts.min_over_chance
    measured = (f"fused accuracy {fused:.1%} on {n} test clips is {ratio:.1f}× chance ({result.chance:.1%}), "
                f"binomial p = {result.p_value:.2g}; needs p < {opts.alpha:g} and "
                f"≥ {opts.min_over_chance:g}× chance")  # fmt: skip
    full = result.minutes_needed() if result.stopped_on_time else None
    # Only a result that does not pass asks whether any could (up to a binomial test per count).
    decidable, best_p = (True, result.p_value) if passes else could_pass(
        result.labels, len(result.classes), opts.alpha, opts.min_over_chance)  # fmt: skip
    undecidable = not decidable
    if undecidable:  # what no longer training could change comes first
        report.add(Finding(
            Reason.LEARNING_INCONCLUSIVE,
            f"inconclusive: too few or too alike test clips to decide (no answers to these {n} could pass: "
            f"the best reach p = {best_p:.2g}); generate more videos; {measured}",
            file=str(root), severity="warn",
            numbers={"accuracy": fused, "chance": result.chance, "p_value": result.p_value,
                     "best_possible_p_value": best_p},
        ))  # fmt: skip
    elif not passes and full is not None:
        report.add(Finding(
            Reason.LEARNING_INCONCLUSIVE,
            f"inconclusive: {result.budget_note(opts.budget_minutes)}; {measured}",
            file=str(root), severity="warn",
            numbers={"accuracy": fused, "chance": result.chance, "p_value": result.p_value, "minutes_needed": full},
        ))  # fmt: skip
    elif not passes:
        report.add(Finding(Reason.NOT_LEARNABLE, measured, file=str(root), numbers={
            "accuracy": fused, "chance": result.chance, "p_value": result.p_value}))  # fmt: skip
    elif full is not None:
        report.notes.append(f"{result.budget_note(opts.budget_minutes)}; the partial result already passes")
    if opts.shuffle_labels:
        report.notes.append("labels were shuffled (control run): this check is expected to fail")
    mixed = result.videos.get("mixed", [])
    streams = ", ".join(f"{s} {result.accuracy(s):.1%}" for s in result.scores)
    numbers: dict[str, Any] = {
        "flow": opts.flow, "split": opts.split, "train_clips": result.train_clips, "test_clips": n,
        "chance": result.chance, "fused_accuracy": fused, "times_chance": ratio, "p_value": result.p_value,
        "training_minutes": result.minutes, "held_out": result.held_out,
        "fused_ci95": list(result.interval()),
        **{f"{s}_accuracy": result.accuracy(s) for s in result.scores},
        **{f"{s}_ci95": list(result.interval(s)) for s in result.scores},
        "mixed_test_clips": len(mixed), "fused_accuracy_mixed": result.mixed_accuracy,
        "mixed_in_verdict": result.mixed_in_verdict,
        "train_clips_with_held_out_background": len(result.videos.get("background_seen", [])),
        "test_clips_per_class": result.test_clips_per_class(),
        "epochs": result.epochs, "schedule_epochs": result.schedule, "stopped_by_budget": result.stopped_on_time,
        "full_schedule_minutes": result.full_minutes(), "settings": result.settings,
        "per_class": result.per_class(),
        "confused_pairs": [{"classes": [a, b], "clips": k} for a, b, k in result.confused_pairs()],
        "split_videos": result.split_json(opts.split, opts.background),
    }  # fmt: skip
    if opts.out_dir is not None:
        image = opts.out_dir / "confusion.png"
        write_confusion_png(result.confusion(), result.classes, image)
        numbers["confusion_png"] = str(image)
        split_file = opts.out_dir / "split.json"
        with atomic_write(split_file) as tmp:
            tmp.write_text(json.dumps(numbers["split_videos"], indent=1) + "\n", encoding="utf-8")
        numbers["split_json"] = str(split_file)
    lo, hi = result.interval()
    apart = ""
    seen = "a partner" if "actor" in opts.split else "a blended motion"
    if result.mixed_in_verdict:
        apart = f" (every one with {seen} seen in training: no clip has every member unseen)"
    elif mixed and result.mixed_accuracy is not None:
        apart = f" ({len(mixed)} more with {seen} seen in training, scored apart: {result.mixed_accuracy:.1%})"
    held = "held-out " + opts.split if opts.split != "random" else "random-split"
    verdict = "inconclusive, " if (undecidable or (not passes and full is not None)) else ""
    summary = (f"{verdict}{flow}: fused {fused:.1%} (95 % CI {lo:.1%}–{hi:.1%}; {ratio:.1f}× chance "
               f"{result.chance:.1%}, p = {result.p_value:.2g}) on {n} {held} clips{apart}; {streams}; "
               f"{result.minutes:.1f} min training")  # fmt: skip
    return CheckResult.from_report("learnability", report, summary, numbers)


def write_confusion_png(matrix: np.ndarray, classes: Sequence[str], path: Path) -> None:
    """``confusion_png`` written atomically to ``path``."""

    data = confusion_png(matrix, classes)
    with atomic_write(path) as tmp:
        tmp.write_bytes(data)


def confusion_png(matrix: np.ndarray, classes: Sequence[str], *, cell: int = 14) -> bytes:
    """A confusion-matrix heat map as PNG bytes (rows: true class, columns: predicted;
    row-normalised), class names down the left and the accuracy in the title."""

    n = len(classes)
    rows = matrix.sum(axis=1, keepdims=True)
    share = np.divide(matrix, rows, out=np.zeros(matrix.shape, dtype=float), where=rows > 0)
    left, top = 8 + 7 * max(len(c) for c in classes), 30
    image = np.full((top + n * cell + 8, left + n * cell + 8, 3), 255, np.uint8)
    heat = (255 - np.round(share * 255)).astype(np.uint8)
    block = np.repeat(np.repeat(heat, cell, axis=0), cell, axis=1)
    # White → blue (RGB): red and green fall with the share, blue stays full.
    image[top : top + n * cell, left : left + n * cell, :2] = block[..., None]
    for i, name in enumerate(classes):
        cv2.putText(image, name, (4, top + i * cell + cell - 3), cv2.FONT_HERSHEY_PLAIN, 0.8, (0, 0, 0), 1,
                    cv2.LINE_AA)  # fmt: skip
    for k in range(n + 1):
        cv2.line(image, (left, top + k * cell), (left + n * cell, top + k * cell), (220, 220, 220), 1)
        cv2.line(image, (left + k * cell, top), (left + k * cell, top + n * cell), (220, 220, 220), 1)
    total = int(matrix.sum())
    accuracy = np.trace(matrix) / total if total else 0.0
    cv2.putText(image, f"true (rows) vs predicted (columns, same order): {accuracy:.1%} of {total}", (4, 18),
                cv2.FONT_HERSHEY_PLAIN, 1.0, (0, 0, 0), 1, cv2.LINE_AA)  # fmt: skip
    ok, png = cv2.imencode(".png", image[..., ::-1])
    if not ok:  # pragma: no cover - OpenCV encodes any uint8 image
        raise RuntimeError("PNG encoding failed")
    return png.tobytes()
