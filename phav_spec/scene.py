"""Scene data the later stages must honour, declared as data.

Per action: necessary and complementary muscles, the props it needs, the props the
``objects`` variation may add, the pixel classes its environment must contain, whether a child may play it. Per
environment: indoor or not, its static pixel classes, the protagonist's waypoints and the
background actors' waypoints (indoor scenes have none, as in the paper), its ground plane
height and its static collision geometry (oriented boxes, each with its pixel class). The
20 human models of H (anny phenotypes with skin, hair and outfit).
The weather elements and their Bernoulli dependencies. The kite camera's spring variables
with their physical bounds. θ chooses distributions inside these declarations; it cannot
change them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from phav_spec.car_shapes import CAR_BODIES, car_hulls, car_profile
from phav_spec.people import Bottom, Hair, Outfit, Phenotype, Top
from phav_spec.vocab import (
    ACTIONS,
    CAMERAS,
    ENVIRONMENTS,
    MUSCLES,
    OBJECTS,
    PIXEL_CLASSES,
    PixelGroup,
    Registry,
)

Vec3 = tuple[float, float, float]
RGB = tuple[int, int, int]

#: Where a supporting character starts relative to the protagonist.
SUPPORTING_PLACEMENTS: tuple[str, ...] = ("side_by_side", "behind", "facing")

_CORE = ("pelvis", "chest")
_HEAD = ("head",)
_LEGS = (
    "left_upper_leg", "left_lower_leg", "left_foot",
    "right_upper_leg", "right_lower_leg", "right_foot",
)  # fmt: skip
_LEFT_ARM = ("left_upper_arm", "left_lower_arm", "left_hand")
_RIGHT_ARM = ("right_upper_arm", "right_lower_arm", "right_hand")
_ARMS = _LEFT_ARM + _RIGHT_ARM


@dataclass(frozen=True)
class ActionScene:
    """What an action needs from the scene (paper Sections "Actions", "Ragdoll physics")."""

    necessary_muscles: tuple[str, ...]
    objects: tuple[str, ...] = ()
    variation_objects: tuple[str, ...] = ()
    requires_classes: tuple[str, ...] = ()
    supporting_placement: str | None = None  # side_by_side, behind or facing (two people)
    #: The action needs open sky: a climb's flight rises up to 5 m within one clip, and an
    #: indoor environment's ceiling (the house's is 2.8 m) would cut through the climber.
    outdoors: bool = False
    #: The feet slide on the floor on purpose (the moonwalk's gliding stance foot): planted
    #: feet that move are the action, not a glitch.
    slides_feet: bool = False
    #: Whether θ may cast a child (``people.p_child``) in it. Not where sizes are fixed by
    #: an adult partner or prop (the two-people actions, the pull-up bar at adult reach),
    #: not in a car accident, with a gun or staggering drunk.
    children: bool = True
    complementary_muscles: tuple[str, ...] = field(init=False)

    def __post_init__(self) -> None:
        necessary = set(self.necessary_muscles)
        for m in necessary:
            MUSCLES.check(m)
        for o in self.objects + self.variation_objects:
            OBJECTS.check(o)
        for c in self.requires_classes:
            PIXEL_CLASSES.check(c)
        if self.supporting_placement not in (None, *SUPPORTING_PLACEMENTS):
            raise ValueError(f"unknown supporting placement {self.supporting_placement!r}")
        # Complementary = the rest of the 15, in registry order: the two groups are disjoint
        # and cover the ragdoll (paper: "two disjoint groups").
        rest = tuple(m for m in MUSCLES.names if m not in necessary)
        object.__setattr__(self, "necessary_muscles", tuple(m for m in MUSCLES.names if m in necessary))
        object.__setattr__(self, "complementary_muscles", rest)


_HANDHELD = ("cup", "bottle", "ball")


def _action_scenes() -> tuple[tuple[str, ActionScene], ...]:
    s = ActionScene
    scenes = {
        "brush_hair": s(_RIGHT_ARM + _HEAD + ("chest",), objects=("hair_brush",), variation_objects=("cup", "bottle")),
        "catch": s(_ARMS + _HEAD + ("chest",), objects=("ball",)),
        "clap": s(_ARMS + ("chest",)),
        "climb_stairs": s(_LEGS + _CORE, variation_objects=_HANDHELD, requires_classes=("stairs",), outdoors=True),
        "golf": s(_ARMS + _CORE + _HEAD, objects=("golf_club",)),
        "jump": s(_LEGS + _CORE, variation_objects=_HANDHELD),
        "kick_ball": s(_LEGS + ("pelvis",), objects=("ball",), variation_objects=("cup", "bottle")),
        "push": s(_ARMS + _CORE + _LEGS),
        "pick": s(_RIGHT_ARM + _CORE + _LEGS, objects=("bottle",), variation_objects=("cup", "ball")),
        "pour": s(_ARMS + ("chest",), objects=("bottle", "cup")),
        "pull_up": s(_ARMS + ("chest",), objects=("pull_up_bar",), children=False),
        "run": s(_LEGS + ("pelvis",), variation_objects=_HANDHELD),
        "shoot_ball": s(_ARMS + _LEGS + ("chest",), objects=("ball",)),
        "shoot_bow": s(_ARMS + _HEAD + ("chest",), objects=("bow",)),
        "shoot_gun": s(_ARMS + _HEAD + ("chest",), objects=("gun",), children=False),
        "sit": s(_LEGS + _CORE, objects=("chair",), variation_objects=("cup", "bottle")),
        "stand": s(_LEGS + _CORE, objects=("chair",), variation_objects=("cup", "bottle")),
        "swing_baseball": s(_ARMS + _CORE, objects=("baseball_bat",)),
        "throw": s(_RIGHT_ARM + _CORE, objects=("ball",)),
        "walk": s(_LEGS + ("pelvis",), variation_objects=_HANDHELD),
        "wave": s(_RIGHT_ARM, variation_objects=("cup", "bottle")),
        "car_hit": s(_LEGS + _CORE, objects=("car",), variation_objects=_HANDHELD, requires_classes=("road",), children=False),
        "crawl": s(_ARMS + _LEGS + _CORE),
        "dive_floor": s(_ARMS + _CORE, variation_objects=("ball",)),
        "flee": s(_LEGS + _CORE + _HEAD, variation_objects=_HANDHELD),
        "hop": s(_LEGS + ("pelvis",), variation_objects=_HANDHELD),
        "leg_split": s(_LEGS + ("pelvis",), variation_objects=("cup", "bottle")),
        "limp": s(_LEGS + ("pelvis",), variation_objects=_HANDHELD),
        "moonwalk": s(_LEGS + ("pelvis",), variation_objects=("cup", "bottle"), slides_feet=True),
        "stagger": s(_LEGS + _CORE + _HEAD, variation_objects=("bottle",), children=False),
        "surrender": s(_ARMS + ("chest",), variation_objects=("bottle",)),
        "walking_hug": s(_ARMS + _LEGS + _CORE, supporting_placement="side_by_side", children=False),
        "walk_holding_hands": s(_RIGHT_ARM + _LEGS + ("pelvis",), variation_objects=("cup", "bottle"), supporting_placement="side_by_side", children=False),
        "walk_the_line": s(_LEGS + ("pelvis",), variation_objects=_HANDHELD, supporting_placement="behind", children=False),
        "bump_into_each_other": s(_LEGS + _CORE, variation_objects=_HANDHELD, supporting_placement="facing", children=False),
    }  # fmt: skip
    for name, scene in scenes.items():
        if (ACTIONS[name].n_people > 1) != (scene.supporting_placement is not None):
            raise ValueError(f"{name}: a supporting placement is declared exactly for two-people actions")
        if scene.supporting_placement is not None and scene.children:
            raise ValueError(f"{name}: a two-people action is sized for two adults (children=False)")
    return tuple((name, scenes[name]) for name in ACTIONS.names)


#: Per-action scene data, in ACTIONS order.
ACTION_SCENES: Registry[ActionScene] = Registry("action", _action_scenes())


#: Pixel-class groups a static collider may carry: the street / nature classes and the indoor
#: ones. Props, people and joints move; they are never part of the static world.
_STATIC_GROUPS = (PixelGroup.VIRTUAL_KITTI, PixelGroup.INDOORS)

#: Classes a person may stand and walk on (``support_height``); every other class is an obstacle.
WALKABLE_PIXEL_CLASSES: tuple[str, ...] = ("terrain", "road", "floor", "stairs")

#: The highest step (metres) ``support_height`` climbs above its reference height.
MAX_STEP_M = 0.7


@dataclass(frozen=True)
class Collider:
    """A static oriented box of an environment: what physics collides with and the renderer draws.

    ``center`` and ``half_size`` in metres, world frame (+Z up); the box is turned by
    ``yaw_deg`` about +Z around its centre (counter-clockwise seen from above), so its local
    x axis points along (cos yaw, sin yaw). ``pixel_class`` labels its pixels. ``model``
    names the kind of its class it is drawn as where that decides its shape (a parked car's
    body type), and ``hulls``, where given, are the convex solids inside the box that it
    collides as in its place (each as its corners, in the box's frame): the drawn shape's.
    """

    pixel_class: str
    center: Vec3
    half_size: Vec3
    yaw_deg: float = 0.0
    model: str = ""
    hulls: tuple[tuple[Vec3, ...], ...] = ()

    def __post_init__(self) -> None:
        PIXEL_CLASSES.check(self.pixel_class)
        if PIXEL_CLASSES[self.pixel_class].group not in _STATIC_GROUPS or self.pixel_class == "sky":
            raise ValueError(f"pixel class {self.pixel_class!r} is not static scene geometry")
        if len(self.center) != 3 or len(self.half_size) != 3:
            raise ValueError("a collider's center and half_size are 3-vectors")
        center = tuple(float(v) for v in self.center)
        half = tuple(float(v) for v in self.half_size)
        yaw = float(self.yaw_deg)
        if not all(math.isfinite(v) for v in (*center, yaw)):
            raise ValueError(f"collider center and yaw must be finite, got {center}, {yaw}")
        if not all(math.isfinite(h) and h > 0.0 for h in half):
            raise ValueError(f"collider half sizes must be positive and finite, got {half}")
        hulls = tuple(tuple(tuple(float(v) for v in q) for q in hull) for hull in self.hulls)
        for hull in hulls:
            if len(hull) < 4 or any(len(q) != 3 for q in hull):
                raise ValueError("a collider's hull is four or more corners (x, y, z)")
            if not all(math.isfinite(v) and abs(v) <= h + 1e-6 for q in hull for v, h in zip(q, half, strict=True)):
                raise ValueError(f"a {self.pixel_class} collider's hull must lie inside its box {half}")
            corners = np.asarray(hull)
            if np.linalg.matrix_rank(corners - corners[0], tol=1e-6) < 3:
                raise ValueError(f"a {self.pixel_class} collider's hull must enclose a volume")
        if self.model and (self.pixel_class != "car" or self.model not in CAR_BODIES or not hulls):
            raise ValueError(f"a collider's model is a car's body type ({', '.join(CAR_BODIES)}) with its hulls, "
                             f"got {self.model!r} for a {self.pixel_class}")  # fmt: skip
        object.__setattr__(self, "center", center)
        object.__setattr__(self, "half_size", half)
        object.__setattr__(self, "yaw_deg", yaw)
        object.__setattr__(self, "hulls", hulls)

    @property
    def bottom(self) -> float:
        return self.center[2] - self.half_size[2]

    @property
    def top(self) -> float:
        return self.center[2] + self.half_size[2]

    def to_local(self, x: Any, y: Any) -> tuple[Any, Any]:
        """World (x, y) in the box's own horizontal frame (origin at its centre): floats, or
        numpy arrays of points."""
        yaw = math.radians(self.yaw_deg)
        c, s = math.cos(yaw), math.sin(yaw)
        dx, dy = x - self.center[0], y - self.center[1]
        return dx * c + dy * s, -dx * s + dy * c

    def contains_xy(self, x: float, y: float, margin: float = 0.0) -> bool:
        """Whether (x, y) lies in the footprint, at least ``margin`` metres from its edges."""
        lx, ly = self.to_local(x, y)
        return abs(lx) <= self.half_size[0] - margin and abs(ly) <= self.half_size[1] - margin

    def xy_gaps(self, x: Any, y: Any) -> tuple[Any, Any]:
        """How far (m) (x, y) lies beyond the footprint along the box's own x and y (0 within
        it): floats, or numpy arrays of points."""
        lx, ly = self.to_local(x, y)
        return np.maximum(np.abs(lx) - self.half_size[0], 0.0), np.maximum(np.abs(ly) - self.half_size[1], 0.0)

    def xy_distance(self, x: float, y: float) -> float:
        """Horizontal distance from (x, y) to the footprint (0 inside it)."""
        return math.hypot(*self.xy_gaps(x, y))

    def footprint(self) -> tuple[tuple[float, float], ...]:
        """The footprint's four corners, counter-clockwise."""
        yaw = math.radians(self.yaw_deg)
        c, s = math.cos(yaw), math.sin(yaw)
        hx, hy = self.half_size[0], self.half_size[1]
        cx, cy = self.center[0], self.center[1]
        return tuple(
            (cx + lx * c - ly * s, cy + lx * s + ly * c) for lx, ly in ((hx, hy), (-hx, hy), (-hx, -hy), (hx, -hy))
        )


