"""The realism check's world figures without a dataset: the frames it would draw from the
first N recipes of (θ, seed), rendered one by one and judged (docs/realism-gap.md). The figures
are the check's own on the dataset those recipes make (same frames, same pixels, same
bootstrap), in minutes instead of a generation run; ``--set`` renders every recipe with a
condition forced (``phav vary``'s NAME=VALUE), the same scenes in other light.

    .venv/bin/python docs/measure/judged_frames.py [--videos 100] [--seed 52] [--frames 400] [--voc]
    .venv/bin/python docs/measure/judged_frames.py --set weather=fog --set day_phase=day --set clock_hour=13
    .venv/bin/python docs/measure/judged_frames.py --dump judged      # then judged_ceiling.py judged
    .venv/bin/python docs/measure/judged_frames.py --rescore judged   # the same frames, scored anew

It prints the Cityscapes mIoU and per-class IoU of each group (all, each weather, day
phase, clock hour and environment, clear or overcast daytime) over the outdoor frames; with
``--voc`` also the PASCAL VOC IoU of each of our classes it judges, over every frame.
"""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Iterator
from pathlib import Path

import numpy as np

from phav_generator.physics.simulate import simulate
from phav_generator.render.context import gl_context
from phav_generator.render.modalities import encode_frame
from phav_generator.render.video import inputs_renderer, scene_inputs
from phav_generator.sampling import sample_recipes
from phav_generator.vary import parse_settings, vary
from phav_spec.judge_classes import JUDGE_CLASSES
from phav_spec.scene import ENVIRONMENT_SCENES
from phav_spec.theta import load_preset
from phav_validators.checks.scan import class_lut, rgb_code
from phav_validators.realism.check import Tally, cityscapes_miou, conditions_of, draw_frames, judge_world, judged_groups
from phav_validators.realism.judges import load_judges

#: A dump's array of each judge's answers.
_DUMP_NAMES = {"said": "cityscapes", "voc": "pascal_voc"}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--theta", default="phav-v1", help="preset name")
    parser.add_argument("--videos", type=int, default=100)
    parser.add_argument("--seed", type=int, default=52, help="the dataset's seed")
    parser.add_argument("--frames", type=int, default=400)
    parser.add_argument("--check-seed", type=int, default=0, help="the realism check's --seed")
    parser.add_argument("--set", action="append", default=[], help="NAME=VALUE forced on every recipe")
    parser.add_argument("--voc", action="store_true", help="the PASCAL VOC judge too, on every frame (indoors too)")
    parser.add_argument("--json", type=Path)
    parser.add_argument("--dump", type=Path, help="folder for each judged frame's pixels, truth and answers (.npz)")
    parser.add_argument("--rescore", type=Path, help="score the frames a --dump wrote instead of rendering them")
    args = parser.parse_args()
    tally = Tally()
    frames = dumped(args.rescore) if args.rescore else _judged(args)
    voc = {c for ours in judged_groups("pascal_voc").values() for c in ours}  # our classes VOC judges
    for video, where, ours, answers in frames:
        for judge, said in answers.items():
            judge_world(said, ours, JUDGE_CLASSES[judge], tally, video, where)
    out: dict[str, dict[str, float]] = {}
    for group in sorted({key.rsplit("|", 1)[1] for key in tally.parts}):
        miou = cityscapes_miou(tally, args.check_seed, group)
        row = {} if miou is None else {"miou": round(miou.value, 3), "videos": miou.videos,
                                       **({} if miou.low is None else {"low": round(miou.low, 3),
                                                                       "high": round(miou.high, 3)})}  # fmt: skip
        for key in sorted(tally.present):
            judge, c = key.split("|")[1:3]
            if key.endswith(f"|{group}") and (key.startswith("class_iou|cityscapes|") or
                                              (key.startswith("iou|pascal_voc|") and c in voc)):  # fmt: skip
                row[c if judge == "cityscapes" else f"voc {c}"] = round(tally.figure(key, args.check_seed).value, 3)
        if not row:
            continue
        out[group] = row
        classes = " ".join(f"{c} {v:.2f}" for c, v in row.items() if c not in ("miou", "low", "high", "videos"))
        head = ""
        if miou is not None:
            spread = "one video" if miou.low is None else f"{miou.low:.2f}–{miou.high:.2f}, {miou.videos} videos"
            head = f"mIoU {miou.value:.3f} ({spread})"
        print(f"{group:26s} {head}  {classes}")
    if args.json:
        args.json.write_text(json.dumps({"forced": parse_settings(args.set), "groups": out}, indent=1) + "\n")


