"""The realism check's Cityscapes figures without a dataset: the frames it would draw from
the first N recipes of (θ, seed), rendered one by one and judged (docs/realism.md). The
figures are the check's own on the dataset those recipes make (same frames, same pixels,
same bootstrap), in minutes instead of a generation run; ``--set`` renders every recipe
with a condition forced (``phav vary``'s NAME=VALUE), the same scenes in other light.

    .venv/bin/python docs/measure/judged_frames.py [--videos 100] [--seed 52] [--frames 400]
    .venv/bin/python docs/measure/judged_frames.py --set weather=fog --set day_phase=day --set clock_hour=13

It prints the mIoU and per-class IoU of each group (all, each weather, day phase, clock hour
and environment, clear or overcast daytime) over the outdoor frames.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

from phav_generator.physics.simulate import simulate
from phav_generator.render.context import gl_context
from phav_generator.render.modalities import encode_frame
from phav_generator.render.video import inputs_renderer, scene_inputs
from phav_generator.sampling import sample_recipes
from phav_generator.vary import parse_settings, vary
from phav_spec.scene import ENVIRONMENT_SCENES
from phav_spec.theta import load_preset
from phav_validators.checks.scan import class_lut, rgb_code
from phav_validators.realism.check import Tally, _miou, conditions_of, draw_frames, judge_world
from phav_validators.realism.judges import load_judges


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--theta", default="phav-v1", help="preset name")
    parser.add_argument("--videos", type=int, default=100)
    parser.add_argument("--seed", type=int, default=52, help="the dataset's seed")
    parser.add_argument("--frames", type=int, default=400)
    parser.add_argument("--check-seed", type=int, default=0, help="the realism check's --seed")
    parser.add_argument("--set", action="append", default=[], help="NAME=VALUE forced on every recipe")
    parser.add_argument("--json", type=Path)
    args = parser.parse_args()
    theta = load_preset(args.theta)
    forced = parse_settings(args.set)
    recipes = list(sample_recipes(theta, n=args.videos, seed=args.seed))
    chosen = draw_frames(((r.video_id, r.n_frames) for r in recipes), args.frames, args.check_seed)
    city = load_judges().segmenters["cityscapes"]
    lut = class_lut()[0]
    ctx = gl_context()
    tally = Tally()
    outdoor = [r for r in recipes if r.video_id in chosen and not ENVIRONMENT_SCENES[r.environment.name].indoor]
    for k, recipe in enumerate(outdoor):
        recipe = vary(recipe, theta, forced) if forced else recipe
        world = recipe.world
        where = ("all", f"environment={recipe.environment.name}", *conditions_of(world.weather, world.day_phase),
                 f"hour={int(world.clock_hour):02d}")  # fmt: skip
        trajectory = simulate(recipe, keep_state=False)
        last = recipe.n_frames - 1
        with inputs_renderer(scene_inputs(recipe, trajectory), ctx) as renderer:
            for f in chosen[recipe.video_id]:
                frame = renderer.render(f, trajectory.cam_to_world[f], trajectory.cam_to_world[min(f + 1, last)],
                                        trajectory.intrinsics)  # fmt: skip
                encoded = encode_frame(frame)
                rgb = np.ascontiguousarray(encoded["rgb"])
                judge_world(city.labels(rgb), lut[rgb_code(encoded["semantic"])], city.classes, tally,
                            recipe.video_id, where)  # fmt: skip
        print(f"\r{k + 1}/{len(outdoor)} videos", end="", file=sys.stderr, flush=True)
    print(file=sys.stderr)
    out: dict[str, dict[str, float]] = {}
    for group in sorted({key.rsplit("|", 1)[1] for key in tally.parts}):
        miou = _miou(tally, args.check_seed, group)
        if miou is None:
            continue
        row = {"miou": round(miou.value, 3), "low": round(miou.low, 3), "high": round(miou.high, 3),
               "videos": miou.videos}  # fmt: skip
        for key in sorted(tally.parts):
            if key.startswith("class_iou|cityscapes|") and key.endswith(f"|{group}"):
                row[key.split("|")[2]] = round(tally.figure(key, args.check_seed).value, 3)
        out[group] = row
        classes = " ".join(f"{c} {v:.2f}" for c, v in row.items() if c not in ("miou", "low", "high", "videos"))
        print(f"{group:26s} mIoU {row['miou']:.3f} ({row['low']:.2f}–{row['high']:.2f}, {row['videos']} videos)  "
              f"{classes}")  # fmt: skip
    if args.json:
        args.json.write_text(json.dumps({"forced": forced, "groups": out}, indent=1) + "\n")


if __name__ == "__main__":
    main()