def _box(cls: str, x: float, y: float, z_bottom: float, w: float, d: float, h: float, yaw: float = 0.0) -> Collider:
    """A box standing on height ``z_bottom``: footprint ``w`` × ``d`` (its own x, y) centred on (x, y), ``h`` tall."""
    return Collider(cls, (x, y, z_bottom + h / 2), (w / 2, d / 2, h / 2), yaw)


def _parked_car(x: float, y: float, z_bottom: float, body: str, yaw: float = 0.0) -> Collider:
    """A car of ``body`` type parked with its wheels on height ``z_bottom``, in a 4.4 × 1.8 ×
    1.5 m box, colliding as the solids it is drawn from (``car_hulls``): the hood and the
    windscreen where they are, not its box's top."""
    half = (2.2, 0.9, 0.75)
    hulls = car_hulls(car_profile(body, half))
    return Collider("car", (x, y, z_bottom + half[2]), half, yaw, model=body, hulls=hulls)


def _flat(cls: str, x: float, y: float, top: float, w: float, d: float, yaw: float = 0.0) -> Collider:
    """A 0.1 m slab whose top face lies at ``top``: a road or path flush with the ground it marks."""
    return _box(cls, x, y, top - 0.1, w, d, 0.1, yaw)


def _tree(x: float, y: float, z: float, height: float = 6.0, crown: float = 3.0) -> tuple[Collider, ...]:
    """A tree standing on height z: a 0.4 m trunk up to the crown's bottom (``height`` −
    ``crown`` m up) and a crown box ``crown`` m on each side above it."""
    return (
        _box("tree", x, y, z, 0.4, 0.4, height - crown),
        _box("tree", x, y, z + height - crown, crown, crown, crown),
    )


def _pole(x: float, y: float, z: float, height: float) -> Collider:
    return _box("pole", x, y, z, 0.2, 0.2, height)


def _sign(x: float, y: float, z: float, yaw: float = 0.0) -> tuple[Collider, ...]:
    """A traffic sign: a 2.6 m post and a 0.7 m plate at its top, facing along its local y."""
    return (_pole(x, y, z, 2.6), _box("traffic_sign", x, y, z + 2.0, 0.7, 0.06, 0.7, yaw))


def _traffic_light(x: float, y: float, z: float, yaw: float = 0.0) -> tuple[Collider, ...]:
    """A traffic light: a 3.6 m post and a 1 m signal head at its top."""
    return (_pole(x, y, z, 3.6), _box("traffic_light", x, y, z + 2.7, 0.35, 0.35, 1.0, yaw))


def _bench(x: float, y: float, z: float, yaw: float = 0.0) -> tuple[Collider, Collider]:
    """A bench: a 1.8 × 0.5 m seat 0.45 m high and a backrest along the seat's local +y edge,
    0.08 m thick, up to 0.85 m (the asset library draws slats and frames inside both)."""
    back = 0.25 - 0.04
    c, s = math.cos(math.radians(yaw)), math.sin(math.radians(yaw))
    return (
        _box("bench", x, y, z, 1.8, 0.5, 0.45, yaw),
        _box("bench", x - back * s, y + back * c, z + 0.45, 1.8, 0.08, 0.4, yaw),
    )


def _steps(
    cls: str, x: float, y: float, z: float, width: float, run: float, rise: float, n: int, yaw: float
) -> tuple[Collider, ...]:
    """``n`` steps climbing from their foot at (x, y) towards heading ``yaw``: step i is (i + 1) rises tall."""
    c, s = math.cos(math.radians(yaw)), math.sin(math.radians(yaw))
    return tuple(
        _box(cls, x + (i + 0.5) * run * c, y + (i + 0.5) * run * s, z, run, width, (i + 1) * rise, yaw)
        for i in range(n)
    )


#: Half extents (length, width, height), metres, of the vehicles that drive in traffic.
VEHICLE_HALF_SIZES: dict[str, Vec3] = {
    "car": (2.2, 0.9, 0.75),
    "truck": (3.6, 1.2, 1.6),
    "bus": (6.0, 1.2, 1.5),
}


