"""The places: a facade's wall and openings tile its face, windows sit back in it, loggias
deeper behind a parapet inside the box (some urban blocks only), shop windows lit; a road's
markings follow its lanes and leave its crossings to the zebra; pitch lines lie on the
pitch; each environment's slabs, buildings and trees take the look their role asks for;
the materials past the first sixteen reach the shader; clouds cover as much sky as θ says,
a sunset glows only in the sun's quarter;
a stand's tiers show their seats to the pitch, its goals stand on the goal lines, the
lake's reeds stand in its shallows off every walker's path and its banks have a shore; a
house's front door stands where no window is; a crown's clumps keep their height and reach
at every level of detail."""

from __future__ import annotations

import dataclasses
import itertools
import math

import numpy as np
import pytest

from phav_generator.motion.rotations import look_at
from phav_generator.world import places
from phav_generator.world.library import _carriageway, collider_asset
from phav_generator.world.materials import SHOP_TINTS, WINDOW_TINTS, Material
from phav_generator.world.parts import Parts
from phav_spec.scene import ENVIRONMENT_SCENES
from phav_spec.seeding import stream
from phav_spec.vocab import PIXEL_CLASSES
from tests.helpers import luma, part_corners
from tests.validators.learn.helpers import measure_script


def _quad_area(c: np.ndarray) -> float:
    return 0.5 * float(np.linalg.norm(np.cross(c[1] - c[0], c[2] - c[0]) + np.cross(c[2] - c[0], c[3] - c[0])))


def test_a_facade_s_wall_and_openings_tile_its_face_and_windows_sit_back():
    face = places.box_faces((6.0, 4.0, 5.0))[1]  # +y, 12 m wide, 10 m tall
    openings = [places.Opening(s0, s1, z0, z0 + 1.5) for s0, s1 in places._columns(face.width, 3.0, 1.2, 0.8)
                for z0 in (1.0, 4.0, 7.0)]  # fmt: skip
    q = places.Quads()
    places.facade(Parts(0), q, face, openings, (Material.PLASTER, (0.8, 0.8, 0.8)), stream(0, "t"),
                  frame=(1.0, 1.0, 1.0), recessed=True)  # fmt: skip
    walls = np.array([c for (name, *_), quads in q.groups.items() if name == "wall" for c in quads])
    panes = np.array([c for (name, *_), quads in q.groups.items() if name == "pane" for c in quads])
    wall_area = sum(_quad_area(c) for c in walls)
    open_area = sum((o.s1 - o.s0) * (o.z1 - o.z0) for o in openings)
    assert len(panes) == len(openings) == 9  # three bays of 3.5 m, three storeys
    assert wall_area + open_area == pytest.approx(face.width * face.height)
    assert np.allclose(walls[..., 1], 4.0)  # the wall lies on the box's face
    assert np.allclose(panes[..., 1], 4.0 - places.WINDOW_DEPTH_M)  # each pane set back into it
    assert all((np.cross(c[1] - c[0], c[2] - c[0]) @ face.normal) > 0 for c in walls)  # facing out


def test_a_loggia_sits_deep_in_its_wall_behind_a_parapet_and_stays_inside_the_box():
    face = places.box_faces((6.0, 4.0, 5.0))[1]  # +y, 12 m wide, 10 m tall
    loggia = places.Opening(4.9, 7.1, 3.1, 5.6, places.LOGGIA_DEPTH_M, places.PARAPET_M)
    window = places.Opening(1.0, 2.3, 3.85, 5.4)
    q = places.Quads()
    places.facade(Parts(0), q, face, [loggia, window], (Material.PLASTER, (0.8, 0.8, 0.8)), stream(0, "t"),
                  frame=(1.0, 1.0, 1.0), recessed=True)  # fmt: skip
    grouped: dict[str, list] = {}
    for (name, *_), quads in q.groups.items():
        grouped.setdefault(name, []).extend(quads)
    parts = {name: np.array(quads) for name, quads in grouped.items()}
    walls = parts["wall"]
    open_area = sum((o.s1 - o.s0) * (o.z1 - o.z0) for o in (loggia, window))
    assert sum(_quad_area(c) for c in walls) + open_area == pytest.approx(face.width * face.height)
    panes = sorted(float(c[..., 1].mean()) for c in parts["pane"])
    assert panes == pytest.approx([4.0 - places.LOGGIA_DEPTH_M, 4.0 - places.WINDOW_DEPTH_M])
    floor = parts["balcony"]
    assert floor.shape[0] == 1 and np.allclose(floor[0, :, 2], 3.1 - 5.0)  # the storey's floor, box frame
    assert floor[0, :, 1].min() == pytest.approx(4.0 - places.LOGGIA_DEPTH_M)
    ledge = parts["parapet"].reshape(-1, 3)
    assert ledge[:, 2].max() == pytest.approx(3.1 + places.PARAPET_M - 5.0)  # a metre above the floor
    assert ledge[:, 1].max() == pytest.approx(4.0) and ledge[:, 1].min() == pytest.approx(4.0 - places.PARAPET_THICK_M)
    everything = np.concatenate([np.array(v).reshape(-1, 3) for v in q.groups.values()])
    assert np.all(np.abs(everything) <= np.array([6.0, 4.0, 5.0]) + 1e-9)  # nothing outside the box


