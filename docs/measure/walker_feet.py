"""Where background walkers' feet stand (docs/physics.md): plans the walkers of the first N
recipes of (θ, seed), without physics or pixels, and measures per walker the worst frame's
height of both ankles over the surface under each foot (the higher under its heel or its
toes, ``SOLE_M`` ahead along its path, as the planner stands a foot; ``--heel``: under the
ankle only; an ankle joint stands ~10 cm over its sole), the deepest an ankle goes under
it, and the pelvis's largest rise or fall in a frame.

    .venv/bin/python docs/measure/walker_feet.py [--theta phav-v1] [--recipes 300] [--seed 0] [--heel]
"""

from __future__ import annotations

import argparse

import numpy as np

from phav_generator.motion.skeleton import forward_kinematics
from phav_generator.physics.plan.background import _ANKLES, SOLE_M, background_people
from phav_generator.physics.plan.builder import PlanBuilder
from phav_generator.physics.plan.timestep import choose_substeps
from phav_generator.sampling import sample_recipes
from phav_spec.scene import walkable_heights
from phav_spec.theta import load_preset


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--theta", default="phav-v1", help="preset name")
    parser.add_argument("--recipes", type=int, default=300)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--heel", action="store_true", help="the surface under the ankle only, not its toes")
    args = parser.parse_args()
    over, under, step, videos = [], [], [], 0
    for recipe in sample_recipes(load_preset(args.theta), n=args.recipes, seed=args.seed):
        if not recipe.background_actors:
            continue
        videos += 1
        actors = {a.person_id: a for a in recipe.background_actors}
        env = recipe.environment.name
        for walker in background_people(PlanBuilder(recipe, choose_substeps(recipe))):
            t = walker.targets
            bodies, _ = forward_kinematics(walker.dims, t.root_pos, t.root_quat, t.q)
            ankles = bodies[:, _ANKLES]
            reach = ankles[..., 2] + 0.05
            ground = walkable_heights(env, ankles[..., 0], ankles[..., 1], reach)
            if not args.heel:  # a foot whose toes stand on a terrace's edge stands on it
                actor = actors[walker.person_id]
                path = np.subtract(actor.destination, actor.start)[:2]
                along = path / max(float(np.linalg.norm(path)), 1e-9) * SOLE_M
                ground = np.maximum(ground, walkable_heights(env, ankles[..., 0] + along[0], ankles[..., 1] + along[1],
                                                             reach))  # fmt: skip
            height = ankles[..., 2] - ground
            over.append(float(height.min(axis=1).max()))
            under.append(float(-height.min()))
            step.append(float(np.abs(np.diff(t.root_pos[:, 2])).max()))
    print(f"{len(over)} walkers in {videos} videos of the first {args.recipes} of {args.theta}, seed {args.seed}")
    for name, values in (("both ankles over the ground (m)", over), ("an ankle under it (m)", under),
                         ("pelvis rise or fall a frame (m)", step)):  # fmt: skip
        p50, p90, p99, top = np.percentile(values, [50, 90, 99, 100])
        print(f"  {name:34s} median {p50:.3f}  90 % {p90:.3f}  99 % {p99:.3f}  max {top:.3f}")
    high, higher = sum(v > 0.15 for v in over), sum(v > 0.3 for v in over)
    print(f"  walkers with both ankles over 0.15 m: {high}, over 0.3 m: {higher}")


if __name__ == "__main__":
    main()