@dataclass(frozen=True)
class Lane:
    """A traffic lane: vehicles of ``vehicles`` drive along its centre line from ``start`` to
    ``end`` (world metres, on the road's top face); ``half_width`` is the lane's."""

    start: Vec3
    end: Vec3
    half_width: float
    vehicles: tuple[str, ...] = ("car",)

    def __post_init__(self) -> None:
        start = tuple(float(v) for v in self.start)
        end = tuple(float(v) for v in self.end)
        if len(start) != 3 or len(end) != 3 or not all(math.isfinite(v) for v in (*start, *end)):
            raise ValueError(f"a lane's start and end are finite 3-vectors, got {self.start}, {self.end}")
        if math.dist(start[:2], end[:2]) < 10.0:
            raise ValueError("a lane must be at least 10 m long")
        if start[2] != end[2]:  # traffic drives a lane at its start's height (``Traffic.poses``)
            raise ValueError(f"a lane is level: its start and end heights differ ({start[2]} m, {end[2]} m)")
        if not (math.isfinite(self.half_width) and self.half_width > 0.0):
            raise ValueError(f"a lane's half width must be positive, got {self.half_width}")
        for v in self.vehicles:
            OBJECTS.check(v)
            if v not in VEHICLE_HALF_SIZES:
                raise ValueError(f"{v!r} is not a vehicle ({', '.join(VEHICLE_HALF_SIZES)})")
            if VEHICLE_HALF_SIZES[v][1] > self.half_width:
                raise ValueError(f"a {v} is wider than the lane")
            if 2.0 * VEHICLE_HALF_SIZES[v][0] >= math.dist(start[:2], end[:2]):
                raise ValueError(f"a {v} is as long as the lane or longer")
        object.__setattr__(self, "start", start)
        object.__setattr__(self, "end", end)
        object.__setattr__(self, "half_width", float(self.half_width))

    @property
    def length(self) -> float:
        return math.dist(self.start[:2], self.end[:2])


@dataclass(frozen=True)
class EnvironmentScene:
    """An environment: indoor or not, its static pixel classes, its two waypoint graphs, its
    ground plane and its static collision geometry.

    The ground is an infinite plane at ``ground_z`` (pixel class ``terrain`` outdoors, ``floor``
    indoors); ``colliders`` are the static boxes standing on or above it (roads, terraces,
    buildings, furniture, ...). Moving things (cars driving, people, props) are not colliders;
    ``lanes`` say where traffic drives (outdoor scenes with roads).
    """

    indoor: bool
    pixel_classes: tuple[str, ...]
    protagonist_waypoints: tuple[Vec3, ...]
    background_waypoints: tuple[Vec3, ...]
    colliders: tuple[Collider, ...] = ()
    ground_z: float = 0.0
    lanes: tuple[Lane, ...] = ()
    #: Open water (lake): (x0, y0, x1, y1, level_z), a flat surface the renderer draws with
    #: class ``misc`` (the pixel-class table has no water class); no collider.
    water: tuple[float, float, float, float, float] | None = None

    def __post_init__(self) -> None:
        for c in self.pixel_classes:
            PIXEL_CLASSES.check(c)
        if not self.protagonist_waypoints:
            raise ValueError("an environment needs at least one protagonist waypoint")
        if self.indoor and self.background_waypoints:
            raise ValueError("indoor scenes have no background-actor waypoint graph")
        if not self.indoor and len(self.background_waypoints) < 2:
            raise ValueError("an outdoor background graph needs a start and a destination")
        if not math.isfinite(self.ground_z):
            raise ValueError(f"ground_z must be finite, got {self.ground_z}")
        if self.indoor and self.lanes:
            raise ValueError("indoor scenes have no traffic lanes")
        for lane in self.lanes:
            if not isinstance(lane, Lane):
                raise TypeError(f"lanes must be Lane objects, got {type(lane).__name__}")
        for collider in self.colliders:
            if not isinstance(collider, Collider):
                raise TypeError(f"colliders must be Collider boxes, got {type(collider).__name__}")
            if collider.pixel_class not in self.pixel_classes:
                raise ValueError(
                    f"collider class {collider.pixel_class!r} is not one of the environment's pixel classes"
                )

    def in_water(self, c: Collider) -> bool:
        """Whether collider ``c`` stands in the open water (its centre over the water's
        rectangle): a bed of reeds where it is ``vegetation``."""
        if self.water is None:
            return False
        x0, y0, x1, y1, _ = self.water
        return x0 <= c.center[0] <= x1 and y0 <= c.center[1] <= y1

    @property
    def room_colliders(self) -> tuple[Collider, ...]:
        """Indoors, the colliders of the room (its walls and what stands within them), not the
        garden its windows look out on (``GARDEN_CLASSES``); outdoors, all of them."""
        if not self.indoor:
            return self.colliders
        return tuple(c for c in self.colliders if c.pixel_class not in GARDEN_CLASSES)

    @property
    def ground_pixel_class(self) -> str:
        """The pixel class of the ground plane."""
        return "floor" if self.indoor else "terrain"


_OUTDOOR_BASE = ("sky", "terrain", "misc")
#: The classes of what an indoor scene's windows look out on (outside its walls).
GARDEN_CLASSES = ("terrain", "vegetation", "tree", "building")


def _grid(xs: tuple[float, ...], ys: tuple[float, ...], z: float = 0.0) -> tuple[Vec3, ...]:
    return tuple((x, y, z) for x in xs for y in ys)


# Static collision geometry, one builder per environment. Every box stands on the surface it
# rests on (``_box``'s z is its bottom); roads and paths are slabs flush with the ground. The
# data keep a 3 m radius free around each protagonist waypoint from 0.05 m above its standing
# height up to 2.5 m (its own support excepted), stand every waypoint on the plane or on the
# top face of a box, and keep non-walkable boxes off the straight background-actor paths;
# tests/spec/test_colliders.py checks all of it.


def _two_way(half_length: float, offset: float, half_width: float, vehicles: tuple[str, ...]) -> tuple[Lane, ...]:
    """Two lanes along a straight road on the x axis (y = 0 its middle): eastbound at
    y = −offset, westbound at y = +offset (right-hand traffic)."""
    return (
        Lane((-half_length, -offset, 0.0), (half_length, -offset, 0.0), half_width, vehicles),
        Lane((half_length, offset, 0.0), (-half_length, offset, 0.0), half_width, vehicles),
    )


def _simple_colliders() -> tuple[Collider, ...]:
    return (_flat("road", 0.0, 0.0, 0.0, 200.0, 8.0),)  # a straight road, y ∈ [-4, 4]


def _urban_colliders() -> tuple[Collider, ...]:
    g = 0.0
    street = (
        _flat("road", 0.0, 0.0, g, 140.0, 9.0),  # carriageway, y ∈ [-4.5, 4.5]
        _flat("road", 0.0, 8.5, g, 140.0, 8.0),  # north sidewalk, y ∈ [4.5, 12.5]
        _flat("road", 0.0, -8.5, g, 140.0, 8.0),  # south sidewalk
        # The raised plaza (top 0.6): A carries waypoint (30, 10, 0.6) with 3 m to spare,
        # B the background waypoint (40, 12, 0.6); (35, 7, 0) stays on the sidewalk below.
        _box("road", 30.0, 11.45, g, 8.0, 9.1, 0.6),  # A: x ∈ [26, 34], y ∈ [6.9, 16]
        _box("road", 40.0, 12.5, g, 12.0, 7.0, 0.6),  # B: x ∈ [34, 46], y ∈ [9, 16]
        *_steps("stairs", 25.1, 12.25, g, 3.5, 0.45, 0.2, 2, 0.0),  # up to A from the west
    )
    buildings = (
        _box("building", -41.0, 21.5, g, 38.0, 18.0, 18.0),  # north side, y ∈ [12.5, 30.5]
        _box("building", -11.0, 21.5, g, 18.0, 18.0, 26.0),
        _box("building", 12.0, 21.5, g, 24.0, 18.0, 14.0),
        _box("building", 43.0, 26.0, g, 34.0, 18.0, 30.0),  # behind the plaza, y ∈ [17, 35]
        _box("building", -42.5, -21.5, g, 35.0, 18.0, 22.0),  # south side, y ∈ [-30.5, -12.5]
        _box("building", -11.0, -21.5, g, 22.0, 18.0, 12.0),
        _box("building", 16.5, -21.5, g, 27.0, 18.0, 28.0),
        _box("building", 46.5, -21.5, g, 27.0, 18.0, 16.0),
    )
    furniture = (
        _pole(-40.0, 5.0, g, 7.0),  # street lights along the kerbs
        _pole(-4.5, 4.8, g, 7.0),
        _pole(17.0, 5.0, g, 7.0),
        _pole(-45.0, -5.0, g, 7.0),
        _pole(10.0, -5.0, g, 7.0),
        _pole(45.0, -5.0, g, 7.0),
        *_traffic_light(-18.0, 5.2, g),  # a pedestrian crossing at x = -18
        *_traffic_light(-18.0, -5.2, g, 180.0),
        *_traffic_light(18.0, 5.2, g),  # and one at x = 18
        *_traffic_light(18.0, -5.2, g, 180.0),
        *_sign(-25.0, 5.2, g),
        *_sign(40.0, -5.2, g, 180.0),
        *_sign(7.0, 5.2, g),
        *_sign(0.0, -5.2, g, 180.0),
        *_sign(11.5, -5.2, g, 180.0),
        _box("guard_rail", -46.0, 4.7, g, 28.0, 0.1, 0.9),  # kerb rails where no background path crosses the street
        _box("guard_rail", -46.0, -4.7, g, 28.0, 0.1, 0.9),
        _box("guard_rail", 53.5, -4.7, g, 13.0, 0.1, 0.9),
        _box("guard_rail", 36.0, 15.95, 0.6, 20.0, 0.1, 1.0),  # plaza railings
        _box("guard_rail", 45.95, 12.5, 0.6, 0.1, 7.0, 1.0),
        _box("guard_rail", 43.75, 9.05, 0.6, 4.5, 0.1, 1.0),
        *_bench(-5.0, 11.7, g),
        *_bench(7.0, 11.7, g),
        *_bench(-35.0, -11.7, g, 180.0),
        *_bench(10.0, -11.7, g, 180.0),
        *_bench(43.0, 14.8, 0.6),
        *_tree(-40.0, -10.0, g, 8.0, 5.0),  # street trees, their crowns over the pavements
        *_tree(-15.0, -10.0, g, 8.0, 5.0),
        *_tree(5.0, -10.0, g, 7.5, 4.5),
        *_tree(25.0, -10.0, g, 8.0, 5.0),
        *_tree(-30.0, 10.0, g, 8.0, 5.0),
        *_tree(1.0, 10.0, g, 7.5, 4.5),
        _box("vegetation", -15.0, 11.6, g, 2.0, 1.2, 0.8),  # planters
        _box("vegetation", 20.0, 11.6, g, 2.0, 1.2, 0.8),
        _box("vegetation", 0.0, -11.6, g, 2.0, 1.2, 0.8),
        _parked_car(-50.0, 3.4, g, "van"),  # parked in the kerb lane
        _parked_car(52.0, -3.4, g, "suv"),
    )
    return street + buildings + furniture


