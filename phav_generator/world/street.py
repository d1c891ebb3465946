"""Street furniture, each fitted into its collision box (the box's frame: origin at its
centre, +z up, the box's local y the way a sign or signal faces): lamp posts, plain posts,
floodlight masts and heads, traffic-light heads, sign plates, benches, guard rails."""

from __future__ import annotations

import math

import numpy as np

from phav_generator.world.materials import STREET_METALS, WOODS, Material, pick
from phav_generator.world.parts import LAMP_GLOW, Asset, Parts, Vec3, circle

_SIGN_FACES = ("round", "triangle", "octagon", "square")
_RED, _WHITE, _BLUE, _AMBER = (0.75, 0.06, 0.05), (0.95, 0.95, 0.93), (0.05, 0.25, 0.65), (0.95, 0.65, 0.05)


def post(half: Vec3, rng: np.random.Generator, level: int = 0, *, lantern: bool = False) -> Asset:
    """A round post filling the box's height (a sign's or signal's post; a lamp post when
    ``lantern``: tapered, with a lantern on a collar at its top, its glass lit by the lamps)."""
    hx, hy, hz = half
    p = Parts(level)
    r = 0.8 * min(hx, hy)
    if not lantern:  # galvanised steel
        p.cylinder("post", "pole", Material.METAL, (0.55, 0.57, 0.58), (0.0, 0.0, -hz), (0.0, 0.0, hz), 0.7 * r)
        return p.build()
    metal = pick(STREET_METALS, rng)
    top = hz - 0.35
    p.frustum("base", "pole", Material.PAINT, metal, (0.0, 0.0, -hz), (0.0, 0.0, -hz + 0.6), r, 0.85 * r)
    p.frustum("shaft", "pole", Material.PAINT, metal, (0.0, 0.0, -hz + 0.6), (0.0, 0.0, top), 0.8 * r, 0.6 * r)
    p.cylinder("collar", "pole", Material.PAINT, metal, (0.0, 0.0, top), (0.0, 0.0, top + 0.05), 0.7 * r)
    p.frustum("lantern", "pole", Material.GLASS, (0.9, 0.85, 0.7), (0.0, 0.0, top + 0.05), (0.0, 0.0, hz - 0.06),
              0.6 * r, r, segments=6, glow=LAMP_GLOW)  # fmt: skip
    p.frustum("cap", "pole", Material.PAINT, metal, (0.0, 0.0, hz - 0.06), (0.0, 0.0, hz), r, 0.2 * r, segments=6)
    return p.build()


def mast(half: Vec3, rng: np.random.Generator, level: int = 0) -> Asset:
    """A floodlight mast: a tapered steel tube on a base plate."""
    hx, hy, hz = half
    p = Parts(level)
    p.span("plate", "pole", Material.CONCRETE, (0.6, 0.6, 0.58), (-hx, -hy, -hz), (hx, hy, -hz + 0.3))
    p.frustum("tube", "pole", Material.METAL, (0.62, 0.63, 0.64), (0.0, 0.0, -hz + 0.3), (0.0, 0.0, hz),
              0.8 * min(hx, hy), 0.35 * min(hx, hy))  # fmt: skip
    return p.build()


def floodlight_head(half: Vec3, rng: np.random.Generator, level: int = 0) -> Asset:
    """A floodlight head: a frame holding rows of lamps that show on both its faces across
    the box's x (the collider's yaw turns them to the pitch)."""
    hx, hy, hz = half
    p = Parts(level)
    p.box("frame", "pole", Material.METAL, (0.5, 0.5, 0.52), (0.0, 0.0, 0.0), (0.6 * hx, 0.6 * hy, 0.9 * hz))
    rows, cols = (3, 6) if p.fine else (2, 3)
    for i in range(rows):
        for j in range(cols):
            y = -0.9 * hy + (j + 0.5) * 1.8 * hy / cols
            z = -0.85 * hz + (i + 0.5) * 1.7 * hz / rows
            p.box(f"lamp{i}{j}", "pole", Material.CHROME, (0.95, 0.95, 0.9), (0.0, y, z),
                  (hx * 0.98, 0.8 * hy / cols, 0.75 * hz / rows), glow=LAMP_GLOW)  # fmt: skip
    return p.build()


def traffic_light(half: Vec3, rng: np.random.Generator, level: int = 0) -> Asset:
    """A signal head: a dark housing with red, amber and green lenses under visors, on both
    faces (±y), and a backplate."""
    hx, hy, hz = half
    p = Parts(level)
    p.box("housing", "traffic_light", Material.PAINT, (0.05, 0.05, 0.05), (0.0, 0.0, 0.0), (0.8 * hx, 0.45 * hy, hz))
    p.box("backplate", "traffic_light", Material.PLASTIC, (0.03, 0.03, 0.03), (0.0, 0.0, 0.0), (hx, 0.05 * hy, hz))
    lenses = ((_RED, 0.62), (_AMBER, 0.0), ((0.05, 0.7, 0.3), -0.62))
    r = 0.6 * hx
    for colour, z in lenses:
        for sgn in (-1.0, 1.0):
            y0, y1 = sgn * 0.45 * hy, sgn * (0.45 * hy + 0.01)
            p.cylinder(f"lens{z:+.1f}{sgn:+.0f}", "traffic_light", Material.GLASS, colour, (0.0, y0, z * hz),
                       (0.0, y1, z * hz), r)  # fmt: skip
            if p.fine:
                p.box(f"visor{z:+.1f}{sgn:+.0f}", "traffic_light", Material.PAINT, (0.05, 0.05, 0.05),
                      (0.0, sgn * (0.45 * hy + 0.045), z * hz + r + 0.01), (r, 0.045, 0.008))  # fmt: skip
    return p.build()


