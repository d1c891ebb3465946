"""Props: what people hold, kick, push and open, each shaped round the physics shape it
moves with (``PropTrack.shape`` and ``size``, in the prop's frame: a capsule along z, a
sphere, a box), its body inside it; a few thin parts reach past it and do not collide (a
cup's handle, a golf club's head, a bow's bent limbs). Each is held where the hand is: the
grip sits where the hand grips (``physics.plan.handheld``: a bat's, club's or brush's
handle at the capsule's +z end, a bow's riser in its middle).
"""

from __future__ import annotations

import math

import numpy as np

from phav_generator.physics.plan.push import CART_CLEARANCE_M
from phav_generator.world.materials import WOODS, Material, pick
from phav_generator.world.parts import Asset, Parts, Vec3, rotation

_BALLS = ((0.95, 0.95, 0.93), (0.85, 0.40, 0.10), (0.80, 0.10, 0.08), (0.95, 0.85, 0.15))
_BOTTLES = ((0.10, 0.35, 0.15), (0.35, 0.20, 0.08), (0.75, 0.85, 0.85))
_CUPS = ((0.95, 0.95, 0.93), (0.20, 0.35, 0.65), (0.70, 0.15, 0.12), (0.15, 0.15, 0.15))
_BLACK = (0.04, 0.04, 0.045)
_STEEL = (0.65, 0.66, 0.68)


def ball(radius: float, rng: np.random.Generator, level: int = 0, cls: str = "ball") -> Asset:
    """A ball: a leather-look sphere in one of a few colours, its seams as darker bands."""
    p = Parts(level)
    colour = _BALLS[int(rng.integers(0, len(_BALLS)))]
    p.ellipsoid("ball", cls, Material.LEATHER, colour, (0.0, 0.0, 0.0), (radius,) * 3, segments=p.round + 4)
    if p.fine:
        for k, rot in enumerate((rotation(), rotation(roll=math.pi / 2))):
            p.cylinder(f"seam{k}", cls, Material.RUBBER, _BLACK, rot @ np.array([0.0, 0.0, -0.004]),
                       rot @ np.array([0.0, 0.0, 0.004]), radius * 1.005, segments=p.round + 4)  # fmt: skip
    return p.build()


def bat(radius: float, half: float, rng: np.random.Generator, level: int = 0, cls: str = "baseball_bat") -> Asset:
    """A baseball bat: the barrel at −z tapering to the handle and its knob at +z."""
    p = Parts(level)
    wood = pick(WOODS[:4], rng)
    top, bottom = half + radius, -half - radius
    p.frustum("barrel", cls, Material.WOOD, wood, (0.0, 0.0, bottom), (0.0, 0.0, bottom + 0.45), radius, radius * 0.95)
    p.frustum(
        "taper", cls, Material.WOOD, wood, (0.0, 0.0, bottom + 0.45), (0.0, 0.0, top - 0.3), radius * 0.95, 0.4 * radius
    )
    p.cylinder("handle", cls, Material.RUBBER, _BLACK, (0.0, 0.0, top - 0.3), (0.0, 0.0, top - 0.02), 0.42 * radius)
    p.cylinder("knob", cls, Material.WOOD, wood, (0.0, 0.0, top - 0.02), (0.0, 0.0, top), 0.65 * radius)
    return p.build()


def golf_club(radius: float, half: float, rng: np.random.Generator, level: int = 0, cls: str = "golf_club") -> Asset:
    """A golf club: a rubber grip at +z, a steel shaft, a wooden driver's head at −z."""
    p = Parts(level)
    top, bottom = half + radius, -half - radius
    p.cylinder("grip", cls, Material.RUBBER, _BLACK, (0.0, 0.0, top - 0.25), (0.0, 0.0, top), 0.9 * radius)
    p.cylinder("shaft", cls, Material.CHROME, _STEEL, (0.0, 0.0, bottom + 0.06), (0.0, 0.0, top - 0.25), 0.45 * radius)
    p.ellipsoid("head", cls, Material.PAINT, (0.08, 0.08, 0.09), (0.035, 0.0, bottom + 0.03), (0.055, 0.04, 0.03))
    return p.build()


