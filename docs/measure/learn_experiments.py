"""Why the learnability check scores what it scores: controlled experiments on PHAV clips
(docs/experiments/learnability.md's tables).

Every cell trains both streams (or the ones asked for) on held-out-actor splits, one per
seed, and reports the mean test accuracy with its spread (min–max over seeds), the
training minutes and the seconds per epoch. Clips are read once per dataset and stored
size and kept in a cache file beside the first dataset, so a grid of cells re-reads
nothing. A cell changes one thing against the baseline:

- ``clips=N``: N training clips, a seeded class-stratified subsample of the training side;
- ``size=WxH``: the stored frame size;
- any ``TrainConfig`` field (``epochs=40``, ``widths=32-64-128``, ``stem_pool=true``, …).

    .venv/bin/python docs/measure/learn_experiments.py /tmp/d1 /tmp/d2 --seeds 0,1,2 \\
        --cell baseline --cell clips=320 --cell size=128x96 --json /tmp/cells.json

With ``--keep DIR`` each trained stream is kept there as a checkpoint named by its
settings, seed and training clips, so cells that change only the RGB stream train the flow
stream (its teacher) once per seed.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import time
from dataclasses import dataclass, fields, replace
from pathlib import Path
from typing import Any

import numpy as np

from phav_spec.errors import PhavUserError
from phav_validators.learn.data import Clip, ClipSet, load_phav
from phav_validators.learn.experiment import subsample
from phav_validators.learn.learnability import binomial_p, chance_level
from phav_validators.learn.splits import make_split
from phav_validators.learn.train import (
    TrainConfig,
    default_precision,
    default_threads,
    fuse,
    predict,
    stream_configs,
    teacher_of,
    train,
)


def inputs_name(size: tuple[int, int], flow: str) -> str:
    """What a cell's clips are: stored size and flow source, e.g. ``85x64-gt``."""
    return f"{size[0]}x{size[1]}-{flow}"


#: The inputs of the check and of the tables unless a cell says otherwise.
DEFAULT_INPUTS = inputs_name((85, 64), "gt")


def cached_clips(roots: list[Path], size: tuple[int, int], flow: str, workers: int = 2) -> ClipSet:
    """All clips of ``roots`` (keys prefixed by the dataset's folder name), read once (by
    ``workers`` processes) and kept in ``<first root>+<n>.clips-<size>-<flow>.npz``."""
    cache = roots[0].parent / f"{roots[0].name}+{len(roots)}.clips-{inputs_name(size, flow)}.npz"
    if cache.exists():
        z = np.load(cache, allow_pickle=False)
        meta = json.loads(str(z["meta"]))
        if meta["roots"] == [str(r) for r in roots]:
            cuts = np.cumsum([0] + meta["frames"])
            rgb, flow = z["rgb"], z["flow"]  # each z[...] reads the whole array
            clips = [Clip(key, label, "virtual", rgb[a:b], flow[a:b], groups)
                     for key, label, groups, a, b in zip(meta["keys"], meta["labels"], meta["groups"], cuts[:-1],
                                                          cuts[1:], strict=True)]  # fmt: skip
            return ClipSet("virtual", meta["classes"], clips)
    clips, classes = [], []
    for root in roots:
        start = time.perf_counter()
        part = load_phav(root, size=size, flow=flow, workers=workers)
        print(f"read {len(part)} clips of {root} in {time.perf_counter() - start:.0f} s", flush=True)
        classes = part.classes
        clips += [replace(c, key=f"{root.name}/{c.key}") for c in part.clips]
    meta = {"roots": [str(r) for r in roots], "classes": classes, "keys": [c.key for c in clips],
            "labels": [c.label for c in clips], "groups": [c.groups for c in clips],
            "frames": [c.n_frames for c in clips]}  # fmt: skip
    tmp = cache.with_suffix(".tmp.npz")
    np.savez(tmp, meta=json.dumps(meta), rgb=np.concatenate([c.rgb for c in clips]),
             flow=np.concatenate([c.flow for c in clips]))  # fmt: skip
    tmp.rename(cache)
    return ClipSet("virtual", classes, clips)


@dataclass
class Cell:
    """One row of a table: the overrides against the baseline and what they gave per seed."""

    name: str
    clips: int | None
    size: tuple[int, int]
    config: dict[str, Any]
    runs: list[dict[str, Any]]


def parse_cell(text: str, size: tuple[int, int]) -> tuple[int | None, tuple[int, int], dict[str, Any]]:
    """``baseline`` or ``key=value,key=value``: (clips, size, TrainConfig overrides)."""
    clips, overrides = None, {}
    types = {f.name: f.type for f in fields(TrainConfig)}
    for item in [] if text == "baseline" else text.split(","):
        key, _, value = item.partition("=")
        if key == "clips":
            clips = int(value)
        elif key == "size":
            w, h = value.split("x")
            size = (int(w), int(h))
        elif key not in types:
            raise SystemExit(f"unknown cell field {key!r}")
        elif "tuple" in str(types[key]):
            overrides[key] = tuple(int(v) for v in value.split("-"))
        elif "bool" in str(types[key]):
            overrides[key] = value.lower() in ("1", "true", "yes")
        elif "int" in str(types[key]):
            overrides[key] = int(value)
        elif "float" in str(types[key]):
            overrides[key] = float(value)
        else:
            overrides[key] = value
    return clips, size, overrides


