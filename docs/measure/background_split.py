"""Does seeing a held-out model in the background during training change the check's
result? The held-out-actor split's training clips with a held-out model among their
background people are excluded in one arm and kept in the other, which is subsampled to
the first arm's size, so both train on as many clips and test on the same clips
(docs/learnability.md, "The split").

Clips are read once; each arm trains both streams with the check's defaults.

    .venv/bin/python docs/measure/background_split.py /work/sets/g24 --seed 0 --json /tmp/background.json
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import time
from pathlib import Path

from phav_spec.seeding import seeded_rng
from phav_validators.learn.data import load_phav
from phav_validators.learn.learnability import LearnOptions, run_learnability
from phav_validators.learn.splits import Split, make_split


def equal_arms(clips: list, *, seed: int) -> dict[str, Split]:
    """The split with background-exposed training clips excluded, and the split that keeps
    them with its training clips drawn down (seeded) to the first's number."""
    excluded = make_split(clips, "actor", seed=seed, background="exclude")
    kept = make_split(clips, "actor", seed=seed, background="keep")
    order = seeded_rng(seed, 0xB6).permutation(len(kept.train))[: len(excluded.train)]
    train = sorted(kept.train[int(i)] for i in order)
    seen = sorted(set(train) & set(kept.background_seen))
    return {"exclude": excluded, "keep (subsampled)": dataclasses.replace(kept, train=train, background_seen=seen)}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("dataset", type=Path)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--minutes", type=float, default=60.0, help="budget per arm (a ceiling)")
    parser.add_argument("--json", type=Path, default=None)
    args = parser.parse_args()
    start = time.perf_counter()
    clips = load_phav(args.dataset, workers=2)
    print(f"read {len(clips)} clips in {time.perf_counter() - start:.0f} s", flush=True)
    opts = LearnOptions(seed=args.seed, budget_minutes=args.minutes)
    rows = []
    for name, split in equal_arms(clips.clips, seed=args.seed).items():
        result = run_learnability(clips, opts, split=split)
        row = {"arm": name, "train_clips": len(split.train), "with_held_out_background": len(split.background_seen),
               "test_clips": len(split.test), "fused": result.accuracy(), "rgb": result.accuracy("rgb"),
               "flow": result.accuracy("flow"), "minutes": result.minutes,
               "stopped": result.stopped_on_time}  # fmt: skip
        rows.append(row)
        print(json.dumps(row), flush=True)
    print(
        "| arm | training clips | with a held-out model in the background | test clips | fused | flow | RGB | minutes |"
    )
    print("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")
    for r in rows:
        print(f"| {r['arm']} | {r['train_clips']} | {r['with_held_out_background']} | {r['test_clips']} | "
              f"{r['fused']:.1%} | {r['flow']:.1%} | {r['rgb']:.1%} | {r['minutes']:.1f} |")  # fmt: skip
    if args.json is not None:
        args.json.write_text(json.dumps(rows, indent=2) + "\n", encoding="utf-8")


if __name__ == "__main__":
    main()
