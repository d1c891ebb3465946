"""Recipe + trajectory → drawables: the sampled environment, the action's boxes, props,
traffic and every person's body parts, each with its pixel class, instance id and colour.

Only the sampled environment is built. People are anny bodies skinned to their ragdolls
(``render.people``: classes per part and joint, clothes, hair); their instance id is person
id + 1 (0 is "no person").
"""

from __future__ import annotations

import numpy as np

from phav_generator.motion.rotations import quat_to_matrix, yaw_matrix
from phav_generator.physics.plan.car_hit import CAR_CLEARANCE_M, CAR_LOOK_STREAM
from phav_generator.physics.plan.scene_plan import PropPlan
from phav_generator.physics.trajectory import PersonTrack, PropTrack, Trajectory
from phav_generator.render.assets import WET_CLASSES, asset_drawable, vehicle_drawables
from phav_generator.render.gl import GROUND, SPECKLE, WATER, Drawable
from phav_generator.render.lighting import Lighting
from phav_generator.render.meshes import box, capsule, ground, sphere
from phav_generator.render.people import level_of_detail, person_drawables
from phav_generator.world import props
from phav_generator.world.library import box_asset, collider_asset, ground_asset, is_light, level_for, vehicle
from phav_generator.world.vehicles import Vehicle
from phav_spec.recipe import HumanSpec, Recipe
from phav_spec.scene import ENVIRONMENT_SCENES, VEHICLE_HALF_SIZES, EnvironmentScene
from phav_spec.seeding import stream
from phav_spec.vocab import PIXEL_CLASSES

#: Half extent (m) of the ground square: past the far fog, under every environment.
GROUND_HALF_M = 400.0
#: The ground plane is drawn this far (m) below its height so roads and paths flush with it
#: (slabs whose top is the ground) win the depth test instead of flickering with it.
GROUND_DROP_M = 0.01

# Base colours of static classes (linear RGB, 0–1); anything unlisted is mid grey.
_CLASS_COLOURS: dict[str, tuple[float, float, float]] = {
    "terrain": (0.33, 0.45, 0.25),
    "floor": (0.55, 0.45, 0.35),
    "road": (0.30, 0.30, 0.32),
    "building": (0.62, 0.58, 0.52),
    "vegetation": (0.25, 0.55, 0.20),
    "tree": (0.20, 0.45, 0.15),
}
#: Open water's colour (deep green-blue; the sky's reflection does the rest).
_WATER_COLOUR = (0.04, 0.10, 0.12)
#: Warm emission of a lamp's head when the lamps are on.
_LAMP_EMISSION = (2.2, 1.7, 1.1)
#: Height of the storey above an interior's highest part (its ceiling closes stairwells).
_UPPER_STOREY_M = 2.6
#: A lamp post's light sits this far below its top, in its lantern.
_LANTERN_BELOW_TOP_M = 0.2


def class_id(name: str) -> int:
    return PIXEL_CLASSES[name].class_id


def _static(mesh, transform: np.ndarray, cls: str, n: int, **look) -> Drawable:
    given = look.pop("material", 0)
    material = GROUND if cls in WET_CLASSES else given  # wet ground darkens: its own material
    return Drawable(mesh, np.broadcast_to(transform, (n, 4, 4)), class_id(cls), 0,
                    look.pop("colour", _CLASS_COLOURS.get(cls, (0.5,) * 3)), material=material, **look)  # fmt: skip


def lamp_positions(name: str) -> np.ndarray:
    """Where environment ``name``'s lights hang (n, 3): in the lanterns of lamp posts, in the
    floodlights' heads, at indoor lamps (not on the posts of signs and signals)."""
    env = ENVIRONMENT_SCENES[name]
    out = []
    for i, c in enumerate(env.colliders):
        if c.pixel_class == "lamp":
            out.append(c.center)
        elif c.pixel_class == "pole" and is_light(name, i):
            out.append((c.center[0], c.center[1], c.top - _LANTERN_BELOW_TOP_M))
    return np.array(out, dtype=np.float64).reshape(-1, 3)


def _pose(rotation: np.ndarray, translation) -> np.ndarray:
    """Transforms (..., 4, 4) from rotations (..., 3, 3) and translations (..., 3)."""
    out = np.zeros((*rotation.shape[:-2], 4, 4))
    out[..., :3, :3] = rotation
    out[..., :3, 3] = translation
    out[..., 3, 3] = 1.0
    return out


