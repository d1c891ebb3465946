"""``phav train``: TSN / Cool-TSN on PHAV and real datasets, the paper's protocol as options.

Registered on the ``phav`` app by ``phav_app.cli``; torch is imported only when it runs.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated, Any

import typer
from rich.markup import escape
from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn
from rich.table import Table

from phav_app.console import console
from phav_spec.errors import PhavUserError
from phav_spec.files import atomic_write
from phav_validators.findings import ProgressFactory
from phav_validators.learn.config import require_torch
from phav_validators.learn.data import FLOW_SOURCES, ClipSet, load_phav, load_real, real_split
from phav_validators.learn.experiment import MODES, RunResult, phav_runs, real_runs, summarise
from phav_validators.learn.learnability import confusion_matrix, write_confusion_png
from phav_validators.learn.splits import check_split_kind
from phav_validators.learn.train import (
    RECOMMENDED,
    RGB_EPOCH_SHARE,
    TrainConfig,
    recommended_config,
    stream_configs,
    torch_device,
)


def _size(text: str) -> tuple[int, int]:
    w, _, h = text.lower().partition("x")
    if not (w.isdigit() and h.isdigit()) or int(w) < 16 or int(h) < 16:
        raise PhavUserError(f"expected WIDTHxHEIGHT of at least 16x16, e.g. 85x64, got {text!r}", field="--size")
    return int(w), int(h)


def _ints(text: str, field: str) -> tuple[int, ...]:
    try:
        values = tuple(int(v) for v in text.split(",") if v.strip())
    except ValueError:
        raise PhavUserError(f"expected comma-separated integers, got {text!r}", field=field) from None
    if not values:
        raise PhavUserError("give at least one value", field=field)
    return values


def _fractions(text: str) -> tuple[float, ...]:
    try:
        values = tuple(float(v) for v in text.split(",") if v.strip())
    except ValueError:
        raise PhavUserError(f"expected comma-separated fractions, e.g. 0.01,0.25,1, got {text!r}",
                            field="--real-fraction") from None  # fmt: skip
    if not values or any(not 0.0 < v <= 1.0 for v in values):
        raise PhavUserError(f"fractions must be in (0, 1], got {text!r}", field="--real-fraction")
    return values


def _real(text: str) -> tuple[str, Path]:
    layout, sep, path = text.partition("=")
    if not sep or layout not in ("ucf101", "hmdb51"):
        raise PhavUserError(f"expected ucf101=PATH or hmdb51=PATH, got {text!r}", field="--real")
    return layout, Path(path)


def train_command(
    dataset: Annotated[Path | None, typer.Argument(help="A PHAV dataset directory (shards are streamed).")] = None,
    out: Annotated[Path, typer.Option(help="Output folder: checkpoints (a rerun resumes), results.json.")] = Path(
        "phav-train"
    ),
    streams: Annotated[str, typer.Option(help="Comma-separated streams: rgb, flow.")] = "rgb,flow",
    split: Annotated[
        str, typer.Option(help="PHAV split: random, actor, motion or actor+motion (held out).")
    ] = "random",
    splits: Annotated[int, typer.Option(min=1, max=3, help="Splits averaged (PHAV: seeded 80/20; real: 1..N).")] = 1,
    epochs: Annotated[
        int,
        typer.Option(
            min=1,
            help=f"Epochs of the flow stream (the RGB stream: {RGB_EPOCH_SHARE}, or --rgb-epochs).",
        ),
    ] = RECOMMENDED.epochs,
    rgb_epochs: Annotated[
        int | None,
        typer.Option(
            min=1,
            help=f"Epochs of the RGB stream (default: {RGB_EPOCH_SHARE} of --epochs).",
        ),
    ] = None,
    lr: Annotated[float, typer.Option(help="Peak learning rate of TSN's SGD (cosine decay).")] = 0.05,
    batch: Annotated[int, typer.Option(min=1, help="Clips per mini-batch (single source).")] = 32,
    size: Annotated[str, typer.Option(help="Stored frame size WIDTHxHEIGHT; crops are 7/8 of it.")] = "85x64",
    widths: Annotated[str, typer.Option(help="Backbone widths, one stride-2 stage each.")] = "32,64,128,192",
    stem_pool: Annotated[
        bool | None,
        typer.Option(
            help="Max-pool after the stem: a quarter of the pixels in every later layer "
            "(default: on a CPU, epochs in 1/2 to 2/3 of the time; off on a GPU, where it cost accuracy)."
        ),
    ] = None,
    dropout: Annotated[float, typer.Option(help="Dropout before the classifiers.")] = 0.3,
    crop: Annotated[float, typer.Option(help="Side of the training crop, share of the stored frame.")] = 0.875,
    scale_jitter: Annotated[
        bool | None,
        typer.Option(help="TSN's multi-scale training crops (2/3 to all of the frame, resized; testing: centre)."),
    ] = None,
    segments: Annotated[int, typer.Option(min=1, help="Snippets per clip while training (TSN's K).")] = 3,
    rgb_frames: Annotated[int, typer.Option(min=1, help="RGB frames stacked per snippet (1: TSN's).")] = (
        RECOMMENDED.rgb_frames
    ),
    rgb_diff: Annotated[
        bool | None,
        typer.Option(
            help="Stacked RGB frames enter as the first frame and consecutive differences "
            "(default: on with 2 or more frames)."
        ),
    ] = None,
    diff_gain: Annotated[
        float,
        typer.Option(help="Factor on the RGB differences (a difference is ~4x smaller than a frame; 1: as they are)."),
    ] = RECOMMENDED.diff_gain,
    distill: Annotated[
        float | None,
        typer.Option(
            min=0.0,
            help="RGB stream: weight of matching the flow stream's features (trained first; "
            f"default {RECOMMENDED.distill:g} when both streams train, else 0).",
        ),
    ] = None,
    flow: Annotated[str, typer.Option(help="Flow: gt (PHAV's ground truth), farneback or tvl1 (estimated).")] = "gt",
    real: Annotated[
        str | None, typer.Option(help="A real dataset: ucf101=PATH or hmdb51=PATH (official split files beside it).")
    ] = None,
    mode: Annotated[str, typer.Option(help="With --real: tsn (real only), cool (Cool-TSN) or ft (TSN-FT).")] = "tsn",
    mix: Annotated[str, typer.Option(help="Cool-TSN clips per batch, virtual:real (the paper: 10:22).")] = "10:22",
    real_fraction: Annotated[str, typer.Option(help="Fractions of real training data swept, e.g. 0.01,0.25,1.")] = "1",
    init: Annotated[Path | None, typer.Option(help="TSN-FT: a phav train output folder (or checkpoint).")] = None,
    device: Annotated[str, typer.Option(help="cpu, cuda or cuda:N.")] = "cpu",
    threads: Annotated[
        int | None,
        typer.Option(
            min=1, help="Torch threads; on a GPU also the threads cutting snippets (default: the usable cores)."
        ),
    ] = None,
    precision: Annotated[
        str | None, typer.Option(help="fp32 or bf16 autocast (default: bf16 where the device computes it faster).")
    ] = None,
    workers: Annotated[int, typer.Option(min=1, help="Processes decoding shards.")] = 1,
    seed: Annotated[int, typer.Option(min=0, help="Seed of splits and training (split k of --splits: seed + k).")] = 0,
) -> None:
    """Train TSN on PHAV, or TSN / TSN-FT / Cool-TSN on a real dataset; print accuracies."""

    require_torch()
    # Every option is checked before any data is read.
    stream_list = _streams(streams)
    check_split_kind(split)
    torch_device(device)
    fractions = _fractions(real_fraction)
    real_source = _real(real) if real is not None else None
    _check_mode(mode, real_source, dataset, init, stream_list)
    if flow not in FLOW_SOURCES:
        raise PhavUserError(f"choose from {', '.join(FLOW_SOURCES)}, got {flow!r}", field="--flow")
    clips_per_batch = _mix(mix)
    stored = _size(size)
    # RECOMMENDED with every option given; what is left unset is resolved for these streams
    # and this device (distillation, threads, precision, stem).
    chosen = {"distill": distill, "threads": threads, "precision": precision, "rgb_epochs": rgb_epochs,
              "rgb_diff": rgb_diff, "scale_jitter": scale_jitter, "stem_pool": stem_pool}  # fmt: skip
    base = recommended_config(stream_list, device=device, widths=_ints(widths, "--widths"), epochs=epochs, lr=lr,
                              mix=(("virtual", batch),), seed=seed, dropout=dropout, segments=segments,
                              rgb_frames=rgb_frames, diff_gain=diff_gain, crop=crop,
                              **{k: v for k, v in chosen.items() if v is not None})  # fmt: skip
    stream_configs(stream_list, base)
    if dataset is None and real is None:
        raise PhavUserError("give a PHAV dataset directory, --real, or both", field="DATASET")
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as e:
        raise PhavUserError(f"cannot create the output folder: {e.strerror}", source=str(out)) from None

    with Progress(TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(), TimeElapsedColumn(),
                  console=console, transient=True) as bar:  # fmt: skip

        def progress(description: str, total: int):
            task = bar.add_task(description, total=total or None)
            return lambda n: bar.advance(task, n)

        virtual = None
        if dataset is not None:
            virtual = load_phav(dataset, size=stored, flow=flow, workers=workers, progress=progress("reading PHAV", 0))
        if real_source is None:
            runs = phav_runs(virtual, base, stream_list, out, split_kind=split, splits=splits, device=device,
                             progress=progress)  # fmt: skip
            classes = {r.name: virtual.classes for r in runs}  # run name → its test classes
        else:
            runs, classes = _real_runs(real_source, virtual, base, stream_list, out, splits=splits, size=stored,
                                       flow=flow, mode=mode, mix=clips_per_batch, fractions=fractions, init=init,
                                       device=device, progress=progress)  # fmt: skip
    rows = summarise(runs)
    _print_accuracies(rows, f"test accuracy ({'PHAV ' + split if real is None else real + ' ' + mode})")
    _write_results(out, runs, classes, rows, base)


def _streams(text: str) -> tuple[str, ...]:
    """The comma-separated streams, at least one."""
    stream_list = tuple(s.strip() for s in text.split(",") if s.strip())
    if not stream_list:
        raise PhavUserError("name at least one stream", field="--streams")
    if len(set(stream_list)) != len(stream_list):  # a stream twice made a "fused" row of one stream
        raise PhavUserError(f"name each stream once, got {text!r}", field="--streams")
    return stream_list


def _check_mode(
    mode: str, real_source: tuple[str, Path] | None, dataset: Path | None, init: Path | None, streams: tuple[str, ...]
) -> None:
    """A known mode, with what it needs: Cool-TSN a PHAV dataset, TSN-FT a PHAV run to start
    from, holding a checkpoint for each stream trained (found now, not once every real video
    is decoded and the first stream trained)."""
    if mode not in MODES:
        raise PhavUserError(f"choose from {', '.join(MODES)}, got {mode!r}", field="--mode")
    if real_source is not None and mode == "cool" and dataset is None:
        raise PhavUserError("Cool-TSN mixes PHAV clips into every batch: give a PHAV dataset", field="--mode")
    if real_source is not None and mode == "ft" and init is None:
        raise PhavUserError("TSN-FT starts from a PHAV run: give --init (a phav train output folder)", field="--init")
    if init is not None and not init.exists():
        raise PhavUserError("no such folder or checkpoint", source=str(init), field="--init")
    if init is not None and init.is_file() and len(streams) != 1:
        raise PhavUserError(f"a checkpoint starts one stream: name its stream alone with --streams, not "
                            f"{','.join(streams)}", source=str(init), field="--init")  # fmt: skip
    if init is not None and init.is_dir():
        missing = [f"split1-{s}.pt" for s in streams if not (init / f"split1-{s}.pt").is_file()]
        if missing:
            raise PhavUserError(f"no {', '.join(missing)} to start from (a phav train output folder holds "
                                "split1-STREAM.pt)", source=str(init), field="--init")  # fmt: skip


def _mix(text: str) -> tuple[int, int]:
    """Cool-TSN's VIRTUAL:REAL clips per batch."""
    n_virtual, _, n_real = text.partition(":")
    if not (n_virtual.isdigit() and n_real.isdigit()) or int(n_virtual) < 1 or int(n_real) < 1:
        raise PhavUserError(f"expected VIRTUAL:REAL clip counts, e.g. 10:22, got {text!r}", field="--mix")
    return int(n_virtual), int(n_real)


