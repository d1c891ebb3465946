"""Static collision geometry: every waypoint stands on something, people have room to act,
classes agree with the environment, background paths keep off obstacles, support_height."""

from __future__ import annotations

import dataclasses
import itertools
import math

import numpy as np
import pytest

from phav_spec.scene import (
    ENVIRONMENT_SCENES,
    MAX_STEP_M,
    WALKABLE_PIXEL_CLASSES,
    Collider,
    EnvironmentScene,
    support_height,
)
from phav_spec.vocab import ENVIRONMENTS

#: Free radius around each protagonist waypoint (all environments, house_interior included),
#: and the height band it covers above the standing height.
CLEARANCE_RADIUS_M = 3.0
CLEARANCE_BAND_M = (0.05, 2.5)
#: A protagonist waypoint's support extends this far around it (a person moves a few metres).
SUPPORT_MARGIN_M = 3.0
SUPPORT_TOLERANCE_M = 1e-3
#: A background pedestrian's body: radius and height.
BODY_RADIUS_M = 0.35
BODY_HEIGHT_M = 1.8
#: At most this many static boxes a scene (the house with its garden has 74): the physics
#: broad phase and the renderer take one geom and one drawable each.
MAX_COLLIDERS = 80

#: Classes that need no collider: sky, the ground plane's classes, catch-all misc, and the
#: vehicles, which drive (dynamic); parked cars may still be colliders.
NO_COLLIDER_NEEDED = {"sky", "terrain", "floor", "misc", "car", "truck", "bus"}
#: Things fixed to a wall rather than standing on a surface.
MOUNTED_CLASSES = {"curtain", "screen", "window", "door"}

ENV_ITEMS = ENVIRONMENT_SCENES.items()
PROTAGONIST_CASES = [(name, wp) for name, env in ENV_ITEMS for wp in env.protagonist_waypoints]
BACKGROUND_CASES = [(name, wp) for name, env in ENV_ITEMS for wp in env.background_waypoints]


def _supports(env: EnvironmentScene, wp, margin: float) -> list[Collider]:
    x, y, z = wp
    return [c for c in env.colliders if abs(c.top - z) <= SUPPORT_TOLERANCE_M and c.contains_xy(x, y, margin)]


def _segment_footprint_distance(c: Collider, a, b) -> float:
    """Horizontal distance between the segment a–b and the collider's footprint (0 if they meet)."""
    ax, ay = c.to_local(a[0], a[1])
    bx, by = c.to_local(b[0], b[1])
    hx, hy = c.half_size[0], c.half_size[1]
    dx, dy = bx - ax, by - ay
    t0, t1 = 0.0, 1.0  # Liang–Barsky clipping of the segment against the rectangle
    for p, q in ((-dx, ax + hx), (dx, hx - ax), (-dy, ay + hy), (dy, hy - ay)):
        if p == 0.0:
            if q < 0.0:
                break
        else:
            t = q / p
            t0, t1 = (max(t0, t), t1) if p < 0 else (t0, min(t1, t))
            if t0 > t1:
                break
    else:
        return 0.0

    def to_rect(px: float, py: float) -> float:
        return math.hypot(max(abs(px) - hx, 0.0), max(abs(py) - hy, 0.0))

    def to_segment(px: float, py: float) -> float:
        t = max(0.0, min(1.0, ((px - ax) * dx + (py - ay) * dy) / (dx * dx + dy * dy)))
        return math.hypot(ax + t * dx - px, ay + t * dy - py)

    corners = [to_segment(sx * hx, sy * hy) for sx in (-1, 1) for sy in (-1, 1)]
    return min(to_rect(ax, ay), to_rect(bx, by), *corners)


# --- the Collider box ---------------------------------------------------------------------