def _green_colliders() -> tuple[Collider, ...]:
    # The base plane (-0.2) is the lowest ground; grass terraces raise the rest of the park.
    g = -0.2
    terraces = (
        _box("terrain", -3.0, 13.25, g, 13.0, 33.5, 0.2),  # top 0.0: x ∈ [-9.5, 3.5], y ∈ [-3.5, 30]
        _box("terrain", -17.75, -7.0, g, 24.5, 30.0, 0.2),  # top 0.0: x ∈ [-30, -5.5], y ∈ [-22, 8]
        _box("terrain", 12.75, 10.25, g, 16.5, 21.5, 0.3),  # top 0.1: x ∈ [4.5, 21], y ∈ [-0.5, 21]
        # top 0.2 under (12, -2): turned so its face toward (8, 3, 0.1) stays 3.2 m away.
        _box("terrain", 12.0, -2.0, g, 6.4, 8.0, 0.4, -51.34),
        _box("terrain", 25.0, 0.0, g, 6.0, 6.0, 0.4),  # top 0.2 under (25, 0)
        _box("terrain", 3.5, -8.25, g, 9.0, 9.5, 0.1),  # top -0.1: x ∈ [-1, 8], y ∈ [-13, -3.5]
    )
    # The background paths criss-cross the middle of the park; obstacles keep off them.
    park = (
        *_tree(-10.0, 10.0, g),
        *_tree(10.0, -10.0, g, 7.0),
        *_tree(-20.0, 14.0, g, 8.0, 4.0),
        *_tree(14.0, -18.0, g),
        *_tree(-24.0, -16.0, 0.0, 8.0, 4.0),
        *_tree(24.0, 16.0, g),
        # Trees among the paths, near where people act (their crowns above the walkers).
        *_tree(-12.0, -9.0, 0.0, 8.5, 5.5),
        *_tree(-3.0, -17.0, g, 9.0, 6.0),
        *_tree(-2.0, 14.0, 0.0, 8.5, 5.5),
        *_tree(4.0, 16.0, g, 9.0, 6.0),
        *_tree(-12.0, 3.0, 0.0, 8.0, 5.0),
        *_tree(12.0, 8.0, 0.1, 8.5, 5.5),
        *_tree(15.0, -7.0, g, 9.0, 6.0),
        _box("vegetation", -4.0, -8.0, g, 2.0, 1.5, 1.0),  # bushes
        _box("vegetation", 4.0, 8.0, g, 1.5, 1.5, 0.9),
        _box("vegetation", -6.5, -10.0, 0.0, 1.6, 2.0, 1.2),
        _box("vegetation", 16.0, -14.0, g, 1.8, 1.2, 0.8),
        _box("vegetation", -12.0, 22.0, g, 2.5, 1.5, 1.0),
        *_bench(6.0, -4.5, -0.1),
        *_bench(-16.0, -4.0, 0.0, 90.0),
        *_bench(26.0, -8.0, g, 90.0),
        _pole(16.0, 4.0, 0.1, 4.0),  # lamp posts
        _pole(-14.0, 16.0, g, 4.0),
        _pole(20.0, -14.0, g, 4.0),
    )
    return terraces + park


def _middle_colliders() -> tuple[Collider, ...]:
    g = 0.0
    ground = (
        _flat("road", 0.0, 0.0, g, 160.0, 7.0),  # y ∈ [-3.5, 3.5]
        _box("terrain", 0.0, 31.0, g, 10.0, 6.0, 0.5),  # a raised garden under (0, 30, 0.5)
    )
    houses = (
        _box("building", -30.0, -16.0, g, 10.0, 12.0, 7.0),
        _box("building", 0.0, -16.0, g, 12.0, 12.0, 9.0),
        _box("building", 30.0, -16.0, g, 10.0, 12.0, 6.0),
        _box("building", 30.0, 27.0, g, 12.0, 10.0, 8.0),
        _box("building", -30.0, 27.0, g, 12.0, 10.0, 10.0),
    )
    street = (
        _box("guard_rail", 0.0, -3.9, g, 32.0, 0.1, 0.9),  # x ∈ [-16, 16]
        *_sign(-10.0, -4.5, g, 180.0),
        *_sign(45.0, 4.5, g),
        *_sign(5.0, 4.2, g),
        *_sign(-15.0, 4.2, g),
        *_sign(25.0, -4.5, g, 180.0),
        _pole(-5.0, 4.2, g, 6.0),
        _pole(15.0, 4.2, g, 6.0),
        _pole(10.0, -4.5, g, 6.0),
        _parked_car(36.0, -9.0, g, "hatchback", 90.0),  # parked in a driveway
        *_tree(5.0, 14.0, g),
        *_tree(-8.0, 16.0, g, 7.0),
        *_tree(-15.0, -10.0, g),
        *_tree(15.0, -10.0, g, 5.0, 2.5),
        _box("vegetation", -22.0, -9.0, g, 4.0, 1.0, 1.0),  # hedges
        _box("vegetation", 22.0, -9.0, g, 4.0, 1.0, 1.0),
        _box("vegetation", 30.0, 20.5, g, 6.0, 1.0, 1.0),
    )
    return ground + houses + street


def _lake_colliders() -> tuple[Collider, ...]:
    # The base plane (0.0) is the lake bed; the banks are terraces around it and leave the
    # lake, x ∈ [-13, 13], y ∈ [-7, 14], a hollow the renderer fills with water (no collider).
    g = 0.0
    banks = (
        _box("terrain", 0.0, -13.5, g, 68.0, 13.0, 0.2),  # south promenade, top 0.2, y ∈ [-20, -7]
        _box("terrain", 21.5, 7.0, g, 17.0, 26.0, 0.3),  # east bank, top 0.3, x ∈ [13, 30], y ∈ [-6, 20]
        _box("terrain", -21.5, 7.5, g, 17.0, 25.0, 0.3),  # west bank, top 0.3, x ∈ [-30, -13], y ∈ [-5, 20]
        _box("terrain", 0.0, 21.0, g, 26.0, 14.0, 0.4),  # north bank, top 0.4, y ∈ [14, 28]
    )
    park = (
        *_bench(-20.0, -18.0, 0.2, 180.0),
        *_bench(-5.0, -18.0, 0.2, 180.0),
        *_bench(5.0, -18.0, 0.2, 180.0),
        *_bench(20.0, -18.0, 0.2, 180.0),
        *_bench(27.0, 3.0, 0.3, 90.0),
        *_bench(-8.0, 25.0, 0.4),
        *_tree(-12.0, -19.0, 0.2),
        *_tree(12.0, -19.0, 0.2, 7.0),
        *_tree(28.0, -2.0, 0.3),
        *_tree(-27.0, 5.0, 0.3, 8.0, 4.0),
        *_tree(8.0, 26.0, 0.4),
        _box("vegetation", 0.0, -19.2, 0.2, 3.0, 1.0, 0.9),  # shrubs
        _box("vegetation", -28.0, 10.0, 0.3, 1.5, 3.0, 1.0),
        _box("vegetation", 15.0, 18.0, 0.3, 2.0, 2.0, 1.2),
    )
    # Reeds in the shallows off the promenade, standing on the lake bed, where no background
    # walker's straight path between its waypoints crosses the water.
    reeds = (
        _box("vegetation", -5.0, -6.7, g, 3.0, 0.6, 1.6),
        _box("vegetation", 0.3, -6.7, g, 2.4, 0.6, 1.4),
        _box("vegetation", 4.0, -6.75, g, 2.0, 0.5, 1.7),
    )
    return banks + park + reeds