def _bounding_radius(shape: str, size: tuple[float, ...]) -> float:
    """The bounding radius of a physics shape: a box's half extents, a sphere's radius, a
    capsule's radius and half length."""
    if shape == "box":
        return float(np.linalg.norm(size))
    if shape == "capsule":
        return float(size[0] + size[1])
    return float(size[0])


def _level_along(positions: np.ndarray, radius: float, eyes: np.ndarray, focal: float) -> int:
    """The level of detail of something of bounding ``radius`` at ``positions`` (one, or one
    per frame) seen from the camera's ``eyes``: by its nearest approach over the video."""
    n = min(len(positions), len(eyes)) if len(positions) > 1 else len(eyes)
    at = positions[:n] if len(positions) > 1 else positions
    nearest = float(np.linalg.norm(eyes[:n] - at, axis=1).min()) - radius
    return level_for(radius, nearest, focal)


def drawn_vehicle(recipe: Recipe, prop: PropPlan | PropTrack, level: int = 0) -> Vehicle:
    """The vehicle drawn for a vehicle prop (a ``PropPlan`` or ``PropTrack``): the car of
    ``car_hit``, seeded by the recipe's physics seed on the stream its plan took its body
    type from (so that it collides as drawn), or traffic, by the background seed."""
    if prop.name == "car":
        return vehicle(prop.object, prop.size, stream(recipe.seeds.physics, CAR_LOOK_STREAM), level,
                       below=CAR_CLEARANCE_M)  # fmt: skip
    return vehicle(prop.object, prop.size, stream(recipe.seeds.background, f"world/{prop.name}"), level)


def humans_by_id(recipe: Recipe) -> dict[int, HumanSpec]:
    """Every person's human model in the recipe, by person id."""
    out = {recipe.protagonist.person_id: recipe.protagonist.human}
    out.update({s.person_id: s.human for s in recipe.supporting_characters})
    out.update({a.person_id: a.human for a in recipe.background_actors})
    return out


def tallest_px(track: PersonTrack, trajectory: Trajectory) -> float:
    """The most pixels tall a person can appear in the video: its height over its nearest
    distance to the camera, times the focal length (an upper bound: never too coarse)."""
    eye = trajectory.cam_to_world[:, :3, 3]
    n = min(len(eye), len(track.body_pos))
    nearest = float(np.linalg.norm(track.body_pos[:n, 0] - eye[:n], axis=1).min())
    return trajectory.intrinsics[1] * track.height_m / max(nearest, 1e-3)


def _person(track: PersonTrack, human: HumanSpec, trajectory: Trajectory) -> list[Drawable]:
    """A person's dressed body and hair, skinned to its ragdoll's bodies every frame, at the
    level of detail its size on screen asks for."""
    level = level_of_detail(tallest_px(track, trajectory))
    return person_drawables(
        human.phenotype, human.skin_rgb, human.outfit, human.hair.style, human.hair.rgb,
        track.body_pos, quat_to_matrix(track.body_quat), track.person_id + 1, level,
    )  # fmt: skip


def _upper_storey(env: EnvironmentScene, n: int) -> list[Drawable]:
    """The storey above an interior: walls and a ceiling around the whole house, so a
    stairwell shows the floor above, never the sky."""
    lo = np.min([np.array(c.center) - np.array(c.half_size) for c in env.room_colliders], axis=0)
    hi = np.max([np.array(c.center) + np.array(c.half_size) for c in env.room_colliders], axis=0)
    mid, half = (hi + lo) / 2, (hi - lo) / 2
    top = hi[2] + _UPPER_STOREY_M
    z, hz = (hi[2] + top) / 2 - 0.2, (top - hi[2]) / 2 + 0.2
    t = 0.1
    parts = [
        ("ceiling", (mid[0], mid[1], top), (half[0], half[1], t)),
        ("misc", (lo[0], mid[1], z), (t, half[1], hz)),
        ("misc", (hi[0], mid[1], z), (t, half[1], hz)),
        ("misc", (mid[0], lo[1], z), (half[0], t, hz)),
        ("misc", (mid[0], hi[1], z), (half[0], t, hz)),
    ]
    return [_static(box(h), _pose(np.eye(3), c), cls, n) for cls, c, h in parts]