def _judged(args: argparse.Namespace) -> Iterator[tuple[str, tuple[str, ...], np.ndarray, dict[str, np.ndarray]]]:
    """Render the check's frames of the first recipes and judge them: (video, groups, our
    classes, each judge's answers) per frame, each written to ``args.dump`` if asked."""
    theta = load_preset(args.theta)
    forced = parse_settings(args.set)
    recipes = list(sample_recipes(theta, n=args.videos, seed=args.seed))
    chosen = draw_frames(((r.video_id, r.n_frames) for r in recipes), args.frames, args.check_seed)
    segmenters = load_judges().segmenters
    lut = class_lut()[0]
    ctx = gl_context()
    indoor = {r.video_id: ENVIRONMENT_SCENES[r.environment.name].indoor for r in recipes}
    shown = [r for r in recipes if r.video_id in chosen and (args.voc or not indoor[r.video_id])]
    for k, recipe in enumerate(shown):
        recipe = vary(recipe, theta, forced) if forced else recipe
        world = recipe.world
        where = ("all", f"environment={recipe.environment.name}", *conditions_of(world.weather, world.day_phase),
                 f"hour={int(world.clock_hour):02d}")  # fmt: skip
        judges = (*(() if indoor[recipe.video_id] else ("cityscapes",)), *(("pascal_voc",) if args.voc else ()))
        trajectory = simulate(recipe, keep_state=False)
        with inputs_renderer(scene_inputs(recipe, trajectory), ctx) as renderer:
            for f in chosen[recipe.video_id]:
                # The trajectory holds one camera pose past the last frame, as render_video reads it.
                frame = renderer.render(f, trajectory.cam_to_world[f], trajectory.cam_to_world[f + 1],
                                        trajectory.intrinsics)  # fmt: skip
                encoded = encode_frame(frame)
                rgb = np.ascontiguousarray(encoded["rgb"])
                ours = lut[rgb_code(encoded["semantic"])]
                answers = {n: segmenters[n].labels(rgb) for n in judges}
                if args.dump:
                    args.dump.mkdir(parents=True, exist_ok=True)
                    arrays = {n: answers[j] for n, j in _DUMP_NAMES.items() if j in answers}
                    np.savez_compressed(args.dump / f"{recipe.video_id}-{f:03d}.npz", rgb=rgb, ours=ours,
                                        where=np.array(where), **arrays)  # fmt: skip
                yield recipe.video_id, where, ours, answers
        print(f"\r{k + 1}/{len(shown)} videos", end="", file=sys.stderr, flush=True)
    print(file=sys.stderr)


def dump_files(folder: Path) -> list[Path]:
    """The frame files a ``--dump`` wrote in ``folder``, in order; a clear exit if none."""
    files = sorted(folder.glob("*.npz"))
    if not files:
        raise SystemExit(f"{folder}: no .npz frames (write them with judged_frames.py --dump {folder})")
    return files


def dumped(folder: Path) -> Iterator[tuple[str, tuple[str, ...], np.ndarray, dict[str, np.ndarray]]]:
    """The frames a ``--dump`` wrote, as ``_judged`` yields them (judged_ceiling.py reads them
    so too)."""
    for f in dump_files(folder):
        with np.load(f) as z:
            answers = {judge: z[name] for name, judge in _DUMP_NAMES.items() if name in z}
            yield f.stem.split("-")[0], tuple(str(g) for g in z["where"]), z["ours"], answers


if __name__ == "__main__":
    main()
