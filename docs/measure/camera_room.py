"""How close a spring camera comes to the people it films (docs/framing.md): per video of the
first N recipes of (θ, seed), the camera's nearest approach to a body origin of the
protagonist or a supporting person, and the frames it spends within ``--within`` metres.

    .venv/bin/python docs/measure/camera_room.py [--theta phav-v1] [--videos 100] [--seed 52]

It prints the videos that come within ``--show`` metres and the total over every video
filmed by a spring (kite or close-up) camera.
"""

from __future__ import annotations

import argparse

import numpy as np

from phav_generator.physics.simulate import simulate
from phav_generator.sampling import sample_recipes
from phav_spec.theta import load_preset


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--theta", default="phav-v1", help="preset name")
    parser.add_argument("--videos", type=int, default=100)
    parser.add_argument("--seed", type=int, default=52)
    parser.add_argument("--within", type=float, default=0.5, help="metres counted as too close")
    parser.add_argument("--show", type=float, default=0.7, help="list videos that come this close")
    args = parser.parse_args()
    frames = close = videos = 0
    for recipe in sample_recipes(load_preset(args.theta), n=args.videos, seed=args.seed):
        if recipe.camera.springs is None:
            continue
        tr = simulate(recipe, keep_state=False)
        cams = tr.cam_to_world[:, :3, 3]
        near = np.min([np.linalg.norm(np.asarray(p.body_pos) - cams[:, None, :], axis=2).min(axis=1)
                       for p in tr.people if p.role in ("protagonist", "supporting")], axis=0)  # fmt: skip
        videos += 1
        frames += len(near)
        close += int((near < args.within).sum())
        if near.min() < args.show:
            print(f"{recipe.video_id} {recipe.action} in {recipe.environment.name}: nearest {near.min():.2f} m, "
                  f"{int((near < args.within).sum())} of {len(near)} frames within {args.within} m")  # fmt: skip
    print(f"{videos} videos with a spring camera: {close:,} of {frames:,} frames within {args.within} m of a body")


if __name__ == "__main__":
    main()
