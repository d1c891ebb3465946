"""Where the car of `car_hit` touches people, against the car the renderer draws (docs/physics.md).

Simulates the first N `car_hit` recipes of phav-v1 (as drawn: their clips, environments
and variations) and, at every physics step, takes each contact between the car's collision
geoms and a person's. A contact point outside the drawn car's solids (``phav_spec.car_shapes``)
is measured against the drawn car (its body, bumpers and wheels, sampled densely over their
surfaces): the air a person meets where the collider is larger than the car; MuJoCo's
penetration gives how deep the person presses in. Per frame with a contact, the largest of
each. Prints, per recipe and over all, those frames, the share whose air exceeds 5 and
15 cm, the depth's quantiles, where the hit lands (the lowest contact's height), and the
frames whose camera is inside the drawn car or within 30 cm of a face plane of its solids
(up to about 50 cm off a corner).

Since the car collides as the drawn car's solids, a contact's point lies inside them (for
two convex shapes MuJoCo puts it midway into their overlap): the air counted is no longer
air between the collider and the paint, which the asset tests hold within 2 cm, but the
few contact points that fall outside the solids.

    python docs/measure/car_contact.py [--recipes 12] [--seed 0]
"""

from __future__ import annotations

import argparse
import math

import mujoco
import numpy as np
from scipy.spatial import ConvexHull, cKDTree

from phav_generator.physics.control import SimulationRun
from phav_generator.physics.plan.car_hit import CAR_CLEARANCE_M, CAR_LOOK_STREAM
from phav_generator.physics.plan.scene import plan_scene
from phav_generator.physics.simulate import simulate_plan
from phav_generator.sampling import sample_recipes
from phav_generator.world.library import vehicle
from phav_spec.car_shapes import car_body, car_hulls, car_profile
from phav_spec.seeding import stream
from phav_spec.theta import load_preset

SURFACE_SAMPLES = 40_000


def _surface(vertices: np.ndarray, triangles: np.ndarray, n: int, rng: np.random.Generator) -> np.ndarray:
    """``n`` points spread over a mesh's surface, area-weighted."""
    a, b, c = (vertices[triangles[:, k]] for k in range(3))
    area = 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1)
    pick = rng.choice(len(triangles), size=n, p=area / area.sum())
    u, v = rng.random((2, n))
    flip = u + v > 1
    u[flip], v[flip] = 1 - u[flip], 1 - v[flip]
    return a[pick] + u[:, None] * (b - a)[pick] + v[:, None] * (c - a)[pick]


def drawn_car(recipe, size) -> cKDTree:
    """The drawn car of ``recipe`` (body and wheels) in its box's frame, as a point tree."""
    car = vehicle("car", size, stream(recipe.seeds.physics, CAR_LOOK_STREAM), 0, below=CAR_CLEARANCE_M)
    rng = np.random.default_rng(0)
    points = [_surface(car.body.positions.astype(float), car.body.triangles, SURFACE_SAMPLES, rng)]
    wheel = _surface(car.wheel.positions.astype(float), car.wheel.triangles, 2_000, rng)
    points += [wheel + axle for axle in car.axles]
    return cKDTree(np.concatenate(points))


def _hull_planes(recipe, size) -> list[np.ndarray]:
    """The face planes of the drawn car's solids (``phav_spec.car_shapes``), in its box's frame."""
    outline = car_profile(car_body(stream(recipe.seeds.physics, CAR_LOOK_STREAM)), size, CAR_CLEARANCE_M)
    return [ConvexHull(np.array(h)).equations for h in car_hulls(outline)]


def _outside(planes: list[np.ndarray], local: np.ndarray) -> float:
    """How far ``local`` lies outside the nearest solid, by its farthest face plane (negative
    inside): exact off a face, less than the true distance off an edge or corner."""
    return min(float(np.max(e[:, :3] @ local + e[:, 3])) for e in planes)


def camera_near_car(planes: list[np.ndarray], track, eyes: np.ndarray) -> np.ndarray:
    """Per frame, how far (m) the camera is outside the drawn car's solids (negative: inside)."""
    out = np.empty(len(eyes))
    for f, (pos, quat) in enumerate(zip(track.pos, track.quat, strict=True)):
        rot = np.empty(9)
        mujoco.mju_quat2Mat(rot, quat)
        out[f] = _outside(planes, rot.reshape(3, 3).T @ (eyes[f] - pos))
    return out