def bow(radius: float, half: float, rng: np.random.Generator, level: int = 0, cls: str = "bow") -> Asset:
    """A recurve bow along z: a riser with a grip in the middle, two limbs bending back to
    −x, and the string between their tips."""
    p = Parts(level)
    wood = pick(WOODS[:4], rng)
    p.cylinder("riser", cls, Material.WOOD, wood, (0.0, 0.0, -0.15), (0.0, 0.0, 0.15), radius * 1.3)
    p.cylinder("grip", cls, Material.LEATHER, (0.25, 0.15, 0.08), (0.0, 0.0, -0.05), (0.0, 0.0, 0.05), radius * 1.5)
    reach = half + radius
    bend = 0.12
    for sgn in (-1.0, 1.0):
        points = [(0.0, 0.15), (-0.3 * bend, 0.45 * reach), (-0.8 * bend, 0.8 * reach), (-bend, reach)]
        for k in range(len(points) - 1):
            (x0, z0), (x1, z1) = points[k], points[k + 1]
            p.frustum(f"limb{k}{sgn:+.0f}", cls, Material.WOOD, wood, (x0, 0.0, sgn * z0), (x1, 0.0, sgn * z1),
                      radius * (1.0 - 0.25 * k), radius * (0.75 - 0.25 * k), segments=6)  # fmt: skip
    p.cylinder("string", cls, Material.PLAIN, (0.9, 0.9, 0.85), (-bend, 0.0, -reach + 0.01), (-bend, 0.0, reach - 0.01),
               0.002, segments=4)  # fmt: skip
    return p.build()


def brush(radius: float, half: float, rng: np.random.Generator, level: int = 0, cls: str = "hair_brush") -> Asset:
    """A hair brush: a handle at +z, an oval head with a bristle pad at −z."""
    p = Parts(level)
    colour = pick(((0.15, 0.15, 0.15), (0.55, 0.35, 0.20), (0.75, 0.30, 0.45)), rng)
    top, bottom = half + radius, -half - radius
    p.frustum(
        "handle", cls, Material.PLASTIC, colour, (0.0, 0.0, bottom + 0.09), (0.0, 0.0, top), 0.6 * radius, 0.8 * radius
    )
    p.ellipsoid("head", cls, Material.PLASTIC, colour, (0.0, 0.0, bottom + 0.05), (radius, 0.7 * radius, 0.05))
    p.box(
        "bristles",
        cls,
        Material.FABRIC,
        (0.1, 0.1, 0.1),
        (radius * 0.9, 0.0, bottom + 0.05),
        (0.012, 0.55 * radius, 0.04),
    )
    return p.build()


def cup(radius: float, half: float, rng: np.random.Generator, level: int = 0, cls: str = "misc") -> Asset:
    """A mug: a ceramic body, coffee at its rim and a handle on its side."""
    p = Parts(level)
    colour = _CUPS[int(rng.integers(0, len(_CUPS)))]
    h = half + radius
    r = 0.85 * radius
    p.cylinder("body", cls, Material.PLASTIC, colour, (0.0, 0.0, -h), (0.0, 0.0, h - 0.005), r)
    p.cylinder("coffee", cls, Material.PLAIN, (0.18, 0.10, 0.05), (0.0, 0.0, h - 0.005), (0.0, 0.0, h), 0.85 * r)
    p.box("handle", cls, Material.PLASTIC, colour, (-(r + 0.012), 0.0, 0.0), (0.012, 0.006, 0.6 * h))
    return p.build()