def kept_stream(keep: Path | None, config: TrainConfig, clips: list[Clip], inputs: str = DEFAULT_INPUTS) -> Path | None:
    """Where a stream trained with ``config`` on ``clips`` is kept (None: not kept); the name
    carries ``inputs`` (stored size and flow source) when they are not the defaults, so a
    cell on other inputs never meets another's checkpoint."""
    if keep is None:
        return None
    h = hashlib.sha256(json.dumps(config.changed(), sort_keys=True).encode())
    h.update("\n".join(c.key for c in clips).encode())
    tag = "" if inputs == DEFAULT_INPUTS else f"{inputs}-"
    return keep / f"{config.stream}-s{config.seed}-{tag}{h.hexdigest()[:16]}.pt"


def cell_config(overrides: dict[str, Any], seed: int, streams: list[str], device: str = "cpu") -> TrainConfig:
    """The settings a cell trains ``streams`` with (each stream's are ``for_stream`` of them);
    a setting ``TrainConfig`` refuses is a ``PhavUserError``."""
    settings = {"threads": default_threads(), "precision": default_precision(device), **overrides}
    return TrainConfig(stream="rgb" if "rgb" in streams else streams[0], seed=seed, **settings)


def check_cells(cells: list[tuple[str, dict[str, Any]]], streams: list[str], device: str = "cpu") -> None:
    """Refuse, before anything is read or trained, a cell whose settings cannot train
    ``streams`` (e.g. ``distill`` without the RGB stream): one line naming the cell."""
    for text, overrides in cells:
        try:
            stream_configs(streams, cell_config(overrides, 0, streams, device))
        except PhavUserError as e:
            raise SystemExit(f"--cell {text} with --streams {','.join(streams)}: {e}") from None


def run_cell(
    data: ClipSet,
    clips: int | None,
    overrides: dict[str, Any],
    seed: int,
    streams: list[str],
    keep: Path | None,
    inputs: str = DEFAULT_INPUTS,
    device: str = "cpu",
) -> dict:
    """Train ``streams`` on the seed's held-out-actor split (subsampled to ``clips``), test, fuse;
    trained streams are kept in ``keep`` (a checkpoint there is reused, not retrained);
    ``inputs`` is the clips' stored size and flow source (``inputs_name``); the networks run
    on ``device`` in its default precision unless the cell sets one."""
    split = make_split(data.clips, "actor", seed=seed)
    train_clips = [data.clips[i] for i in split.train]
    if clips is not None and clips < len(train_clips):
        train_clips = subsample(train_clips, clips / len(train_clips), seed)
    test = [data.clips[i] for i in split.test]
    labels = np.array([c.label for c in test])
    scores, minutes, epoch_s, train_acc = {}, {}, {}, {}
    base = cell_config(overrides, seed, streams, device)
    teacher = None
    for stream, config in stream_configs(streams, base).items():
        result = train({"virtual": train_clips}, {"virtual": len(data.classes)}, config, teacher=teacher,
                       checkpoint=kept_stream(keep, config, train_clips, inputs), device=device)  # fmt: skip
        teacher = teacher_of(stream, result, base)
        scores[stream] = predict(result.model, test, config, "virtual", device=device)
        minutes[stream] = result.seconds / 60
        epoch_s[stream] = result.seconds / len(result.history)
        train_acc[stream] = result.history[-1].train_accuracy
    accuracy = {s: float((p.argmax(1) == labels).mean()) for s, p in scores.items()}
    if len(streams) > 1:
        fused = fuse(scores)
        accuracy["fused"] = float((fused.argmax(1) == labels).mean())
        chance = chance_level(labels, fused.argmax(1), len(data.classes))
        accuracy["p_fused"] = binomial_p(int((fused.argmax(1) == labels).sum()), len(labels), chance)
    # The test clips' class probabilities per stream, kept so fusion can be studied afterwards.
    probabilities = {s: np.round(p, 5).tolist() for s, p in scores.items()}
    return {"seed": seed, "train_clips": len(train_clips), "test_clips": len(test), "accuracy": accuracy,
            "minutes": minutes, "epoch_seconds": epoch_s, "train_accuracy": train_acc,
            "test_labels": labels.tolist(), "test_scores": probabilities,
            "test_keys": [c.key for c in test]}  # fmt: skip


def accuracy_on(run: dict, streams: list[str], prefix: str) -> dict[str, float]:
    """A run's accuracy per stream (and fused) on its test clips whose key starts with
    ``prefix`` (e.g. ``g7/``: one dataset's clips of a pooled run), from its kept scores."""
    if "test_keys" not in run:
        raise SystemExit(f"seed {run['seed']}'s run predates test_keys: delete it from the JSON and rerun")
    mine = np.array([k.startswith(prefix) for k in run["test_keys"]])
    if not mine.any():
        raise SystemExit(f"no test clip's key starts with {prefix!r}")
    labels = np.array(run["test_labels"])[mine]
    scores = {s: np.array(run["test_scores"][s])[mine] for s in streams}
    if len(streams) > 1:
        scores["fused"] = fuse(scores)
    return {s: float((p.argmax(1) == labels).mean()) for s, p in scores.items()}