def test_some_urban_blocks_have_loggias_and_no_other_building_does():
    with_loggias = []
    for env in ("urban", "middle", "stadium"):
        for i, c in enumerate(ENVIRONMENT_SCENES[env].colliders):
            if c.pixel_class == "building":
                names = {name for name, *_ in collider_asset(env, i, 0).parts}
                with_loggias.append((env, "balcony" in names and "parapet" in names))
    urban = [has for env, has in with_loggias if env == "urban"]
    assert 0 < sum(urban) < len(urban)
    assert not any(has for env, has in with_loggias if env != "urban")


def test_every_urban_and_suburban_facade_has_windows_and_the_houses_face_the_street():
    for env, style in (("urban", "urban"), ("middle", "suburban")):
        for i, c in enumerate(ENVIRONMENT_SCENES[env].colliders):
            if c.pixel_class != "building":
                continue
            asset = collider_asset(env, i, 0)
            names = {name for name, *_ in asset.parts}
            assert {"wall", "pane", "reveal", "sill", "frame"} <= names, f"{env} building {i}: {names}"
            if style == "suburban":
                assert {"roof", "gable", "door"} <= names
                door = next(k for k, (name, *_) in enumerate(asset.parts) if name == "door")
                _, first, end, _ = asset.parts[door]
                y = asset.positions[asset.triangles[first:end].reshape(-1), 1].mean()
                assert math.copysign(1.0, y) == -math.copysign(1.0, c.center[1])  # on the side of the road (y = 0)


def _as_stored(tints) -> set[tuple[float, ...]]:
    """Colours as an asset stores them per vertex (float32)."""
    return {tuple(float(x) for x in np.float32(t)) for t in tints}


def test_urban_shop_fronts_show_a_lit_shop_and_the_storeys_above_their_rooms():
    shops, rooms = set(), set()
    for i, c in enumerate(ENVIRONMENT_SCENES["urban"].colliders):
        if c.pixel_class != "building":
            continue
        asset = collider_asset("urban", i, 0)
        ground = float(asset.bounds()[0][2])
        for name, first, end, _ in asset.parts:
            if name == "pane":
                v = asset.triangles[first:end].reshape(-1)
                tint = tuple(float(x) for x in asset.colours[v[0]])
                (shops if asset.positions[v, 2].max() - ground < 3.2 else rooms).add(tint)
    assert shops and shops <= _as_stored(SHOP_TINTS)  # a shop window shows its lit goods,
    assert rooms and rooms <= _as_stored(WINDOW_TINTS)  # a flat's its dark room or curtains
    assert min(luma(np.array(t)) for t in SHOP_TINTS) > max(luma(np.array(t)) for t in WINDOW_TINTS)


def test_the_urban_carriageway_has_its_two_lanes_and_the_signalled_crossings():
    env = ENVIRONMENT_SCENES["urban"]
    roads = [(i, c) for i, c in enumerate(env.colliders) if c.pixel_class == "road"]
    found = {i: _carriageway("urban", c) for i, c in roads}
    carriageways = [i for i, (lanes, _) in found.items() if lanes]
    assert len(carriageways) == 1  # the pavements and the plaza have none
    lanes, crossings = found[carriageways[0]]
    assert lanes == [-1.25, 1.25] and crossings == [-18.0, 18.0]


