"""Which asset stands in each collider of an environment, and the asset library's identity.

An environment's colliders (``phav_spec.scene``) stay the one source of what physics and
the failures check collide with: each object's asset is built to fit its box (its drawn
shape inside the box, touching its faces where a person or a car meets it), and so is each
place (buildings, trees, hedges, roads, pavements, terraces: ``places``). Classes the
library does not model return None and stay boxes. The look of an environment's objects
and places is fixed by the environment (seeded from its name and the collider's index), as
the paper's scenes were, or a video's own (``look_seed``, θ's ``world_variety: video``); a
vehicle's from the stream it is given.
"""

from __future__ import annotations

import hashlib
import math
from collections.abc import Callable
from functools import cache, lru_cache

import numpy as np

from phav_generator.world import interiors, places, props, street, vehicles
from phav_generator.world import materials as looks
from phav_generator.world.materials import Material, pick
from phav_generator.world.parts import LEVELS, Asset, Parts, Vec3
from phav_generator.world.vehicles import Vehicle
from phav_spec.car_shapes import car_body
from phav_spec.scene import ENVIRONMENT_SCENES, Collider
from phav_spec.seeding import stream

#: Bumped when an asset's shape, materials or choice changes what existing recipes render.
WORLD_LIBRARY_VERSION = 20
#: Classes the library models (the objects and the places); every other static class stays a box.
MODELLED_CLASSES: tuple[str, ...] = (
    "pole", "traffic_light", "traffic_sign", "bench", "guard_rail", "car", "truck", "bus", "stairs",
    "chair", "table", "sofa", "bed", "shelf", "screen", "fridge", "fireplace", "lamp", "window", "door", "curtain",
    "building", "tree", "vegetation", "road", "terrain", "misc", "ceiling",
)  # fmt: skip
#: Of those, the places (``places``); the rest are the objects.
PLACE_CLASSES: tuple[str, ...] = ("building", "tree", "vegetation", "road", "terrain", "misc", "ceiling")
#: A pole at least this tall (m) is a floodlight mast; a pole collider this far above the
#: ground is a floodlight's head.
MAST_M = 15.0
HEAD_ABOVE_M = 10.0
#: Projected size (pixels, the bounding sphere's radius) down to which a level is used.
LEVEL_PX = (60.0, 15.0)


@cache
def world_library_sha256() -> str:
    """sha256 of what the asset library builds: its version, every environment's assets in
    its fixed look at every level of detail, its ground, and every catalogue kind at every
    level. The renderer fingerprint records it for the world: a refactor that leaves every
    mesh, material and colour as it was keeps it; a change to any of them moves it."""
    h = hashlib.sha256(f"phav-world {WORLD_LIBRARY_VERSION}\n".encode())

    def add(built: Asset | Vehicle | None) -> None:
        if isinstance(built, Vehicle):
            h.update(built.body.digest_bytes() + built.wheel.digest_bytes() + built.axles.tobytes())
        elif built is not None:
            h.update(built.digest_bytes())

    for env_name in ENVIRONMENT_SCENES.names:
        env = ENVIRONMENT_SCENES[env_name]
        add(ground_asset(env_name, 1.0, 0.0))
        for index in range(len(env.colliders)):
            for level in range(LEVELS):
                add(collider_asset(env_name, index, level))
    for kind in sorted(CATALOGUE):
        for level in range(LEVELS):
            add(CATALOGUE[kind][0](stream(0, f"fingerprint/{kind}"), level))
    # The boxes actions add: a chair's seat and back, a step, each plain box's look.
    for cls, half in (("chair", (0.22, 0.22, 0.23)), ("chair", (0.22, 0.04, 0.25)), ("stairs", (0.6, 0.15, 0.09)),
                      *((c, (0.05, 0.5, 1.0)) for c in sorted(_BOX_LOOKS))):  # fmt: skip
        for level in range(LEVELS):
            add(box_asset(cls, half, stream(0, f"fingerprint/box/{cls}"), level, indoor=True))
    return h.hexdigest()


