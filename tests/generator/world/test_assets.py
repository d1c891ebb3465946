"""The asset library: every kind deterministic (also at numpy's SIMD baseline), its meshes
valid and within budget at each level, labelled with its own classes only, and fitted to
the colliders it stands in; a truck's guards and bar clear of its tyres, every vehicle's
lamps lit, and the fingerprint covering the boxes actions add."""

from __future__ import annotations

import hashlib
import math
import os
import subprocess
import sys

import numpy as np
import pytest

from phav_generator.world import library, vehicles
from phav_generator.world.library import (
    CATALOGUE,
    MODELLED_CLASSES,
    collider_asset,
    modelled_indices,
    world_library_sha256,
)  # fmt: skip
from phav_generator.world.materials import TRIM, Material
from phav_generator.world.parts import LAMP_GLOW, LEVELS, Asset, Parts, crease_normals
from phav_generator.world.vehicles import BUS_ARCH_GAP_M, Vehicle
from phav_spec.car_shapes import CAR_BODIES
from phav_spec.scene import ENVIRONMENT_SCENES
from phav_spec.seeding import stream
from phav_spec.vocab import PIXEL_CLASSES
from tests.helpers import outside_hulls, part_corners

#: How far (m) a drawn shape may stray outside the box it stands in.
FIT_M = 0.02
#: The coarser levels' fit: drawn far enough away to be chosen, 4 cm is under a pixel (a car
#: at level 2 rounds its sides with one station where its hulls, level 0's, take four).
FIT_COARSE_M = 0.04
KINDS = sorted(CATALOGUE)


def _assets(built: Asset | Vehicle) -> list[Asset]:
    return [built.body, built.wheel] if isinstance(built, Vehicle) else [built]


def _build(kind: str, level: int = 0) -> Asset | Vehicle:
    return CATALOGUE[kind][0](stream(3, f"test/{kind}"), level)


def _catalogue_digest() -> str:
    h = hashlib.sha256()
    for kind in KINDS:
        for level in range(LEVELS):
            for asset in _assets(_build(kind, level)):
                h.update(asset.digest_bytes())
    return h.hexdigest()


@pytest.mark.parametrize("kind", KINDS)
def test_the_same_parameters_and_seed_give_the_same_bytes(kind):
    first, second = _assets(_build(kind)), _assets(_build(kind))
    assert [a.digest_bytes() for a in first] == [a.digest_bytes() for a in second]


def test_the_catalogue_gives_the_same_bytes_at_numpys_simd_baseline():
    from numpy._core._multiarray_umath import __cpu_dispatch__, __cpu_features__

    above = " ".join(f for f in __cpu_dispatch__ if __cpu_features__.get(f))
    if not above:
        pytest.skip("numpy dispatches nothing above its baseline on this CPU")
    code = ("import sys; sys.path.insert(0, sys.argv[1]); "
            "from test_assets import _catalogue_digest; print(_catalogue_digest())")  # fmt: skip
    run = subprocess.run([sys.executable, "-c", code, os.path.dirname(__file__)], capture_output=True, text=True,
                         env=os.environ | {"NPY_DISABLE_CPU_FEATURES": above}, check=True)  # fmt: skip
    assert run.stdout.strip() == _catalogue_digest()


def _closed_edges_pair_up(positions: np.ndarray, triangles: np.ndarray) -> bool:
    """Whether every directed edge of a closed part (vertices welded by position) is met by
    its reverse exactly once: a watertight, consistently wound surface."""
    _, weld = np.unique(np.round(positions.astype(np.float64), 6), axis=0, return_inverse=True)
    t = weld.reshape(-1)[triangles]
    edges = np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]])
    edges = edges[edges[:, 0] != edges[:, 1]]
    forward = {tuple(e) for e in edges.tolist()}
    return len(forward) == len(edges) and all((b, a) in forward for a, b in forward)


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("level", range(LEVELS))
def test_meshes_are_valid_and_within_their_triangle_budget(kind, level):
    built = _build(kind, level)
    budget = CATALOGUE[kind][1][level]
    triangles = built.n_triangles
    assert triangles <= budget, f"{kind} at level {level}: {triangles} triangles, budget {budget}"
    if level:
        assert triangles <= _build(kind, level - 1).n_triangles
    for asset in _assets(built):
        _assert_valid(asset, kind)


