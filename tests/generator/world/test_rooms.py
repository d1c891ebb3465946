"""The house's room: its walls are cut round their windows and doors, papered or painted
above a skirting board inside their boxes, one look per room; its windows are open frames
that look out on a garden of lawn, hedges, trees and neighbours' houses, which the room's
own geometry (furniture facing, the storey above) never counts as part of the room."""

from __future__ import annotations

import numpy as np
import pytest

from phav_generator.world import interiors, places
from phav_generator.world.library import _into_room, _openings, _room, collider_asset, ground_asset, modelled_indices
from phav_generator.world.materials import Material
from phav_spec.scene import ENVIRONMENT_SCENES, GARDEN_CLASSES

HOUSE = "house_interior"


def _walls() -> list[int]:
    env = ENVIRONMENT_SCENES[HOUSE]
    return [i for i, c in enumerate(env.colliders) if c.pixel_class == "misc"]


def _hits(asset, origin, direction) -> int:
    """How many of ``asset``'s triangles the ray from ``origin`` along ``direction`` crosses."""
    t = asset.positions[asset.triangles]
    e1, e2 = t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]
    p = np.cross(direction, e2)
    det = np.einsum("ij,ij->i", e1, p)
    ok = np.abs(det) > 1e-12
    s = origin - t[:, 0]
    u = np.einsum("ij,ij->i", s, p) / np.where(ok, det, 1.0)
    q = np.cross(s, e1)
    v = (q @ direction) / np.where(ok, det, 1.0)
    d = np.einsum("ij,ij->i", e2, q) / np.where(ok, det, 1.0)
    return int(np.sum(ok & (u >= 0) & (v >= 0) & (u + v <= 1) & (d > 0)))


def _inside(index: int) -> tuple[float, float]:
    """The axis of wall ``index``'s frame that points into the room."""
    return _into_room(HOUSE, ENVIRONMENT_SCENES[HOUSE].colliders[index])


def test_each_wall_is_cut_where_its_windows_and_doors_are_and_solid_elsewhere():
    env = ENVIRONMENT_SCENES[HOUSE]
    cuts = {}
    for i in _walls():
        c = env.colliders[i]
        wall = collider_asset(HOUSE, i, 0)
        inside = next(f for f in places.box_faces(c.half_size) if float(f.normal[:2] @ np.array(_inside(i))) > 0.5)
        openings = _openings(HOUSE, c, _inside(i))
        cuts[i] = len(openings)
        for o in openings:  # a ray across the wall through the opening's middle meets nothing
            start = inside.at((o.s0 + o.s1) / 2, (o.z0 + o.z1) / 2) + 0.05 * inside.normal
            assert _hits(wall, start, -inside.normal) == 0
        solid = inside.at(0.5, 2.6) + 0.05 * inside.normal  # above every opening, near a corner
        assert _hits(wall, solid, -inside.normal) >= 2  # the room's face and the outside's
    # The plan: two windows south, a window and a door north, a window east, a door west.
    assert sorted(cuts.values()) == [1, 1, 2, 2]
    assert sum(cuts.values()) == sum(c.pixel_class in ("window", "door") for c in env.colliders)


def test_the_skirting_board_and_the_wall_stay_inside_the_box():
    env = ENVIRONMENT_SCENES[HOUSE]
    for i in _walls():
        c = env.colliders[i]
        lo, hi = collider_asset(HOUSE, i, 0).bounds()
        assert np.all(lo >= -np.array(c.half_size) - 1e-5) and np.all(hi <= np.array(c.half_size) + 1e-5)  # float32
    wall = collider_asset(HOUSE, _walls()[0], 0)
    names = {n for n, *_ in wall.parts}
    assert {"wall", "skirting", "outside"} <= names


def test_the_room_has_one_wall_look_and_the_seed_may_paper_it():
    looks = set()
    for seed in (None, *range(12)):
        walls = [collider_asset(HOUSE, i, 0, seed) for i in _walls()]
        inner = {(int(w.materials[k]), tuple(w.colours[k])) for w in walls for k in range(len(w.materials))
                 if w.parts and _part_of(w, k) == "wall"}  # fmt: skip
        assert len(inner) == 1  # every wall of the room alike
        looks |= inner
    assert {m for m, _ in looks} == {int(Material.PLAIN), int(Material.WALLPAPER)}