def level_for(radius_m: float, distance_m: float, focal_px: float) -> int:
    """The level of detail of an object of bounding radius ``radius_m`` seen from at least
    ``distance_m`` with focal length ``focal_px``: 0 close up, coarser as it shrinks."""
    px = focal_px * radius_m / max(distance_m, 1e-3)
    for level, floor_px in enumerate(LEVEL_PX):
        if px >= floor_px:
            return level
    return LEVELS - 1


def _local(c: Collider, direction: np.ndarray) -> tuple[float, float]:
    """A world horizontal direction in the collider's frame, snapped to its nearest axis."""
    yaw = math.radians(c.yaw_deg)
    x = direction[0] * math.cos(yaw) + direction[1] * math.sin(yaw)
    y = -direction[0] * math.sin(yaw) + direction[1] * math.cos(yaw)
    return (math.copysign(1.0, x), 0.0) if abs(x) >= abs(y) else (0.0, math.copysign(1.0, y))


def _room(env_name: str) -> tuple[float, float, float, float]:
    """An environment's footprint (x0, y0, x1, y1) over its room's colliders (outdoors, all)."""
    env = ENVIRONMENT_SCENES[env_name]
    corners = np.array([pt for c in env.room_colliders for pt in c.footprint()])
    return (
        float(corners[:, 0].min()),
        float(corners[:, 1].min()),
        float(corners[:, 0].max()),
        float(corners[:, 1].max()),
    )


def _away_from_wall(env_name: str, c: Collider) -> np.ndarray:
    """The world direction from the room's nearest outer wall towards ``c``'s front."""
    x0, y0, x1, y1 = _room(env_name)
    pts = np.array(c.footprint())
    gaps = {(1.0, 0.0): pts[:, 0].min() - x0, (-1.0, 0.0): x1 - pts[:, 0].max(),
            (0.0, 1.0): pts[:, 1].min() - y0, (0.0, -1.0): y1 - pts[:, 1].max()}  # fmt: skip
    return np.array(min(gaps, key=lambda k: (gaps[k], k)))


def _into_room(env_name: str, wall: Collider) -> tuple[float, float]:
    """The axis across ``wall`` (its thinner one, in its frame) that points into the room."""
    x0, y0, x1, y1 = _room(env_name)
    lx, ly = wall.to_local((x0 + x1) / 2, (y0 + y1) / 2)
    if wall.half_size[0] < wall.half_size[1]:
        return (math.copysign(1.0, lx), 0.0)
    return (0.0, math.copysign(1.0, ly))


def _towards_table(env_name: str, c: Collider) -> np.ndarray:
    """The world direction from a chair to its nearest table (or away from the wall)."""
    env = ENVIRONMENT_SCENES[env_name]
    tables = [t for t in env.colliders if t.pixel_class == "table"]
    if not tables:
        return _away_from_wall(env_name, c)
    near = min(tables, key=lambda t: math.dist(t.center[:2], c.center[:2]))
    return np.array(near.center[:2]) - np.array(c.center[:2])


def _towards_road(env_name: str, c: Collider) -> tuple[float, float] | None:
    """The direction, in ``c``'s frame snapped to an axis, from ``c`` across the nearest road
    slab's width towards it (where a house's door faces); None without a road."""
    env = ENVIRONMENT_SCENES[env_name]
    roads = [r for r in env.colliders if r.pixel_class == "road"]
    if not roads:
        return None
    near = min(roads, key=lambda r: (r.xy_distance(c.center[0], c.center[1]), r.center))
    _, across = near.to_local(c.center[0], c.center[1])
    yaw = math.radians(near.yaw_deg)
    side = -math.copysign(1.0, across)  # from the building back across to the road
    return _local(c, np.array([-math.sin(yaw) * side, math.cos(yaw) * side]))