def _assert_valid(asset: Asset, what: str) -> None:
    """Finite, no degenerate or inside-out triangle, every closed part watertight and wound
    outwards (positive signed volume: a flat part's normals come from its own triangles,
    so the winding test alone cannot see a part turned inside out whole)."""
    p, tri = asset.positions.astype(np.float64), asset.triangles.astype(np.int64)
    assert np.isfinite(p).all()
    a, b, c = p[tri[:, 0]], p[tri[:, 1]], p[tri[:, 2]]
    cross = np.cross(b - a, c - a)
    area = 0.5 * np.linalg.norm(cross, axis=1)
    assert area.min() > 1e-8, f"{what}: a degenerate triangle"
    # Winding agrees with the normals: no triangle turned inside out.
    n = asset.normals[tri].astype(np.float64).sum(axis=1)
    assert (np.einsum("ij,ij->i", cross, n) > 0).all(), f"{what}: an inverted triangle"
    for name, first, end, closed in asset.parts:
        if closed:
            assert _closed_edges_pair_up(p, tri[first:end]), f"{what}: part {name} is not closed"
            t = p[tri[first:end]]
            volume = np.einsum("ij,ij->i", t[:, 0], np.cross(t[:, 1], t[:, 2])).sum() / 6.0
            assert volume > 0, f"{what}: part {name} is inside out (signed volume {volume:.3g} m³)"


@pytest.mark.parametrize("env", ENVIRONMENT_SCENES.names)
def test_every_asset_of_every_environment_is_valid_at_every_level(env):
    for index in modelled_indices(env):
        for level in range(LEVELS):
            for asset in _assets(collider_asset(env, index, level)):
                _assert_valid(asset, f"{env} collider {index} at level {level}")


def _classes_of(built: Asset | Vehicle) -> set[str]:
    return {c for a in _assets(built) for c in a.pixel_classes()}


@pytest.mark.parametrize("kind", KINDS)
def test_an_asset_rendered_alone_shows_its_classes_and_nothing_else(ctx, kind):
    from phav_generator.render.assets import asset_drawable, turntable, vehicle_drawables

    built = _build(kind)
    still = np.broadcast_to(np.eye(4), (2, 4, 4))
    drawables = vehicle_drawables(built, still) if isinstance(built, Vehicle) else [asset_drawable(built, still)]
    frames = turntable(ctx, drawables, built.body if isinstance(built, Vehicle) else built, height=96)
    seen = {PIXEL_CLASSES.names[int(i)] for f in frames for i in np.unique(f.class_id)}
    own = _classes_of(built)
    assert seen - {"sky"} <= own, f"{kind} shows {seen - own - {'sky'}}"
    assert own <= seen, f"{kind} never shows {own - seen}"
    assert all((f.instance == 0).all() for f in frames)


def test_a_turntable_camera_zoomed_in_stands_that_much_closer_on_the_same_line():
    from phav_generator.render.assets import turntable_camera

    block = _build("urban_block")
    centre = np.add(*block.bounds()) / 2
    (far, k), (near, k2) = (turntable_camera(block, 40.0, zoom=z) for z in (1.0, 2.0))
    assert k == k2
    assert np.linalg.norm(near[:3, 3] - centre) == pytest.approx(np.linalg.norm(far[:3, 3] - centre) / 2)
    assert np.allclose(near[:3, :3], far[:3, :3])  # looking the same way, at the same point


def _box_gaps(asset: Asset, half) -> tuple[float, np.ndarray]:
    """How far the asset strays outside a box of ``half`` around its origin, and the gap
    between each box face (−x, +x, −y, +y, −z, +z) and the asset's nearest vertex."""
    p = asset.positions.astype(np.float64)
    h = np.asarray(half, dtype=np.float64)
    outside = float(np.max(np.abs(p) - h, initial=0.0))
    lo, hi = p.min(axis=0), p.max(axis=0)
    gaps = np.array([lo[0] + h[0], h[0] - hi[0], lo[1] + h[1], h[1] - hi[1], lo[2] + h[2], h[2] - hi[2]])
    return outside, gaps


#: Faces people and vehicles meet, per class: the drawn shape reaches them (−x, +x, −y, +y, −z, +z).
_TOUCHED = {"car": (0, 1, 2, 3, 5), "truck": (0, 1, 2, 3, 5), "bus": (0, 1, 2, 3, 5), "bench": (0, 1, 5),
            "chair": (5,), "table": (0, 1, 2, 3, 4, 5), "sofa": (4, 5), "bed": (0, 1, 2, 3, 4),
            "stairs": (0, 1, 2, 3, 4, 5), "fridge": (4, 5), "shelf": (4, 5), "guard_rail": (0, 1, 4, 5),
            "fireplace": (4, 5), "building": (0, 1, 2, 3, 4, 5), "road": (0, 1, 2, 3, 5),
            "terrain": (0, 1, 2, 3, 5), "misc": (0, 1, 2, 3, 4, 5), "ceiling": (0, 1, 2, 3, 4, 5)}  # fmt: skip