def test_road_markings_follow_the_lanes_and_leave_the_crossing_to_the_zebra():
    half = (30.0, 4.5, 0.05)
    marks = np.array(places.road_markings(half, [-1.25, 1.25], [0.0]))
    assert (marks[:, 0] >= -half[0]).all() and (marks[:, 2] <= half[0]).all()
    assert (np.abs(marks[:, [1, 3]]) <= half[1]).all()
    centre = marks[np.isclose((marks[:, 1] + marks[:, 3]) / 2, 0.0) & (marks[:, 3] - marks[:, 1] < 0.2)]
    assert len(centre) >= 5 and ((centre[:, 2] - centre[:, 0]) <= 3.0 + 1e-9).all()  # a dashed centre line
    lines = marks[marks[:, 3] - marks[:, 1] < 0.2]
    assert not ((lines[:, 0] < 2.5) & (lines[:, 2] > -2.5)).any()  # no line runs through the crossing
    zebra = marks[(marks[:, 0] == -2.0) & (marks[:, 2] == 2.0)]
    assert len(zebra) >= 6 and np.allclose(zebra[:, 3] - zebra[:, 1], 0.5)


def test_pitch_lines_lie_on_the_pitch_and_the_centre_circle_is_round():
    quads = np.array(places.pitch_lines(100.0, 54.0))
    assert (np.abs(quads[..., 0]) <= 50.0 + 1e-9).all() and (np.abs(quads[..., 1]) <= 27.0 + 1e-9).all()
    radii = np.linalg.norm(quads[-48:], axis=2)
    assert np.allclose(radii.mean(axis=1), 9.15, atol=0.01)


def test_places_take_the_look_of_their_role():
    looks = {}
    for env in ("urban", "green", "middle", "stadium"):
        for i, c in enumerate(ENVIRONMENT_SCENES[env].colliders):
            if c.pixel_class in ("road", "terrain"):
                asset = collider_asset(env, i, 0)
                top = next(k for k, (name, *_) in enumerate(asset.parts) if name == "top")
                first = asset.parts[top][1]
                looks.setdefault((env, c.pixel_class, bool(_carriageway(env, c)[0])), set()).add(
                    int(asset.materials[asset.triangles[first, 0]])
                )
    assert looks[("urban", "road", True)] == {Material.ASPHALT}
    assert looks[("urban", "road", False)] == {Material.PAVING}
    assert looks[("green", "terrain", False)] == {Material.GRASS}
    ground = places.ground(50.0, 0.0, indoor=False, pitch=(100.0, 54.0))
    assert {int(m) for m in np.unique(ground.materials)} == {Material.GRASS, Material.PITCH, Material.PLAIN}
    assert ground.pixel_classes() == ("terrain",)


def test_trees_come_in_several_species_and_a_tree_s_trunk_and_crown_agree():
    barks = {}
    for env in ENVIRONMENT_SCENES.names:
        for i, c in enumerate(ENVIRONMENT_SCENES[env].colliders):
            if c.pixel_class == "tree":
                asset = collider_asset(env, i, 0)
                bark = asset.colours[asset.materials == Material.BARK]
                barks.setdefault((env, c.center[0], c.center[1]), set()).add(tuple(np.round(bark[0], 3)))
    assert all(len(b) == 1 for b in barks.values())  # the crown's boughs in its trunk's bark
    assert len({next(iter(b)) for b in barks.values()}) >= 2


def test_no_material_code_outgrows_the_vertex_packing():
    assert max(Material) < 256  # gl packs surface × 256 + pattern into one integer


def _plain_quad_frame(ctx, material: Material):
    from phav_generator.render.assets import asset_drawable, turntable

    asset = places.slab((2.0, 2.0, 0.05), stream(0, "q"), 0, cls="terrain", look=(material, (0.3, 0.5, 0.2)))
    still = np.broadcast_to(np.eye(4), (2, 4, 4))
    # The top seen from above, large enough that the finest patterns are not faded out.
    return turntable(ctx, [asset_drawable(asset, still)], asset, angles=(30.0,), height=256, elevation_deg=60.0)[0]


