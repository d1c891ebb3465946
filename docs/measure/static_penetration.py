"""How deep people go into the world's static objects, as drawn (docs/world.md).

For every person and frame of a dataset: its 13 joints and the midpoints of its limbs
(``people.parquet``) against the closed parts of what the renderer draws for each of the
environment's colliders (the ground plane excluded): with ``--drawn boxes`` the collider
boxes themselves (how a dataset made before the asset library drew them), with
``--drawn assets`` the asset library's meshes (convex parts: boxes, cylinders, cones,
ellipsoids, convex prisms); an asset drawn with open panels only (a building's walls on
its box's faces, a slab's top) has no inside of its own and counts as its box.
``--objects-only`` leaves out the places (terraces, roads, buildings, trees, hedges).
Prints the share of person-frames with a point more than 1, 2, 5 and 8 cm inside, and
depth quantiles.

    python docs/measure/static_penetration.py DATA --drawn assets
"""

from __future__ import annotations

import argparse
from functools import cache
from pathlib import Path

import numpy as np
import pyarrow.parquet as pq

from phav_generator.world.library import MODELLED_CLASSES, PLACE_CLASSES, collider_asset
from phav_generator.world.vehicles import Vehicle
from phav_spec.recipe_table import read_recipe_table
from phav_spec.scene import ENVIRONMENT_SCENES
from phav_validators.checks.failures import BoxSet, boxes, people_series, probe_points

THRESHOLDS_M = (0.01, 0.02, 0.05, 0.08)


def _closed_parts(env: str, index: int) -> bool:
    """Whether collider ``index``'s asset has a closed part (an inside to be in)."""
    built = collider_asset(env, index, 0)
    asset = built.body if isinstance(built, Vehicle) else built
    return asset is not None and any(closed for *_, closed in asset.parts)


@cache
def _planes(env: str) -> list[tuple[int, np.ndarray, np.ndarray]]:
    """Per closed convex part of the drawn statics: its collider's index, its faces' outward
    normals (k, 3) and offsets (k,), in world coordinates."""
    out = []
    for i, c in enumerate(ENVIRONMENT_SCENES[env].colliders):
        built = collider_asset(env, i, 0)
        asset = built.body if isinstance(built, Vehicle) else built
        if asset is None:
            continue
        yaw = np.radians(c.yaw_deg)
        rot = np.array([[np.cos(yaw), -np.sin(yaw), 0.0], [np.sin(yaw), np.cos(yaw), 0.0], [0.0, 0.0, 1.0]])
        p = asset.positions.astype(np.float64) @ rot.T + np.array(c.center)
        for _, first, end, closed in asset.parts:
            if not closed:
                continue
            tri = asset.triangles[first:end].astype(np.int64)
            a, b, cc = p[tri[:, 0]], p[tri[:, 1]], p[tri[:, 2]]
            n = np.cross(b - a, cc - a)
            n /= np.linalg.norm(n, axis=1, keepdims=True)
            out.append((i, n, np.einsum("ij,ij->i", n, a)))
    return out


def depth_assets(env: str, points: np.ndarray, *, objects_only: bool = False) -> np.ndarray:
    """Deepest depth (m) of each point (..., 3) inside any drawn part (−inf: none); with
    ``objects_only`` inside the library's objects only, not the places' boxes."""
    flat = points.reshape(-1, 3)
    best = np.full(len(flat), -np.inf)
    colliders = ENVIRONMENT_SCENES[env].colliders
    solid = {i for i in range(len(colliders)) if _closed_parts(env, i)}
    for i, n, d in _planes(env):
        if objects_only and colliders[i].pixel_class in PLACE_CLASSES:
            continue
        best = np.maximum(best, (d[None, :] - flat @ n.T).min(axis=1))
    unmodelled = boxes(env)
    keep = [i for i in range(len(colliders)) if i not in solid]
    if keep and not objects_only:
        depth = (unmodelled.half[keep] - np.abs(unmodelled.local(flat)[:, keep])).min(axis=-1)
        best = np.maximum(best, depth.max(axis=1))
    return best.reshape(points.shape[:-1])


def depth_boxes(env: str, points: np.ndarray, *, objects_only: bool = False) -> np.ndarray:
    """Deepest depth (m) of each point inside a collider (its box, or its hulls where it has
    them); with ``objects_only`` the colliders of the classes the library models only."""
    box = boxes(env)
    if not objects_only:
        return box.depth_inside(points)[0]
    keep = [c for c in box.colliders if c.pixel_class in MODELLED_CLASSES and c.pixel_class not in PLACE_CLASSES]
    if not keep:
        return np.full(points.shape[:-1], -np.inf)
    return BoxSet(keep).depth_inside(points)[0]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("data", type=Path)
    parser.add_argument("--drawn", choices=("boxes", "assets"), required=True)
    parser.add_argument("--objects-only", action="store_true", help="the library's objects, not the places")
    args = parser.parse_args()
    envs = dict(zip(*[read_recipe_table(args.data / "recipes.parquet").table.column(c).to_pylist()
                      for c in ("video_id", "environment")], strict=True))  # fmt: skip
    series = people_series(pq.read_table(args.data / "people.parquet"))
    depth_of = depth_assets if args.drawn == "assets" else depth_boxes
    deepest = []
    for vid, people in sorted(series.items()):
        for person in people:
            depth = depth_of(envs[vid], probe_points(person.joints), objects_only=args.objects_only)
            deepest.append(np.nan_to_num(depth, nan=-np.inf).max(axis=1))
    d = np.concatenate(deepest)
    what = "the objects" if args.objects_only else "every static collider"
    print(f"{args.data}: {len(d)} person-frames against {what}, drawn as {args.drawn}")
    for t in THRESHOLDS_M:
        print(f"  deeper than {t * 100:.0f} cm: {100 * np.mean(d > t):.2f} %")
    inside = d[d > 0]
    q = np.percentile(inside, [50, 90, 99]) if len(inside) else [0.0] * 3
    print(f"  inside at all: {100 * len(inside) / len(d):.2f} %; depth quantiles 50/90/99 %: "
          + " / ".join(f"{v * 100:.1f} cm" for v in q))  # fmt: skip


if __name__ == "__main__":
    main()
