"""Where a driven prop goes: the car of `car_hit` or a pushed load, through what it should not (docs/physics.md).

Simulates the first N recipes of a θ of one action (phav-v1's, its action weights set to
`car_hit` or `push` alone) and, per frame, tests the driven prop's box (45 points over its
volume, turned as it is) against the environment's colliders (the failures check's
``BoxSet``, a parked car as its hulls), and the gap under it against the one it started
with over the ground there (``support_height``). Prints per video any frames inside a
collider or off its ground and how it moved (the car: whether it touched the protagonist,
at what speed, and whether it started under half its top speed; a load: how far it went,
and whether its pusher halted behind it), then the counts over all. A pushed door is no driven prop.

    python docs/measure/driven_way.py [--action car_hit] [--recipes 60] [--seed 7]
"""

from __future__ import annotations

import argparse

import mujoco
import numpy as np
import yaml

from phav_generator.physics.plan.scene import plan_scene
from phav_generator.physics.simulate import simulate_plan
from phav_generator.sampling import sample_recipes
from phav_spec.scene import support_height
from phav_spec.theta import PRESETS_DIR, Theta, parse_theta
from phav_validators.checks.failures import boxes

#: The driven prop of each action.
DRIVEN = {"car_hit": ("car",), "push": ("box", "shopping_cart")}
#: Where the 45 points sit in the prop's box, as fractions of its half extents.
GRID = np.array([[x, y, z] for x in (-1, -0.5, 0, 0.5, 1) for y in (-1, 0, 1) for z in (-0.7, 0, 1)])
#: A point this deep (m) inside a collider, or a gap under the prop this far off its start's, counts.
TOLERANCE_M = 0.05


def action_theta(action: str) -> Theta:
    """phav-v1 with its action weights on ``action`` alone (as physics.md's `sed` makes it)."""
    data = yaml.safe_load((PRESETS_DIR / "phav-v1.yaml").read_text())
    return parse_theta({**data, "theta_a": {action: 1}}, source=f"phav-v1, {action} only")


def measure(recipe) -> dict[str, object] | None:
    """One video: the frames whose driven prop is inside a collider or off its ground, how it
    moved; None where the action drives none (a pushed door)."""
    plan = plan_scene(recipe)
    driven = next((p for p in plan.props if p.path is not None and p.name in DRIVEN[recipe.action]), None)
    if driven is None:
        return None
    trajectory = simulate_plan(plan, keep_state=False)
    prop = next(t for t in trajectory.props if t.name == driven.name)
    env = recipe.environment.name
    half = np.asarray(driven.size)
    rot = np.empty(9)
    points = []
    for pos, quat in zip(prop.pos, prop.quat, strict=True):
        mujoco.mju_quat2Mat(rot, np.asarray(quat, dtype=np.float64))
        points.append(pos + (GRID * half) @ rot.reshape(3, 3).T)
    depth, which = boxes(env).depth_inside(np.array(points))
    inside = depth.max(axis=1) > TOLERANCE_M
    bottom = prop.pos[:, 2] - half[2]
    ground = np.array([support_height(env, float(x), float(y), reference_z=float(z))
                       for (x, y, _), z in zip(prop.pos, bottom, strict=True)])  # fmt: skip
    gap = bottom - ground
    off = np.abs(gap - gap[0]) > TOLERANCE_M
    speed = np.linalg.norm(np.diff(prop.pos[:, :2], axis=0), axis=1) * recipe.video.fps
    first = int(np.flatnonzero(inside)[0]) if inside.any() else -1
    row: dict[str, object] = {
        "inside": int(inside.sum()),
        "what": boxes(env).colliders[int(which[first].max())].pixel_class if first >= 0 else "",
        "off_ground": int(off.sum()),
        "travel": float(np.linalg.norm(prop.pos[-1, :2] - prop.pos[0, :2])),
    }
    if recipe.action == "car_hit":
        touched = np.flatnonzero(trajectory.contacts["car_protagonist"])
        row["touch_speed"] = float(speed[max(int(touched[0]) - 1, 0)]) if touched.size else float("nan")
        row["from_rest"] = bool(speed[0] < 0.5 * speed.max())
    else:
        # A halted pusher's planned pelvis stands still at the end (a walking one moves cm in 0.1 s).
        planned = plan.people[0].targets.root_pos
        row["halted"] = bool(np.array_equal(planned[-1], planned[-1 - plan.substeps * 3]))
    return row


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--action", choices=sorted(DRIVEN), default="car_hit")
    ap.add_argument("--recipes", type=int, default=60)
    ap.add_argument("--seed", type=int, default=7)
    args = ap.parse_args()
    rows = []
    for recipe in sample_recipes(action_theta(args.action), n=args.recipes, seed=args.seed):
        m = measure(recipe)
        if m is None:
            print(f"{recipe.video_id} {recipe.environment.name:7s} a door: nothing driven", flush=True)
            continue
        rows.append(m)
        notes = []
        if m["inside"]:
            notes.append(f"inside a {m['what']} in {m['inside']} frames")
        if m["off_ground"]:
            notes.append(f"off its ground in {m['off_ground']} frames")
        if args.action == "car_hit":
            notes.append("no touch" if np.isnan(m["touch_speed"]) else f"touches at {m['touch_speed']:.1f} m/s")
            if m["from_rest"]:
                notes.append("starts under half its speed")
        else:
            notes.append(f"pushed {m['travel']:.2f} m" + (", the pusher halted" if m["halted"] else ""))
        print(f"{recipe.video_id} {recipe.environment.name:7s} " + "; ".join(notes), flush=True)
    n = len(rows)
    what = "car" if args.action == "car_hit" else "load"
    print(f"\n{n} {args.action} videos with a driven {what} (seed {args.seed}):")
    print(f"  the {what} inside a collider: {sum(r['inside'] > 0 for r in rows)} videos, "
          f"{sum(r['inside'] for r in rows)} frames")  # fmt: skip
    print(f"  off its ground: {sum(r['off_ground'] > 0 for r in rows)} videos")
    if args.action == "car_hit":
        print(f"  no touch: {sum(np.isnan(r['touch_speed']) for r in rows)} videos")
        print(f"  starting under half its speed: {sum(r['from_rest'] for r in rows)} videos")
    else:
        print(f"  the pusher halted: {sum(r['halted'] for r in rows)} videos")


if __name__ == "__main__":
    main()