FITTED = [(name, i) for name in ENVIRONMENT_SCENES.names for i in modelled_indices(name)]


@pytest.mark.parametrize(("env", "index"), FITTED, ids=[f"{e}-{i}" for e, i in FITTED])
def test_each_drawn_shape_fits_its_collider(env, index):
    c = ENVIRONMENT_SCENES[env].colliders[index]
    built = collider_asset(env, index, 0)
    for level in range(LEVELS):
        at_level, fit = collider_asset(env, index, level), FIT_M if level == 0 else FIT_COARSE_M
        for asset in [at_level.body] if isinstance(at_level, Vehicle) else [at_level]:
            outside, gaps = _box_gaps(asset, c.half_size)
            assert outside <= fit, f"{c} at level {level}: drawn {outside:.3f} m outside its box"
            for face in _TOUCHED.get(c.pixel_class, ()):
                gap = gaps[face]
                assert gap <= fit, f"{c} at level {level}: face {face} is {gap:.3f} m from the drawn shape"
    if c.hulls:  # a parked car collides as the solids it is drawn from
        _assert_drawn_as_hulls(built.body, c.hulls, f"{env} {index}")
    if isinstance(built, Vehicle):  # its wheels stand on the ground inside the box's footprint
        wheel_bottom = built.axles[:, 2] - built.wheel_radius
        assert np.allclose(wheel_bottom, -c.half_size[2], atol=1e-6)
        assert (
            np.abs(built.axles[:, :2]) + built.wheel_radius * np.array([1.0, 0.0]) <= np.array(c.half_size[:2])
        ).all()


def test_every_modelled_class_is_drawn_somewhere_and_boxes_stay_for_the_places():
    drawn = {ENVIRONMENT_SCENES[e].colliders[i].pixel_class for e, i in FITTED}
    assert drawn == set(MODELLED_CLASSES) - {"truck", "bus"}  # those two only drive
    for env in ENVIRONMENT_SCENES.names:
        for i, c in enumerate(ENVIRONMENT_SCENES[env].colliders):
            if c.pixel_class not in MODELLED_CLASSES:
                assert collider_asset(env, i, 0) is None


def test_the_renderer_fingerprint_names_the_asset_library(ctx):
    from phav_generator.dataset.fingerprint import WORLD_LIBRARY_KEY, renderer_fingerprint
    from phav_generator.render.context import gl_strings
    from phav_generator.world.library import world_library_sha256

    versions = renderer_fingerprint(gl_strings(ctx)).versions
    assert versions[WORLD_LIBRARY_KEY] == world_library_sha256()
    assert len(versions[WORLD_LIBRARY_KEY]) == 64


#: Props and the physics shape they move as: (shape, size) — and how far (m) each may be
#: drawn outside it: a bow's limbs recurve behind its straight capsule, a club's head sits
#: off its shaft, a cart's castors stand below its floating basket.
PROP_SHAPES = {
    "ball": ("sphere", (0.11,), FIT_M), "baseball_bat": ("capsule", (0.03, 0.42), FIT_M),
    "golf_club": ("capsule", (0.015, 0.5), 0.08), "bow": ("capsule", (0.015, 0.7), 0.13),
    "hair_brush": ("capsule", (0.02, 0.1), FIT_M), "cup": ("capsule", (0.04, 0.04), FIT_M),
    "bottle": ("capsule", (0.035, 0.1), FIT_M), "gun": ("box", (0.11, 0.02, 0.06), FIT_M),
    "crate": ("box", (0.3, 0.35, 0.5), FIT_M), "shopping_cart": ("box", (0.45, 0.28, 0.35), 0.16),
    "door_leaf": ("box", (0.02, 0.45, 1.0), 0.06), "pull_up_bar": ("capsule", (0.02, 0.6), FIT_M),
}  # fmt: skip