def row(cell: Cell, streams: list[str], prefix: str | None = None) -> str:
    """A markdown row: mean (min–max) per stream over seeds, clips, minutes, seconds per epoch;
    with ``prefix``, the accuracy on the test clips whose key starts with it (``accuracy_on``)."""
    found = [r["accuracy"] if prefix is None else accuracy_on(r, streams, prefix) for r in cell.runs]
    cols = []
    for s in [*streams, "fused"] if len(streams) > 1 else streams:
        values = [100 * a[s] for a in found]
        cols.append(f"{np.mean(values):.1f} ({min(values):.0f}–{max(values):.0f})")
    n_train = round(np.mean([r["train_clips"] for r in cell.runs]))
    tested = [r["test_clips"] if prefix is None else sum(k.startswith(prefix) for k in r["test_keys"])
              for r in cell.runs]  # fmt: skip
    n_test = round(np.mean(tested))
    minutes = np.mean([sum(r["minutes"].values()) for r in cell.runs])
    per_epoch = " / ".join(f"{np.mean([r['epoch_seconds'][s] for r in cell.runs]):.1f}" for s in streams)
    fit = " / ".join(f"{100 * np.mean([r['train_accuracy'][s] for r in cell.runs]):.0f}" for s in streams)
    return (f"| {cell.name} | {len(cell.runs)} | {n_train} / {n_test} | " + " | ".join(cols)
            + f" | {fit} | {minutes:.1f} | {per_epoch} |")  # fmt: skip


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("datasets", type=Path, nargs="+")
    parser.add_argument("--cell", action="append", default=[], help="baseline, or key=value,… (repeatable)")
    parser.add_argument("--seeds", default="0,1,2")
    parser.add_argument("--streams", default="rgb,flow")
    parser.add_argument("--size", default="85x64")
    parser.add_argument("--flow", default="gt")
    parser.add_argument("--device", default="cpu", help="where the networks run: cpu, cuda, cuda:1")
    parser.add_argument("--workers", type=int, default=2, help="processes reading the datasets (once, then cached)")
    parser.add_argument("--json", type=Path, default=None, help="results, appended to and resumed from")
    parser.add_argument("--keep", type=Path, default=None, help="folder where trained streams are kept and reused")
    parser.add_argument(
        "--test-on",
        default=None,
        metavar="PREFIX",
        help="also score each cell on the test clips whose key starts with PREFIX (e.g. g7/)",
    )
    args = parser.parse_args()
    if args.keep is not None:
        args.keep.mkdir(parents=True, exist_ok=True)
    streams = args.streams.split(",")
    w, h = args.size.split("x")
    seeds = [int(s) for s in args.seeds.split(",")]
    done: dict[str, Any] = {}
    if args.json is not None and args.json.exists():
        done = json.loads(args.json.read_text(encoding="utf-8"))
    parsed = [(text, *parse_cell(text, (int(w), int(h)))) for text in args.cell or ["baseline"]]
    check_cells([(text, overrides) for text, _, _, overrides in parsed], streams, args.device)
    loaded: dict[tuple[int, int], ClipSet] = {}
    cells = []
    for text, clips, size, overrides in parsed:
        if size not in loaded:
            loaded[size] = cached_clips(args.datasets, size, args.flow, args.workers)
        cell = Cell(text, clips, size, overrides, [])
        inputs = inputs_name(size, args.flow)
        for seed in seeds:
            key = f"{text}|{args.flow}|{args.streams}|{seed}|{'+'.join(str(d) for d in args.datasets)}"
            if key not in done:
                start = time.perf_counter()
                done[key] = run_cell(loaded[size], clips, overrides, seed, streams, args.keep, inputs, args.device)
                done[key]["wall_seconds"] = time.perf_counter() - start
                if args.json is not None:
                    args.json.write_text(json.dumps(done, indent=1) + "\n", encoding="utf-8")
            cell.runs.append(done[key])
            print(text, seed, {k: round(v, 3) for k, v in done[key]["accuracy"].items()}, flush=True)
        cells.append(cell)
    print(f"\nflow: {args.flow}; held-out actors; accuracy % mean (min–max over {len(seeds)} seeds)")
    names = [*streams, "fused"] if len(streams) > 1 else streams
    print("| cell | seeds | train / test clips | " + " | ".join(names) + " | train acc % | minutes | s/epoch |")
    print("| --- | ---: | ---: | " + " | ".join("---:" for _ in names) + " | ---: | ---: | ---: |")
    for cell in cells:
        print(row(cell, streams))
    if args.test_on is not None:
        print(f"\nthe same cells on the test clips whose key starts with {args.test_on!r}")
        for cell in cells:
            print(row(cell, streams, args.test_on))


if __name__ == "__main__":
    main()