def build_drawables(
    recipe: Recipe,
    trajectory: Trajectory,
    lighting: Lighting | None = None,
    *,
    people: bool = True,
    assets: bool = True,
) -> list[Drawable]:
    """Everything the camera may see in this video, static world first (lamps glow when
    ``lighting`` switches them on);
    ``people=False`` leaves the people out, ``assets=False`` draws the objects and places
    as their colliders' boxes on a plain ground and the props as their physics shapes (the
    bench measures what each costs)."""
    env_name = recipe.environment.name
    env = ENVIRONMENT_SCENES[env_name]
    n = len(trajectory.times)
    eye = np.eye(4)
    lamps_on = lighting is not None and lighting.lamp_intensity > 0.01
    glow = tuple(lighting.lamp_intensity * e for e in _LAMP_EMISSION) if lamps_on else (0.0, 0.0, 0.0)
    if assets:
        out = [asset_drawable(ground_asset(env_name, GROUND_HALF_M, GROUND_DROP_M), np.broadcast_to(eye, (n, 4, 4)))]
    else:
        ground_mesh = ground(GROUND_HALF_M, env.ground_z - GROUND_DROP_M)
        out = [_static(ground_mesh, eye, env.ground_pixel_class, n, pattern=SPECKLE)]
    focal = trajectory.intrinsics[1]
    eyes = trajectory.cam_to_world[:, :3, 3]
    for i, c in enumerate(env.colliders):
        pose = _pose(yaw_matrix(np.deg2rad(c.yaw_deg)), c.center)
        level = _level_along(np.array(c.center)[None], float(np.linalg.norm(c.half_size)), eyes, focal)
        asset = collider_asset(env_name, i, level, recipe.environment.look_seed) if assets else None
        if isinstance(asset, Vehicle):
            out += vehicle_drawables(asset, np.broadcast_to(pose, (n, 4, 4)), lamp_glow=glow)
            continue
        if asset is not None:
            out.append(asset_drawable(asset, np.broadcast_to(pose, (n, 4, 4)), lamp_glow=glow))
            continue
        out.append(_static(box(c.half_size), pose, c.pixel_class, n))
    if env.indoor:
        out += _upper_storey(env, n)
    if env.water is not None:
        x0, y0, x1, y1, level = env.water
        pose = _pose(np.eye(3), ((x0 + x1) / 2, (y0 + y1) / 2, 0.0))
        out.append(_static(ground(1.0, level), pose @ np.diag([(x1 - x0) / 2, (y1 - y0) / 2, 1.0, 1.0]), "misc", n,
                           colour=_WATER_COLOUR, material=WATER, casts_shadow=False))  # fmt: skip
    for k, (cls, center, half, yaw) in enumerate(trajectory.boxes):
        pose = _pose(yaw_matrix(np.deg2rad(yaw)), center)
        if not assets:
            out.append(_static(box(half), pose, cls, n))
            continue
        rng = stream(recipe.seeds.physics, f"world/box{k}")
        level = _level_along(np.array(center)[None], float(np.linalg.norm(half)), eyes, focal)
        built = box_asset(cls, half, rng, level, indoor=env.indoor)
        out.append(asset_drawable(built, np.broadcast_to(pose, (n, 4, 4))))
    for prop in trajectory.props:
        transforms = _pose(quat_to_matrix(prop.quat), prop.pos)
        level = _level_along(prop.pos, _bounding_radius(prop.shape, prop.size), eyes, focal)
        if assets and prop.object in VEHICLE_HALF_SIZES:
            out += vehicle_drawables(drawn_vehicle(recipe, prop, level), transforms, lamp_glow=glow)
            continue
        rng = stream(recipe.seeds.physics, f"world/{prop.name}")
        look = props.prop(prop.object, prop.pixel_class, prop.shape, prop.size, rng, level) if assets else None
        if look is not None:
            out.append(asset_drawable(look, transforms))
            continue
        if prop.shape == "box":
            mesh = box(prop.size)
        elif prop.shape == "sphere":
            mesh = sphere(prop.size[0])
        else:  # MuJoCo capsule: radius, half length along z
            mesh = capsule((0.0, 0.0, -prop.size[1]), (0.0, 0.0, prop.size[1]), prop.size[0])
        out.append(
            Drawable(mesh, transforms, class_id(prop.pixel_class), 0, _CLASS_COLOURS.get(prop.pixel_class, (0.5,) * 3))
        )
    humans = humans_by_id(recipe)
    for track in trajectory.people if people else ():
        out += _person(track, humans[track.person_id], trajectory)
    return out
