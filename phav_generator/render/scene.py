"""Recipe + trajectory → drawables: the sampled environment, the action's boxes, props,
traffic and every person's body parts, each with its pixel class, instance id and colour.

Only the sampled environment is built. People are rigid capsules per body (the pelvis split
into left and right hip halves, as DESIGN.md labels it) plus a sphere per joint carrying the
joint's class; their instance id is person id + 1 (0 is "no person").
"""

from __future__ import annotations

import numpy as np

from phav_generator.body.model import rest_body
from phav_generator.motion.rotations import quat_to_matrix, yaw_matrix
from phav_generator.motion.skeleton import BONES, JOINT_BODIES, JOINT_NAMES, PARENTS
from phav_generator.physics.trajectory import PersonTrack, Trajectory
from phav_generator.render.gl import EMISSIVE, GROUND, WATER, Drawable
from phav_generator.render.lighting import Lighting
from phav_generator.render.meshes import box, capsule, ground, sphere
from phav_spec.recipe import HumanSpec, Recipe
from phav_spec.scene import ENVIRONMENT_SCENES, EnvironmentScene
from phav_spec.vocab import PIXEL_CLASSES

#: Half extent (m) of the ground square: past the far fog, under every environment.
GROUND_HALF_M = 400.0
#: The ground plane is drawn this far (m) below its height so roads and paths flush with it
#: (slabs whose top is the ground) win the depth test instead of flickering with it.
GROUND_DROP_M = 0.01
#: A joint's sphere is this much wider than the thickest capsule meeting there.
JOINT_SCALE = 1.12

# Base colours of static classes (linear RGB, 0–1); anything unlisted is mid grey.
_CLASS_COLOURS: dict[str, tuple[float, float, float]] = {
    "terrain": (0.33, 0.45, 0.25),
    "floor": (0.55, 0.45, 0.35),
    "road": (0.30, 0.30, 0.32),
    "building": (0.62, 0.58, 0.52),
    "vegetation": (0.25, 0.55, 0.20),
    "tree": (0.20, 0.45, 0.15),
    "car": (0.70, 0.15, 0.12),
    "truck": (0.85, 0.85, 0.80),
    "bus": (0.90, 0.70, 0.10),
    "stairs": (0.60, 0.60, 0.58),
}
#: Classes whose upward faces are ground: they get wet in the rain.
_GROUND_CLASSES = {"terrain", "road", "floor", "stairs"}
#: Open water's colour (deep green-blue; the sky's reflection does the rest).
_WATER_COLOUR = (0.04, 0.10, 0.12)
#: Warm emission of a lamp's head when the lamps are on.
_LAMP_EMISSION = (2.2, 1.7, 1.1)
#: Height of the storey above an interior's highest part (its ceiling closes stairwells).
_UPPER_STOREY_M = 2.6
#: Street lamps sit this far above their pole's top.
_LAMP_ABOVE_M = 0.25
_SKIN_PARTS = {"head", "left_hand", "right_hand", "left_lower_arm", "right_lower_arm"}
_TOP_PARTS = {"chest", "left_upper_arm", "right_upper_arm"}
_SHOE_PARTS = {"left_foot", "right_foot"}


def joint_radius(dims, body: int) -> float:
    """Radius of the sphere drawn at the joint at ``body``'s origin: a little wider than the
    thickest capsule meeting there, so the joint's class shows where it is not hidden."""
    return JOINT_SCALE * max(dims.capsules[body].radius, dims.capsules[PARENTS[body]].radius)


def class_id(name: str) -> int:
    return PIXEL_CLASSES[name].class_id


def _static(mesh, transform: np.ndarray, cls: str, n: int, **look) -> Drawable:
    material = GROUND if cls in _GROUND_CLASSES else look.pop("material", 0)
    return Drawable(mesh, np.broadcast_to(transform, (n, 4, 4)), class_id(cls), 0,
                    look.pop("colour", _CLASS_COLOURS.get(cls, (0.5,) * 3)), material=material, **look)  # fmt: skip