def _stadium_colliders() -> tuple[Collider, ...]:
    # The pitch is the base plane. The main (north) stand's first terrace, top 1.5, carries
    # waypoint (0, 32, 1.5) with 3 m to spare; the background waypoint (0, 27, 0) stands 2 m
    # in front of it.
    g = 0.0
    north = (
        _box("stairs", 0.0, 32.5, g, 60.0, 7.0, 1.5),  # terrace, y ∈ [29, 36]
        *(_box("stairs", 0.0, 36.75 + 1.5 * i, g, 60.0, 1.5, 2.0 + 0.5 * i) for i in range(4)),  # tiers, 0.5 m rises
        _box("building", 0.0, 43.0, g, 64.0, 2.0, 12.0),  # back wall
        _box("building", 0.0, 39.0, 11.0, 64.0, 10.0, 0.5),  # roof
        _box("guard_rail", -17.5, 29.1, 1.5, 25.0, 0.1, 1.0),  # the terrace's front rail, open at |x| < 5
        _box("guard_rail", 17.5, 29.1, 1.5, 25.0, 0.1, 1.0),
    )
    south = (
        *(_box("stairs", 0.0, -35.0 - 2.0 * i, g, 80.0, 2.0, 0.6 * (i + 1)) for i in range(4)),  # tiers, y ∈ [-42, -34]
        _box("building", 0.0, -43.0, g, 84.0, 2.0, 8.0),
        _box("guard_rail", 0.0, -33.8, g, 80.0, 0.1, 1.0),
    )
    sides = tuple(
        c
        for s in (1.0, -1.0)
        for c in (
            *(
                _box("stairs", s * (56.0 + 2.0 * i), 0.0, g, 2.0, 56.0, 0.6 * (i + 1)) for i in range(3)
            ),  # |x| ∈ [55, 61]
            _box("building", s * 62.0, 0.0, g, 2.0, 60.0, 7.0),
            _box("guard_rail", s * 54.8, 0.0, g, 0.1, 56.0, 1.0),
        )
    )
    lights = tuple(
        c
        for x, y in ((-45.0, 40.0), (45.0, 40.0), (-45.0, -40.0), (45.0, -40.0))
        for c in (
            _box("pole", x, y, g, 0.6, 0.6, 25.0),
            _box("pole", x, y, 25.0, 6.0, 1.0, 3.0, math.degrees(math.atan2(-y, -x))),
        )
    )
    benches = (*_bench(-12.0, -31.5, g), *_bench(12.0, -31.5, g))  # the teams' benches
    return north + south + sides + lights + benches + _goal(-50.0, g) + _goal(50.0, g)


def _goal(x: float, g: float) -> tuple[Collider, ...]:
    # A football goal on the goal line at x: 7.32 m between the posts, 2.44 m under the bar,
    # 12 cm bars (no net: it would be a cut-out). Its pixels are misc.
    w, h, bar = 7.32, 2.44, 0.12
    return (
        _box("misc", x, -(w + bar) / 2, g, bar, bar, h),
        _box("misc", x, (w + bar) / 2, g, bar, bar, h),
        _box("misc", x, 0.0, g + h - bar, bar, w, bar),
    )


def _house_colliders() -> tuple[Collider, ...]:
    # One open-plan ground floor, interior x ∈ [-8, 9.5], y ∈ [-7.5, 8], 2.8 m high: large
    # enough to keep the 3 m radius free around every waypoint, furniture along the walls.
    x0, x1, y0, y1, h = -8.0, 9.5, -7.5, 8.0, 2.8
    cx, cy, w, d = (x0 + x1) / 2, (y0 + y1) / 2, x1 - x0 + 0.4, y1 - y0
    shell = (
        _box("misc", cx, y0 - 0.1, 0.0, w, 0.2, h),  # walls, 0.2 m thick
        _box("misc", cx, y1 + 0.1, 0.0, w, 0.2, h),
        _box("misc", x0 - 0.1, cy, 0.0, 0.2, d, h),
        _box("misc", x1 + 0.1, cy, 0.0, 0.2, d, h),
        # Ceiling slab at 2.8 m with a stairwell over the staircase (x ∈ [8.2, 9.5], y ∈ [4.1, 8]).
        _box("ceiling", (x0 - 0.2 + 8.2) / 2, cy, h, 8.2 - x0 + 0.2, d + 0.4, 0.2),
        _box("ceiling", (8.2 + x1 + 0.2) / 2, (y0 - 0.2 + 4.1) / 2, h, x1 + 0.2 - 8.2, 4.1 - y0 + 0.2, 0.2),
        _box("window", -3.5, y0 - 0.1, 0.9, 2.0, 0.3, 1.4),  # windows and doors: thin boxes through the walls
        _box("window", 3.0, y0 - 0.1, 0.9, 2.0, 0.3, 1.4),
        _box("window", 5.5, y1 + 0.1, 0.9, 2.0, 0.3, 1.4),
        _box("window", x1 + 0.1, -1.0, 0.9, 0.3, 2.0, 1.4),
        _box("door", x0 - 0.1, 0.0, 0.0, 0.3, 1.0, 2.1),
        _box("door", 2.0, y1 + 0.1, 0.0, 1.0, 0.3, 2.1),
        _box("curtain", -4.8, y0 + 0.06, 0.3, 0.5, 0.1, 2.4),
        _box("curtain", -2.2, y0 + 0.06, 0.3, 0.5, 0.1, 2.4),
        _box("curtain", 1.7, y0 + 0.06, 0.3, 0.5, 0.1, 2.4),
        _box("curtain", 4.3, y0 + 0.06, 0.3, 0.5, 0.1, 2.4),
    )
    living = (
        _box("sofa", -4.5, 7.45, 0.0, 2.2, 0.9, 0.85),
        _box("table", -4.5, 5.6, 0.0, 1.2, 0.6, 0.45),  # coffee table
        _box("shelf", x0 + 0.25, 5.5, 0.0, 0.5, 1.8, 0.6),  # TV cabinet and the TV
        _box("screen", x0 + 0.05, 5.5, 0.9, 0.1, 1.4, 0.8),
        _box("fireplace", x0 + 0.3, -3.0, 0.0, 0.6, 1.6, 1.1),
        _box("fireplace", x0 + 0.2, -3.0, 1.1, 0.4, 1.2, h - 1.1),  # chimney breast
        _box("shelf", -1.0, y1 - 0.2, 0.0, 2.4, 0.4, 2.0),  # bookcase
        _box("lamp", -7.4, 7.4, 0.0, 0.1, 0.1, 1.5),  # floor lamp: stem and shade
        _box("lamp", -7.4, 7.4, 1.5, 0.4, 0.4, 0.3),
        _box("lamp", 0.5, 0.5, 2.55, 0.5, 0.5, 0.25),  # ceiling lamp, above the 2.5 m free height
        _box("bench", x0 + 0.3, 2.2, 0.0, 1.8, 0.5, 0.45, 90.0),  # by the entrance
    )
    sleeping = (
        _box("bed", -5.8, -6.5, 0.0, 1.6, 2.0, 0.55),
        _box("lamp", -7.4, -7.0, 0.0, 0.5, 0.5, 0.6),  # bedside lamp
    )
    kitchen = (
        _box("fridge", 9.0, -7.1, 0.0, 0.8, 0.7, 1.9),
        _box("shelf", 7.0, -7.2, 0.0, 3.0, 0.6, 0.9),  # kitchen counter
        _box("shelf", 7.0, -7.35, 1.5, 3.0, 0.3, 0.7),  # wall cupboard
        _box("table", 6.5, -4.8, 0.0, 1.6, 0.9, 0.75),
        _box("chair", 5.9, -3.95, 0.0, 0.45, 0.45, 0.9),
        _box("chair", 7.1, -3.95, 0.0, 0.45, 0.45, 0.9),
        _box("chair", 5.9, -5.65, 0.0, 0.45, 0.45, 0.9),
        _box("chair", 7.1, -5.65, 0.0, 0.45, 0.45, 0.9),
    )
    staircase = _steps("stairs", 8.85, 4.1, 0.0, 1.3, 0.3, 0.2, 13, 90.0)  # up the east wall to y = 8
    return (
        shell + living + sleeping + kitchen + staircase + _garden_colliders(x0 - 0.25, y0 - 0.25, x1 + 0.25, y1 + 0.25)
    )


