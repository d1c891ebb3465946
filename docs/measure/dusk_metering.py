"""Dusk videos as the camera meters them and at the base exposure, the middle frame each,
side by side (docs/rendering.md), with the mean luma of each frame.

    .venv/bin/python docs/measure/dusk_metering.py OUT.jpg [--videos 4] [--seed 52]

The recipes are the first outdoor dusk recipes of phav-v1 at the seed.
"""

from __future__ import annotations

import argparse
import dataclasses
from pathlib import Path

import cv2
import numpy as np

from phav_generator.physics.simulate import simulate
from phav_generator.render.context import gl_context
from phav_generator.render.lighting import EXPOSURE
from phav_generator.render.modalities import encode_frame
from phav_generator.render.video import inputs_renderer, scene_inputs
from phav_generator.sampling import sample_recipes
from phav_spec.scene import ENVIRONMENT_SCENES
from phav_spec.theta import load_preset

_LUMA = np.array([0.2126, 0.7152, 0.0722])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", type=Path)
    parser.add_argument("--videos", type=int, default=4)
    parser.add_argument("--seed", type=int, default=52)
    args = parser.parse_args()
    recipes = [r for r in sample_recipes(load_preset(), n=200, seed=args.seed)
               if r.world.day_phase == "dusk" and not ENVIRONMENT_SCENES[r.environment.name].indoor]  # fmt: skip
    ctx = gl_context()
    rows = []
    for recipe in recipes[: args.videos]:
        trajectory = simulate(recipe, keep_state=False)
        middle = (recipe.n_frames - 1) // 2
        s = scene_inputs(recipe, trajectory)
        row = []
        for exposure in (EXPOSURE, s.lighting.exposure):
            metered = dataclasses.replace(s, lighting=dataclasses.replace(s.lighting, exposure=exposure))
            with inputs_renderer(metered, ctx) as renderer:
                frame = renderer.render(middle, trajectory.cam_to_world[middle], trajectory.cam_to_world[middle + 1],
                                        trajectory.intrinsics)  # fmt: skip
            rgb = np.ascontiguousarray(encode_frame(frame)["rgb"])
            luma = float((rgb @ _LUMA).mean())
            label = f"{recipe.video_id} {recipe.environment.name} {recipe.world.weather} " + (
                f"{recipe.world.clock_hour:.1f} h, exposure {exposure / EXPOSURE:.1f}x, luma {luma:.0f}"
            )
            print(label)
            cv2.putText(rgb, label, (4, 14), cv2.FONT_HERSHEY_SIMPLEX, 0.33, (255, 255, 255), 1, cv2.LINE_AA)
            row.append(rgb)
        rows.append(np.concatenate(row, axis=1))
    cv2.imwrite(str(args.out), np.concatenate(rows, axis=0)[..., ::-1], [cv2.IMWRITE_JPEG_QUALITY, 85])


if __name__ == "__main__":
    main()
