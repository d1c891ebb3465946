"""Recipe + trajectory → drawables: the sampled environment, the action's boxes, props,
traffic and every person's body parts, each with its pixel class, instance id and colour.

Only the sampled environment is built. People are rigid capsules per body (the pelvis split
into left and right hip halves, as DESIGN.md labels it) plus a sphere per joint carrying the
joint's class; their instance id is person id + 1 (0 is "no person").
"""

from __future__ import annotations

import numpy as np

from phav_generator.physics.trajectory import PersonTrack, Trajectory
from phav_generator.render.gl import Drawable
from phav_generator.render.meshes import box, capsule, ground, sphere
from phav_generator.rotations import quat_to_matrix, yaw_matrix
from phav_generator.skeleton import BONES, JOINT_BODIES, JOINT_NAMES, PARENTS, dims_for
from phav_spec.recipe import HumanSpec, Recipe
from phav_spec.scene import ENVIRONMENT_SCENES
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
_SKIN_PARTS = {"head", "left_hand", "right_hand", "left_lower_arm", "right_lower_arm"}
_TOP_PARTS = {"chest", "left_upper_arm", "right_upper_arm"}
_SHOE_PARTS = {"left_foot", "right_foot"}


def class_id(name: str) -> int:
    return PIXEL_CLASSES[name].class_id


def _static(mesh, transform: np.ndarray, cls: str, n: int) -> Drawable:
    return Drawable(mesh, np.broadcast_to(transform, (n, 4, 4)), class_id(cls), 0, _CLASS_COLOURS.get(cls, (0.5,) * 3))


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
    dims = dims_for(human)
    transforms = _pose(quat_to_matrix(track.body_quat), track.body_pos)  # (F, 15, 4, 4)
    instance = track.person_id + 1
    colours = {
        "skin": _rgb(human.skin_rgb),
        "top": _rgb(human.top_rgb),
        "bottom": _rgb(human.bottom_rgb),
        "shoes": _rgb(human.shoes_rgb),
    }
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
        out.append(Drawable(mesh, transforms[:, k], class_id(bone.name), instance, colours[part]))
    for name, body in zip(JOINT_NAMES, JOINT_BODIES, strict=True):
        parent = PARENTS[body]
        radius = JOINT_SCALE * max(dims.capsules[body].radius, dims.capsules[parent].radius)
        colour = colours["skin"] if name == "neck" else colours["top"] if "hip" not in name else colours["bottom"]
        out.append(Drawable(sphere(radius), transforms[:, body], class_id(name), instance, colour))
    return out


def build_drawables(recipe: Recipe, trajectory: Trajectory) -> list[Drawable]:
    """Everything the camera may see in this video, static world first."""
    env = ENVIRONMENT_SCENES[recipe.environment.name]
    n = len(trajectory.times)
    eye = np.eye(4)
    out = [_static(ground(GROUND_HALF_M, env.ground_z - GROUND_DROP_M), eye, env.ground_pixel_class, n)]
    for c in env.colliders:
        out.append(_static(box(c.half_size), _pose(yaw_matrix(np.deg2rad(c.yaw_deg)), c.center), c.pixel_class, n))
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