def _inner_top(frame) -> np.ndarray:
    """The slab's top pixels away from its edge: the raw colour is anti-aliased, so its edge
    pixels blend in the sky."""
    top = frame.class_id == PIXEL_CLASSES["terrain"].class_id
    inner = top.copy()
    inner[1:-1, 1:-1] &= top[:-2, 1:-1] & top[2:, 1:-1] & top[1:-1, :-2] & top[1:-1, 2:]
    return inner


@pytest.mark.parametrize(
    "material",
    [Material.GRASS, Material.WALLPAPER, Material.SEATS, Material.FLOOR_TILES, Material.SHORE],
    ids=lambda m: m.name,
)
def test_the_later_materials_reach_the_shader(ctx, material):
    plain = _plain_quad_frame(ctx, Material.PLAIN)
    grass = _plain_quad_frame(ctx, material)
    inner = _inner_top(plain)
    pairs = inner[:, 1:] & inner[:, :-1]
    assert pairs.sum() > 500

    def grain(frame) -> float:  # mean colour step between neighbouring pixels of the slab
        c = frame.colour.astype(np.float64)
        return float(np.abs(c[:, 1:] - c[:, :-1]).sum(axis=2)[pairs].mean())

    assert grain(grass) > 2.0 * grain(plain)  # the pattern (code 16 and up) is drawn, not lost in packing


def test_foliage_is_lit_clumps_with_shadowed_gaps_and_keeps_its_colour_s_brightness(ctx):
    plain = _plain_quad_frame(ctx, Material.PLAIN)
    leaves = _plain_quad_frame(ctx, Material.LEAVES)
    inner = _inner_top(plain)
    ratio = leaves.colour.astype(np.float64).sum(axis=2)[inner] / plain.colour.astype(np.float64).sum(axis=2)[inner]
    assert inner.sum() > 5000
    assert 0.85 < ratio.mean() < 1.2  # the clumps' light and the gaps' shadow average out
    assert 0.05 < (ratio < 0.5).mean() < 0.35  # gaps in shadow between the clumps ...
    assert np.median(ratio) > 1.0  # ... and most of the surface a lit clump


@pytest.mark.parametrize("material", [Material.ASPHALT, Material.PAVING, Material.LEAVES], ids=lambda m: m.name)
def test_roads_and_foliage_keep_grain_at_the_pixel_s_scale_near_and_far(ctx, material):
    """A 40 m slab seen at a low angle: each octave of its material's grain fades out under
    the pixel (no aliasing) and hands over to the next coarser one, so the pixel-to-pixel
    contrast stays near and far. Where the fine octaves had faded and the coarse cells
    spanned many pixels, a street model took a smooth grey road for a car's paint."""
    from phav_generator.render.assets import asset_drawable, turntable

    asset = places.slab((20.0, 20.0, 0.05), stream(0, "g"), 0, cls="terrain", look=(material, (0.3, 0.3, 0.3)))
    still = np.broadcast_to(np.eye(4), (2, 4, 4))
    frame = turntable(
        ctx, [asset_drawable(asset, still)], asset, angles=(30.0,), height=256, elevation_deg=8.0, zoom=2.5
    )[0]
    inner = _inner_top(frame)
    rows = np.flatnonzero(inner.any(axis=1))
    near, far = rows[rows > np.percentile(rows, 75)], rows[rows < np.percentile(rows, 25)]
    contrast = measure_script("pixel_grain").contrast(frame.colour)  # as it measures real photographs
    for band in (near, far):
        mask = np.zeros_like(inner)
        mask[band] = inner[band]
        assert mask.sum() > 1000
        # PLAIN: 0. Near, asphalt faded to its coarse cells was 0.005 and paving 0.000 (now
        # 0.07 and 0.04); far, both about 0.02 either way.
        assert np.median(contrast[mask]) > 0.012