def _openings(env_name: str, wall: Collider, inside: tuple[float, float]) -> list[places.Opening]:
    """The windows and doors set into ``wall``, as openings of its face towards ``inside``
    (along it from its left end seen from the room, up from the wall's bottom)."""
    env = ENVIRONMENT_SCENES[env_name]
    normal = np.array([inside[0], inside[1], 0.0])
    along = np.cross(places.UP, normal)[:2]
    width = 2.0 * float(abs(along @ np.array(wall.half_size[:2])))
    out = []
    for o in env.colliders:
        if o.pixel_class not in ("window", "door") or not wall.contains_xy(o.center[0], o.center[1]):
            continue
        s = [float(along @ np.array(wall.to_local(x, y))) + width / 2 for x, y in o.footprint()]
        out.append(places.Opening(max(min(s), 0.0), min(max(s), width), o.bottom - wall.bottom, o.top - wall.bottom))
    return sorted(out, key=lambda o: (o.s0, o.z0))


def _shores(water: tuple[float, float, float, float, float], c: Collider) -> list[tuple[int, float, float]]:
    """The stretches of bank ``c``'s sides (``places.box_faces`` order, from s0 to s1 along
    each) that meet the open ``water``: a side on one of its edges, facing into it."""
    if c.yaw_deg % 360.0 != 0.0:
        return []
    lo, hi = np.array(water[:2]), np.array(water[2:4])
    centre, half = np.array(c.center[:2]), np.array(c.half_size[:2])
    out = []
    for i, face in enumerate(places.box_faces(c.half_size)):
        axis = 0 if abs(face.normal[0]) > 0.5 else 1
        facing = face.normal[axis] > 0.0
        side = centre[axis] + (half[axis] if facing else -half[axis])
        if abs(side - (lo if facing else hi)[axis]) > 1e-6:
            continue
        other = 1 - axis
        a = max(centre[other] - half[other], lo[other]) - centre[other]
        b = min(centre[other] + half[other], hi[other]) - centre[other]
        if b <= a:
            continue
        s0, s1 = sorted(float((v - face.corner[other]) * face.along[other]) for v in (a, b))
        out.append((i, s0, s1))
    return out


def _pole_kind(env_name: str, c: Collider) -> str:
    """What a pole collider ``c`` is: a floodlight's ``head`` (high above the ground), the
    ``mast`` under it, a ``lamp_post`` with a lantern, or a ``post`` carrying a signal head
    or sign plate."""
    env = ENVIRONMENT_SCENES[env_name]
    if c.bottom - env.ground_z > HEAD_ABOVE_M:
        return "head"
    if c.top - c.bottom >= MAST_M:
        return "mast"
    carries = any(o.pixel_class in ("traffic_light", "traffic_sign") and math.dist(o.center[:2], c.center[:2]) < 0.5
                  for o in env.colliders)  # fmt: skip
    return "post" if carries else "lamp_post"


def is_light(env_name: str, index: int) -> bool:
    """Whether pole collider ``index`` holds a light: a lamp post's lantern or a floodlight's
    head, not the mast under it nor a post carrying a sign or signal."""
    c = ENVIRONMENT_SCENES[env_name].colliders[index]
    return c.pixel_class == "pole" and _pole_kind(env_name, c) in ("head", "lamp_post")


def look_stream(env_name: str, name: str, look_seed: int | None) -> np.random.Generator:
    """The stream a look of environment ``env_name`` is drawn from: its one fixed look
    (``look_seed`` None) or a video's own (a recipe's ``environment.look_seed``)."""
    if look_seed is None:
        return stream(0, f"world/{env_name}/{name}")
    return stream(look_seed, f"world/look/{env_name}/{name}")


def collider_asset(env_name: str, index: int, level: int, look_seed: int | None = None) -> Asset | Vehicle | None:
    """The asset that stands in collider ``index`` of environment ``env_name`` at ``level``
    in the look of ``look_seed`` (None: the environment's fixed look), cached per process;
    None where the class stays a box."""
    return _collider_asset(env_name, index, level, look_seed)


