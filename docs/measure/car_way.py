"""Where the car of `car_hit` drives: through what it should not, and whether it hits (docs/physics.md).

Simulates the first N recipes of a θ of only `car_hit` (phav-v1's, its action weights set to
`car_hit` alone) and, per frame, tests the car's box (45 points over its volume, turned as
it is) against the environment's colliders (the failures check's ``BoxSet``, a parked car
as its hulls), and its wheels' height against the ground under its centre
(``support_height``). Prints per video any frames inside a collider or off its ground,
whether the car touched the protagonist and at what speed, and whether it started under
half its top speed (from a standstill or a roll), then the counts over all.

    python docs/measure/car_way.py [--recipes 60] [--seed 7]
"""

from __future__ import annotations

import argparse

import mujoco
import numpy as np
import yaml

from phav_generator.physics.plan.car_hit import CAR_CLEARANCE_M
from phav_generator.physics.simulate import simulate
from phav_generator.sampling import sample_recipes
from phav_spec.scene import support_height
from phav_spec.theta import PRESETS_DIR, Theta, parse_theta
from phav_validators.checks.failures import boxes

#: The car's box (half extents, m) and where its 45 points sit, as fractions of them.
HALF = np.array([2.1, 0.9, 0.7])
GRID = np.array([[x, y, z] for x in (-1, -0.5, 0, 0.5, 1) for y in (-1, 0, 1) for z in (-0.7, 0, 1)]) * HALF
#: A point this deep (m) inside a collider, or wheels this far off the ground, counts.
TOLERANCE_M = 0.05


def car_hit_theta() -> Theta:
    """phav-v1 with its action weights on `car_hit` alone (as physics.md's `sed` makes it)."""
    data = yaml.safe_load((PRESETS_DIR / "phav-v1.yaml").read_text())
    return parse_theta({**data, "theta_a": {"car_hit": 1}}, source="phav-v1, car_hit only")


def measure(recipe) -> dict[str, object]:
    """One video: the frames whose car is inside a collider or off its ground, its touch."""
    trajectory = simulate(recipe, keep_state=False)
    car = next(t for t in trajectory.props if t.name == "car")
    env = recipe.environment.name
    rot = np.empty(9)
    points = []
    for pos, quat in zip(car.pos, car.quat, strict=True):
        mujoco.mju_quat2Mat(rot, np.asarray(quat, dtype=np.float64))
        points.append(pos + GRID @ rot.reshape(3, 3).T)
    depth, which = boxes(env).depth_inside(np.array(points))
    inside = depth.max(axis=1) > TOLERANCE_M
    wheels = car.pos[:, 2] - HALF[2] - CAR_CLEARANCE_M
    ground = np.array([support_height(env, float(x), float(y), reference_z=float(w))
                       for (x, y, _), w in zip(car.pos, wheels, strict=True)])  # fmt: skip
    off = np.abs(wheels - ground) > TOLERANCE_M
    speed = np.linalg.norm(np.diff(car.pos[:, :2], axis=0), axis=1) * recipe.video.fps
    touched = np.flatnonzero(trajectory.contacts["car_protagonist"])
    first = int(np.flatnonzero(inside)[0]) if inside.any() else -1
    return {
        "inside": int(inside.sum()),
        "what": boxes(env).colliders[int(which[first].max())].pixel_class if first >= 0 else "",
        "off_ground": int(off.sum()),
        "touch_speed": float(speed[max(int(touched[0]) - 1, 0)]) if touched.size else float("nan"),
        "from_rest": bool(speed[0] < 0.5 * speed.max()),
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--recipes", type=int, default=60)
    ap.add_argument("--seed", type=int, default=7)
    args = ap.parse_args()
    rows = []
    for recipe in sample_recipes(car_hit_theta(), n=args.recipes, seed=args.seed):
        m = measure(recipe)
        rows.append(m)
        notes = []
        if m["inside"]:
            notes.append(f"inside a {m['what']} in {m['inside']} frames")
        if m["off_ground"]:
            notes.append(f"off its ground in {m['off_ground']} frames")
        notes.append("no touch" if np.isnan(m["touch_speed"]) else f"touches at {m['touch_speed']:.1f} m/s")
        if m["from_rest"]:
            notes.append("starts under half its speed")
        print(f"{recipe.video_id} {recipe.environment.name:7s} " + "; ".join(notes), flush=True)
    n = len(rows)
    print(f"\n{n} car_hit videos (seed {args.seed}):")
    print(f"  the car inside a collider: {sum(r['inside'] > 0 for r in rows)} videos, "
          f"{sum(r['inside'] for r in rows)} frames")  # fmt: skip
    print(f"  off its ground: {sum(r['off_ground'] > 0 for r in rows)} videos")
    print(f"  no touch: {sum(np.isnan(r['touch_speed']) for r in rows)} videos")
    print(f"  starting under half its speed: {sum(r['from_rest'] for r in rows)} videos")


if __name__ == "__main__":
    main()