def test_still_neighbours_continue_one_pattern_across_their_seam(ctx):
    """Two grass slabs side by side draw the lawn one slab as large draws: a still drawable's
    materials take their patterns where it stands. Each in its own frame, the park's
    terraces met in hard-edged blocks of other patches, bands at a low angle."""
    from phav_generator.render.assets import asset_drawable
    from phav_generator.render.gl import FrameRenderer

    def lawn(slabs) -> np.ndarray:
        drawables = []
        for half, x in slabs:
            pose = np.eye(4)
            pose[0, 3] = x
            asset = places.slab(half, stream(0, "lawn"), 0, cls="terrain", look=places.GRASS)
            drawables.append(asset_drawable(asset, np.broadcast_to(pose, (2, 4, 4))))
        c2w = np.eye(4)
        c2w[:3, :3], c2w[:3, 3] = look_at(np.array([0.0, -14.0, 2.5]), np.array([0.0, 4.0, 0.0])), (0.0, -14.0, 2.5)
        with FrameRenderer(ctx, 170, 128, drawables, sky_class=PIXEL_CLASSES["sky"].class_id,
                           focus=np.zeros(3)) as renderer:  # fmt: skip
            return renderer.render(0, c2w, c2w, (150.0, 150.0, 85.0, 64.0)).colour.astype(np.float64)

    one = lawn([((16.0, 16.0, 0.05), 0.0)])
    two = lawn([((8.0, 16.0, 0.05), -8.0), ((8.0, 16.0, 0.05), 8.0)])
    assert np.abs(one - two).max(axis=2).mean() < 0.5  # 8-bit levels; each in its own frame: 8.6
    assert (np.abs(one - two).max(axis=2) > 8).mean() < 0.01


def _sky(ctx, cover: float, lighting=None, towards=(0.0, 1.0, 0.5)) -> np.ndarray:
    """The sky seen ``towards`` a direction (27° above the horizon by default)."""
    from phav_generator.render.assets import asset_drawable
    from phav_generator.render.gl import FrameRenderer, _default_lighting

    lighting = dataclasses.replace(lighting or _default_lighting(), cloud_cover=cover)
    c2w = np.eye(4)
    c2w[:3, :3] = look_at(np.zeros(3), np.asarray(towards, dtype=np.float64))
    below = places.ground(5.0, -100.0, indoor=False)  # out of view: the renderer wants something to draw
    drawables = [asset_drawable(below, np.broadcast_to(np.eye(4), (1, 4, 4)))]
    with FrameRenderer(ctx, 96, 64, drawables, sky_class=PIXEL_CLASSES["sky"].class_id, focus=np.zeros(3),
                       lighting=lighting) as renderer:  # fmt: skip
        return renderer.render(0, c2w, c2w, (80.0, 80.0, 48.0, 32.0)).colour.astype(np.float64)


def test_clouds_cover_the_sky_as_theta_s_cloud_intensity_says(ctx):
    clear, broken, overcast = (_sky(ctx, c) for c in (0.0, 0.5, 0.95))
    grey = np.abs(broken - broken.mean(axis=2, keepdims=True)).sum(axis=2) < 6  # cloud is grey-white
    grey_clear = np.abs(clear - clear.mean(axis=2, keepdims=True)).sum(axis=2) < 6
    grey_overcast = np.abs(overcast - overcast.mean(axis=2, keepdims=True)).sum(axis=2) < 6
    assert grey_clear.mean() < 0.05 < grey.mean() < grey_overcast.mean()
    assert luma(overcast).std() < 1.0 < 2.5 < luma(broken).std()  # a deck, not bellies


def test_a_clear_sunset_glows_low_in_the_sun_s_quarter_and_stays_blue_above_and_opposite(ctx):
    from phav_generator.render.lighting import lighting_for
    from phav_generator.vary import vary
    from tests.generator.physics.support import recipe_for, theta_for

    dusk = {"weather": "clear", "clouds": False, "fog": False, "rain": False, "day_phase": "dusk", "clock_hour": 18.0}
    world = vary(recipe_for("walk", "simple"), theta_for("walk", "simple"), dusk).world
    lighting = lighting_for(world, indoor=False)
    sun = lighting.sun_dir[:2] / np.linalg.norm(lighting.sun_dir[:2])
    up = math.tan(math.radians(5.0))
    rb = {}  # red minus blue, where the camera looks
    for name, d in (("towards", (*sun, up)), ("opposite", (*-sun, up)), ("above", (*sun, 2.0))):
        sky = _sky(ctx, 0.0, lighting, d)
        rb[name] = float((sky[..., 0] - sky[..., 2]).mean())
    assert rb["towards"] > 0.0  # warm near the sun
    assert rb["opposite"] < rb["towards"] - 10.0 and rb["above"] < -30.0  # blue elsewhere


