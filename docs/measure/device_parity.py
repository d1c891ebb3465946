"""Does a stream trained on another device (``--device cuda``) learn what it learns on the
CPU, up to the order of floating-point sums? (docs/experiments/learnability.md, "On a GPU".)

Trains one stream with the same settings, seed and clips on each device, in float32 on
both (bfloat16 would compare arithmetics, not devices), and prints per device the loss
of each epoch, the training and test accuracy and the seconds per epoch, then how far
the second device's losses and test probabilities are from the first's.

    .venv/bin/python docs/measure/device_parity.py /tmp/g7 --devices cpu,cuda --epochs 4
"""

from __future__ import annotations

import argparse
import json
from collections.abc import Sequence
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np

from phav_validators.learn.data import DEFAULT_SIZE, Clip, load_phav
from phav_validators.learn.experiment import subsample
from phav_validators.learn.splits import make_split
from phav_validators.learn.train import RECOMMENDED, predict, recommended_config, train


def compare_devices(
    train_clips: Sequence[Clip],
    test: Sequence[Clip],
    n_classes: int,
    devices: Sequence[str],
    *,
    stream: str = "flow",
    epochs: int = 4,
    seed: int = 0,
    **settings: Any,
) -> dict[str, Any]:
    """Train ``stream`` on each device in float32 from the same seed; under ``runs`` per device
    (in order) its losses, seconds per epoch and accuracies, and under ``difference`` how far
    the last run's losses (relative) and test probabilities are from the first's."""
    labels = np.array([c.label for c in test])
    settings = {"stem_pool": RECOMMENDED.stem_pool, **settings}  # the same network on every device
    losses, probs, runs = [], [], []
    for dev in devices:
        config = replace(recommended_config((stream,), device=dev, epochs=epochs, seed=seed, **settings),
                         precision="fp32")  # fmt: skip
        result = train({"virtual": train_clips}, {"virtual": n_classes}, config, device=dev)
        probs.append(predict(result.model, test, config, "virtual", device=dev))
        losses.append(np.array([e.losses["virtual"] for e in result.history]))
        runs.append({"device": dev, "losses": losses[-1].tolist(), "epoch_seconds": [e.seconds for e in result.history],
                     "train_clips": len(train_clips), "train_accuracy": result.history[-1].train_accuracy,
                     "test_accuracy": float((probs[-1].argmax(1) == labels).mean())})  # fmt: skip
    difference = {
        "loss_relative": float((np.abs(losses[-1] - losses[0]) / np.abs(losses[0])).max()),
        "probability": float(np.abs(probs[-1] - probs[0]).max()),
        "same_class": float((probs[-1].argmax(1) == probs[0].argmax(1)).mean()),
    }
    return {"runs": runs, "difference": difference}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("dataset", type=Path)
    ap.add_argument("--devices", default="cpu,cuda", help="Two devices, the reference first.")
    ap.add_argument("--stream", default="flow", choices=("flow", "rgb"))
    ap.add_argument("--epochs", type=int, default=4)
    ap.add_argument("--fraction", type=float, default=0.25, help="Share of the training clips used.")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--json", type=Path, help="Also write the figures here.")
    args = ap.parse_args()
    devices = [d.strip() for d in args.devices.split(",") if d.strip()]

    clips = load_phav(args.dataset, size=DEFAULT_SIZE, workers=args.workers)
    split = make_split(clips.clips, "actor", seed=args.seed)
    train_clips = subsample([clips.clips[i] for i in split.train], args.fraction, args.seed)
    test = [clips.clips[i] for i in split.test]
    print(f"{len(train_clips)} training clips, {len(test)} test clips (held-out actors, seed {args.seed}), "
          f"{args.stream} stream, {args.epochs} epochs, float32")  # fmt: skip
    figures = compare_devices(train_clips, test, len(clips.classes), devices, stream=args.stream, epochs=args.epochs,
                              seed=args.seed)  # fmt: skip
    for f in figures["runs"]:
        print(f"{f['device']:>8}: losses {' '.join(f'{v:.4f}' for v in f['losses'])}; train {f['train_accuracy']:.1%}, "
              f"test {f['test_accuracy']:.1%}; {np.mean(f['epoch_seconds']):.2f} s/epoch")  # fmt: skip
    d = figures["difference"]
    print(f"{devices[-1]} against {devices[0]}: loss per epoch differs by {d['loss_relative']:.2e} at most "
          f"(relative); test probabilities by {d['probability']:.4f} at most; same predicted class for "
          f"{d['same_class']:.1%} of test clips")  # fmt: skip
    if args.json is not None:
        args.json.write_text(json.dumps(figures, indent=1) + "\n", encoding="utf-8")


if __name__ == "__main__":
    main()
