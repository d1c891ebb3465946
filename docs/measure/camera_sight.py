"""What stands between the kite camera and its protagonist (docs/framing.md): per frame of
the first N kite videos of (θ, seed), as simulated, whether the line from the camera to the
protagonist's pelvis passes through a box (an environment's collider, an action's static
box, or a prop no one holds, at its pose in that frame: a car of `car_hit` as the bounds of
the solids it collides as, ``sight_boxes``; a bed of reeds counted apart, as the body shows
between its blades), whether the pelvis projects
outside the frame, and whether the camera trails more than ``--trail`` metres beyond its
rest length from the pelvis.

    .venv/bin/python docs/measure/camera_sight.py [--theta phav-v1] [--videos 100] [--seed 0]

It prints each video with a hidden, trailing or reed-screened frame (what hid it, and how
often), then the totals over the kite videos.
"""

from __future__ import annotations

import argparse
import json
import math
from collections import Counter
from pathlib import Path

import numpy as np

from phav_generator.motion.rotations import quat_to_matrix
from phav_generator.motion.skeleton import BONE_INDEX
from phav_generator.physics.plan.camera import Blocker, collider_blockers, sees, sight_boxes, stands_free
from phav_generator.physics.plan.scene import plan_scene
from phav_generator.physics.plan.scene_plan import StaticBox
from phav_generator.physics.simulate import simulate_plan
from phav_generator.render.camera import project
from phav_generator.sampling import RecipeSampler
from phav_spec.scene import ENVIRONMENT_SCENES, Collider, EnvironmentScene
from phav_spec.theta import load_preset

#: What a bed of reeds is called: the line of sight passes between its blades (the body
#: shows through them), so a frame it alone stands in is not counted hidden.
REEDS = "reeds"


def _name(env: EnvironmentScene, c: Collider | StaticBox) -> str:
    """What hides the pelvis, by the collider's class; a bed of reeds by that name."""
    return REEDS if isinstance(c, Collider) and c.pixel_class == "vegetation" and env.in_water(c) else c.pixel_class


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--theta", default="phav-v1", help="preset name")
    parser.add_argument("--videos", type=int, default=100, help="kite videos to measure")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--trail", type=float, default=2.0, help="metres beyond the rest length counted as trailing")
    parser.add_argument("--json", type=Path)
    args = parser.parse_args()
    sampler = RecipeSampler(load_preset(args.theta))
    rows = []
    index = 0
    while len(rows) < args.videos:
        recipe = sampler.sample(args.seed, index)
        index += 1
        if recipe.camera.kind != "kite":
            continue
        plan = plan_scene(recipe)
        tr = simulate_plan(plan, keep_state=False)
        env = ENVIRONMENT_SCENES[recipe.environment.name]
        statics = [(_name(env, c), blocker) for c in (*env.colliders, *plan.boxes) for blocker in collider_blockers(c)]
        loose = {p.name for p in plan.props if stands_free(p)}
        props = [t for t in tr.props if t.name in loose]
        planned = {p.name: p for p in plan.props}
        pelvis = tr.people[0].body_pos[:, BONE_INDEX["pelvis"]]
        cams = tr.cam_to_world[:, :3, 3]
        rest = math.dist(plan.camera_start, plan.camera_target)
        hid: Counter[str] = Counter()
        through = 0
        frames = recipe.n_frames
        for f in range(frames):
            boxes = list(statics)
            for t in props:
                rot = quat_to_matrix(t.quat[f])
                boxes += [(t.name, Blocker.of(t.pos[f] + rot @ c, h, rot)) for c, h in sight_boxes(planned[t.name])]
            between = [name for name, box in boxes if not sees(cams[f], pelvis[f], [box])]
            solid = [name for name in between if name != REEDS]
            if solid:
                hid[solid[0]] += 1
            elif between:
                through += 1
        trailing = int(np.sum(np.linalg.norm(cams[:frames] - pelvis[:frames], axis=1) > rest + args.trail))
        uv = np.array([project(pelvis[f], tr.cam_to_world[f], tr.intrinsics) for f in range(frames)])
        inside = (uv[:, 0] >= 0) & (uv[:, 0] < recipe.video.width) & (uv[:, 1] >= 0) & (uv[:, 1] < recipe.video.height)
        outside = int(np.sum(~inside))  # NaN (behind the camera) compares false: outside
        rows.append({"video": recipe.video_id, "action": recipe.action, "environment": recipe.environment.name,
                     "frames": frames, "hidden": dict(sorted(hid.items())), "through_reeds": through,
                     "outside": outside, "trailing": trailing})  # fmt: skip
        if hid or through or trailing or outside:
            print(f"{recipe.video_id} {recipe.action} in {recipe.environment.name}: hidden in {sum(hid.values())} "
                  f"of {frames} frames {dict(sorted(hid.items()))}, through reeds in {through}, outside the frame "
                  f"in {outside}, trailing in {trailing}")  # fmt: skip
    total = sum(r["frames"] for r in rows)
    hidden = sum(sum(r["hidden"].values()) for r in rows)
    trailing, outside = sum(r["trailing"] for r in rows), sum(r["outside"] for r in rows)
    hid_in, trail_in = sum(bool(r["hidden"]) for r in rows), sum(r["trailing"] > 0 for r in rows)
    out_in = sum(r["outside"] > 0 for r in rows)
    through = sum(r["through_reeds"] for r in rows)
    print(f"{len(rows)} kite videos, {total:,} frames: the pelvis hidden in {hidden:,} ({hidden / total:.2%}, "
          f"{hid_in} videos), outside the frame in {outside:,} ({outside / total:.2%}, {out_in} videos); the "
          f"camera trailing > {args.trail} m beyond its rest length in {trailing:,} ({trailing / total:.2%}, "
          f"{trail_in} videos); seen only through a reed bed in {through:,} ({through / total:.2%})")  # fmt: skip
    if args.json:
        args.json.write_text(json.dumps(rows, indent=1), encoding="utf-8")


if __name__ == "__main__":
    main()
