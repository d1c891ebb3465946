"""The skinned meshes against the world over many clips: how deep any simulated person's
mesh goes into the ground or a box prop, and how far standing soles are from the floor.

Simulation only (no rendering). For the first N recipes of a θ and seed:

    .venv/bin/python docs/measure/contact.py phav-v1-short 100 3
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from phav_generator.physics.simulate import simulate
from phav_generator.render.contact import measure_contact
from phav_generator.sampling import sample_recipes
from phav_spec.theta import load_theta


def main(theta: str, n: int, seed: int) -> None:
    start = time.perf_counter()
    depths, soles, worst = [], [], []
    for recipe in sample_recipes(load_theta(theta), n=n, seed=seed):
        trajectory = simulate(recipe, keep_state=False)
        c = measure_contact(recipe, trajectory)
        depths.append(c.depth_m.reshape(-1))
        soles.append(c.standing_sole_m)
        worst.append((float(c.depth_m.max(initial=0.0)), recipe.video_id, recipe.action))
    d, s = np.concatenate(depths), np.concatenate(soles)
    print(f"{theta}, seed {seed}, {n} videos, {len(d)} person-frames, {len(s)} standing-foot frames, "
          f"{time.perf_counter() - start:.0f} s")  # fmt: skip
    print("| measure | p50 | p95 | p99 | max | share within 2 cm |")
    print("| --- | ---: | ---: | ---: | ---: | ---: |")
    for name, v in (("mesh depth into ground or prop (cm)", d), ("standing sole above floor (cm)", s)):
        p = np.percentile(v, [50, 95, 99]) * 100
        print(f"| {name} | {p[0]:.1f} | {p[1]:.1f} | {p[2]:.1f} | {100 * np.abs(v).max():.1f} | "
              f"{100 * np.mean(np.abs(v) < 0.02):.1f} % |")  # fmt: skip
    print("deepest:", sorted(worst, reverse=True)[:5])


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("theta", help="preset name or θ file, e.g. phav-v1-short")
    parser.add_argument("n", type=int, help="the first N recipes")
    parser.add_argument("seed", type=int, help="the dataset's seed")
    args = parser.parse_args()
    main(args.theta, args.n, args.seed)
