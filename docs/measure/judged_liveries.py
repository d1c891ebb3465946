"""The judges on our buses in the street, livery by livery: the frames of the urban and
suburban videos among the first N phav-v1 recipes of a seed that show a bus, each rendered
again with every livery of ``BUS_LIVERIES`` in turn (every other draw unchanged), and the
share of the bus's pixels each judge names `bus` (Cityscapes, and its `train`).

    .venv/bin/python docs/measure/judged_liveries.py [--seed 52] [--videos 700] [--min-px 2000]

A video counts when one of its frames, looked at every 15th, shows at least --min-px of bus;
it is judged at that frame and 10 frames either side (those showing 1,000 px or more).
"""

from __future__ import annotations

import argparse
import sys
from unittest import mock

import numpy as np

from phav_generator.physics.simulate import simulate
from phav_generator.render.context import gl_context
from phav_generator.render.modalities import encode_frame
from phav_generator.render.video import inputs_renderer, scene_inputs
from phav_generator.sampling import sample_recipes
from phav_generator.world import vehicles
from phav_spec.theta import load_preset
from phav_spec.vocab import PIXEL_CLASSES
from phav_validators.checks.scan import class_lut, rgb_code
from phav_validators.realism.judges import load_judges

#: The palette's liveries by name, in ``BUS_LIVERIES`` order.
LIVERY_NAMES = ("red", "yellow", "green", "white", "blue")
#: Frames looked at to find a video's bus, and the frames judged either side of its most.
SCAN_STEP, SIDE = 15, 10
#: The least bus (px) a judged frame shows.
MIN_JUDGED_PX = 1000


def _render(renderer, trajectory, f: int) -> dict[str, np.ndarray]:
    """Frame ``f`` as the dataset has it (the trajectory holds a pose past the last frame)."""
    frame = renderer.render(f, trajectory.cam_to_world[f], trajectory.cam_to_world[f + 1], trajectory.intrinsics)
    return encode_frame(frame)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seed", type=int, default=52)
    parser.add_argument("--videos", type=int, default=700)
    parser.add_argument("--min-px", type=int, default=2000)
    args = parser.parse_args()
    assert len(LIVERY_NAMES) == len(vehicles.BUS_LIVERIES)
    lut, bus = class_lut()[0], PIXEL_CLASSES["bus"].class_id
    ctx = gl_context()
    recipes = [r for r in sample_recipes(load_preset("phav-v1"), n=args.videos, seed=args.seed)
               if r.environment.name in ("urban", "middle")]  # fmt: skip
    shown = []  # (recipe, trajectory, frames)
    for k, recipe in enumerate(recipes):
        trajectory, last = simulate(recipe, keep_state=False), recipe.n_frames - 1
        with inputs_renderer(scene_inputs(recipe, trajectory), ctx) as renderer:
            counts = [(int((lut[rgb_code(_render(renderer, trajectory, f)["semantic"])] == bus).sum()), f)
                      for f in range(0, recipe.n_frames, SCAN_STEP)]  # fmt: skip
        most, f = max(counts)
        if most >= args.min_px:
            shown.append((recipe, trajectory, sorted({max(0, f - SIDE), f, min(last, f + SIDE)})))
        print(f"\r{k + 1}/{len(recipes)} videos looked at, {len(shown)} with a bus", end="", file=sys.stderr)
    print(file=sys.stderr)
    if not shown:  # nothing to judge: say so, not a row of NaNs per livery
        raise SystemExit(f"none of the first {args.videos} recipes' urban videos shows a bus; give more --videos")
    judges = load_judges().segmenters
    city, voc = judges["cityscapes"], judges["pascal_voc"]
    print(f"{len(shown)} videos: {', '.join(r.video_id for r, _, _ in shown)}\n")
    print("| livery | frames | bus px | Cityscapes `bus` | Cityscapes `train` | VOC `bus` |")
    print("| --- | ---: | ---: | ---: | ---: | ---: |")
    for name, livery in zip(LIVERY_NAMES, vehicles.BUS_LIVERIES, strict=True):
        frames_px = np.zeros(2, dtype=int)
        named = np.zeros(3, dtype=int)  # Cityscapes bus, train; VOC bus
        # Every draw of the bus kept, its livery whichever it draws (a measure, not the generator).
        with mock.patch.object(vehicles, "BUS_LIVERIES", (livery,) * len(vehicles.BUS_LIVERIES)):
            for recipe, trajectory, frames in shown:
                with inputs_renderer(scene_inputs(recipe, trajectory), ctx) as renderer:
                    for f in frames:
                        encoded = _render(renderer, trajectory, f)
                        ours = lut[rgb_code(encoded["semantic"])] == bus
                        if ours.sum() < MIN_JUDGED_PX:
                            continue
                        rgb = np.ascontiguousarray(encoded["rgb"])
                        said, voc_said = city.labels(rgb)[ours], voc.labels(rgb)[ours]
                        frames_px += (1, int(ours.sum()))
                        named += (int(np.isin(said, city.classes.answer_ids("bus")).sum()),
                                  int(np.isin(said, city.classes.answer_ids("train")).sum()),
                                  int(np.isin(voc_said, voc.classes.answer_ids("bus")).sum()))  # fmt: skip
        shares = " | ".join(f"{n / frames_px[1]:.2f}" for n in named)
        print(f"| {name} | {frames_px[0]} | {frames_px[1]} | {shares} |")


if __name__ == "__main__":
    main()
