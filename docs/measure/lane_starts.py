"""Where `car_hit`'s camera starts against the car's lane (docs/physics.md, docs/framing.md).

Plans the `car_hit` recipes among the first N of (θ, seed) and counts the camera starts,
as sampled and put on the protagonist's first pose, that stand in the wide lane (the car's
way as wide as the car and ``LANE_MARGIN_M`` more each side), the planned starts still in
it (those kept out of the narrow lane, ``LANE_MARGIN_MIN_M``, instead), any planned start
in the narrow lane, and the spring cameras walled off from the car's way.

    .venv/bin/python docs/measure/lane_starts.py [--theta phav-v1] [--recipes 1400] [--seed 0]
"""

from __future__ import annotations

import argparse

import numpy as np

from phav_generator.physics.plan.camera import LANE_MARGIN_M, LANE_MARGIN_MIN_M, driven_lanes
from phav_generator.physics.plan.scene import plan_scene
from phav_generator.sampling import sample_recipes
from phav_spec.theta import load_preset


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--theta", default="phav-v1", help="preset name")
    parser.add_argument("--recipes", type=int, default=1400)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    recipes = [r for r in sample_recipes(load_preset(args.theta), n=args.recipes, seed=args.seed)
               if r.action == "car_hit"]  # fmt: skip
    sampled_in = planned_wide = planned_narrow = walled = 0
    for recipe in recipes:
        plan = plan_scene(recipe)
        target = recipe.camera.target if plan.camera_target is None else plan.camera_target
        sampled = np.add(recipe.camera.position, np.subtract(target, recipe.camera.target))
        wide, narrow = driven_lanes(plan.props), driven_lanes(plan.props, LANE_MARGIN_MIN_M)
        sampled_in += any(lane.holds(sampled) for lane in wide)
        planned_wide += any(lane.holds(plan.camera_start) for lane in wide)
        planned_narrow += any(lane.holds(plan.camera_start) for lane in narrow)
        walled += bool(plan.camera_walls)
    print(f"{len(recipes)} car_hit recipes among the first {args.recipes} of {args.theta}, seed {args.seed}")
    print(f"  sampled starts in the wide lane ({LANE_MARGIN_M:g} m): {sampled_in}")
    print(f"  planned starts still in it, kept out of the narrow one ({LANE_MARGIN_MIN_M:g} m): {planned_wide}")
    print(f"  planned starts in the narrow lane: {planned_narrow}")
    print(f"  spring cameras walled off from the car's way: {walled}")


if __name__ == "__main__":
    main()
