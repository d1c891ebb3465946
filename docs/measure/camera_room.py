"""How close a spring camera comes to people (docs/framing.md): per video of the first N
recipes of (θ, seed), the camera's nearest approach to a body origin of the protagonist or
a supporting person, and the frames it spends within ``--within`` metres; the same for the
background walkers apart.

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
    frames = videos = 0
    close = {"filmed": 0, "background": 0}
    for recipe in sample_recipes(load_preset(args.theta), n=args.videos, seed=args.seed):
        if recipe.camera.springs is None:
            continue
        tr = simulate(recipe, keep_state=False)
        cams = tr.cam_to_world[:, :3, 3]
        videos += 1
        frames += len(cams)
        for who in close:
            bodies = [p.body_pos for p in tr.people if (p.role == "background") == (who == "background")]
            if not bodies:
                continue
            each = [np.linalg.norm(np.asarray(b) - cams[:, None, :], axis=2).min(axis=1) for b in bodies]
            near = np.min(each, axis=0)
            n = int((near < args.within).sum())
            close[who] += n
            if near.min() < args.show:
                print(f"{recipe.video_id} {recipe.action} in {recipe.environment.name}, {who} people: nearest "
                      f"{near.min():.2f} m, {n} of {len(near)} frames within {args.within} m")  # fmt: skip
    print(f"{videos} videos with a spring camera, {frames:,} frames: within {args.within} m of a body origin "
          f"of the protagonist or a supporting person in {close['filmed']:,}, of a background walker in "
          f"{close['background']:,}")  # fmt: skip


if __name__ == "__main__":
    main()