def test_a_stand_s_tiers_show_their_seats_to_the_pitch():
    env = ENVIRONMENT_SCENES["stadium"]
    tiers = [i for i, c in enumerate(env.colliders) if c.pixel_class == "stairs" and min(c.half_size[:2]) <= 1.0]
    assert len(tiers) == 4 + 4 + 6  # north, south and both sides
    for i in tiers:
        c = env.colliders[i]
        tier = collider_asset("stadium", i, 0)
        seats = np.isin(tier.triangles, np.flatnonzero(tier.materials == Material.SEATS)).all(axis=1)
        assert seats.any() and set(tier.pixel_classes()) == {"stairs"}
        t = tier.positions[tier.triangles[seats]]
        normal = np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0])
        to_pitch = -np.array(c.to_local(0.0, 0.0))  # the box's centre seen from the pitch's, in its frame
        assert np.all(normal[:, :2] @ -to_pitch > 0)  # facing the pitch
        assert t[..., 2].min() == pytest.approx(c.half_size[2] - places.SEAT_M, abs=1e-5)  # the face's top


def test_each_goal_stands_on_its_goal_line_and_is_drawn_as_white_bars():
    env = ENVIRONMENT_SCENES["stadium"]
    bars = [(i, c) for i, c in enumerate(env.colliders) if c.pixel_class == "misc"]
    assert sorted({c.center[0] for _, c in bars}) == [-50.0, 50.0]  # the pitch is 100 m long
    for x in (-50.0, 50.0):
        posts = sorted(c.center[1] for _, c in bars if c.center[0] == x and c.half_size[2] > 1.0)
        assert posts[1] - posts[0] - 0.12 == pytest.approx(7.32)  # between the posts' inner faces
    for i, c in bars:
        bar = collider_asset("stadium", i, 0)
        lo, hi = bar.bounds()
        assert np.allclose(hi - lo, 2 * np.array(c.half_size), atol=0.01)
        assert set(bar.pixel_classes()) == {"misc"} and np.all(bar.colours.min(axis=1) > 0.9)


def test_reeds_stand_in_the_lake_s_shallows_off_every_walker_s_path():
    env = ENVIRONMENT_SCENES["lake"]
    x0, y0, x1, y1, level = env.water
    beds = [(i, c) for i, c in enumerate(env.colliders) if c.pixel_class == "vegetation" and x0 <= c.center[0] <= x1
            and y0 <= c.center[1] <= y1]  # fmt: skip
    assert len(beds) == 3
    graph = np.array(env.background_waypoints)[:, :2]
    for i, c in beds:
        assert c.bottom == env.ground_z and c.top > level + 1.0  # on the bed, well out of the water
        reeds = collider_asset("lake", i, 0)
        assert set(reeds.pixel_classes()) == {"vegetation"}
        lo, hi = reeds.bounds()
        assert np.all(lo >= -np.array(c.half_size) - 1e-5) and np.all(hi <= np.array(c.half_size) + 1e-5)
        for a, b in itertools.combinations(graph, 2):  # background walkers go straight between waypoints
            along = [a + t * (b - a) for t in np.linspace(0.0, 1.0, 400)]
            assert min(c.xy_distance(*pt) for pt in along) > 0.5
    for level_ in range(1, 3):  # coarser levels: fewer blades
        assert (
            collider_asset("lake", beds[0][0], level_).n_triangles
            < collider_asset("lake", beds[0][0], level_ - 1).n_triangles
        )