@lru_cache(maxsize=4096)
def _collider_asset(env_name: str, index: int, level: int, look_seed: int | None) -> Asset | Vehicle | None:
    env = ENVIRONMENT_SCENES[env_name]
    c = env.colliders[index]
    rng = look_stream(env_name, str(index), look_seed)
    half, cls = c.half_size, c.pixel_class
    if cls == "pole":
        kind = _pole_kind(env_name, c)
        if kind == "head":
            return street.floodlight_head(half, rng, level)
        if kind == "mast":
            return street.mast(half, rng, level)
        return street.post(half, rng, level, lantern=kind == "lamp_post")
    if cls == "traffic_light":
        return street.traffic_light(half, rng, level)
    if cls == "traffic_sign":
        return street.sign_plate(half, rng, level)
    if cls == "bench":
        thin = min(half[0], half[1]) < 0.1
        return (street.bench_back if thin else street.bench_seat)(half, rng, level)
    if cls == "guard_rail":
        return street.guard_rail(half, rng, level)
    if cls == "car" and c.model:
        # The body type it collides as; the look's stream still draws a body first, so the
        # paint each look draws after it stays.
        car_body(rng)
        return vehicles.car(half, rng, level, body=c.model)
    if cls in ("car", "truck", "bus"):
        return vehicle(cls, half, rng, level)
    if cls == "stairs":
        if env_name == "stadium" and max(half[:2]) > 10.0 and min(half[:2]) <= 1.0:  # a stand's tier
            seats = pick(looks.SEAT_COLOURS, look_stream(env_name, "seats", look_seed))
            return places.tier(half, rng, level, front=_local(c, -np.array(c.center[:2])), seats=seats)
        return interiors.step(half, rng, level, indoor=env.indoor)
    if cls == "chair":
        return interiors.chair(half, rng, level, front=_local(c, _towards_table(env_name, c)))
    if cls == "table":
        return interiors.table(half, rng, level)
    if cls in ("sofa", "shelf", "screen", "fridge"):
        build = {"sofa": interiors.sofa, "shelf": interiors.shelf, "screen": interiors.screen,
                 "fridge": interiors.fridge}[cls]  # fmt: skip
        return build(half, rng, level, front=_local(c, _away_from_wall(env_name, c)))
    if cls == "fireplace":
        if c.bottom - env.ground_z > 0.5:
            return interiors.chimney(half, rng, level)
        return interiors.fireplace(half, rng, level, front=_local(c, _away_from_wall(env_name, c)))
    if cls == "bed":
        return interiors.bed(half, rng, level, head=_local(c, -_away_from_wall(env_name, c)))
    if cls == "lamp":
        return interiors.lamp(half, rng, level)
    if cls == "misc" and not env.indoor:  # a goal's post or crossbar
        return places.goal_frame(half, rng, level)
    if cls == "misc":  # a room's wall, cut round its windows and doors
        inside = _into_room(env_name, c)
        walls = look_stream(env_name, "walls", look_seed)
        return interiors.room_wall(half, rng, level, inside=inside, openings=_openings(env_name, c, inside),
                                   look=interiors.wall_look(walls))  # fmt: skip
    if cls == "ceiling":
        return interiors.ceiling(half, rng, level)
    if cls in ("window", "door", "curtain"):
        return {"window": interiors.window, "door": interiors.door, "curtain": interiors.curtain}[cls](half, rng, level)
    if cls == "building":
        style = _BUILDING_STYLES.get(env_name, "urban")
        road = _towards_road(env_name, c) if style == "suburban" else None
        loggias = places.loggias_of(look_stream(env_name, f"loggias/{index}", look_seed)) if style == "urban" else None
        return places.building(half, rng, level, style=style, street=road, loggias=loggias)
    if cls == "tree":
        # trunk and crown are two colliders: the tree's species and bark come from where it stands
        tree = look_stream(env_name, f"tree/{c.center[0]:.2f},{c.center[1]:.2f}", look_seed)
        species = places.species_of(tree)
        bark = places.bark_of(species, tree)
        if min(half[0], half[1]) < TRUNK_HALF_M:
            return places.trunk(half, rng, level, species=species, bark=bark)
        return places.crown(half, rng, level, species=species, bark=bark)
    if cls == "vegetation":
        if env.in_water(c):
            return places.reeds(half, rng, level)
        return places.shrub(half, rng, level, planter=env_name == "urban")
    if cls == "road":
        lanes, crossings = _carriageway(env_name, c)
        if not lanes:
            return places.slab(half, rng, level, cls="road", look=places.PAVING)
        markings = places.road_markings(half, lanes, crossings)
        return places.slab(half, rng, level, cls="road", look=places.ASPHALT, markings=markings)
    if cls == "terrain":
        shores = _shores(env.water, c) if env.water is not None else []
        return places.slab(half, rng, level, cls="terrain", look=places.GRASS, shores=shores)
    return None