def test_collider_geometry_follows_its_yaw():
    c = Collider("building", (10, 0, 5), (4, 1, 5), 90)
    assert isinstance(c.center[0], float) and c.bottom == 0.0 and c.top == 10.0
    # Turned by 90°: its long local x axis runs along world y.
    assert c.contains_xy(10.0, 3.9) and not c.contains_xy(13.9, 0.0)
    assert c.contains_xy(10.0, 0.9, margin=0.5) and not c.contains_xy(10.0, 3.9, margin=0.5)
    assert c.xy_distance(10.0, 0.0) == 0.0
    assert c.xy_distance(13.0, 0.0) == pytest.approx(2.0)
    assert c.xy_distance(12.0, 7.0) == pytest.approx(math.hypot(1.0, 3.0))
    # many points at once (the physics plan's obstacles): each as xy_distance says, bit for bit
    px, py = np.array([10.0, 13.0, 12.0, 8.5]), np.array([0.0, 0.0, 7.0, -4.5])
    gx, gy = c.xy_gaps(px, py)
    each = [c.xy_distance(x, y) for x, y in zip(px, py, strict=True)]
    assert [math.hypot(a, b) for a, b in zip(gx, gy, strict=True)] == each
    xs, ys = zip(*c.footprint(), strict=True)
    assert (min(xs), max(xs), min(ys), max(ys)) == pytest.approx((9.0, 11.0, -4.0, 4.0))
    assert hash(c) == hash(Collider("building", (10.0, 0.0, 5.0), (4.0, 1.0, 5.0), 90.0))
    with pytest.raises(dataclasses.FrozenInstanceError):
        c.yaw_deg = 0.0  # type: ignore[misc]


def test_collider_rejects_bad_boxes():
    with pytest.raises(KeyError):
        Collider("skyscraper", (0, 0, 1), (1, 1, 1))
    for cls in ("sky", "unlabeled", "ball", "head", "left_knee"):  # not static scene geometry
        with pytest.raises(ValueError):
            Collider(cls, (0, 0, 1), (1, 1, 1))
    for half in ((0, 1, 1), (1, -1, 1), (1, 1, math.inf), (1, math.nan, 1)):
        with pytest.raises(ValueError):
            Collider("building", (0, 0, 1), half)
    for center in ((math.nan, 0, 0), (0, math.inf, 0)):
        with pytest.raises(ValueError):
            Collider("building", center, (1, 1, 1))
    with pytest.raises(ValueError):
        Collider("building", (0, 0, 1), (1, 1, 1), math.inf)
    with pytest.raises(ValueError):
        Collider("building", (0, 0), (1, 1, 1))  # type: ignore[arg-type]


def test_environment_scene_checks_its_colliders():
    simple = ENVIRONMENT_SCENES["simple"]
    kwargs = dict(
        indoor=False,
        pixel_classes=simple.pixel_classes,
        protagonist_waypoints=simple.protagonist_waypoints,
        background_waypoints=simple.background_waypoints,
    )
    assert EnvironmentScene(**kwargs).colliders == () and EnvironmentScene(**kwargs).ground_z == 0.0
    with pytest.raises(ValueError, match="not one of the environment's pixel classes"):
        EnvironmentScene(**kwargs, colliders=(Collider("building", (0, 0, 5), (1, 1, 5)),))
    with pytest.raises(TypeError):
        EnvironmentScene(**kwargs, colliders=(("road", (0, 0, 0), (1, 1, 1)),))  # type: ignore[arg-type]
    with pytest.raises(ValueError):
        EnvironmentScene(**kwargs, ground_z=math.nan)


# --- per-environment declarations ---------------------------------------------------------


@pytest.mark.parametrize("name", ENVIRONMENTS.names)
def test_collider_classes_match_the_environment(name):
    env = ENVIRONMENT_SCENES[name]
    assert 0 < len(env.colliders) <= MAX_COLLIDERS
    used = {c.pixel_class for c in env.colliders}
    assert used <= set(env.pixel_classes)
    missing = set(env.pixel_classes) - NO_COLLIDER_NEEDED - used
    assert not missing, f"{name}: static classes with no collider: {sorted(missing)}"
    assert env.ground_pixel_class == ("floor" if env.indoor else "terrain")
    assert env.ground_pixel_class in env.pixel_classes