def _part_of(asset, vertex: int) -> str:
    tri = int(np.nonzero((asset.triangles == vertex).any(axis=1))[0][0])
    return next(name for name, first, end, _ in asset.parts if first <= tri < end)


def test_a_window_is_an_open_frame():
    window = interiors.window((1.0, 0.15, 0.7), np.random.default_rng(0), 0)
    assert set(window.pixel_classes()) == {"window"}
    assert Material.GLASS not in set(window.materials.tolist())
    assert _hits(window, np.array([-0.5, 1.0, 0.2]), np.array([0.0, -1.0, 0.0])) == 0  # a pane's middle is open


def test_each_window_looks_out_on_the_garden_not_the_floor():
    env = ENVIRONMENT_SCENES[HOUSE]
    garden = [c for c in env.colliders if c.pixel_class in GARDEN_CLASSES and c.pixel_class != "terrain"]
    for w in (c for c in env.colliders if c.pixel_class == "window"):
        i = min(_walls(), key=lambda k: env.colliders[k].xy_distance(*w.center[:2]))
        out = -np.array(_inside(i))  # the house's walls stand square to the world's axes
        along = [np.array(w.center[:2]) + t * out for t in np.arange(1.0, 45.0, 0.5)]
        seen = [c for c in garden if c.top > w.center[2] and any(c.contains_xy(*pt) for pt in along)]
        assert seen, f"the window at {w.center[:2]} looks out on nothing taller than itself"


def test_the_garden_is_outside_the_room():
    env = ENVIRONMENT_SCENES[HOUSE]
    room = env.room_colliders
    assert all(c.pixel_class not in GARDEN_CLASSES for c in room)
    x0, y0, x1, y1 = _room(HOUSE)
    walls = [env.colliders[i] for i in _walls()]
    corners = np.array([p for c in walls for p in c.footprint()])
    walled = (*corners.min(axis=0), *corners.max(axis=0))  # the frames stand 5 cm proud of the walls
    assert np.abs(np.array((x0, y0, x1, y1)) - np.array(walled)).max() <= 0.05 + 1e-9
    for c in env.colliders:
        if c.pixel_class in GARDEN_CLASSES:  # wholly outside the walls
            fx, fy = np.array(c.footprint()).T
            assert fx.max() <= x0 + 1e-9 or fx.min() >= x1 - 1e-9 or fy.max() <= y0 + 1e-9 or fy.min() >= y1 - 1e-9
    classes = {env.colliders[i].pixel_class for i in modelled_indices(HOUSE)}
    assert {"misc", "ceiling", "building", "tree", "vegetation", "terrain"} <= classes


def test_the_kitchen_floor_is_tiled_and_the_rest_of_the_room_is_wood():
    floor = ground_asset("house_interior", 400.0, 0.02)
    tiles = floor.materials == Material.FLOOR_TILES
    lo, hi = floor.positions[tiles].min(axis=0), floor.positions[tiles].max(axis=0)
    room = ENVIRONMENT_SCENES["house_interior"].room_colliders
    kitchen = [c for c in room if c.pixel_class in ("fridge", "shelf", "table", "chair") and c.center[1] < -3.0]
    assert kitchen and all(
        lo[0] - 1e-4 <= x <= hi[0] + 1e-4 and lo[1] - 1e-4 <= y <= hi[1] + 1e-4
        for c in kitchen
        for x, y in c.footprint()
    )
    # the tiles and the wood round them cover the ground once: no overlap, no gap
    p = floor.positions.astype(np.float64)
    tri = floor.triangles
    area = 0.5 * np.abs(np.cross(p[tri[:, 1]] - p[tri[:, 0]], p[tri[:, 2]] - p[tri[:, 0]])[:, 2]).sum()
    assert area == pytest.approx(800.0**2, rel=1e-6)
    assert set(floor.pixel_classes()) == {"floor"} and (floor.materials[~tiles] == Material.WOOD).all()