def _garden_colliders(x0: float, y0: float, x1: float, y1: float) -> tuple[Collider, ...]:
    # What the house's windows look out on, round its walls and the frames set in them
    # ((x0, y0)–(x1, y1)): a lawn
    # 2 cm above the floor's plane, hedges, trees and the neighbours' houses. Nobody walks
    # there; the renderer draws it from these boxes as it draws every other place.
    r = 40.0
    lawn = (
        _flat("terrain", 0.0, (-r + y0) / 2, 0.02, 2 * r, y0 + r),
        _flat("terrain", 0.0, (y1 + r) / 2, 0.02, 2 * r, r - y1),
        _flat("terrain", (-r + x0) / 2, (y0 + y1) / 2, 0.02, x0 + r, y1 - y0),
        _flat("terrain", (x1 + r) / 2, (y0 + y1) / 2, 0.02, r - x1, y1 - y0),
    )
    # The hedges stand far enough out that the lawn shows under a window's sill from the room.
    hedges = (
        _box("vegetation", 0.0, -25.0, 0.02, 36.0, 0.9, 1.5),
        _box("vegetation", 3.0, 26.0, 0.02, 34.0, 0.9, 1.5),
        _box("vegetation", 26.0, 0.0, 0.02, 0.9, 30.0, 1.5),
    )
    trees = (
        *_tree(-7.0, -19.0, 0.02, 7.0, 3.0),
        *_tree(6.0, -21.0, 0.02, 8.0, 3.5),
        *_tree(1.0, 20.0, 0.02, 7.0, 3.0),
        *_tree(12.0, 21.0, 0.02, 6.0, 2.5),
        *_tree(20.0, -6.0, 0.02, 7.0, 3.0),
        *_tree(21.0, 7.0, 0.02, 6.0, 2.5),
        *_tree(-18.0, -6.0, 0.02, 7.0, 3.0),
    )
    neighbours = (
        _box("building", 0.0, -33.0, 0.02, 14.0, 9.0, 8.5),
        _box("building", 6.0, 34.0, 0.02, 12.0, 9.0, 8.5),
        _box("building", 35.0, 0.0, 0.02, 9.0, 14.0, 8.5),
    )
    return lawn + hedges + trees + neighbours


#: Environments in ENVIRONMENTS order; coordinates in metres, MuJoCo world frame (+Z up).
ENVIRONMENT_SCENES: Registry[EnvironmentScene] = Registry(
    "environment",
    (
        (
            "simple",
            EnvironmentScene(
                indoor=False,
                pixel_classes=(*_OUTDOOR_BASE, "road"),
                protagonist_waypoints=_grid((-4.0, 0.0, 4.0), (-3.0, 3.0)),
                background_waypoints=_grid((-20.0, 20.0), (-15.0, 0.0, 15.0)),
                colliders=_simple_colliders(),
                lanes=_two_way(100.0, 2.0, 2.0, ("car",)),
            ),
        ),
        (
            "urban",
            EnvironmentScene(
                indoor=False,
                pixel_classes=(
                    *_OUTDOOR_BASE,
                    "road",
                    "building",
                    "pole",
                    "traffic_light",
                    "traffic_sign",
                    "vegetation",
                    "tree",
                    "car",
                    "truck",
                    "bus",
                    "guard_rail",
                    "stairs",
                    "bench",
                ),
                protagonist_waypoints=(
                    (2.0, 6.0, 0.0),
                    (12.0, 6.0, 0.0),
                    (22.0, 6.5, 0.0),
                    (-8.0, 6.0, 0.0),
                    (5.0, -6.0, 0.0),
                    (15.0, -6.5, 0.0),
                    (30.0, 10.0, 0.6),
                ),
                background_waypoints=(
                    (-30.0, 7.0, 0.0),
                    (-10.0, 7.5, 0.0),
                    (10.0, 7.0, 0.0),
                    (35.0, 7.0, 0.0),
                    (-30.0, -7.0, 0.0),
                    (0.0, -7.5, 0.0),
                    (35.0, -7.0, 0.0),
                    (40.0, 12.0, 0.6),
                ),
                colliders=_urban_colliders(),
                lanes=_two_way(70.0, 1.25, 1.25, ("car", "truck", "bus")),
            ),
        ),
        (
            "green",
            EnvironmentScene(
                indoor=False,
                pixel_classes=(*_OUTDOOR_BASE, "vegetation", "tree", "bench", "pole"),
                protagonist_waypoints=(
                    (0.0, 0.0, 0.0),
                    (8.0, 3.0, 0.1),
                    (-6.0, 5.0, 0.0),
                    (3.0, -8.0, -0.1),
                    (-9.0, -4.0, 0.0),
                    (12.0, -2.0, 0.2),
                ),
                background_waypoints=(
                    (-25.0, 0.0, 0.0),
                    (25.0, 0.0, 0.2),
                    (0.0, 25.0, 0.0),
                    (0.0, -25.0, -0.2),
                    (18.0, 18.0, 0.1),
                    (-18.0, -18.0, 0.0),
                ),
                colliders=_green_colliders(),
                ground_z=-0.2,
            ),
        ),
        (
            "middle",
            EnvironmentScene(
                indoor=False,
                pixel_classes=(
                    *_OUTDOOR_BASE,
                    "road",
                    "vegetation",
                    "tree",
                    "pole",
                    "traffic_sign",
                    "guard_rail",
                    "car",
                    "building",
                ),
                protagonist_waypoints=(
                    (0.0, 5.0, 0.0),
                    (10.0, 5.5, 0.0),
                    (-10.0, 5.0, 0.0),
                    (20.0, -5.0, 0.0),
                    (-20.0, -5.5, 0.0),
                ),
                background_waypoints=(
                    (-40.0, 6.0, 0.0),
                    (40.0, 6.0, 0.0),
                    (-40.0, -6.0, 0.0),
                    (40.0, -6.0, 0.0),
                    (0.0, 30.0, 0.5),
                ),
                colliders=_middle_colliders(),
                lanes=_two_way(80.0, 1.75, 1.75, ("car", "truck")),
            ),
        ),
        (
            "lake",
            EnvironmentScene(
                indoor=False,
                pixel_classes=(*_OUTDOOR_BASE, "vegetation", "tree", "bench"),
                protagonist_waypoints=(
                    (0.0, -12.0, 0.2),
                    (10.0, -10.0, 0.2),
                    (-10.0, -11.0, 0.2),
                    (16.0, 0.0, 0.3),
                    (-16.0, 2.0, 0.3),
                ),
                background_waypoints=(
                    (-30.0, -14.0, 0.2),
                    (30.0, -14.0, 0.2),
                    (22.0, 14.0, 0.3),
                    (-22.0, 14.0, 0.3),
                    (0.0, 20.0, 0.4),
                ),
                colliders=_lake_colliders(),
                water=(-13.0, -7.0, 13.0, 14.0, 0.08),
            ),
        ),
        (
            "stadium",
            EnvironmentScene(
                indoor=False,
                pixel_classes=(*_OUTDOOR_BASE, "building", "pole", "stairs", "bench", "guard_rail"),
                protagonist_waypoints=_grid((-20.0, 0.0, 20.0), (-8.0, 8.0)) + ((0.0, 32.0, 1.5),),
                background_waypoints=(
                    (-45.0, 0.0, 0.0),
                    (45.0, 0.0, 0.0),
                    (0.0, -30.0, 0.0),
                    (0.0, 27.0, 0.0),
                    (-30.0, 20.0, 0.0),
                    (30.0, -20.0, 0.0),
                ),
                colliders=_stadium_colliders(),
            ),
        ),
        (
            "house_interior",
            EnvironmentScene(
                indoor=True,
                pixel_classes=(
                    "ceiling",
                    "floor",
                    "chair",
                    "table",
                    "bed",
                    "lamp",
                    "sofa",
                    "window",
                    "door",
                    "stairs",
                    "curtain",
                    "fireplace",
                    "shelf",
                    "bench",
                    "screen",
                    "fridge",
                    "misc",
                    # the garden seen through the windows
                    "sky",
                    "terrain",
                    "vegetation",
                    "tree",
                    "building",
                ),
                protagonist_waypoints=(
                    (0.0, 0.0, 0.0),
                    (2.5, 1.0, 0.0),
                    (-2.0, 1.5, 0.0),
                    (1.0, -2.0, 0.0),
                    (-2.5, -1.5, 0.0),
                    (4.0, 3.0, 0.0),
                ),
                background_waypoints=(),
                colliders=_house_colliders(),
            ),
        ),
    ),
)


def why_not_hosted(action: str, environment: str) -> str | None:
    """Why ``environment`` cannot host ``action`` (a pixel class it needs is missing, or it
    needs open sky indoors), in words; None when it can."""
    scene, env = ACTION_SCENES[action], ENVIRONMENT_SCENES[environment]
    missing = [c for c in scene.requires_classes if c not in env.pixel_classes]
    if missing:
        return f"{environment} has no {missing[0]}, which {action} needs"
    if scene.outdoors and env.indoor:
        return f"{action} needs open sky (its flights rise up to 5 m) and {environment} is indoors"
    return None


def support_height(env_name: str, x: float, y: float, *, reference_z: float | None = None) -> float:
    """Height of the walkable surface under (x, y) in environment ``env_name``.

    The top of the highest walkable collider (class in ``WALKABLE_PIXEL_CLASSES``: roads,
    terraces, steps) whose footprint contains (x, y) and whose top is at most ``MAX_STEP_M``
    above ``reference_z`` (default: the ground plane), else the ground plane's height. With
    the default a surface is one a person steps onto from the ground; pass the current
    standing height to follow someone on a raised terrace (the stadium's stand at 1.5 m).
    Benches, beds and other furniture are obstacles, never support.
    """
    env = ENVIRONMENT_SCENES[env_name]
    limit = (env.ground_z if reference_z is None else reference_z) + MAX_STEP_M
    return float(walkable_heights(env_name, np.float64(x), np.float64(y), limit))