def bottle(radius: float, half: float, rng: np.random.Generator, level: int = 0, cls: str = "misc") -> Asset:
    """A bottle: a glass body, its shoulder and neck, a cap and a label."""
    p = Parts(level)
    glass = _BOTTLES[int(rng.integers(0, len(_BOTTLES)))]
    h = half + radius
    r = radius
    p.cylinder("body", cls, Material.GLASS, glass, (0.0, 0.0, -h), (0.0, 0.0, 0.2 * h), r)
    p.frustum("shoulder", cls, Material.GLASS, glass, (0.0, 0.0, 0.2 * h), (0.0, 0.0, 0.55 * h), r, 0.35 * r)
    p.cylinder("neck", cls, Material.GLASS, glass, (0.0, 0.0, 0.55 * h), (0.0, 0.0, 0.93 * h), 0.33 * r)
    p.cylinder("cap", cls, Material.METAL, (0.75, 0.65, 0.2), (0.0, 0.0, 0.93 * h), (0.0, 0.0, h), 0.36 * r)
    p.cylinder("label", cls, Material.PLAIN, pick(((0.9, 0.9, 0.85), (0.8, 0.2, 0.1), (0.1, 0.2, 0.5)), rng),
               (0.0, 0.0, -0.7 * h), (0.0, 0.0, -0.1 * h), 1.03 * r)  # fmt: skip
    return p.build()


def gun(half: Vec3, rng: np.random.Generator, level: int = 0, cls: str = "gun") -> Asset:
    """A pistol along +x: a slide over a barrel, a frame with a trigger guard and a grip
    slanting down at the back."""
    hx, hy, hz = half
    p = Parts(level)
    p.span("slide", cls, Material.METAL, (0.12, 0.12, 0.13), (-hx, -hy, 0.25 * hz), (hx, hy, hz))
    p.span("frame", cls, Material.PLASTIC, _BLACK, (-hx, -0.85 * hy, -0.05 * hz), (0.7 * hx, 0.85 * hy, 0.25 * hz))
    p.box("grip", cls, Material.PLASTIC, _BLACK, (-0.6 * hx, 0.0, -0.5 * hz), (0.22 * hx, 0.8 * hy, 0.48 * hz),
          rot=rotation(pitch=-0.25))  # fmt: skip
    p.span(
        "guard", cls, Material.PLASTIC, _BLACK, (-0.15 * hx, -0.3 * hy, -0.45 * hz), (0.3 * hx, 0.3 * hy, -0.35 * hz)
    )
    return p.build()


def crate(half: Vec3, rng: np.random.Generator, level: int = 0, cls: str = "misc") -> Asset:
    """A wooden crate: a box with boards and corner posts."""
    hx, hy, hz = half
    p = Parts(level)
    wood = pick(WOODS[:4], rng)
    p.span("box", cls, Material.WOOD, wood, (-hx + 0.02, -hy + 0.02, -hz), (hx - 0.02, hy - 0.02, hz))
    for x in (-hx + 0.02, hx - 0.02):
        for y in (-hy + 0.02, hy - 0.02):
            p.span(
                f"post{x:+.1f}{y:+.1f}",
                cls,
                Material.WOOD,
                WOODS[1],
                (x - 0.02, y - 0.02, -hz),
                (x + 0.02, y + 0.02, hz),
            )
    return p.build()


