"""How fast a car hit throws the protagonist's joints (docs/validation.md's speed limits).

Simulates the first N `car_hit` recipes of (θ, seed) and takes, per clip, the fastest joint
between frames while the pins hold the body and once the car's touch has let them go.

    .venv/bin/python docs/measure/hit_speeds.py [--theta phav-v1] [--videos 40] [--seed 52]

It prints each clip's two speeds (m/s), then their median, 90th percentile and maximum.
"""

from __future__ import annotations

import argparse

import numpy as np

from phav_generator.motion.skeleton import JOINT_BODIES
from phav_generator.physics.simulate import simulate
from phav_generator.sampling import sample_recipes
from phav_spec.theta import load_preset


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--theta", default="phav-v1", help="preset name")
    parser.add_argument("--videos", type=int, default=40)
    parser.add_argument("--seed", type=int, default=52)
    args = parser.parse_args()
    drawn = sample_recipes(load_preset(args.theta), n=100 * args.videos, seed=args.seed)
    recipes = [r for r in drawn if r.action == "car_hit"][: args.videos]
    held, thrown = [], []
    for recipe in recipes:
        n = recipe.n_frames
        person = next(p for p in simulate(recipe, keep_state=False).people if p.role == "protagonist")
        joints, pinned = person.body_pos[:n, list(JOINT_BODIES)], person.pin[:n] >= 0.5
        speed = np.linalg.norm(np.diff(joints, axis=0), axis=-1).max(axis=1) * recipe.video.fps
        both = pinned[:-1] & pinned[1:]
        held.append(float(speed[both].max(initial=0.0)))
        thrown.append(float(speed[~both].max(initial=0.0)))
        print(f"{recipe.video_id}  held {held[-1]:5.1f}  thrown {thrown[-1]:5.1f}", flush=True)
    for name, values in (("held", held), ("thrown", thrown)):
        p50, p90, top = np.percentile(values, [50, 90, 100])
        print(f"{name:6s} {len(values)} clips: median {p50:.1f}, 90th percentile {p90:.1f}, max {top:.1f} m/s")


if __name__ == "__main__":
    main()