#: The building style of each environment with buildings (``places.STYLES``).
_BUILDING_STYLES = {"urban": "urban", "middle": "suburban", "stadium": "stadium", "house_interior": "suburban"}
#: A tree collider narrower than this (half width, m) is its trunk; wider, its crown.
TRUNK_HALF_M = 0.5


def _carriageway(env_name: str, c: Collider) -> tuple[list[float], list[float]]:
    """The lanes (their centres across the slab, local y) that run along road slab ``c``, and
    where (local x) a signalled crossing meets it: empty for a pavement or plaza."""
    env = ENVIRONMENT_SCENES[env_name]
    lanes = []
    for lane in env.lanes:
        _, ay = c.to_local(lane.start[0], lane.start[1])
        _, by = c.to_local(lane.end[0], lane.end[1])
        if abs(ay - by) < 1e-6 and abs(ay) < c.half_size[1]:
            lanes.append(ay)
    crossings = []
    if lanes:
        for o in env.colliders:
            x, y = c.to_local(o.center[0], o.center[1])
            if o.pixel_class == "traffic_light" and abs(x) < c.half_size[0] and abs(y) < c.half_size[1] + 2.0:
                crossings.append(round(x, 6))
    return sorted(set(lanes)), sorted(set(crossings))


@cache
def ground_asset(env_name: str, half_extent: float, drop: float) -> Asset:
    """Environment ``env_name``'s ground plane: ``half_extent`` round the origin, ``drop``
    below its ground height (cached per process)."""
    env = ENVIRONMENT_SCENES[env_name]
    return places.ground(half_extent, env.ground_z - drop, indoor=env.indoor, pitch=_PITCHES.get(env_name),
                         tiled=_TILED.get(env_name))  # fmt: skip


#: Football pitches (length, width, m) marked on an environment's ground at its middle.
_PITCHES = {"stadium": (100.0, 54.0)}
#: Tiled floors (x0, y0, x1, y1): the house's kitchen, round its counter, fridge and table.
_TILED = {"house_interior": (4.6, -7.5, 9.5, -3.0)}


def vehicle(kind: str, half: Vec3, rng: np.random.Generator, level: int = 0, *, below: float = 0.0) -> Vehicle:
    """A vehicle of ``kind`` (car, truck, bus) filling a box of half extents ``half``."""
    if kind == "car":
        return vehicles.car(half, rng, level, below=below)
    if kind == "truck":
        return vehicles.truck(half, rng, level, below=below)
    if kind == "bus":
        return vehicles.bus(half, rng, level, below=below)
    raise ValueError(f"{kind!r} is not a vehicle (car, truck, bus)")


@cache
def modelled_indices(env_name: str) -> tuple[int, ...]:
    """The indices of an environment's colliders the library draws as assets."""
    env = ENVIRONMENT_SCENES[env_name]
    return tuple(i for i, c in enumerate(env.colliders) if c.pixel_class in MODELLED_CLASSES)


#: Materials and colours of an action's plain boxes (a door's frame, a pull-up bar's posts).
_BOX_LOOKS = {"door": (Material.WOOD, (0.92, 0.92, 0.90)), "misc": (Material.METAL, (0.55, 0.56, 0.58))}


