"""Car IoU of both judges on `car_hit` videos, with the camera's lane margin as given
(docs/realism-gap.md): K evenly spaced frames of each of the first N `car_hit` recipes of
(θ, seed), rendered and judged without writing a dataset.

    .venv/bin/python docs/measure/car_hit_iou.py [--videos 12] [--skip 0] [--frames 8] [--margin 2.5]

``--margin`` sets ``LANE_MARGIN_M``, how far the camera keeps from the car's way (the
narrower fallback stays 0.5 m); ``--skip`` passes over the first recipes (another set to
check a change on). It prints each video's car pixels and IoUs, then the pooled
IoU, recall and precision of each judge.
"""

from __future__ import annotations

import argparse

import numpy as np

import phav_generator.physics.plan.camera as camera
from phav_generator.physics.simulate import simulate
from phav_generator.render.context import gl_context
from phav_generator.render.modalities import encode_frame
from phav_generator.render.video import inputs_renderer, scene_inputs
from phav_generator.sampling import sample_recipes
from phav_spec.judge_classes import JUDGE_CLASSES
from phav_spec.theta import load_preset
from phav_spec.vocab import PIXEL_CLASSES
from phav_validators.checks.scan import class_lut, rgb_code
from phav_validators.realism.judges import load_judges


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--theta", default="phav-v1", help="preset name")
    parser.add_argument("--seed", type=int, default=52)
    parser.add_argument("--videos", type=int, default=12)
    parser.add_argument("--skip", type=int, default=0, help="car_hit recipes passed over first")
    parser.add_argument("--frames", type=int, default=8)
    parser.add_argument("--margin", type=float, default=camera.LANE_MARGIN_M)
    args = parser.parse_args()
    camera.LANE_MARGIN_M = args.margin  # read by driven_lanes at each call
    drawn = sample_recipes(load_preset(args.theta), n=300 * (args.skip + args.videos), seed=args.seed)
    recipes = [r for r in drawn if r.action == "car_hit"][args.skip : args.skip + args.videos]
    segmenters, lut, ctx = load_judges().segmenters, class_lut()[0], gl_context()
    car = list(PIXEL_CLASSES).index("car")
    judged = {name: JUDGE_CLASSES[name].answer_ids(JUDGE_CLASSES[name].judged_as["car"]) for name in segmenters}
    total = {name: np.zeros(3, dtype=np.int64) for name in segmenters}  # both, ours, theirs
    for recipe in recipes:
        trajectory = simulate(recipe, keep_state=False)
        mine = {name: np.zeros(3, dtype=np.int64) for name in segmenters}
        with inputs_renderer(scene_inputs(recipe, trajectory), ctx) as renderer:
            for f in np.linspace(0, recipe.n_frames - 1, args.frames).round().astype(int):
                frame = renderer.render(f, trajectory.cam_to_world[f], trajectory.cam_to_world[f + 1],
                                        trajectory.intrinsics)  # fmt: skip
                encoded = encode_frame(frame)
                ours = lut[rgb_code(encoded["semantic"])] == car
                for name, judge in segmenters.items():
                    said = np.isin(judge.labels(np.ascontiguousarray(encoded["rgb"])), judged[name])
                    mine[name] += [(ours & said).sum(), ours.sum(), said.sum()]
        for name in segmenters:
            total[name] += mine[name]
        ious = "  ".join(f"{n} {_iou(m):.2f}" for n, m in mine.items())
        print(f"{recipe.video_id} {recipe.environment.name:7s} car px {mine['cityscapes'][1]:7d}  {ious}", flush=True)
    for name, (both, ours, theirs) in total.items():
        print(f"{name}: IoU {_iou(total[name]):.3f}  recall {both / max(ours, 1):.3f}  "
              f"precision {both / max(theirs, 1):.3f}  (margin {args.margin:g} m)")  # fmt: skip


def _iou(counts: np.ndarray) -> float:
    both, ours, theirs = (int(v) for v in counts)
    return both / max(ours + theirs - both, 1)


if __name__ == "__main__":
    main()