@pytest.mark.parametrize(("name", "wp"), PROTAGONIST_CASES)
def test_protagonist_waypoint_stands_on_a_support(name, wp):
    env = ENVIRONMENT_SCENES[name]
    on_plane = wp[2] == env.ground_z
    assert on_plane or _supports(env, wp, SUPPORT_MARGIN_M), f"{name} {wp}: nothing to stand on"
    assert support_height(name, wp[0], wp[1], reference_z=wp[2]) == pytest.approx(wp[2], abs=SUPPORT_TOLERANCE_M)


@pytest.mark.parametrize(("name", "wp"), PROTAGONIST_CASES)
def test_protagonist_waypoint_has_room_to_act(name, wp):
    env = ENVIRONMENT_SCENES[name]
    x, y, z = wp
    low, high = z + CLEARANCE_BAND_M[0], z + CLEARANCE_BAND_M[1]
    own = set(map(id, _supports(env, wp, SUPPORT_MARGIN_M)))
    for c in env.colliders:
        if id(c) in own or c.top <= low or c.bottom >= high:
            continue
        assert c.xy_distance(x, y) >= CLEARANCE_RADIUS_M, f"{name} {wp}: {c} intrudes"


@pytest.mark.parametrize(("name", "wp"), BACKGROUND_CASES)
def test_background_waypoint_stands_on_a_support_and_is_free(name, wp):
    env = ENVIRONMENT_SCENES[name]
    x, y, z = wp
    assert wp[2] == env.ground_z or _supports(env, wp, 0.0), f"{name} {wp}: nothing to stand on"
    intruders = [
        c
        for c in env.colliders
        if c.top > z + CLEARANCE_BAND_M[0] and c.bottom < z + BODY_HEIGHT_M and c.xy_distance(x, y) < BODY_RADIUS_M
    ]
    assert not intruders, f"{name} {wp}: inside {intruders}"


@pytest.mark.parametrize("name", [n for n, e in ENV_ITEMS if e.background_waypoints])
def test_background_paths_keep_off_obstacles(name):
    """Background actors walk straight between any two waypoints; only walkable surfaces at
    most one step up (terraces, steps, roads) may lie on those lines."""
    env = ENVIRONMENT_SCENES[name]
    for a, b in itertools.combinations(env.background_waypoints, 2):
        z_max = max(a[2], b[2])
        for c in env.colliders:
            walkable = c.pixel_class in WALKABLE_PIXEL_CLASSES and c.top <= z_max + MAX_STEP_M
            if walkable or c.bottom >= z_max + BODY_HEIGHT_M:
                continue
            assert _segment_footprint_distance(c, a, b) >= BODY_RADIUS_M, f"{name} {a}->{b} meets {c}"


@pytest.mark.parametrize("name", ENVIRONMENTS.names)
def test_standing_things_rest_on_a_surface(name):
    """Anything low enough to stand (not a tree crown, roof or lamp shade) stands on the ground
    or on a walkable surface, unless fixed to a wall or standing on a part of its own object
    (a bench's back on its seat)."""
    env = ENVIRONMENT_SCENES[name]
    for c in env.colliders:
        if c.pixel_class in {*WALKABLE_PIXEL_CLASSES, *MOUNTED_CLASSES} or c.bottom > env.ground_z + 1.0:
            continue
        on_own_part = [o for o in env.colliders if o is not c and o.pixel_class == c.pixel_class
                       and o.top == pytest.approx(c.bottom, abs=1e-6) and o.contains_xy(*c.center[:2])]  # fmt: skip
        if on_own_part:
            continue
        surface = support_height(name, c.center[0], c.center[1], reference_z=c.bottom)
        assert c.bottom == pytest.approx(surface, abs=1e-6), f"{name}: {c} floats or sinks"