@pytest.mark.parametrize("kind", sorted(PROP_SHAPES))
def test_each_prop_is_drawn_within_its_physics_shape(kind):
    shape, size, allowance = PROP_SHAPES[kind]
    p = _build(kind).positions.astype(np.float64)
    if shape == "sphere":
        outside = np.linalg.norm(p, axis=1) - size[0]
    elif shape == "capsule":
        along = np.clip(p[:, 2], -size[1], size[1])
        outside = np.linalg.norm(p - np.stack([0 * along, 0 * along, along], axis=1), axis=1) - size[0]
    else:
        outside = np.max(np.abs(p) - np.asarray(size), axis=1)
    assert outside.max() <= allowance, f"{kind}: drawn {outside.max():.3f} m outside its {shape}"


def test_the_seed_chooses_a_car_s_look():
    looks = {CATALOGUE["sedan"][0](stream(seed, "look"), 0).body.colours.tobytes() for seed in range(8)}
    assert len(looks) > 1


def test_a_cushion_fills_its_box_with_rounded_corners():
    """Squareness 1 is the ellipsoid, vertex for vertex; a cushion's (0.3) vertices stay in
    the same box but reach far nearer its corners, and its normals still point outwards."""

    def built(**kw) -> Asset:
        p = Parts(0)
        p.ellipsoid("c", "sofa", Material.FABRIC, (0.5, 0.5, 0.5), (0.0, 0.0, 0.0), (0.4, 0.3, 0.1), **kw)
        return p.build()

    plain, same, cushion = built(), built(squareness=1.0), built(squareness=0.3)
    assert plain.digest_bytes() == same.digest_bytes()
    half = np.array([0.4, 0.3, 0.1], np.float32)
    for asset in (plain, cushion):
        assert np.all(np.abs(asset.positions) <= half + 1e-6)
        assert np.all(np.sum(asset.normals * asset.positions, axis=1) > 0.0)

    # How far into the corner octant each gets: the largest min over axes of |x| / half.
    def reach(asset: Asset) -> float:
        return float(np.max(np.min(np.abs(asset.positions) / half, axis=1)))

    assert reach(plain) < 0.6 < 0.8 < reach(cushion)


def test_a_loft_through_sections_is_a_closed_solid_facing_out():
    """Three square sections along x make a box: closed, every face outward, the volume of
    its two slabs; collinear points on a section (the cap's fan is from its centroid) and
    sections of unequal size are handled, the latter refused by name."""
    square = [(-0.5, -0.5), (0.0, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)]  # CCW seen along +x
    p = Parts(0)
    p.loft("slab", "car", Material.PAINT, (0.5, 0.5, 0.5), [[(x, -y, z) for y, z in square] for x in (0.0, 0.5, 2.0)])
    asset = p.build()
    _assert_valid(asset, "loft")
    pos, tri = asset.positions.astype(np.float64), asset.triangles.astype(np.int64)
    volume = np.einsum("ij,ij->i", pos[tri[:, 0]], np.cross(pos[tri[:, 1]], pos[tri[:, 2]])).sum() / 6.0
    assert volume == pytest.approx(2.0)
    with pytest.raises(ValueError, match="bad: a loft needs two or more sections of one size"):
        Parts(0).loft("bad", "car", Material.PAINT, (0.5, 0.5, 0.5), [[(0, 0, 0), (0, 1, 0), (0, 1, 1)], [(1, 0, 0)]])


def test_a_crease_shades_a_curved_loft_smooth_and_keeps_its_sharp_edges():
    """A 12-sided prism lofted with a 40° crease shades round: each side corner's normal is
    its vertex's radial direction, as on a cylinder; its caps, 90° from the side, stay flat.
    A box, every edge 90°, comes out as flat-shaded."""
    ring = [(math.cos(math.pi * k / 6), math.sin(math.pi * k / 6)) for k in range(12)]  # CCW along +x

    def lofted(loop, crease):
        p = Parts(0)
        p.loft("s", "car", Material.PAINT, (0.5, 0.5, 0.5), [[(x, -y, z) for y, z in loop] for x in (0.0, 1.0)],
               crease=crease)  # fmt: skip
        return p.build()

    prism = lofted(ring, 40.0)
    _assert_valid(prism, "crease")
    pos, nrm = prism.positions.astype(np.float64), prism.normals.astype(np.float64)
    cap = np.abs(nrm[:, 0]) > 0.5
    on_cap_plane = np.isclose(pos[:, 0], 0.0) | np.isclose(pos[:, 0], 1.0)
    assert np.all(on_cap_plane[cap])
    np.testing.assert_allclose(np.abs(nrm[cap, 0]), 1.0, atol=1e-6)
    radial = pos[~cap] * np.array([0.0, 1.0, 1.0])
    np.testing.assert_allclose(nrm[~cap], radial / np.linalg.norm(radial, axis=1, keepdims=True), atol=1e-6)
    assert (~cap).sum() == 12 * 2 * 3  # every side corner (two triangles a side)
    square = [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)]
    box, flat = lofted(square, 40.0), lofted(square, None)
    np.testing.assert_array_equal(box.positions, flat.positions)
    np.testing.assert_array_equal(box.normals, flat.normals)  # +0 and -0 alike
    with pytest.raises(ValueError, match="polygons: one non-negative id per triangle"):
        crease_normals(np.eye(3), np.array([[0, 1, 2]]), 40.0, np.array([0, 1]))