def _real_runs(
    real_source: tuple[str, Path],
    virtual: ClipSet | None,
    base: TrainConfig,
    streams: tuple[str, ...],
    out: Path,
    *,
    splits: int,
    size: tuple[int, int],
    flow: str,
    mode: str,
    mix: tuple[int, int],
    fractions: tuple[float, ...],
    init: Path | None,
    device: str,
    progress: ProgressFactory,
) -> tuple[list[RunResult], dict[str, list[str]]]:
    """Train and test on each official split of the real dataset; the runs and each run's classes."""
    layout, root = real_source
    runs: list[RunResult] = []
    classes: dict[str, list[str]] = {}
    for k in range(1, splits + 1):
        official = real_split(layout, root, k)
        load = progress(f"decoding {layout} split {k}", len(official.train) + len(official.test))
        train_clips = load_real(official.train, size=size, flow=flow, progress=load)
        test_clips = load_real(official.test, size=size, flow=flow, progress=load)
        done = real_runs(mode, train_clips, test_clips, len(official.classes), base, streams, out,
                         virtual=virtual, mix=mix, fractions=fractions, split=k,
                         init=init, device=device, progress=progress)  # fmt: skip
        runs += done
        classes |= {r.name: official.classes for r in done}
    return runs, classes


def _print_accuracies(rows: list[dict[str, Any]], title: str) -> None:
    """The test accuracies per fraction and stream, as a table."""
    table = Table(title=title)
    for col in ("fraction", "stream", "splits", "mean", "min", "max"):
        table.add_column(col, justify="right")
    for row in rows:
        table.add_row(f"{row['fraction']:g}", row["stream"], str(row["splits"]), f"{row['mean_accuracy']:.1%}",
                      f"{row['min']:.1%}", f"{row['max']:.1%}")  # fmt: skip
    console.print(table)


def _write_results(
    out: Path, runs: list[RunResult], classes: dict[str, list[str]], rows: list[dict[str, Any]], base: TrainConfig
) -> None:
    """Each run's confusion image (of the fused predictions, or the only stream's) and results.json."""
    for run in runs:
        names = classes[run.name]
        write_confusion_png(confusion_matrix(run.labels, run.predicted, len(names)), names,
                            out / f"{run.name}-confusion.png")  # fmt: skip
    results = {"runs": [r.to_json() for r in runs], "summary": rows, "config": base.to_json()}
    with atomic_write(out / "results.json") as tmp:
        tmp.write_text(json.dumps(results, indent=2) + "\n", encoding="utf-8")
    console.print(f"results: {escape(str(out / 'results.json'))}")