def test_the_lake_s_banks_have_a_shore_along_the_water_and_nowhere_else():
    env = ENVIRONMENT_SCENES["lake"]
    x0, y0, x1, y1, _ = env.water
    banks = [(i, c) for i, c in enumerate(env.colliders) if c.pixel_class == "terrain"]
    assert len(banks) == 4
    for i, c in banks:
        bank = collider_asset("lake", i, 0)
        p = bank.positions.astype(np.float64)[bank.materials == Material.SHORE] + np.array(c.center)  # not turned
        top = p[p[:, 2] > c.top]  # the strip on the bank (the rest is its muddy side)
        assert len(top) and np.all(top[:, 2] - c.top < 0.01)
        # the strip lies outside the water and within SHORE_M of it ...
        dx = np.maximum(np.maximum(x0 - top[:, 0], top[:, 0] - x1), 0.0)
        dy = np.maximum(np.maximum(y0 - top[:, 1], top[:, 1] - y1), 0.0)
        assert np.all(np.hypot(dx, dy) <= places.SHORE_M + 1e-4)
        # ... and its water side runs the whole length where the bank's side meets the water
        (lo_x, lo_y), (hi_x, hi_y) = np.array(c.center[:2]) - c.half_size[:2], np.array(c.center[:2]) + c.half_size[:2]
        if abs(hi_x - x0) < 1e-6 or abs(lo_x - x1) < 1e-6:  # a west or east bank
            on = np.isclose(top[:, 0], x0 if abs(hi_x - x0) < 1e-6 else x1)
            assert np.ptp(top[on, 1]) == pytest.approx(min(hi_y, y1) - max(lo_y, y0))
        else:  # a south or north bank
            on = np.isclose(top[:, 1], y0 if abs(hi_y - y0) < 1e-6 else y1)
            assert np.ptp(top[on, 0]) == pytest.approx(min(hi_x, x1) - max(lo_x, x0))
    for name in ENVIRONMENT_SCENES.names:
        if ENVIRONMENT_SCENES[name].water is None:
            for i, c in enumerate(ENVIRONMENT_SCENES[name].colliders):
                if c.pixel_class == "terrain":
                    assert not (collider_asset(name, i, 0).materials == Material.SHORE).any()


def _part_triangles(asset, prefix: str) -> np.ndarray:
    """(m, 3, 3): the corners of every triangle of the parts so named (one per look)."""
    return np.concatenate([c for _, c in part_corners(asset, prefix)] or [np.zeros((0, 3, 3))])


def test_a_house_s_front_door_stands_where_no_window_is():
    doors = 0
    for i, c in enumerate(ENVIRONMENT_SCENES["middle"].colliders):
        if c.pixel_class != "building":
            continue
        asset = collider_asset("middle", i, 0)
        door = _part_triangles(asset, "door").reshape(-1, 3)
        if not len(door):
            continue
        doors += 1
        lo, hi = door.min(axis=0), door.max(axis=0)
        across = int(np.argmin(hi - lo))  # the door lies in the plane of its face
        along = [a for a in range(3) if a != across]
        panes = _part_triangles(asset, "pane")
        on_face = np.abs(panes[:, :, across].mean(axis=1) - lo[across]) < 0.5
        p_lo, p_hi = panes.min(axis=1)[on_face], panes.max(axis=1)[on_face]
        overlap = np.all((p_lo[:, along] < hi[along]) & (p_hi[:, along] > lo[along]), axis=1)
        assert not overlap.any(), f"middle building {i}: a window behind the door"
    assert doors >= 2


@pytest.mark.parametrize("species", ["broadleaf", "birch"])
def test_a_crown_s_clumps_keep_their_height_and_reach_at_every_level_of_detail(species):
    """A coarser level spreads fewer clumps evenly round the trunk; each keeps the height and
    reach it has at the finest level (its lumps and segments aside)."""
    half = (2.0, 2.0, 2.0)
    crowns = [places.crown(half, stream(3, "crown"), level, species=species) for level in range(3)]

    def centres(asset) -> dict[str, np.ndarray]:
        return {name: c.reshape(-1, 3).mean(axis=0) for name, c in part_corners(asset, "clump")}

    finest = centres(crowns[0])
    for coarser in crowns[1:]:
        shared = centres(coarser)
        assert shared and set(shared) < set(finest)
        for name, at in shared.items():
            assert abs(at[2] - finest[name][2]) < 0.06, name
            assert abs(math.hypot(*at[:2]) - math.hypot(*finest[name][:2])) < 0.06, name