def _covers(triangles: list[np.ndarray], px: float, pz: float) -> bool:
    """Whether a point of the (x, z) plane lies in one of ``triangles`` ((3, 2) each)."""
    for a, b, c in triangles:
        d = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
        u = ((b[0] - px) * (c[1] - pz) - (b[1] - pz) * (c[0] - px)) / d
        v = ((c[0] - px) * (a[1] - pz) - (c[1] - pz) * (a[0] - px)) / d
        if u >= 0 and v >= 0 and u + v <= 1:
            return True
    return False


def test_a_bus_s_wheel_arches_are_round_over_its_wheels():
    """Seen from the side, the skirt's paint comes down to a circle round each axle (a tram's
    skirt is straight, and a street model took a square-arched bus for a tram)."""
    bus = _build("bus")
    assert isinstance(bus, Vehicle)
    body = bus.body
    arch_r = bus.wheel_radius + BUS_ARCH_GAP_M
    arches = [t for name, first, end, _ in body.parts if name.startswith("arch") for t in body.triangles[first:end]]
    for x, y, z in bus.axles:
        side = [body.positions[t][:, [0, 2]].astype(np.float64) for t in arches
                if np.sign(body.positions[t[0], 1]) == np.sign(y)]  # fmt: skip
        assert side, "no arch on this side"
        top = max(float(t[:, 1].max()) for t in side)  # the skirt's top
        for dx in np.linspace(-0.98, 0.98, 15) * arch_r:
            for pz in np.linspace(z + 0.02, top - 0.02, 9):
                r = float(np.hypot(dx, pz - z))
                if r > arch_r + 0.01:
                    assert _covers(side, x + dx, pz), f"the arch's corner open at ({dx:+.2f}, {pz - z:+.2f}) m"
                elif r < arch_r - 0.01:
                    assert not _covers(side, x + dx, pz), f"paint over the wheel at ({dx:+.2f}, {pz - z:+.2f}) m"


@pytest.mark.parametrize("level", range(LEVELS))
def test_a_bus_s_side_windows_sit_in_a_black_surround(level):
    """Flush glazing, as a city bus has: on each side the glass lies within a black surround
    that reaches past it fore and aft, just behind the glass and outside the paint, and the
    pillars between the panes are black (painted pillars in a band of glass read as a tram)."""
    bus = _build("bus", level)
    body = bus.body
    ranges = {name: (first, end) for name, first, end, _ in body.parts}

    def vertices(name: str) -> np.ndarray:
        first, end = ranges[name]
        return np.unique(body.triangles[first:end].ravel())

    for sgn in ("-1", "+1"):
        glass, surround = vertices(f"windows{sgn}"), vertices(f"glazing_surround{sgn}")
        g, s = body.positions[glass].astype(np.float64), body.positions[surround].astype(np.float64)
        assert s[:, 0].min() <= g[:, 0].min() - 0.19 and s[:, 0].max() >= g[:, 0].max() + 0.19
        assert s[:, 2].min() < g[:, 2].min() and s[:, 2].max() > g[:, 2].max()
        side = float(np.sign(g[0, 1]))
        assert 0.0 < side * (g[0, 1] - s[0, 1]) < 0.005, "the surround is just behind the glass"
        np.testing.assert_allclose(body.colours[surround], [TRIM] * len(surround), atol=1e-6)
        pillars = [name for name in ranges if name.startswith("mullion") and name.endswith(sgn)]
        assert bool(pillars) == (level < 2)  # the finer levels draw them (`Parts.fine`)
        for name in pillars:
            np.testing.assert_allclose(body.colours[vertices(name)], [TRIM] * len(vertices(name)), atol=1e-6)


