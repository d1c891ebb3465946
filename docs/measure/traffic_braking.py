"""How the background traffic drives (docs/physics.md): over the first N recipes of (θ, seed),
as simulated, each vehicle's speed from frame to frame, its hardest braking, how close it
comes to anyone and whether the camera is ever inside it.

    .venv/bin/python docs/measure/traffic_braking.py [--theta phav-v1] [--videos 200] [--seed 52]

It prints the videos whose vehicles brake harder than ``--hard`` m/s², then the totals over
the videos with traffic.
"""

from __future__ import annotations

import argparse

import numpy as np

from phav_generator.motion.rotations import quat_to_matrix
from phav_generator.physics.simulate import simulate
from phav_generator.physics.trajectory import Trajectory
from phav_generator.sampling import sample_recipes
from phav_spec.scene import ENVIRONMENT_SCENES, VEHICLE_HALF_SIZES
from phav_spec.theta import load_preset


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--theta", default="phav-v1", help="preset name")
    parser.add_argument("--videos", type=int, default=200, help="recipes to look through")
    parser.add_argument("--seed", type=int, default=52)
    parser.add_argument("--hard", type=float, default=8.0, help="braking (m/s²) listed per video")
    args = parser.parse_args()
    rows = []
    vehicles = 0
    for recipe in sample_recipes(load_preset(args.theta), n=args.videos, seed=args.seed):
        if not ENVIRONMENT_SCENES[recipe.environment.name].lanes:
            continue
        trajectory = simulate(recipe, keep_state=False)
        tracks = [p for p in trajectory.props if p.name.startswith("traffic_")]
        if not tracks:
            continue
        vehicles += len(tracks)
        centres = np.array([t.pos[:, :2] for t in tracks])  # (V, F, 2)
        speed = np.linalg.norm(np.diff(centres, axis=1), axis=-1) * trajectory.fps
        braking = float(np.max(-np.diff(speed, axis=1), initial=0.0)) * trajectory.fps
        clearance = float(np.min(trajectory.traffic_clearance_m))
        rows.append((recipe.video_id, recipe.action, braking, clearance, _camera_depth_m(trajectory, tracks)))
        if braking > args.hard:
            print(f"{recipe.video_id} {recipe.action:20s} brakes at {braking:7.1f} m/s²")
    if not rows:
        raise SystemExit(f"none of the first {args.videos} recipes has traffic")
    braking = np.array([r[2] for r in rows])
    clearance = np.array([r[3] for r in rows])
    depth = np.array([r[4] for r in rows])
    print(f"{len(rows)} videos with traffic, {vehicles} vehicles")
    print(f"hardest braking: median {np.median(braking):.1f}, largest {braking.max():.1f} m/s²; "
          f"videos braking harder than {args.hard:g} m/s²: {int(np.sum(braking > args.hard))}")  # fmt: skip
    print(f"closest to anyone: {clearance.min():.2f} m; videos closer than 0.5 m: {int(np.sum(clearance < 0.5))}")
    print(f"camera inside a vehicle: {int(np.sum(depth > 0.0))} videos (deepest {max(depth.max(), 0.0):.2f} m)")


def _camera_depth_m(trajectory: Trajectory, tracks: list) -> float:
    """The deepest the camera comes inside any vehicle's box over the clip (m; ≤ 0: outside)."""
    deepest = -np.inf
    eyes = trajectory.cam_to_world[:, :3, 3]
    for track in tracks:
        half = np.array(VEHICLE_HALF_SIZES[track.object])
        rot = quat_to_matrix(track.quat)  # (F, 3, 3)
        local = np.einsum("fji,fj->fi", rot, eyes - track.pos)
        deepest = max(deepest, float(np.max(np.min(half - np.abs(local), axis=-1))))
    return deepest


if __name__ == "__main__":
    main()