def lamp_positions(env: EnvironmentScene) -> np.ndarray:
    """Where the environment's lights hang (n, 3): above street poles, at indoor lamps."""
    out = [
        (c.center[0], c.center[1], c.top + (_LAMP_ABOVE_M if c.pixel_class == "pole" else 0.0))
        for c in env.colliders
        if c.pixel_class in ("pole", "lamp")
    ]
    return np.array(out, dtype=np.float64).reshape(-1, 3)


def _pose(rotation: np.ndarray, translation) -> np.ndarray:
    """Transforms (..., 4, 4) from rotations (..., 3, 3) and translations (..., 3)."""
    out = np.zeros((*rotation.shape[:-2], 4, 4))
    out[..., :3, :3] = rotation
    out[..., :3, 3] = translation
    out[..., 3, 3] = 1.0
    return out


def _rgb(c) -> tuple[float, float, float]:
    return tuple(float(x) / 255.0 for x in c)  # type: ignore[return-value]


def humans_by_id(recipe: Recipe) -> dict[int, HumanSpec]:
    """Every person's human model in the recipe, by person id."""
    out = {recipe.protagonist.person_id: recipe.protagonist.human}
    out.update({s.person_id: s.human for s in recipe.supporting_characters})
    out.update({a.person_id: a.human for a in recipe.background_actors})
    return out


def _person(track: PersonTrack, human) -> list[Drawable]:
    dims = rest_body(human.phenotype).dims
    transforms = _pose(quat_to_matrix(track.body_quat), track.body_pos)  # (F, 15, 4, 4)
    instance = track.person_id + 1
    colours = {
        "skin": _rgb(human.skin_rgb),
        "top": _rgb(human.outfit.top.rgb),
        "bottom": _rgb(human.outfit.bottom.rgb),
        "shoes": _rgb(human.outfit.shoes_rgb),
    }
    style = {"stripes": 1, "checks": 2}.get(human.outfit.top.fabric, 0)  # plain, striped or checked tops
    darker = _rgb(human.outfit.top.pattern_rgb)
    out = []
    for k, bone in enumerate(BONES):
        cap = dims.capsules[k]
        if bone.name == "pelvis":
            mid = tuple((np.array(cap.a) + np.array(cap.b)) / 2)
            left, right = (cap.a, cap.b) if cap.a[1] > cap.b[1] else (cap.b, cap.a)
            halves = (("left_hip", left), ("right_hip", right))
            for cls, end in halves:
                mesh = capsule(mid, end, cap.radius)
                out.append(Drawable(mesh, transforms[:, k], class_id(cls), instance, colours["bottom"]))
            continue
        part = "skin" if bone.name in _SKIN_PARTS else "top" if bone.name in _TOP_PARTS else "bottom"
        if bone.name in _SHOE_PARTS:
            part = "shoes"
        mesh = capsule(cap.a, cap.b, cap.radius)
        pattern = style if part == "top" else 0
        out.append(Drawable(mesh, transforms[:, k], class_id(bone.name), instance, colours[part],
                            pattern=pattern, pattern_colour=darker))  # fmt: skip
        if bone.name == "head" and human.hair.style != "bald":
            out += _hair(cap, human, transforms[:, k], instance)
    for name, body in zip(JOINT_NAMES, JOINT_BODIES, strict=True):
        radius = joint_radius(dims, body)
        colour = colours["skin"] if name == "neck" else colours["top"] if "hip" not in name else colours["bottom"]
        out.append(Drawable(sphere(radius), transforms[:, body], class_id(name), instance, colour))
    return out


def _hair(head, human, transforms: np.ndarray, instance: int) -> list[Drawable]:
    """A hair cap over the back and top of the head (class head), and a tail or long hair."""
    r = head.radius
    centre = np.array(head.b) + np.array([-0.25 * r, 0.0, 0.1 * r])
    colour = _rgb(human.hair.rgb)
    cls = class_id("head")
    out = [Drawable(capsule(tuple(centre), tuple(centre), 1.04 * r), transforms, cls, instance, colour)]
    if human.hair.style in ("long", "tied"):
        top = centre + np.array([-0.75 * r, 0.0, 0.0])
        length, width = (1.6 * r, 0.55 * r) if human.hair.style == "long" else (1.3 * r, 0.25 * r)
        tail = capsule(tuple(top), tuple(top + np.array([-0.15 * r, 0.0, -length])), width)
        out.append(Drawable(tail, transforms, cls, instance, colour))
    return out