def measure(recipe) -> dict[str, float]:
    """Air between the car's contacts with people and the drawn car, and how deep they press
    in, over one simulation."""
    plan = plan_scene(recipe)
    car = next(p for p in plan.props if p.object == "car")
    tree, planes = drawn_car(recipe, car.size), _hull_planes(recipe, car.size)
    frames: dict[int, list[tuple[float, float, float]]] = {}
    original = SimulationRun.check_contacts

    def spy(run: SimulationRun, t: float) -> set[str]:
        d, m = run.d, run.m
        main = next(h.geom for h, p in zip(run.scene.props, plan.props, strict=True) if p.object == "car")
        car_body = int(m.geom_bodyid[main])
        people = {int(g) for h in run.scene.people for g in h.geoms}
        rot = d.geom_xmat[main].reshape(3, 3)
        for k in range(d.ncon):
            c = d.contact[k]
            g1, g2 = int(c.geom1), int(c.geom2)
            if not (
                (m.geom_bodyid[g1] == car_body and g2 in people) or (m.geom_bodyid[g2] == car_body and g1 in people)
            ):
                continue
            local = rot.T @ (np.asarray(c.pos) - d.geom_xpos[main])
            air = float(tree.query(local)[0]) if _outside(planes, local) > 0 else 0.0
            # Plan step k ends at frame ⌈k / substeps⌉ (``SimulationRun.step_frame``).
            frame = -(-round(t / plan.timestep) // plan.substeps)
            frames.setdefault(frame, []).append((air, max(-float(c.dist), 0.0), float(c.pos[2])))
        return original(run, t)

    SimulationRun.check_contacts = spy
    try:
        trajectory = simulate_plan(plan, keep_state=False)
    finally:
        SimulationRun.check_contacts = original
    track = next(t for t in trajectory.props if t.name == "car")
    near = camera_near_car(planes, track, trajectory.cam_to_world[:, :3, 3])
    air = np.array([max(a for a, _, _ in v) for v in frames.values()]) if frames else np.zeros(0)
    depth = np.array([max(p for _, p, _ in v) for v in frames.values()]) if frames else np.zeros(0)
    low = min((z for v in frames.values() for *_, z in v), default=math.nan)
    return {
        "frames": len(air),
        "air_over_5cm": float(np.mean(air > 0.05)) if len(air) else math.nan,
        "air_max": float(air.max()) if len(air) else math.nan,
        "depth_max": float(depth.max()) if len(depth) else math.nan,
        "lowest": low - recipe.protagonist.position[2],
        "camera_in_car": int(np.sum(near < 0.0)),
        "camera_within_30cm": int(np.sum(near < 0.3)),
        "air": air,
        "depth": depth,
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--recipes", type=int, default=12)
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args()
    theta = load_preset("phav-v1")
    rows, airs, depths = [], [], []
    for recipe in sample_recipes(theta, n=4000, seed=args.seed):
        if recipe.action != "car_hit":
            continue
        r = measure(recipe)
        airs.append(r.pop("air"))
        depths.append(r.pop("depth"))
        rows.append(r)
        print(
            f"{recipe.video_id} {recipe.environment.name:8s} " + " ".join(f"{k} {v:.3g}" for k, v in r.items()),
            flush=True,
        )
        if len(rows) == args.recipes:
            break
    air, depth = np.concatenate(airs), np.concatenate(depths)
    print(f"{len(rows)} recipes, {len(air)} frames with a contact between the car and a person:")
    print(
        f"  air (contact outside the drawn car) > 5 cm in {np.mean(air > 0.05):.1%}, "
        f"> 15 cm in {np.mean(air > 0.15):.1%}, largest {air.max():.3f} m"
    )
    print(
        f"  depth pressed in: median {np.median(depth):.3f} m, 95th percentile {np.percentile(depth, 95):.3f} m, "
        f"largest {depth.max():.3f} m"
    )
    print(
        f"  camera inside the car in {sum(r['camera_in_car'] for r in rows)} frames, "
        f"within 30 cm of it in {sum(r['camera_within_30cm'] for r in rows)}"
    )


if __name__ == "__main__":
    main()
