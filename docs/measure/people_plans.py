"""How planned people move (docs/experiments/motion.md): plans the first N recipes of (θ, seed),
without physics or pixels, and measures

- walks: how far off its recipe's heading each walking protagonist goes (degrees, its
  pelvis from the first frame to the last; the walks that go straight);
- background walkers: the median speed of a planted foot (its worse foot), and the
  fastest any body part moves in a frame (a walker set standing in one frame);
- partners walking with the protagonist: how much their pelvises' distance changes over
  the clip;
- `climb_stairs`: the deepest a sole goes into the floor or a tread;
- people walking into each other (`facing`): how near their chests come (the pelvises'
  closest distance less the two chests' radii; below zero, one walks into the other).

    .venv/bin/python docs/measure/people_plans.py [--theta phav-v1] [--recipes 1200] [--seed 0]
"""

from __future__ import annotations

import argparse
import math

import numpy as np

from phav_generator.motion.skeleton import BONE_INDEX, BONES, capsule_points, forward_kinematics
from phav_generator.physics.plan.background import background_people
from phav_generator.physics.plan.builder import PlanBuilder
from phav_generator.physics.plan.scene import plan_scene
from phav_generator.physics.plan.timestep import choose_substeps
from phav_generator.sampling import sample_recipes
from phav_spec.theta import load_preset

#: The catalogue's straight walks: their path has no turn, so their way is their heading.
STRAIGHT = ("walk_forward_01", "run_forward_01", "walk_hand_in_hand_01", "run_away_panic_01")
FEET = ("left_foot", "right_foot")


def heading_error(recipe, plan) -> float:
    """Degrees between the protagonist's recipe heading and the way its pelvis went."""
    root = plan.people[0].targets.root_pos
    way = root[-1, :2] - root[0, :2]
    off = math.degrees(math.atan2(way[1], way[0])) - recipe.protagonist.heading_deg
    return abs((off + 180.0) % 360.0 - 180.0)


def walker_feet(walker, fps: int) -> tuple[float, float]:
    """A background walker's worse foot's median planted speed (m/s), and the fastest any
    of its bodies moves in a frame (m/s)."""
    t = walker.targets
    bodies, _ = forward_kinematics(walker.dims, t.root_pos, t.root_quat, t.q)
    walking = np.abs(t.q).max(axis=1) > 0.0
    worse = 0.0
    for foot in FEET:
        z, xy = bodies[:, BONE_INDEX[foot], 2], bodies[:, BONE_INDEX[foot], :2]
        low = (z < z[walking].min() + 0.01) & walking if walking.any() else np.zeros(len(z), bool)
        stands = low[1:] & low[:-1]
        if stands.any():
            worse = max(worse, float(np.median(np.linalg.norm(np.diff(xy, axis=0), axis=1)[stands])) * fps)
    return worse, float(np.linalg.norm(np.diff(bodies, axis=0), axis=-1).max()) * fps


def stairs_depth(recipe, plan) -> float:
    """How deep (m) a sole of the protagonist goes into the floor or a built tread."""
    me, s = plan.people[0], plan.substeps
    pos, rot = forward_kinematics(me.dims, me.targets.root_pos[::s], me.targets.root_quat[::s], me.targets.q[::s])
    feet = [BONE_INDEX[f] for f in FEET]
    ends = np.concatenate(capsule_points(me.dims, pos, rot), axis=-2)[:, feet + [f + len(BONES) for f in feet]]
    top = np.full(ends.shape[:-1], recipe.protagonist.position[2])
    for box in (b for b in plan.boxes if b.pixel_class == "stairs"):
        c, s_ = math.cos(math.radians(box.yaw_deg)), math.sin(math.radians(box.yaw_deg))
        d = ends[..., :2] - np.array(box.center[:2])
        inside = (np.abs(d[..., 0] * c + d[..., 1] * s_) <= box.half_size[0]) & (
            np.abs(-d[..., 0] * s_ + d[..., 1] * c) <= box.half_size[1]
        )
        top = np.where(inside, np.maximum(top, box.center[2] + box.half_size[2]), top)
    return float(-(ends[..., 2] - me.dims.capsules[feet[0]].radius - top).min())


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--theta", default="phav-v1", help="preset name")
    parser.add_argument("--recipes", type=int, default=1200)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    heading, slide, fastest, drift, stairs, facing = [], [], [], [], [], []
    for recipe in sample_recipes(load_preset(args.theta), n=args.recipes, seed=args.seed):
        for walker in background_people(PlanBuilder(recipe, choose_substeps(recipe))):
            s, f = walker_feet(walker, recipe.video.fps)
            slide.append(s)
            fastest.append(f)
        walks = recipe.motion.base_motion in STRAIGHT
        placement = recipe.supporting_characters[0].placement if recipe.supporting_characters else None
        pair = placement is not None and placement != "facing"
        if not (walks or placement or recipe.action == "climb_stairs"):
            continue
        plan = plan_scene(recipe)
        if walks:
            heading.append(heading_error(recipe, plan))
        if pair:
            a, b = plan.people[0].targets.root_pos, plan.people[1].targets.root_pos
            apart = np.linalg.norm((a - b)[:, :2], axis=1)
            drift.append(abs(float(apart[-1] - apart[0])))
        if placement == "facing":
            a, b = plan.people[0], plan.people[1]
            apart = np.linalg.norm((a.targets.root_pos - b.targets.root_pos)[:, :2], axis=1)
            facing.append(float(apart.min()) - sum(p.dims.capsules[BONE_INDEX["chest"]].radius for p in (a, b)))
        if recipe.action == "climb_stairs":
            stairs.append(stairs_depth(recipe, plan))
    print(f"the first {args.recipes} recipes of {args.theta}, seed {args.seed}")
    rows = (
        ("straight walks: off their heading (deg)", heading),
        ("background walkers: planted foot (m/s)", slide),
        ("background walkers: fastest body (m/s)", fastest),
        ("partners: change of distance (m)", drift),
        ("climb_stairs: deepest sole (m)", stairs),
    )
    for name, values in rows:
        if values:
            p50, p90, top = np.percentile(values, [50, 90, 100])
            print(f"  {name:42s} n {len(values):4d}  median {p50:.3f}  90 % {p90:.3f}  max {top:.3f}")
    if facing:
        gaps = np.array(facing)
        print(
            f"  {'walking into each other: chests apart (m)':42s} n {len(gaps):4d}  min {gaps.min():.3f}  "
            f"median {np.median(gaps):.3f}  into each other {int((gaps < 0).sum())}  "
            f"within 0.5 m {int(((gaps >= 0) & (gaps < 0.5)).sum())}  never within 1 m {int((gaps >= 1).sum())}"
        )


if __name__ == "__main__":
    main()