def box_asset(cls: str, half: Vec3, rng: np.random.Generator, level: int = 0, *, indoor: bool) -> Asset:
    """The asset of a box an action adds (``Trajectory.boxes``): a chair's seat (legs under a
    seat at the box's top) or back (a thin box standing on the seat), a step of a flight, or
    a plain box in its class's material."""
    if cls == "chair":
        if min(half[0], half[1]) < 0.1:
            return interiors.chair_back(half, rng, level)
        return interiors.chair(half, rng, level, seat=2 * half[2])
    if cls == "stairs":
        return interiors.step(half, rng, level, indoor=indoor)
    material, colour = _BOX_LOOKS.get(cls, (Material.PLAIN, (0.5, 0.5, 0.5)))
    p = Parts(level)
    p.box(cls, cls, material, colour, (0.0, 0.0, 0.0), half)
    return p.build()


def _slab_kind(kind: str, rng: np.random.Generator, level: int) -> Asset:
    """The catalogue's slabs: a two-lane carriageway with a crossing, a pavement, a terrace,
    a lake's bank with its shore."""
    if kind == "carriageway":
        half = (30.0, 4.5, 0.05)
        markings = places.road_markings(half, [-1.25, 1.25], [0.0])
        return places.slab(half, rng, level, cls="road", look=places.ASPHALT, markings=markings)
    if kind == "pavement":
        return places.slab((30.0, 4.0, 0.05), rng, level, cls="road", look=places.PAVING)
    if kind == "lake_bank":  # its +y side on the water from 2 m to 16 m along, its −x side all along
        shores = [(1, 2.0, 16.0), (2, 0.0, 12.0)]
        return places.slab((8.0, 6.0, 0.15), rng, level, cls="terrain", look=places.GRASS, shores=shores)
    return places.slab((8.0, 6.0, 0.1), rng, level, cls="terrain", look=places.GRASS)