# --- the character of each environment ----------------------------------------------------


def test_simple_is_flat_ground_and_a_road():
    env = ENVIRONMENT_SCENES["simple"]
    assert {c.pixel_class for c in env.colliders} == {"road"}
    assert all(c.top == pytest.approx(env.ground_z) for c in env.colliders)  # flush with the ground


@pytest.mark.parametrize("name", ["urban", "middle"])
def test_every_street_waypoint_has_a_sign_or_signal_in_view(name):
    """The camera frames the people, within 10 m of them: a street's signs and signals stand
    where its protagonists act, not only where nobody is filmed."""
    env = ENVIRONMENT_SCENES[name]
    furniture = [c for c in env.colliders if c.pixel_class in ("traffic_sign", "traffic_light")]
    for x, y, _ in env.protagonist_waypoints:
        nearest = min(c.xy_distance(x, y) for c in furniture)
        assert nearest <= 15.0, f"{name} ({x}, {y}): the nearest sign or signal is {nearest:.1f} m away"


def test_every_park_waypoint_has_a_tree_near_it():
    """A park's trees stand among its paths, where its protagonists act and the camera looks,
    not only round its edge (a crown 30 m off is a few pixels a frame)."""
    from phav_generator.world.library import TRUNK_HALF_M  # the library's rule for a trunk

    env = ENVIRONMENT_SCENES["green"]
    trunks = [c for c in env.colliders if c.pixel_class == "tree" and min(c.half_size[:2]) < TRUNK_HALF_M]
    for x, y, _ in env.protagonist_waypoints:
        nearest = min(c.xy_distance(x, y) for c in trunks)
        assert nearest <= 13.0, f"green ({x}, {y}): the nearest tree is {nearest:.1f} m away"


def test_urban_has_tall_buildings_and_steps_up_to_the_plaza():
    env = ENVIRONMENT_SCENES["urban"]
    heights = [c.top - c.bottom for c in env.colliders if c.pixel_class == "building"]
    assert len(heights) >= 4 and all(10.0 <= h <= 30.0 for h in heights)
    steps = sorted((c for c in env.colliders if c.pixel_class == "stairs"), key=lambda c: c.top)
    assert len(steps) >= 2 and all(0.0 < c.top < 0.6 for c in steps)
    assert all(c.xy_distance(30.0, 10.0) < 6.0 for c in steps)
    assert all(c.top == pytest.approx(env.ground_z) for c in env.colliders if c.pixel_class == "road" and c.top < 0.1)


def test_stadium_stand_carries_the_raised_waypoint():
    (terrace,) = _supports(ENVIRONMENT_SCENES["stadium"], (0.0, 32.0, 1.5), SUPPORT_MARGIN_M)
    assert terrace.pixel_class == "stairs"
    assert support_height("stadium", 0.0, 32.0) == 0.0  # a 1.5 m terrace is no step up from the pitch
    assert support_height("stadium", 0.0, 32.0, reference_z=1.5) == pytest.approx(1.5)
    assert support_height("stadium", 0.0, 37.0, reference_z=1.5) == pytest.approx(2.0)  # the next tier


def test_lake_water_is_no_collider():
    env = ENVIRONMENT_SCENES["lake"]
    assert not [c for c in env.colliders if c.contains_xy(0.0, 2.0)]  # the lake's middle
    assert support_height("lake", 0.0, 2.0) == env.ground_z
    banks = [support_height("lake", x, y) for x, y in ((0.0, -12.0), (16.0, 0.0), (-16.0, 2.0), (0.0, 20.0))]
    assert banks == pytest.approx([0.2, 0.3, 0.3, 0.4]) and min(banks) > env.ground_z


