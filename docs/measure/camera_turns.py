"""How often a camera's start is turned for its view (docs/framing.md): over the first N
recipes of (θ, seed), planned without physics, the kite and indoor starts, those that
something hides some of the protagonist's planned path from (blocked), how many of those
starts' path points are hidden before the turn and after it.

    .venv/bin/python docs/measure/camera_turns.py [--theta phav-v1] [--recipes 400] [--seed 0]

The start before the turn is the one cleared of the geometry (lifted or slid); after, the
plan's (``clear_camera_start``'s answer, the last one a plan asks for).
"""

from __future__ import annotations

import argparse

import numpy as np

import phav_generator.physics.plan.camera as camera
import phav_generator.physics.plan.scene as scene
from phav_generator.sampling import sample_recipes
from phav_spec.scene import ENVIRONMENT_SCENES
from phav_spec.theta import load_preset


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--theta", default="phav-v1", help="preset name")
    parser.add_argument("--recipes", type=int, default=400)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    seen: dict[str, tuple[str, int, int, int]] = {}  # video → (kind, points, hidden before, after)
    plain = camera.clear_camera_start

    def watched(recipe, clearance=0.25, *, shift=None, blockers=(), anchors=(), keep_out=()):
        out = plain(recipe, clearance, shift=shift, blockers=blockers, anchors=anchors, keep_out=keep_out)
        env = ENVIRONMENT_SCENES[recipe.environment.name]
        offset = np.zeros(3) if shift is None else np.asarray(shift, dtype=np.float64)
        start, target = np.array(recipe.camera.position) + offset, np.array(recipe.camera.target) + offset
        cleared = camera._cleared(env.colliders, float(env.ground_z), start, target, clearance)
        before, after = camera.hidden(cleared, anchors, blockers), camera.hidden(out, anchors, blockers)
        seen[recipe.video_id] = (recipe.camera.kind, len(anchors), before, after)
        return out

    scene.clear_camera_start = watched  # the name plan_scene calls
    for recipe in sample_recipes(load_preset(args.theta), n=args.recipes, seed=args.seed):
        scene.plan_scene(recipe)
    for kind in ("kite", "indoors"):
        rows = [v for v in seen.values() if v[0] == kind]
        blocked = [v for v in rows if v[2] > 0]
        print(f"{kind}: {len(rows)} starts, {len(blocked)} blocked; their {sum(v[1] for v in blocked)} path points: "
              f"{sum(v[2] for v in blocked)} hidden before the turn, {sum(v[3] for v in blocked)} after")  # fmt: skip


if __name__ == "__main__":
    main()