def walkable_heights(env_name: str, x: np.ndarray, y: np.ndarray, ceiling: np.ndarray | float) -> np.ndarray:
    """``support_height`` for many points at once: per point (x, y of one broadcast shape),
    the top of the highest walkable collider whose footprint holds it and whose top is at
    most ``ceiling`` (per point or one value), else the ground plane's height."""
    env = ENVIRONMENT_SCENES[env_name]
    x, y, ceiling = np.broadcast_arrays(np.asarray(x, float), np.asarray(y, float), np.asarray(ceiling, float))
    height = np.full(x.shape, env.ground_z)
    for c in env.colliders:
        if c.pixel_class not in WALKABLE_PIXEL_CLASSES:
            continue
        lx, ly = c.to_local(x, y)
        inside = (np.abs(lx) <= c.half_size[0]) & (np.abs(ly) <= c.half_size[1])
        height = np.where(inside & (c.top <= ceiling), np.maximum(height, c.top), height)
    return height


@dataclass(frozen=True)
class HumanModel:
    """One of the 20 fixed people of H: anny's phenotype, skin, hair and outfit.

    The paper's 20 artist-made models become 20 anny bodies, chosen as a varied set (table
    in ``_human_models``): ages 14 to 78, ten men and ten women, adults from 1.50 m to
    1.95 m (men 1.78 m and women 1.63 m on average, the WHO reference being 1.77 m and
    1.63 m), light to heavy builds, skin tones across the Monk scale and every top,
    bottom, fabric and hair style.
    """

    phenotype: Phenotype
    skin_rgb: RGB
    hair: Hair
    outfit: Outfit

    def human(self, name: str) -> dict[str, Any]:
        """The recipe's ``HumanSpec`` of this model, as JSON-ready data."""
        return {
            "model": name,
            "phenotype": self.phenotype.model_dump(),
            "skin_rgb": self.skin_rgb,
            "hair": self.hair.model_dump(),
            "outfit": self.outfit.model_dump(),
            "sampled": None,
        }


def _model(phenotype: tuple[float, ...], skin: RGB, hair: tuple, top: tuple, bottom: tuple, shoes: RGB) -> HumanModel:
    """A model from one row: phenotype (gender, age, muscle, weight, height, proportions),
    skin, hair (style, colour), top and bottom (kind, fabric, colour, pattern colour[, scale]), shoes."""

    def garment(kind: str, fabric: str, rgb: RGB, pattern_rgb: RGB, scale: float = 1.0) -> dict[str, Any]:
        return {"kind": kind, "fabric": fabric, "rgb": rgb, "pattern_rgb": pattern_rgb, "scale": scale}

    keys = ("gender", "age", "muscle", "weight", "height", "proportions")
    return HumanModel(
        phenotype=Phenotype(**dict(zip(keys, phenotype, strict=True))),
        skin_rgb=skin,
        hair=Hair(style=hair[0], rgb=hair[1]),
        outfit=Outfit(top=Top(**garment(*top)), bottom=Bottom(**garment(*bottom)), shoes_rgb=shoes),
    )


def _human_models() -> tuple[tuple[str, HumanModel], ...]:
    """The 20 models. Statures are anny's (``population.estimated_stature``, within 2 mm of
    the body model); skin tone t is the position on the Monk scale (0 lightest, 1 darkest).

    ========  ===  ====  =========  ======  ======  ====  ====================  ===========
    model     sex  age   stature m  muscle  weight  t     top                   bottom
    ========  ===  ====  =========  ======  ======  ====  ====================  ===========
    model_01  M    24    1.77       0.55    0.45    0.30  short sleeves, solid  trousers, denim
    model_02  F    21    1.61       0.35    0.40    0.12  sleeveless, print     skirt, solid
    model_03  M    34    1.72       0.70    0.60    0.72  long sleeves, checks  trousers, solid
    model_04  F    14    1.58       0.40    0.35    0.05  short, stripes        shorts, denim
    model_05  M    55    1.95       0.60    0.80    0.45  long, solid           trousers, solid
    model_06  F    26    1.72       0.45    0.45    0.92  short, solid          trousers, print
    model_07  M    15    1.70       0.40    0.40    0.58  sleeveless, solid     shorts, checks
    model_08  F    37    1.67       0.50    0.65    0.35  long, stripes         skirt, denim
    model_09  M    29    1.85       0.80    0.55    0.85  short, print          shorts, solid
    model_10  F    52    1.76       0.50    0.75    0.22  long, checks          trousers, solid
    model_11  M    41    1.79       0.55    0.90    0.64  short, stripes        trousers, denim
    model_12  F    31    1.55       0.30    0.25    0.78  sleeveless, solid     shorts, solid
    model_13  M    66    1.75       0.40    0.70    0.08  long, solid           trousers, checks
    model_14  F    17    1.66       0.45    0.30    0.50  short, print          skirt, stripes
    model_15  M    47    1.68       0.30    0.85    0.97  short, checks         trousers, solid
    model_16  F    61    1.57       0.30    0.80    0.40  long, print           trousers, solid
    model_17  M    19    1.81       0.65    0.35    0.15  sleeveless, stripes   shorts, denim
    model_18  F    44    1.63       0.55    0.55    0.68  short, solid          skirt, checks
    model_19  M    78    1.66       0.20    0.45    0.27  long, stripes         trousers, solid
    model_20  F    72    1.50       0.25    0.60    0.88  long, solid           skirt, print
    ========  ===  ====  =========  ======  ======  ====  ====================  ===========

    Hair: bald (05, 15, 19), short, long and tied; black, brown, blond, red and grey (the
    four oldest and model_05). Each row was made with ``population.phenotype_for`` from the
    sex, age, stature, build, proportions and gender offset, then rounded.
    """
    h = _model
    rows = [
        h((0.0, 0.7057, 0.55, 0.45, 0.3759, 0.5), (238, 224, 193), ('short', (92, 62, 39)), ('short_sleeves', 'solid', (30, 60, 140), (20, 40, 90)), ('trousers', 'denim', (50, 70, 110), (150, 170, 200)), (20, 20, 20)),  # M 24 y, 1.77 m
        h((0.95, 0.6923, 0.35, 0.4, 0.3494, 0.55), (243, 230, 218), ('long', (212, 180, 124)), ('sleeveless', 'print', (200, 40, 60), (250, 220, 120)), ('skirt', 'solid', (30, 30, 90), (20, 20, 60)), (240, 240, 240)),  # F 21 y, 1.61 m
        h((0.1, 0.7503, 0.7, 0.6, 0.3417, 0.45), (115, 81, 60), ('short', (28, 24, 22)), ('long_sleeves', 'checks', (240, 240, 240), (160, 40, 40), 1.2), ('trousers', 'solid', (60, 70, 60), (40, 45, 40)), (80, 50, 30)),  # M 34 y, 1.72 m
        h((1.0, 0.568, 0.4, 0.35, 0.4328, 0.5), (245, 235, 224), ('tied', (218, 187, 129)), ('short_sleeves', 'stripes', (120, 200, 120), (250, 250, 250), 0.8), ('shorts', 'denim', (70, 100, 150), (170, 190, 220)), (200, 30, 30)),  # F 14 y, 1.58 m
        h((0.05, 0.8439, 0.6, 0.8, 0.5491, 0.55), (213, 191, 148), ('bald', (178, 176, 173)), ('long_sleeves', 'solid', (90, 90, 90), (60, 60, 60)), ('trousers', 'solid', (20, 30, 60), (15, 20, 40)), (30, 30, 30)),  # M 55 y, 1.95 m
        h((0.9, 0.7146, 0.45, 0.45, 0.4457, 0.6), (54, 45, 39), ('short', (24, 20, 19)), ('short_sleeves', 'solid', (250, 200, 40), (200, 150, 20)), ('trousers', 'print', (50, 50, 50), (200, 200, 200), 1.5), (250, 250, 250)),  # F 26 y, 1.72 m
        h((0.0, 0.619, 0.4, 0.4, 0.3643, 0.45), (154, 123, 82), ('short', (35, 29, 27)), ('sleeveless', 'solid', (200, 30, 30), (150, 20, 20)), ('shorts', 'checks', (40, 80, 40), (200, 200, 160), 0.7), (240, 240, 240)),  # M 15 y, 1.70 m
        h((0.9, 0.7636, 0.5, 0.65, 0.4005, 0.5), (231, 210, 181), ('long', (157, 75, 35)), ('long_sleeves', 'stripes', (30, 140, 140), (240, 240, 230)), ('skirt', 'denim', (60, 80, 120), (160, 180, 210)), (120, 80, 40)),  # F 37 y, 1.67 m
        h((0.0, 0.728, 0.8, 0.55, 0.4492, 0.6), (74, 55, 46), ('short', (32, 27, 24)), ('short_sleeves', 'print', (20, 20, 20), (230, 60, 40), 1.3), ('shorts', 'solid', (200, 190, 150), (160, 150, 120)), (220, 220, 220)),  # M 29 y, 1.85 m
        h((0.85, 0.8305, 0.5, 0.75, 0.4805, 0.55), (247, 237, 208), ('tied', (106, 72, 46)), ('long_sleeves', 'checks', (170, 210, 240), (40, 60, 120)), ('trousers', 'solid', (60, 40, 30), (40, 25, 20)), (140, 30, 30)),  # F 52 y, 1.76 m
        h((0.1, 0.7815, 0.55, 0.9, 0.4074, 0.5), (138, 99, 72), ('short', (75, 50, 32)), ('short_sleeves', 'stripes', (0, 90, 160), (255, 255, 255), 1.1), ('trousers', 'denim', (40, 55, 90), (130, 150, 185)), (40, 40, 40)),  # M 41 y, 1.79 m
        h((1.0, 0.7369, 0.3, 0.25, 0.3006, 0.45), (95, 66, 52), ('long', (28, 24, 22)), ('sleeveless', 'solid', (255, 150, 180), (220, 100, 140)), ('shorts', 'solid', (240, 240, 240), (200, 200, 200)), (200, 160, 120)),  # F 31 y, 1.55 m
        h((0.15, 0.893, 0.4, 0.7, 0.3908, 0.5), (244, 231, 222), ('short', (193, 191, 188)), ('long_sleeves', 'solid', (100, 120, 60), (70, 85, 40)), ('trousers', 'checks', (40, 40, 60), (90, 90, 110), 0.6), (90, 60, 30)),  # M 66 y, 1.75 m
        h((1.0, 0.6745, 0.45, 0.3, 0.4011, 0.55), (190, 168, 123), ('tied', (32, 27, 24)), ('short_sleeves', 'print', (240, 120, 20), (30, 50, 100), 0.9), ('skirt', 'stripes', (30, 50, 100), (240, 240, 240)), (250, 250, 250)),  # F 17 y, 1.66 m
        h((0.1, 0.8082, 0.3, 0.85, 0.3138, 0.4), (46, 40, 35), ('bald', (20, 17, 16)), ('short_sleeves', 'checks', (160, 0, 40), (30, 30, 30), 1.4), ('trousers', 'solid', (50, 50, 50), (35, 35, 35)), (20, 20, 20)),  # M 47 y, 1.68 m
        h((0.85, 0.8707, 0.3, 0.8, 0.3066, 0.45), (223, 200, 166), ('short', (186, 184, 180)), ('long_sleeves', 'print', (110, 30, 60), (230, 200, 120), 1.2), ('trousers', 'solid', (60, 40, 30), (40, 25, 20)), (60, 40, 30)),  # F 61 y, 1.57 m
        h((0.0, 0.6834, 0.65, 0.35, 0.4108, 0.6), (244, 234, 215), ('long', (164, 80, 38)), ('sleeveless', 'stripes', (70, 70, 70), (230, 230, 230), 0.8), ('shorts', 'denim', (50, 70, 110), (150, 170, 200)), (50, 50, 50)),  # M 19 y, 1.81 m
        h((0.95, 0.7949, 0.55, 0.55, 0.3704, 0.5), (127, 93, 65), ('long', (84, 57, 36)), ('short_sleeves', 'solid', (40, 110, 40), (30, 80, 30)), ('skirt', 'checks', (110, 30, 60), (230, 230, 200), 1.1), (200, 200, 200)),  # F 44 y, 1.63 m
        h((0.2, 0.9465, 0.2, 0.45, 0.3179, 0.45), (242, 226, 199), ('bald', (201, 199, 195)), ('long_sleeves', 'stripes', (230, 230, 200), (110, 30, 60)), ('trousers', 'solid', (80, 80, 80), (60, 60, 60)), (30, 30, 30)),  # M 78 y, 1.66 m
        h((0.8, 0.9197, 0.25, 0.6, 0.2381, 0.4), (62, 51, 43), ('tied', (178, 176, 173)), ('long_sleeves', 'solid', (20, 40, 80), (15, 30, 60)), ('skirt', 'print', (80, 80, 80), (200, 160, 80)), (120, 90, 60)),  # F 72 y, 1.50 m
    ]  # fmt: skip
    return tuple((f"model_{i + 1:02d}", row) for i, row in enumerate(rows))