def test_the_lake_s_reed_beds_stand_in_its_water_and_nothing_else_does():
    lake = ENVIRONMENT_SCENES["lake"]
    in_water = [c for c in lake.colliders if lake.in_water(c)]
    # The three beds off the promenade, all vegetation; the park's shrubs and trees on land.
    assert len(in_water) == 3 and {c.pixel_class for c in in_water} == {"vegetation"}
    assert any(c.pixel_class == "vegetation" and not lake.in_water(c) for c in lake.colliders)
    assert not any(ENVIRONMENT_SCENES["green"].in_water(c) for c in ENVIRONMENT_SCENES["green"].colliders)


def test_house_interior_is_a_closed_furnished_room():
    env = ENVIRONMENT_SCENES["house_interior"]
    walls = [c for c in env.colliders if c.pixel_class == "misc"]
    assert len(walls) == 4 and all(c.top >= 2.8 for c in walls)
    xs = [p[0] for c in walls for p in c.footprint()]
    ys = [p[1] for c in walls for p in c.footprint()]
    for x, y, _ in env.protagonist_waypoints:  # the walls box every waypoint in
        assert min(xs) < x < max(xs) and min(ys) < y < max(ys)
        assert any(c.pixel_class == "ceiling" and c.contains_xy(x, y) and 2.7 <= c.bottom <= 3.0 for c in env.colliders)
    for cls in ("window", "door"):  # set into the walls
        for c in (c for c in env.colliders if c.pixel_class == cls):
            assert any(
                min(c.xy_distance(*p) for p in w.footprint()) < 0.5 or w.contains_xy(*c.center[:2]) for w in walls
            )


# --- support_height --------------------------------------------------------------------------


def test_support_height_on_the_plane_terraces_and_steps():
    assert support_height("simple", 0.0, 0.0) == 0.0
    assert support_height("simple", 500.0, -300.0) == 0.0
    assert support_height("urban", 30.0, 10.0) == pytest.approx(0.6)  # the plaza
    assert support_height("urban", 40.0, 12.0) == pytest.approx(0.6)
    assert support_height("urban", 25.3, 12.0) == pytest.approx(0.2)  # first step
    assert support_height("urban", 25.8, 12.0) == pytest.approx(0.4)  # second step
    assert support_height("urban", 2.0, 6.0) == 0.0  # a sidewalk flush with the ground
    assert support_height("urban", -5.0, 11.7) == 0.0  # a bench is no floor
    assert support_height("green", 0.0, -25.0) == pytest.approx(-0.2)  # the base plane
    assert support_height("green", 12.0, -2.0) == pytest.approx(0.2)
    assert support_height("green", 8.0, 3.0) == pytest.approx(0.1)
    assert support_height("house_interior", 0.0, 0.0) == 0.0
    assert support_height("house_interior", 8.85, 4.25) == pytest.approx(0.2)  # the staircase's first step
    assert support_height("house_interior", 8.85, 4.85) == pytest.approx(0.6)  # the third
    assert support_height("house_interior", 8.85, 7.9) == 0.0  # top step, 2.6 m: not one step up
    with pytest.raises(KeyError):
        support_height("moon", 0.0, 0.0)


@pytest.mark.parametrize(("name", "wp"), PROTAGONIST_CASES + BACKGROUND_CASES)
def test_support_height_at_waypoints(name, wp):
    """Every waypoint up to one step above the ground is found from the ground; the rest
    (the stadium stand) from their own height."""
    env = ENVIRONMENT_SCENES[name]
    if wp[2] - env.ground_z <= MAX_STEP_M:
        assert support_height(name, wp[0], wp[1]) == pytest.approx(wp[2], abs=SUPPORT_TOLERANCE_M)
    assert support_height(name, wp[0], wp[1], reference_z=wp[2]) == pytest.approx(wp[2], abs=SUPPORT_TOLERANCE_M)


# --- traffic lanes --------------------------------------------------------------------------


