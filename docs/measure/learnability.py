"""Test accuracy against training minutes, per stream and fused, for the random and the
held-out-actor split of one PHAV dataset (docs/experiments/learnability.md, "Measured before
issue 23": accuracy against training minutes).

Clips are read once; each split trains both streams with the default ``phav train``
settings and tests them ``--points`` times over their epochs (``phav_app.bench.training``).

    .venv/bin/phav generate --theta phav-v1-short --videos 640 --seed 11 --workers 2 --out /tmp/d640
    .venv/bin/python docs/measure/learnability.py /tmp/d640 --json /tmp/curve.json
"""

from __future__ import annotations

import argparse
import json
import time
from dataclasses import asdict
from pathlib import Path

from phav_app.bench.training import learning_curve
from phav_validators.learn.data import load_phav
from phav_validators.learn.train import RECOMMENDED, recommended_config


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("dataset", type=Path)
    parser.add_argument("--splits", default="random,actor")
    parser.add_argument("--epochs", type=int, default=RECOMMENDED.epochs)
    parser.add_argument("--points", type=int, default=8)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--json", type=Path, default=None)
    args = parser.parse_args()
    start = time.perf_counter()
    clips = load_phav(args.dataset, workers=2)
    print(f"read {len(clips)} clips in {time.perf_counter() - start:.0f} s", flush=True)
    base = recommended_config(("rgb", "flow"), epochs=args.epochs, seed=args.seed)
    points = []
    for kind in args.splits.split(","):
        points += learning_curve(clips, kind, base, points=args.points, progress=lambda m: print(m, flush=True))
    print("| split | epochs per stream | training minutes (both streams) | RGB | flow | fused | fused × chance | "
          "binomial p |")  # fmt: skip
    print("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")
    for p in points:
        a = p.accuracy
        epochs = " / ".join(str(e) for e in p.epochs.values())
        print(f"| {p.split} ({p.test_clips} test clips) | {epochs} | {p.minutes:.1f} | {a['rgb']:.1%} | "
              f"{a['flow']:.1%} | {a['fused']:.1%} | {a['fused'] / p.chance:.1f} | {p.p_fused:.1g} |")  # fmt: skip
    if args.json is not None:
        args.json.write_text(json.dumps([asdict(p) for p in points], indent=2) + "\n", encoding="utf-8")


if __name__ == "__main__":
    main()