#: The 20 human models (paper Table "key random variables": H, 20 artist-designed models).
HUMAN_MODELS: Registry[HumanModel] = Registry("human model", _human_models())


@dataclass(frozen=True)
class WeatherElement:
    """A boolean weather element; its activation may depend on one earlier element."""

    parent: str | None
    description: str


#: Boolean weather elements in sampling order (parents first). The paper's example: fog
#: visibility influences cloud activation through a Bernoulli (Section "Weather elements").
WEATHER_ELEMENTS: Registry[WeatherElement] = Registry(
    "weather element",
    (
        ("rain", WeatherElement(None, "rain particles visible")),
        ("fog", WeatherElement(None, "volumetric fog visible")),
        ("clouds", WeatherElement("fog", "cloud layer visible")),
        ("wet_ground", WeatherElement("rain", "ground material wet and reflective")),
    ),
)

#: Continuous weather parameters: name → (lower bound, upper bound) a θ range must respect.
WEATHER_LEVELS: dict[str, tuple[float, float]] = {
    "sun_brightness": (0.0, 2.0),
    "ambient_luminosity": (0.0, 2.0),
    "cloud_intensity": (0.0, 1.0),
    "fog_intensity": (0.0, 1.0),
    "rain_intensity": (0.0, 1.0),
}


@dataclass(frozen=True)
class CameraInfo:
    """How a camera behaves: spring-tracked (kite), panning on a fixed mount, or fixed."""

    tracking: str  # "springs" | "pan" | "fixed"
    indoor_only: bool


CAMERA_INFO: Registry[CameraInfo] = Registry(
    "camera",
    (
        ("kite", CameraInfo("springs", indoor_only=False)),
        ("indoors", CameraInfo("pan", indoor_only=True)),
        ("closeup", CameraInfo("springs", indoor_only=False)),
        ("static", CameraInfo("fixed", indoor_only=False)),
    ),
)
assert CAMERA_INFO.names == CAMERAS.names and ENVIRONMENT_SCENES.names == ENVIRONMENTS.names

#: Kite camera spring variables (paper Section "Camera placement and parameters": CT_s,
#: CT_m, TP_s, ...): name → (unit, lower bound, upper bound) a θ range must respect. Spring
#: strengths beyond 1e5 N/m need the implicit integrator and are refused here.
KITE_SPRING_VARIABLES: dict[str, tuple[str, float, float]] = {
    "ct_spring_strength": ("N/m", 0.1, 1.0e5),
    "tp_spring_strength": ("N/m", 0.1, 1.0e5),
    "camera_mass": ("kg", 0.01, 100.0),
    "target_mass": ("kg", 0.01, 100.0),
    "camera_drag": ("1/s", 0.0, 50.0),
    "target_drag": ("1/s", 0.0, 50.0),
}

#: The fastest a spring camera's initial impulse may throw it (m/s): the impulse over the
#: camera's mass. Faster, the camera outruns its springs and the physics step, and the
#: explosion guard, which watches every joint the camera's included, stops the whole clip.
MAX_CAMERA_KICK_MPS = 50.0

#: The spring dead zone (minimum distance at which a spring starts pulling), metres.
SPRING_MIN_DISTANCES_M: tuple[int, ...] = (0, 1, 2)

#: Camera placement variables: name → (unit, lower bound, upper bound).
CAMERA_PLACEMENT_VARIABLES: dict[str, tuple[str, float, float]] = {
    "fov_deg": ("deg", 10.0, 120.0),
    "distance_m": ("m", 0.3, 60.0),
    "height_m": ("m", -2.0, 30.0),
    "azimuth_deg": ("deg", -360.0, 360.0),
}

#: Bounds of the other continuous parameters θ may set: name → (unit, lower, upper). A
#: recipe outside them would be physically meaningless (negative speeds, periods of zero).
PARAMETER_BOUNDS: dict[str, tuple[str, float, float]] = {
    "motion_speed": ("×", 0.1, 5.0),
    "heading_deg": ("deg", -360.0, 720.0),
    "background_speed_mps": ("m/s", 0.1, 5.0),
    "supporting_distance_m": ("m", 0.2, 50.0),
    "perturbation_radius_m": ("m", 0.0, 2.0),
    "perturbation_period_s": ("s", 0.05, 60.0),
    "weakening_strength": ("fraction", 0.0, 1.0),
    "blending_weight": ("fraction", 0.0, 1.0),
    "impulse_strength": ("N·s", 0.0, 1000.0),
    "impulse_azimuth_deg": ("deg", -360.0, 360.0),
    "impulse_elevation_deg": ("deg", -90.0, 90.0),
}

#: Most background pedestrians one scene may hold.
MAX_BACKGROUND_ACTORS = 50