@pytest.mark.parametrize("name", ENVIRONMENTS.names)
def test_lanes_run_on_the_road_clear_of_everything_else(name):
    """Every lane lies on a road slab end to end, and its widest vehicle keeps off every other
    collider (parked cars, poles, rails) over its whole length."""
    from phav_spec.scene import VEHICLE_HALF_SIZES

    env = ENVIRONMENT_SCENES[name]
    roads = [c for c in env.colliders if c.pixel_class == "road"]
    for lane in env.lanes:
        for t in (0.0, 0.25, 0.5, 0.75, 1.0):
            x = lane.start[0] + t * (lane.end[0] - lane.start[0])
            y = lane.start[1] + t * (lane.end[1] - lane.start[1])
            assert any(abs(r.top - lane.start[2]) < 1e-6 and r.contains_xy(x, y, 0.0) for r in roads), (name, x, y)
        body = max(VEHICLE_HALF_SIZES[v][1] for v in lane.vehicles)
        for c in env.colliders:
            if c.pixel_class != "road":
                gap = _segment_footprint_distance(c, lane.start, lane.end)
                assert gap > body, f"{name}: a lane passes {gap:.2f} m from a {c.pixel_class}"
    if env.indoor:
        assert not env.lanes
    assert bool(env.lanes) == (name in ("simple", "urban", "middle"))


def test_lane_rejects_bad_values():
    from phav_spec.scene import Lane

    with pytest.raises(ValueError, match="10 m"):
        Lane((0, 0, 0), (5, 0, 0), 2.0)
    with pytest.raises(ValueError, match="wider than the lane"):
        Lane((0, 0, 0), (50, 0, 0), 1.0, ("bus",))
    with pytest.raises(ValueError, match="not a vehicle"):
        Lane((0, 0, 0), (50, 0, 0), 2.0, ("ball",))
    with pytest.raises(ValueError, match="a bus is as long as the lane"):  # 12 m on 11 m: no room to drive
        Lane((0, 0, 0), (11, 0, 0), 2.0, ("car", "bus"))
    with pytest.raises(ValueError, match="finite"):
        Lane((0, math.nan, 0), (50, 0, 0), 2.0)
    with pytest.raises(ValueError, match="a lane is level"):  # traffic would float over its far end
        Lane((0, 0, 0), (50, 0, 1.0), 2.0)
    lane = ENVIRONMENT_SCENES["simple"].lanes[0]
    with pytest.raises(ValueError, match="indoor"):
        dataclasses.replace(ENVIRONMENT_SCENES["house_interior"], lanes=(lane,))


def test_a_parked_car_collides_as_the_hulls_of_its_body_type():
    """Each parked car names its body type and carries that body's hulls (``car_hulls``), inside
    its box; a hull outside its box is refused."""
    from phav_spec.car_shapes import CAR_BODIES, car_hulls, car_profile

    parked = [c for _, env in ENVIRONMENT_SCENES.items() for c in env.colliders if c.pixel_class == "car"]
    assert len(parked) == 3
    for c in parked:
        assert c.model in CAR_BODIES
        assert c.hulls == car_hulls(car_profile(c.model, c.half_size))
        assert all(abs(v) <= h + 1e-9 for hull in c.hulls for q in hull for v, h in zip(q, c.half_size, strict=True))
    corners = ((0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))
    assert Collider("car", (0, 0, 1), (1, 1, 1), hulls=(corners,)).hulls == (corners,)
    with pytest.raises(ValueError, match="inside its box"):
        Collider("car", (0, 0, 1), (1, 1, 0.5), hulls=(corners,))
    with pytest.raises(ValueError, match="four or more"):
        Collider("car", (0, 0, 1), (1, 1, 1), hulls=(corners[:3],))
    with pytest.raises(ValueError, match="enclose a volume"):
        Collider("car", (0, 0, 1), (1, 1, 1), hulls=((*corners[:3], (1.0, 1.0, 0.0)),))
    for cls, model, hulls in (("car", "limousine", (corners,)), ("car", "van", ()), ("bench", "van", (corners,))):
        with pytest.raises(ValueError, match="body type"):
            Collider(cls, (0, 0, 1), (1, 1, 1), model=model, hulls=hulls)