def cart(half: Vec3, rng: np.random.Generator, level: int = 0, cls: str = "misc") -> Asset:
    """A shopping cart: a wire basket (its handle end at −x, towards the pusher) on a chassis
    with four castors under it (the castors reach to the ground below the box)."""
    hx, hy, hz = half
    p = Parts(level)
    wire = (0.75, 0.76, 0.78)
    t = 0.012
    for sgn in (-1.0, 1.0):  # the basket's sides, open wirework as bars
        p.span(f"side{sgn:+.0f}", cls, Material.CHROME, wire, (-hx, sgn * hy - t, -hz), (hx, sgn * hy + t, -hz + 2 * t))
        p.span(f"rim{sgn:+.0f}", cls, Material.CHROME, wire, (-hx, sgn * hy - t, hz - 2 * t), (hx, sgn * hy + t, hz))
        n = 6 if p.fine else 2
        for k in range(n):
            x = -hx + (k + 0.5) * 2 * hx / n
            p.span(
                f"bar{k}{sgn:+.0f}", cls, Material.CHROME, wire, (x - t, sgn * hy - t, -hz), (x + t, sgn * hy + t, hz)
            )
    for x in (-hx, hx):
        p.span(f"end{x:+.1f}", cls, Material.CHROME, wire, (x - t, -hy, -hz), (x + t, hy, hz))
    p.span("floor", cls, Material.CHROME, wire, (-hx, -hy, -hz), (hx, hy, -hz + t))
    p.cylinder("handle", cls, Material.PLASTIC, (0.7, 0.1, 0.08), (-hx, -hy, hz), (-hx, hy, hz), 0.018)
    for x in (-hx + 0.06, hx - 0.06):
        for y in (-hy + 0.05, hy - 0.05):
            p.cylinder(f"leg{x:+.1f}{y:+.1f}", cls, Material.CHROME, wire, (x, y, -hz - CART_CLEARANCE_M + 0.05),
                       (x, y, -hz), 0.01, segments=6)  # fmt: skip
            axle = -hz - CART_CLEARANCE_M + 0.05
            p.cylinder(f"castor{x:+.1f}{y:+.1f}", cls, Material.RUBBER, _BLACK, (x, y - 0.015, axle),
                       (x, y + 0.015, axle), 0.05, segments=8)  # fmt: skip
    return p.build()


def door_leaf(half: Vec3, rng: np.random.Generator, level: int = 0, cls: str = "door") -> Asset:
    """A door's leaf: a painted slab with two raised panels on each face and a handle."""
    hx, hy, hz = half
    p = Parts(level)
    wood = pick(WOODS, rng)
    p.span("leaf", cls, Material.WOOD, wood, (-hx, -hy, -hz), (hx, hy, hz))
    if p.fine:
        for sgn in (-1.0, 1.0):
            x0, x1 = sorted((sgn * hx, sgn * (hx + 0.01)))
            for k, (z0, z1) in enumerate(((-hz + 0.15, -0.05), (0.1, hz - 0.15))):
                p.span(f"panel{k}{sgn:+.0f}", cls, Material.WOOD, wood, (x0, -hy + 0.1, z0), (x1, hy - 0.1, z1))
            x0, x1 = sorted((sgn * hx, sgn * (hx + 0.05)))
            p.span(
                f"handle{sgn:+.0f}",
                cls,
                Material.CHROME,
                (0.8, 0.78, 0.7),
                (x0, hy - 0.12, -0.02),
                (x1, hy - 0.06, 0.0),
            )
    return p.build()


def bar(radius: float, half: float, rng: np.random.Generator, level: int = 0, cls: str = "misc") -> Asset:
    """A pull-up bar: a chrome tube along z."""
    p = Parts(level)
    p.cylinder("tube", cls, Material.CHROME, _STEEL, (0.0, 0.0, -half - radius), (0.0, 0.0, half + radius), radius)
    return p.build()


#: The prop builders by object: capsules (radius, half length), spheres (radius) and boxes
#: (half extents), as ``PropTrack.size`` gives them.
CAPSULE_PROPS = {"baseball_bat": bat, "golf_club": golf_club, "bow": bow, "hair_brush": brush, "cup": cup,
                 "bottle": bottle, "pull_up_bar": bar}  # fmt: skip
BOX_PROPS = {"gun": gun, "box": crate, "shopping_cart": cart, "door": door_leaf}


def prop(
    obj: str, cls: str, shape: str, size: tuple[float, ...], rng: np.random.Generator, level: int = 0
) -> Asset | None:
    """The asset of a prop of object ``obj`` moving as physics shape ``shape`` of ``size``
    (labelled ``cls``), or None where the library has none for it."""
    if obj == "ball" and shape == "sphere":
        return ball(size[0], rng, level, cls)
    if shape == "capsule" and obj in CAPSULE_PROPS:
        return CAPSULE_PROPS[obj](size[0], size[1], rng, level, cls)
    if shape == "box" and obj in BOX_PROPS:
        return BOX_PROPS[obj](size, rng, level, cls)
    return None
