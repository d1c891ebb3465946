"""How often the camera frames both people of `bump_into_each_other` (docs/framing.md): for
the first N such recipes of each seed, simulated, the share of every tenth frame whose
partner, and whose protagonist, has its pelvis and head inside the image. ``--pull``
sets how far towards the partner the spring camera's target is held
(``phav_generator.physics.plan.camera.PARTNER_PULL``; 0: on the protagonist alone).

    .venv/bin/python docs/measure/pair_framing.py --seeds 52,0,1 --clips 16 --pull 0
    .venv/bin/python docs/measure/pair_framing.py --seeds 52,0,1 --clips 16
"""

from __future__ import annotations

import argparse

import numpy as np

import phav_generator.physics.plan.camera as camera_plan
from phav_generator.motion.skeleton import BONE_INDEX
from phav_generator.physics.simulate import simulate
from phav_generator.render.camera import project
from phav_generator.sampling import RecipeSampler
from phav_spec.theta import load_preset


def in_frame(body_pos: np.ndarray, cam_to_world: np.ndarray, intrinsics, width: int, height: int) -> bool:
    """Whether a person's pelvis and head (world body origins) both project inside the image."""
    uv = project(body_pos[[BONE_INDEX["pelvis"], BONE_INDEX["head"]]], cam_to_world, intrinsics)
    return bool(np.all(np.isfinite(uv)) and np.all((uv >= 0) & (uv < (width, height))))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", default="52,0,1")
    parser.add_argument("--clips", type=int, default=16, help="bump_into_each_other recipes per seed")
    parser.add_argument("--pull", type=float, default=camera_plan.PARTNER_PULL)
    args = parser.parse_args()
    camera_plan.PARTNER_PULL = args.pull
    sampler = RecipeSampler(load_preset("phav-v1"))
    print(f"PARTNER_PULL {args.pull}")
    print("| seed | clips | partner in frame | protagonist in frame | clips never showing the partner |")
    print("| ---: | ---: | ---: | ---: | ---: |")
    for seed in (int(s) for s in args.seeds.split(",")):
        partner, protagonist = [], []
        index = 0
        while len(partner) < args.clips:
            recipe = sampler.sample(seed, index)
            index += 1
            if recipe.action != "bump_into_each_other":
                continue
            tr = simulate(recipe, keep_state=False)
            frames = range(0, recipe.n_frames, 10)
            size = (recipe.video.width, recipe.video.height)
            seen = [[in_frame(p.body_pos[f], tr.cam_to_world[f], tr.intrinsics, *size) for f in frames]
                    for p in (tr.person(1), tr.people[0])]  # fmt: skip
            partner.append(float(np.mean(seen[0])))
            protagonist.append(float(np.mean(seen[1])))
        print(f"| {seed} | {len(partner)} | {np.mean(partner):.2f} | {np.mean(protagonist):.2f} | "
              f"{sum(p == 0 for p in partner)} |", flush=True)  # fmt: skip


if __name__ == "__main__":
    main()