#: How far (m) a drawn car part may stand outside the hulls it collides as: its mirrors, the
#: pillars' trim over the glass's edges, and the dark underside between the wheels,
#: which hangs under the body as the wheels do.
_PROUD_PARTS = {"mirror": 0.09, "pillar": 0.055, "underbody": 0.14}
#: How far (m) a hull's corner may be from the drawn car: the body tucks in under its sills.
_HULL_REACH_M = 0.08


def _assert_drawn_as_hulls(body: Asset, hulls, label: str) -> None:
    """Every part of a drawn car inside its hulls (those allowed proud, by as much) and every
    hull corner near the drawn surface."""
    from scipy.spatial import cKDTree

    p = body.positions.astype(np.float64)
    for name, first, end, _ in body.parts:
        corners = p[np.unique(body.triangles[first:end])]
        allowance = next((m for part, m in _PROUD_PARTS.items() if name.startswith(part)), FIT_M)
        outside = outside_hulls(corners, hulls).max()
        assert outside <= allowance, f"{label} {name}: {outside:.3f} m outside its hulls"
    a, b, c = (p[body.triangles[:, k]] for k in range(3))
    u, v = np.meshgrid(np.linspace(0, 1, 9), np.linspace(0, 1, 9))
    keep = (u + v <= 1).ravel()
    u, v = u.ravel()[keep], v.ravel()[keep]
    surface = (a[:, None] + u[None, :, None] * (b - a)[:, None] + v[None, :, None] * (c - a)[:, None]).reshape(-1, 3)
    reach = cKDTree(surface).query(np.concatenate([np.asarray(h) for h in hulls]))[0]
    assert reach.max() <= _HULL_REACH_M, f"{label}: a hull corner {reach.max():.3f} m from the drawn car"


@pytest.mark.parametrize("kind", ["hatchback", "sedan", "suv", "van"])
@pytest.mark.parametrize("below", [0.0, 0.15])
def test_a_car_is_drawn_as_the_hulls_it_collides_as(kind, below):
    from phav_generator.world.vehicles import car
    from phav_spec.car_shapes import car_hulls, car_profile

    half = (2.1, 0.9, 0.7)
    hulls = car_hulls(car_profile(kind, half, below))
    for level in range(LEVELS):
        _assert_drawn_as_hulls(car(half, np.random.default_rng(0), level, body=kind, below=below).body, hulls, kind)


@pytest.mark.parametrize("level", range(LEVELS))
def test_a_truck_s_side_guards_and_underride_bar_lie_inside_its_box_clear_of_its_tyres(level):
    half = (3.6, 1.2, 1.6)
    truck = vehicles.truck(half, stream(0, "truck"), level)
    bars = [(name, c.reshape(-1, 3)) for name, c in part_corners(truck.body, "guard", "underride_bar")]
    assert len(bars) == (5 if level < 2 else 0)  # two rails of a guard each side, the bar
    y_tyre = truck.wheel.bounds()[1][1]
    for name, pts in bars:
        lo, hi = pts.min(axis=0), pts.max(axis=0)
        assert np.abs(pts[:, 1]).max() <= half[1] - 0.05, name
        for axle in truck.axles:
            reach = np.array([truck.wheel_radius, y_tyre, truck.wheel_radius])
            apart = (hi < axle - reach) | (lo > axle + reach)
            assert apart.any(), f"{name} cuts the tyre at {axle}"


@pytest.mark.parametrize("kind", ["hatchback", "van", "truck", "bus"])
@pytest.mark.parametrize("level", range(LEVELS))
def test_every_vehicle_s_head_and_tail_lights_are_lamps(kind, level):
    body = _build(kind, level).body
    lamps = [(name, first, end) for name, first, end, _ in body.parts
             if name.startswith(("headlight", "taillight", "tail_light"))]  # fmt: skip
    assert {name.rstrip("+-1") for name, *_ in lamps} >= {"headlight", "taillight" if kind in CAR_BODIES else
                                                          "tail_light"}  # fmt: skip
    for name, first, end in lamps:
        assert (body.glow[body.triangles[first:end].reshape(-1)] == LAMP_GLOW).all(), name


def test_the_fingerprint_covers_the_plain_boxes_actions_add(monkeypatch):
    before = world_library_sha256()
    monkeypatch.setattr(library, "_BOX_LOOKS", {**library._BOX_LOOKS, "door": (Material.WOOD, (0.5, 0.3, 0.2))})
    world_library_sha256.cache_clear()
    try:
        assert world_library_sha256() != before
    finally:
        world_library_sha256.cache_clear()
