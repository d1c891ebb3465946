"""What the Cityscapes judge answers on a dataset's frames (docs/world.md): on the pixels of
our classes, which of its classes it names, and where it names one of its classes, which of
our classes are there; per environment, weather and day phase. The same seeded sample of
outdoor frames as the realism check.

    python docs/measure/judged_as.py r52 --ours tree,vegetation --said car,vegetation [--frames 400]
"""

from __future__ import annotations

import argparse
from collections import Counter, defaultdict
from pathlib import Path

import numpy as np

from phav_spec.clips import ClipReader
from phav_spec.recipe_table import read_recipe_table
from phav_spec.scene import ENVIRONMENT_SCENES
from phav_spec.vocab import PIXEL_CLASSES
from phav_validators.checks.scan import class_lut, rgb_code
from phav_validators.realism.check import sample_frames
from phav_validators.realism.judges import load_judges

#: Shares shown per row: the largest few.
SHOWN = 5


def shares(counts: Counter) -> str:
    total = sum(counts.values())
    top = sorted(counts.items(), key=lambda kv: (-kv[1], kv[0]))[:SHOWN]
    return f"{total:,} px: " + ", ".join(f"{name} {n / total:.2f}" for name, n in top)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("root", type=Path)
    parser.add_argument("--ours", default="", help="our pixel classes, comma-separated")
    parser.add_argument("--said", default="", help="the judge's classes, comma-separated")
    parser.add_argument("--frames", type=int, default=400)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    ours = [c for c in args.ours.split(",") if c]
    said = [c for c in args.said.split(",") if c]
    segmenter = load_judges(threads=2).segmenters["cityscapes"]
    names = segmenter.classes.labels
    for c in said:
        if c not in names:
            parser.error(f"--said: {c!r} is not a Cityscapes class ({', '.join(names)})")
    ours_ids = [PIXEL_CLASSES[c].class_id for c in ours]
    our_name = {info.class_id: name for name, info in PIXEL_CLASSES.items()}
    table = read_recipe_table(args.root / "recipes.parquet")
    groups = {v: (e, f"weather={w}", f"day_phase={d}") for v, e, w, d in zip(
        table.column("video_id"), table.column("environment"), table.column("weather"), table.column("day_phase"),
        strict=True)}  # fmt: skip
    answered: dict[str, Counter] = defaultdict(Counter)  # on our classes: what the judge says
    found: dict[tuple[str, str], Counter] = defaultdict(Counter)  # where it says c: our classes
    lut = class_lut()[0]
    reader = ClipReader(args.root)
    try:
        for video, frames in sample_frames(reader, args.frames, args.seed).items():
            if ENVIRONMENT_SCENES[groups[video][0]].indoor:
                continue
            clip = reader.read(video, frames, ("rgb", "semantic"))
            for rgb, semantic in zip(clip["rgb"], clip["semantic"], strict=True):
                classes = lut[rgb_code(semantic)]
                labels = segmenter.labels(rgb)
                where = ("all", *groups[video])
                mask = np.isin(classes, ours_ids)
                for a, n in zip(*np.unique(labels[mask], return_counts=True), strict=True):
                    for g in where:
                        answered[g][names[int(a)]] += int(n)
                for c in said:
                    hit = labels == names.index(c)
                    for a, n in zip(*np.unique(classes[hit], return_counts=True), strict=True):
                        for g in where:
                            found[(c, g)][our_name.get(int(a), str(a))] += int(n)
    finally:
        reader.close()
    if ours:
        print(f"the judge's answers on our {', '.join(ours)}:")
        for g in sorted(answered, key=lambda k: (k != "all", k)):
            print(f"  {g:18s} {shares(answered[g])}")
    for c in said:
        print(f"our classes where the judge says {c}:")
        for cc, g in sorted((k for k in found if k[0] == c), key=lambda k: (k[1] != "all", k[1])):
            print(f"  {g:18s} {shares(found[(cc, g)])}")


if __name__ == "__main__":
    main()