def _upper_storey(env: EnvironmentScene, n: int) -> list[Drawable]:
    """The storey above an interior: walls and a ceiling around the whole house, so a
    stairwell shows the floor above, never the sky."""
    lo = np.min([np.array(c.center) - np.array(c.half_size) for c in env.colliders], axis=0)
    hi = np.max([np.array(c.center) + np.array(c.half_size) for c in env.colliders], axis=0)
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


def build_drawables(recipe: Recipe, trajectory: Trajectory, lighting: Lighting | None = None) -> list[Drawable]:
    """Everything the camera may see in this video, static world first (lamps glow when
    ``lighting`` switches them on; windows show its sky, through the fog when there is fog)."""
    env = ENVIRONMENT_SCENES[recipe.environment.name]
    n = len(trajectory.times)
    eye = np.eye(4)
    lamps_on = lighting is not None and lighting.lamp_intensity > 0.01
    glow = tuple(lighting.lamp_intensity * e for e in _LAMP_EMISSION) if lamps_on else (0.0, 0.0, 0.0)
    out = [_static(ground(GROUND_HALF_M, env.ground_z - GROUND_DROP_M), eye, env.ground_pixel_class, n, pattern=3)]
    for c in env.colliders:
        look: dict = {}
        if c.pixel_class == "window" and lighting is not None:
            # The outside seen through the glass: the horizon, or the fog veiling it.
            look = {"material": EMISSIVE, "emission": tuple(0.9 * x for x in lighting.fog_colour)}
        elif c.pixel_class == "lamp":
            look = {"material": EMISSIVE, "emission": glow}
        pose = _pose(yaw_matrix(np.deg2rad(c.yaw_deg)), c.center)
        out.append(_static(box(c.half_size), pose, c.pixel_class, n, **look))
    if env.indoor:
        out += _upper_storey(env, n)
    for x, y, z in lamp_positions(env) if not env.indoor else ():
        head = box((0.25, 0.25, 0.08))
        out.append(_static(head, _pose(np.eye(3), (x, y, z)), "pole", n, colour=(0.3, 0.3, 0.3),
                           material=EMISSIVE, emission=glow, casts_shadow=False))  # fmt: skip
    if env.water is not None:
        x0, y0, x1, y1, level = env.water
        pose = _pose(np.eye(3), ((x0 + x1) / 2, (y0 + y1) / 2, 0.0))
        out.append(_static(ground(1.0, level), pose @ np.diag([(x1 - x0) / 2, (y1 - y0) / 2, 1.0, 1.0]), "misc", n,
                           colour=_WATER_COLOUR, material=WATER, casts_shadow=False))  # fmt: skip
    for cls, center, half, yaw in trajectory.boxes:
        out.append(_static(box(half), _pose(yaw_matrix(np.deg2rad(yaw)), center), cls, n))
    for prop in trajectory.props:
        if prop.shape == "box":
            mesh = box(prop.size)
        elif prop.shape == "sphere":
            mesh = sphere(prop.size[0])
        else:  # MuJoCo capsule: radius, half length along z
            mesh = capsule((0.0, 0.0, -prop.size[1]), (0.0, 0.0, prop.size[1]), prop.size[0])
        transforms = _pose(quat_to_matrix(prop.quat), prop.pos)
        out.append(
            Drawable(mesh, transforms, class_id(prop.pixel_class), 0, _CLASS_COLOURS.get(prop.pixel_class, (0.5,) * 3))
        )
    humans = humans_by_id(recipe)
    for track in trajectory.people:
        out += _person(track, humans[track.person_id])
    return out