#: Every kind of object at a typical size, with its triangle budget per level of detail:
#: the gallery's subjects and what the tests hold each kind to.
CATALOGUE: dict[str, tuple[Callable[[np.random.Generator, int], Asset | Vehicle], tuple[int, int, int]]] = {
    "hatchback": (lambda rng, lv: vehicles.car((2.0, 0.875, 0.74), rng, lv, body="hatchback"), (2500, 2000, 1000)),
    "sedan": (lambda rng, lv: vehicles.car((2.35, 0.9, 0.725), rng, lv, body="sedan"), (2500, 2000, 1000)),
    "suv": (lambda rng, lv: vehicles.car((2.35, 0.95, 0.85), rng, lv, body="suv"), (2500, 2000, 1000)),
    "van": (lambda rng, lv: vehicles.car((2.6, 1.0, 1.1), rng, lv, body="van"), (2500, 2000, 1000)),
    "truck": (lambda rng, lv: vehicles.truck((3.6, 1.2, 1.6), rng, lv), (3500, 2500, 1200)),
    "bus": (lambda rng, lv: vehicles.bus((6.0, 1.2, 1.5), rng, lv), (3000, 2500, 1000)),
    "lamp_post": (lambda rng, lv: street.post((0.1, 0.1, 3.5), rng, lv, lantern=True), (400, 300, 200)),
    "sign_post": (lambda rng, lv: street.post((0.1, 0.1, 1.3), rng, lv), (100, 80, 60)),
    "floodlight_mast": (lambda rng, lv: street.mast((0.3, 0.3, 12.5), rng, lv), (100, 80, 60)),
    "floodlight_head": (lambda rng, lv: street.floodlight_head((3.0, 0.5, 1.5), rng, lv), (300, 300, 120)),
    "traffic_light": (lambda rng, lv: street.traffic_light((0.175, 0.175, 0.5), rng, lv), (700, 500, 300)),
    "traffic_sign": (lambda rng, lv: street.sign_plate((0.35, 0.03, 0.35), rng, lv), (200, 150, 100)),
    "bench_seat": (lambda rng, lv: street.bench_seat((0.9, 0.25, 0.225), rng, lv), (200, 200, 120)),
    "bench_back": (lambda rng, lv: street.bench_back((0.9, 0.04, 0.2), rng, lv), (120, 120, 60)),
    "guard_rail": (lambda rng, lv: street.guard_rail((14.0, 0.05, 0.45), rng, lv), (250, 250, 250)),
    "chair": (lambda rng, lv: interiors.chair((0.225, 0.225, 0.45), rng, lv), (200, 200, 120)),
    "chair_back": (lambda rng, lv: interiors.chair_back((0.02, 0.22, 0.21), rng, lv), (100, 100, 60)),
    "table": (lambda rng, lv: interiors.table((0.8, 0.45, 0.375), rng, lv), (120, 120, 120)),
    "sofa": (lambda rng, lv: interiors.sofa((1.1, 0.45, 0.425), rng, lv, front=(0.0, -1.0)), (600, 600, 150)),
    "bed": (lambda rng, lv: interiors.bed((0.8, 1.0, 0.275), rng, lv), (200, 200, 200)),
    "bookcase": (lambda rng, lv: interiors.shelf((0.2, 1.2, 1.0), rng, lv), (4000, 4000, 200)),
    "cabinet": (lambda rng, lv: interiors.shelf((1.5, 0.3, 0.45), rng, lv, front=(0.0, 1.0)), (250, 250, 150)),
    "screen": (lambda rng, lv: interiors.screen((0.05, 0.7, 0.4), rng, lv), (60, 60, 60)),
    "fridge": (lambda rng, lv: interiors.fridge((0.4, 0.35, 0.95), rng, lv), (100, 100, 100)),
    "fireplace": (lambda rng, lv: interiors.fireplace((0.3, 0.8, 0.55), rng, lv), (60, 60, 60)),
    "chimney": (lambda rng, lv: interiors.chimney((0.2, 0.6, 0.85), rng, lv), (12, 12, 12)),
    "floor_lamp_stem": (lambda rng, lv: interiors.lamp((0.05, 0.05, 0.75), rng, lv), (150, 100, 60)),
    "table_lamp": (lambda rng, lv: interiors.lamp((0.25, 0.25, 0.3), rng, lv), (150, 100, 60)),
    "lamp_shade": (lambda rng, lv: interiors.lamp((0.2, 0.2, 0.15), rng, lv), (80, 50, 30)),
    "window": (lambda rng, lv: interiors.window((1.0, 0.15, 0.7), rng, lv), (100, 100, 100)),
    "door": (lambda rng, lv: interiors.door((0.15, 0.5, 1.05), rng, lv), (150, 150, 60)),
    "curtain": (lambda rng, lv: interiors.curtain((0.25, 0.05, 1.2), rng, lv), (100, 100, 50)),
    "room_wall": (
        lambda rng, lv: interiors.room_wall(
            (8.95, 0.1, 1.4),
            rng,
            lv,
            inside=(0.0, 1.0),
            openings=[
                places.Opening(1.0, 2.0, 0.0, 2.1),
                places.Opening(3.5, 5.5, 0.9, 2.3),
                places.Opening(10.0, 12.0, 0.9, 2.3),
            ],
            look=interiors.wall_look(rng),
        ),
        (200, 200, 200),
    ),
    "ceiling": (lambda rng, lv: interiors.ceiling((8.0, 7.95, 0.1), rng, lv), (12, 12, 12)),
    "stand_tier": (
        lambda rng, lv: places.tier((30.0, 0.75, 1.0), rng, lv, front=(0.0, -1.0), seats=pick(looks.SEAT_COLOURS, rng)),
        (12, 12, 12),
    ),
    "goal_bar": (lambda rng, lv: places.goal_frame((0.06, 0.06, 1.22), rng, lv), (80, 60, 30)),
    "reeds": (lambda rng, lv: places.reeds((1.5, 0.3, 0.8), rng, lv), (300, 120, 50)),
    "step": (lambda rng, lv: interiors.step((0.15, 0.65, 0.5), rng, lv), (24, 24, 24)),
    "ball": (lambda rng, lv: props.ball(0.11, rng, lv), (600, 300, 120)),
    "baseball_bat": (lambda rng, lv: props.bat(0.03, 0.42, rng, lv), (300, 200, 120)),
    "golf_club": (lambda rng, lv: props.golf_club(0.015, 0.5, rng, lv), (400, 250, 150)),
    "bow": (lambda rng, lv: props.bow(0.015, 0.7, rng, lv), (300, 250, 250)),
    "hair_brush": (lambda rng, lv: props.brush(0.02, 0.1, rng, lv), (300, 200, 120)),
    "cup": (lambda rng, lv: props.cup(0.04, 0.04, rng, lv), (200, 120, 80)),
    "bottle": (lambda rng, lv: props.bottle(0.035, 0.1, rng, lv), (400, 250, 150)),
    "gun": (lambda rng, lv: props.gun((0.11, 0.02, 0.06), rng, lv), (60, 60, 60)),
    "crate": (lambda rng, lv: props.crate((0.3, 0.35, 0.5), rng, lv), (60, 60, 60)),
    "shopping_cart": (lambda rng, lv: props.cart((0.45, 0.28, 0.35), rng, lv), (600, 500, 400)),
    "door_leaf": (lambda rng, lv: props.door_leaf((0.02, 0.45, 1.0), rng, lv), (100, 100, 12)),
    "pull_up_bar": (lambda rng, lv: props.bar(0.02, 0.6, rng, lv), (80, 60, 40)),
    "urban_block": (
        lambda rng, lv: places.building((19.0, 9.0, 9.0), rng, lv, style="urban", loggias=places.loggias_of(rng)),
        (3400, 2800, 480),
    ),
    "suburban_house": (
        lambda rng, lv: places.building((5.0, 6.0, 3.5), rng, lv, style="suburban", street=(0.0, -1.0)),
        (450, 350, 80),
    ),
    "stadium_wall": (lambda rng, lv: places.building((32.0, 1.0, 6.0), rng, lv, style="stadium"), (400, 300, 60)),
    "trunk": (lambda rng, lv: places.trunk((0.2, 0.2, 1.5), rng, lv), (150, 100, 60)),
    "birch_trunk": (lambda rng, lv: places.trunk((0.2, 0.2, 1.5), rng, lv, species="birch"), (150, 100, 60)),
    "broadleaf_crown": (lambda rng, lv: places.crown((1.5, 1.5, 1.5), rng, lv), (900, 400, 150)),
    "conifer_crown": (lambda rng, lv: places.crown((1.5, 1.5, 1.5), rng, lv, species="conifer"), (260, 140, 90)),
    "birch_crown": (lambda rng, lv: places.crown((1.5, 1.5, 1.5), rng, lv, species="birch"), (900, 400, 150)),
    "hedge": (lambda rng, lv: places.shrub((2.0, 0.5, 0.5), rng, lv), (500, 280, 120)),
    "bush": (lambda rng, lv: places.shrub((0.75, 0.75, 0.45), rng, lv), (150, 80, 60)),
    "planter": (lambda rng, lv: places.shrub((1.0, 0.6, 0.4), rng, lv, planter=True), (340, 190, 120)),
    "carriageway": (lambda rng, lv: _slab_kind("carriageway", rng, lv), (60, 60, 60)),
    "pavement": (lambda rng, lv: _slab_kind("pavement", rng, lv), (12, 12, 12)),
    "grass_terrace": (lambda rng, lv: _slab_kind("grass_terrace", rng, lv), (12, 12, 12)),
    "lake_bank": (lambda rng, lv: _slab_kind("lake_bank", rng, lv), (24, 24, 24)),
    "ground": (lambda rng, lv: places.ground(60.0, 0.0, indoor=False), (2, 2, 2)),
    "pitch": (lambda rng, lv: places.ground(90.0, 0.0, indoor=False, pitch=(100.0, 54.0)), (160, 160, 160)),
    "floor": (lambda rng, lv: places.ground(20.0, 0.0, indoor=True, tiled=(4.0, -8.0, 9.0, -3.0)), (10, 10, 10)),
}