def sign_plate(half: Vec3, rng: np.random.Generator, level: int = 0) -> Asset:
    """A traffic sign's plate facing ±y: round (a white disc in a red ring), a warning
    triangle, a stop octagon or a blue square, on a grey metal back."""
    hx, hy, hz = half
    p = Parts(level)
    face = _SIGN_FACES[int(rng.integers(0, len(_SIGN_FACES)))]
    r = min(hx, hz)
    sides = {"round": p.round + 8, "triangle": 3, "octagon": 8, "square": 4}[face]
    phase = {"round": 0.0, "triangle": math.pi / 2, "octagon": math.pi / 8, "square": math.pi / 4}[face]
    scale = {"round": 1.0, "triangle": 1.0, "octagon": 1.0, "square": math.sqrt(2.0)}[face]
    outline = [(scale * r * c, scale * r * s) for c, s in circle(sides, phase)]
    if face == "triangle":
        outline = [(x, z - 0.15 * r) for x, z in outline]
    thick = 0.4 * hy
    p.prism("plate", "traffic_sign", Material.METAL, (0.6, 0.6, 0.62), outline, -thick, thick)
    outer, inner = {"round": (_RED, _WHITE), "triangle": (_RED, _WHITE), "octagon": (_RED, _RED),
                    "square": (_BLUE, _WHITE)}[face]  # fmt: skip
    for sgn in (-1.0, 1.0):
        for k, (colour, shrink, lift) in enumerate(((outer, 0.96, 0.003), (inner, 0.72, 0.006))):
            if face == "octagon" and k == 1:
                colour, shrink = _WHITE, 0.5  # a white band where STOP is written
                ring = [(x * shrink, sgn * (thick + lift), z * 0.18) for x, z in outline]
            else:
                cz = -0.15 * r * (1 - shrink) if face == "triangle" else 0.0
                ring = [(x * shrink, sgn * (thick + lift), z * shrink + cz) for x, z in outline]
            p.panel(f"face{k}{sgn:+.0f}", "traffic_sign", Material.PLAIN, colour, ring if sgn < 0 else ring[::-1])
    return p.build()


def bench_seat(half: Vec3, rng: np.random.Generator, level: int = 0) -> Asset:
    """A bench's seat: slats across two cast-iron frames (its legs)."""
    hx, hy, hz = half
    p = Parts(level)
    wood, iron = pick(WOODS[:4], rng), pick(STREET_METALS[:2], rng)
    slats = 4 if p.fine else 1
    gap = 0.02 if p.fine else 0.0
    depth = (2 * hy - gap * (slats - 1)) / slats
    for k in range(slats):
        y0 = -hy + k * (depth + gap)
        p.span(f"slat{k}", "bench", Material.WOOD, wood, (-hx, y0, hz - 0.05), (hx, y0 + depth, hz))
    for x in (-hx + 0.15, hx - 0.15):
        p.span(
            f"frame{x:+.1f}",
            "bench",
            Material.PAINT,
            iron,
            (x - 0.03, -hy + 0.02, hz - 0.09),
            (x + 0.03, hy - 0.02, hz - 0.05),
        )
        for y in (-hy + 0.05, hy - 0.05):
            p.span(
                f"leg{x:+.1f}{y:+.1f}",
                "bench",
                Material.PAINT,
                iron,
                (x - 0.03, y - 0.03, -hz),
                (x + 0.03, y + 0.03, hz - 0.09),
            )
    return p.build()


def bench_back(half: Vec3, rng: np.random.Generator, level: int = 0) -> Asset:
    """A bench's backrest: slats on the frames' uprights."""
    hx, hy, hz = half
    p = Parts(level)
    wood, iron = pick(WOODS[:4], rng), pick(STREET_METALS[:2], rng)
    slats = 3 if p.fine else 1
    gap = 0.03 if p.fine else 0.0
    height = (2 * hz - 0.05 - gap * (slats - 1)) / slats
    for k in range(slats):
        z0 = -hz + 0.05 + k * (height + gap)
        p.span(f"slat{k}", "bench", Material.WOOD, wood, (-hx, -hy, z0), (hx, -hy + 0.035, z0 + height))
    for x in (-hx + 0.15, hx - 0.15):
        p.span(
            f"upright{x:+.1f}", "bench", Material.PAINT, iron, (x - 0.03, -hy + 0.035, -hz), (x + 0.03, hy, hz - 0.02)
        )
    return p.build()


def guard_rail(half: Vec3, rng: np.random.Generator, level: int = 0) -> Asset:
    """A guard rail along the box's longer horizontal axis: posts every 2 m and two rails."""
    hx, hy, hz = half
    p = Parts(level)
    along_x = hx >= hy
    length, thick = (hx, hy) if along_x else (hy, hx)
    steel = (0.62, 0.64, 0.66)
    n = max(2, int(2 * length / 2.0) + 1)

    def span(name, a0, a1, b0, b1, z0, z1):  # a along the rail, b across it
        lo, hi = ((a0, b0, z0), (a1, b1, z1)) if along_x else ((b0, a0, z0), (b1, a1, z1))
        p.span(name, "guard_rail", Material.METAL, steel, lo, hi)

    for k in range(n):
        a = -length + 0.04 + k * (2 * length - 0.08) / (n - 1)
        span(f"post{k}", a - 0.04, a + 0.04, -thick, thick, -hz, hz - 0.02)
    span("top_rail", -length, length, -thick, thick, hz - 0.06, hz)
    span("mid_rail", -length, length, -0.7 * thick, 0.7 * thick, -0.05 * hz, 0.12 * hz)
    return p.build()
