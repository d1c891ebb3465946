"""How much of the consistency check's flow error is the stored depth's centimetre rounding
(docs/validation.md): renders frames of one video of (θ, seed) and measures the static
pixels' flow against depth and the two camera poses, as the check does, once with the depth
as stored (centimetre codes) and once with the renderer's float depth.

    .venv/bin/python docs/measure/flow_depth_rounding.py [--video v000027] [--seed 52] [--frames 128:144]

It prints per frame the camera's speed and both mean end-point errors (px).
"""

from __future__ import annotations

import argparse

import numpy as np

from phav_generator.physics.simulate import simulate
from phav_generator.render.context import gl_context
from phav_generator.render.modalities import encode_frame
from phav_generator.render.video import inputs_renderer, scene_inputs
from phav_generator.sampling import sample_recipes
from phav_spec.encoding import DEPTH_MAX_CODE
from phav_spec.theta import load_preset
from phav_validators.checks.scan import class_lut, flow_against_depth


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--theta", default="phav-v1", help="preset name")
    parser.add_argument("--seed", type=int, default=52)
    parser.add_argument("--video", default="v000027")
    parser.add_argument("--frames", default="128:144", help="FIRST:END, frames rendered")
    args = parser.parse_args()
    first, end = (int(v) for v in args.frames.split(":"))
    index = int(args.video.removeprefix("v"))
    recipe = list(sample_recipes(load_preset(args.theta), n=index + 1, seed=args.seed))[index]
    trajectory = simulate(recipe, keep_state=False)
    static = class_lut()[2]
    fx, fy, cx, cy = trajectory.intrinsics

    def camera(f: int) -> dict:
        return {"fx": fx, "fy": fy, "cx": cx, "cy": cy, "cam_to_world": np.asarray(trajectory.cam_to_world[f]).ravel()}

    with inputs_renderer(scene_inputs(recipe, trajectory), gl_context()) as renderer:
        for f in range(first, min(end, recipe.n_frames - 1)):
            frame = renderer.render(f, trajectory.cam_to_world[f], trajectory.cam_to_world[f + 1],
                                    trajectory.intrinsics)  # fmt: skip
            encoded = encode_frame(frame)
            stored = encoded["depth"]
            exact = np.where(stored < DEPTH_MAX_CODE, frame.depth_m.astype(np.float64) * 100.0, DEPTH_MAX_CODE)
            errors = [flow_against_depth(d, encoded["flow"], frame.class_id, camera(f), camera(f + 1), static)[1]
                      for d in (stored, exact)]  # fmt: skip
            moved = np.asarray(trajectory.cam_to_world[f + 1])[:3, 3] - np.asarray(trajectory.cam_to_world[f])[:3, 3]
            speed = float(np.linalg.norm(moved)) * recipe.video.fps
            print(f"frame {f}: camera {speed:5.1f} m/s  EPE with stored depth {errors[0]:.3f} px, "
                  f"with float depth {errors[1]:.3f} px")  # fmt: skip


if __name__ == "__main__":
    main()
