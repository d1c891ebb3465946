"""Furniture and fittings of a room, each fitted into its collision box (the box's frame:
origin at its centre, +z up; ``front`` is the box side a chair's or sofa's sitter faces, a
shelf's or screen's open side, as a unit axis in that frame)."""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from phav_generator.world import materials as looks
from phav_generator.world.materials import FABRICS, LEATHERS, WOODS, Material, pick
from phav_generator.world.parts import LAMP_GLOW, Asset, Parts, Vec3, rotation, transform_points
from phav_generator.world.places import Opening, Quads, box_faces, holed, level_rect, rect

Axis = tuple[float, float]  # (x, y) unit vector in the box's frame

_WHITE_GOODS = (0.88, 0.88, 0.86)
_BLACK = (0.03, 0.03, 0.035)
_BOOKS = ((0.55, 0.10, 0.08), (0.10, 0.20, 0.40), (0.15, 0.35, 0.18), (0.85, 0.75, 0.55), (0.12, 0.12, 0.12),
          (0.75, 0.45, 0.10), (0.50, 0.50, 0.55))  # fmt: skip


#: Segments round a cushion (a superellipsoid): its corners are rounded, not its sides.
CUSHION_SEGMENTS = 8


def _turned_boxes(p: Parts, rot: np.ndarray) -> Callable[..., None]:
    """``box(name, cls, material, colour, lo, hi, cushion=None, **kw)``: adds to ``p`` an
    axis-aligned box between corners ``lo`` and ``hi`` of the object's modelling frame, turned
    by ``rot`` (with ``cushion``, the superellipsoid of that squareness filling the box)."""

    def box(name, cls, material, colour, lo, hi, *, cushion: float | None = None, **kw) -> None:
        lo_, hi_ = np.asarray(lo, dtype=np.float64), np.asarray(hi, dtype=np.float64)
        c = transform_points(((lo_ + hi_) / 2)[None], rot, (0.0, 0.0, 0.0))[0]
        centre, half = (float(c[0]), float(c[1]), float(c[2])), tuple((hi_ - lo_) / 2)
        if cushion is None:
            p.box(name, cls, material, colour, centre, half, rot=rot, **kw)
        else:  # a soft part: the box's superellipsoid, ``cushion`` its squareness
            p.ellipsoid(name, cls, material, colour, centre, half, rot=rot, squareness=cushion,
                        segments=CUSHION_SEGMENTS, **kw)  # fmt: skip

    return box


def _frame(p: Parts, half, front: Axis) -> tuple[float, float, Callable[..., None]]:
    """(depth half, width half, box) of a box whose sitter or opening faces ``front``: the
    parts are modelled facing +x and ``box`` turns them to face ``front``."""
    hx, hy, _ = half
    yaw = math.atan2(front[1], front[0])
    depth, width = (hx, hy) if abs(front[0]) > 0.5 else (hy, hx)
    return depth, width, _turned_boxes(p, rotation(yaw))


def _lengthwise(p: Parts, half) -> tuple[float, float, bool, Callable[..., None]]:
    """(length half, thickness half, whether the length runs along x, box) of a thin box (a
    window, a door, a curtain, a chair's back): the parts are modelled along x and ``box``
    turns them to the box's longer horizontal axis."""
    hx, hy, _ = half
    along_x = hx >= hy
    length, thick = (hx, hy) if along_x else (hy, hx)
    return length, thick, along_x, _turned_boxes(p, rotation(0.0 if along_x else math.pi / 2))


def chair(
    half, rng: np.random.Generator, level: int = 0, *, front: Axis = (1.0, 0.0), seat: float | None = None
) -> Asset:
    """A wooden chair: four legs, a seat at ``seat`` (default 0.46 m above the box's bottom,
    or its top when lower) and a back of two uprights and rails up to the box's top."""
    hz = half[2]
    p = Parts(level)
    d, w, box = _frame(p, half, front)
    wood = pick(WOODS, rng)
    s = min(-hz + (seat if seat is not None else 0.46), hz)
    box("seat", "chair", Material.WOOD, wood, (-d, -w, s - 0.04), (d, w, s))
    leg = 0.022
    for x in (-d + leg, d - leg):
        for y in (-w + leg, w - leg):
            box(
                f"leg{x:+.2f}{y:+.2f}",
                "chair",
                Material.WOOD,
                wood,
                (x - leg, y - leg, -hz),
                (x + leg, y + leg, s - 0.04),
            )
    if hz - s > 0.15:  # a back: uprights on the far side from the sitter, rails between them
        for y in (-w + leg, w - leg):
            box(f"upright{y:+.2f}", "chair", Material.WOOD, wood, (-d, y - leg, s), (-d + 2 * leg, y + leg, hz))
        rails = 3 if p.fine else 1
        for k in range(rails):
            z = hz - 0.04 - k * 0.1
            box(f"rail{k}", "chair", Material.WOOD, wood, (-d, -w + leg, z - 0.05), (-d + 0.02, w - leg, z))
    return p.build()


def table(half: Vec3, rng: np.random.Generator, level: int = 0) -> Asset:
    """A table: a top with an apron on four legs."""
    hx, hy, hz = half
    p = Parts(level)
    wood = pick(WOODS, rng)
    p.span("top", "table", Material.WOOD, wood, (-hx, -hy, hz - 0.035), (hx, hy, hz))
    p.span(
        "apron", "table", Material.WOOD, wood, (-hx + 0.06, -hy + 0.06, hz - 0.12), (hx - 0.06, hy - 0.06, hz - 0.035)
    )
    leg = 0.03
    for x in (-hx + 0.06, hx - 0.06):
        for y in (-hy + 0.06, hy - 0.06):
            p.span(
                f"leg{x:+.2f}{y:+.2f}",
                "table",
                Material.WOOD,
                wood,
                (x - leg, y - leg, -hz),
                (x + leg, y + leg, hz - 0.035),
            )
    return p.build()


def sofa(half: Vec3, rng: np.random.Generator, level: int = 0, *, front: Axis = (1.0, 0.0)) -> Asset:
    """A sofa: a base on feet, seat cushions, back cushions and rolled arms, in fabric or
    leather, with two cushions of another fabric at its ends; the soft parts are rounded
    (superellipsoids) where small details are modelled, boxes farther down the levels."""
    hz = half[2]
    p = Parts(level)
    d, w, box = _frame(p, half, front)
    leather = rng.random() < 0.3
    cover, material = (pick(LEATHERS, rng), Material.LEATHER) if leather else (pick(FABRICS, rng), Material.FABRIC)
    soft = 0.3 if p.fine else None
    z0, seat = -hz + 0.08, -hz + 0.43
    arm = 0.16
    box("base", "sofa", material, cover, (-d, -w + arm, z0), (d, w - arm, seat - 0.12))
    for sgn in (-1.0, 1.0):
        y0, y1 = (-w, -w + arm) if sgn < 0 else (w - arm, w)
        box(f"arm{sgn:+.0f}", "sofa", material, cover, (-d, y0, z0), (d, y1, -hz + 0.64), cushion=soft)
    box("back", "sofa", material, cover, (-d, -w + arm, z0), (-d + 0.22, w - arm, hz - (0.1 if p.fine else 0.0)))
    cushions = 3 if p.fine and w > 0.9 else (2 if p.fine else 1)
    span = (2 * (w - arm)) / cushions
    for k in range(cushions):
        y0 = -w + arm + k * span
        box(f"cushion{k}", "sofa", material, cover, (-d + 0.2, y0 + 0.005, seat - 0.14),
            (d - 0.02, y0 + span - 0.005, seat + (0.02 if p.fine else 0.0)), cushion=soft)  # fmt: skip
        if p.fine:
            box(f"back_cushion{k}", "sofa", material, cover, (-d + 0.12, y0 + 0.01, seat - 0.04),
                (-d + 0.4, y0 + span - 0.01, hz), cushion=0.35)  # fmt: skip
    if p.fine:  # throw cushions against the back cushions at both ends, in another cover
        accent = pick(FABRICS, rng)
        for sgn in (-1.0, 1.0):
            y = sgn * (w - arm - 0.24)
            box(f"pillow{sgn:+.0f}", "sofa", Material.FABRIC, accent, (-d + 0.38, y - 0.21, seat),
                (-d + 0.52, y + 0.21, seat + 0.4), cushion=0.5)  # fmt: skip
    for x in (-d + 0.05, d - 0.05):
        for y in (-w + 0.05, w - 0.05):
            box(
                f"foot{x:+.1f}{y:+.1f}",
                "sofa",
                Material.WOOD,
                WOODS[1],
                (x - 0.03, y - 0.03, -hz),
                (x + 0.03, y + 0.03, z0),
            )
    return p.build()


def bed(half: Vec3, rng: np.random.Generator, level: int = 0, *, head: Axis = (0.0, -1.0)) -> Asset:
    """A bed: a wooden frame, a mattress, a duvet, pillows at the head end and a low
    headboard."""
    hz = half[2]
    p = Parts(level)
    d, w, box = _frame(p, half, (-head[0], -head[1]))  # modelled with the head at −x
    wood, duvet = pick(WOODS, rng), pick(FABRICS, rng)
    box("frame", "bed", Material.WOOD, wood, (-d, -w, -hz + 0.12), (d, w, -hz + 0.3))
    for x in (-d + 0.04, d - 0.04):
        for y in (-w + 0.04, w - 0.04):
            box(
                f"leg{x:+.1f}{y:+.1f}",
                "bed",
                Material.WOOD,
                wood,
                (x - 0.04, y - 0.04, -hz),
                (x + 0.04, y + 0.04, -hz + 0.12),
            )
    box("headboard", "bed", Material.WOOD, wood, (-d, -w, -hz + 0.3), (-d + 0.05, w, hz))
    box(
        "mattress",
        "bed",
        Material.FABRIC,
        (0.92, 0.92, 0.90),
        (-d + 0.05, -w + 0.03, -hz + 0.3),
        (d - 0.02, w - 0.03, hz - 0.07),
    )
    box("duvet", "bed", Material.FABRIC, duvet, (-d + 0.55, -w + 0.01, hz - 0.12), (d, w - 0.01, hz - 0.04))
    n = 2 if w > 0.6 else 1
    for k in range(n):
        y0 = -w + 0.08 + k * (2 * w - 0.16) / n
        box(f"pillow{k}", "bed", Material.FABRIC, (0.95, 0.95, 0.93), (-d + 0.08, y0 + 0.02, hz - 0.12),
            (-d + 0.48, y0 + (2 * w - 0.16) / n - 0.02, hz))  # fmt: skip
    return p.build()


def shelf(half: Vec3, rng: np.random.Generator, level: int = 0, *, front: Axis = (1.0, 0.0)) -> Asset:
    """Shelving by its size: a bookcase with books when tall, else a cabinet with doors and
    handles (a counter, a TV cabinet, a wall cupboard)."""
    hz = half[2]
    p = Parts(level)
    d, w, box = _frame(p, half, front)
    wood = pick(WOODS, rng)
    t = 0.02
    if 2 * hz >= 1.5:
        box("back", "shelf", Material.WOOD, wood, (-d, -w, -hz), (-d + t, w, hz))
        for sgn in (-1.0, 1.0):
            box(f"side{sgn:+.0f}", "shelf", Material.WOOD, wood, (-d, sgn * w - (t if sgn > 0 else 0.0), -hz),
                (d, sgn * w + (t if sgn < 0 else 0.0), hz))  # fmt: skip
        boards = 5
        step = (2 * hz - t) / boards
        for k in range(boards + 1):
            z = -hz + k * step
            box(f"board{k}", "shelf", Material.WOOD, wood, (-d + t, -w + t, z), (d, w - t, z + t))
            if k == boards or not p.fine:
                continue
            y = -w + t + 0.01
            while True:  # books of varied thickness and height, left to right
                thick = 0.025 + 0.03 * float(rng.random())
                if y + thick > w - t - 0.01:
                    break
                tall = min(0.18 + 0.12 * float(rng.random()), step - t - 0.02)
                colour = _BOOKS[int(rng.integers(0, len(_BOOKS)))]
                box(f"book{k}_{y:.3f}", "shelf", Material.PLAIN, colour, (-d + t + 0.01, y, z + t),
                    (-d + t + min(2 * d - t - 0.02, 0.2), y + thick, z + t + tall))  # fmt: skip
                y += thick + 0.002
        return p.build()
    box("carcass", "shelf", Material.WOOD, wood, (-d, -w, -hz), (d - 0.02, w, hz - 0.03))
    box("top", "shelf", Material.WOOD, pick(WOODS, rng), (-d, -w, hz - 0.03), (d, w, hz))
    doors = max(1, round(w / 0.3))
    span = 2 * w / doors
    for k in range(doors):
        y0 = -w + k * span
        box(
            f"door{k}",
            "shelf",
            Material.WOOD,
            wood,
            (d - 0.02, y0 + 0.003, -hz + 0.05),
            (d, y0 + span - 0.003, hz - 0.05),
        )
        if p.fine:
            y = y0 + (span - 0.05 if k % 2 == 0 else 0.05)
            box(
                f"handle{k}",
                "shelf",
                Material.CHROME,
                (0.8, 0.8, 0.82),
                (d, y - 0.008, hz - 0.2),
                (d + 0.015, y + 0.008, hz - 0.08),
            )
    return p.build()


def screen(half: Vec3, rng: np.random.Generator, level: int = 0, *, front: Axis = (1.0, 0.0)) -> Asset:
    """A flat television: a thin black bezel around a dark glass panel, a slim body behind."""
    hz = half[2]
    p = Parts(level)
    d, w, box = _frame(p, half, front)
    box("body", "screen", Material.PLASTIC, _BLACK, (-d, -w + 0.1, -hz + 0.1), (d - 0.03, w - 0.1, hz - 0.1))
    box("bezel", "screen", Material.PLASTIC, (0.05, 0.05, 0.055), (d - 0.03, -w, -hz), (d - 0.005, w, hz))
    box(
        "panel",
        "screen",
        Material.GLASS,
        (0.02, 0.025, 0.03),
        (d - 0.005, -w + 0.02, -hz + 0.02),
        (d, w - 0.02, hz - 0.02),
    )
    return p.build()


def fridge(half: Vec3, rng: np.random.Generator, level: int = 0, *, front: Axis = (1.0, 0.0)) -> Asset:
    """A fridge-freezer: a white body, two doors with a seam and long handles."""
    hz = half[2]
    p = Parts(level)
    d, w, box = _frame(p, half, front)
    box("body", "fridge", Material.PAINT, _WHITE_GOODS, (-d, -w, -hz), (d - 0.05, w, hz))
    split = hz - 0.75
    box("fridge_door", "fridge", Material.PAINT, _WHITE_GOODS, (d - 0.05, -w, split + 0.01), (d - 0.01, w, hz))
    box("freezer_door", "fridge", Material.PAINT, _WHITE_GOODS, (d - 0.05, -w, -hz + 0.06), (d - 0.01, w, split - 0.01))
    box("plinth", "fridge", Material.PLASTIC, (0.2, 0.2, 0.2), (d - 0.06, -w, -hz), (d - 0.03, w, -hz + 0.06))
    for z0, z1 in ((split + 0.1, split + 0.5), (split - 0.5, split - 0.1)):
        box(
            f"handle{z0:+.1f}", "fridge", Material.CHROME, (0.8, 0.8, 0.82), (d - 0.01, w - 0.08, z0), (d, w - 0.05, z1)
        )
    return p.build()


def fireplace(half: Vec3, rng: np.random.Generator, level: int = 0, *, front: Axis = (1.0, 0.0)) -> Asset:
    """A fireplace: a stone surround with a mantel shelf and a dark firebox opening."""
    hz = half[2]
    p = Parts(level)
    d, w, box = _frame(p, half, front)
    stone = (0.72, 0.68, 0.62)
    box("surround", "fireplace", Material.CONCRETE, stone, (-d, -w, -hz), (d - 0.06, w, hz - 0.08))
    box("mantel", "fireplace", Material.WOOD, WOODS[1], (-d, -w, hz - 0.08), (d, w, hz))
    box("hearth", "fireplace", Material.CONCRETE, (0.3, 0.3, 0.3), (d - 0.06, -w + 0.1, -hz), (d, w - 0.1, -hz + 0.05))
    box(
        "opening",
        "fireplace",
        Material.PLAIN,
        (0.04, 0.03, 0.03),
        (d - 0.061, -0.55 * w, -hz + 0.05),
        (d - 0.058, 0.55 * w, 0.3 * hz),
    )
    return p.build()


def chimney(half: Vec3, rng: np.random.Generator, level: int = 0) -> Asset:
    """A chimney breast: a plastered column."""
    p = Parts(level)
    p.span("breast", "fireplace", Material.CONCRETE, (0.85, 0.83, 0.80), tuple(-h for h in half), tuple(half))
    return p.build()


def lamp(half: Vec3, rng: np.random.Generator, level: int = 0) -> Asset:
    """A lamp part by its shape: a floor lamp's stem (over twice as tall as it is wide), a
    table lamp (a base and a shade) over 0.4 m tall, else a shade alone (a lit fabric cone)."""
    hx, hy, hz = half
    p = Parts(level)
    r = min(hx, hy)
    if 2 * hz > 4 * r:  # a floor lamp's stem
        p.cylinder("stem", "lamp", Material.METAL, (0.2, 0.2, 0.2), (0.0, 0.0, -hz), (0.0, 0.0, hz), 0.3 * r)
        p.cylinder("foot", "lamp", Material.METAL, (0.2, 0.2, 0.2), (0.0, 0.0, -hz), (0.0, 0.0, -hz + 0.02), r)
        return p.build()
    shade = (0.95, 0.9, 0.8)
    if hz > 0.2:  # a table lamp: a ceramic base, a shade on top
        p.frustum("base", "lamp", Material.PLASTIC, (0.6, 0.5, 0.4), (0.0, 0.0, -hz), (0.0, 0.0, 0.0), 0.5 * r, 0.3 * r)
        p.frustum("shade", "lamp", Material.FABRIC, shade, (0.0, 0.0, 0.0), (0.0, 0.0, hz), r, 0.65 * r, glow=LAMP_GLOW)
        return p.build()
    p.frustum("shade", "lamp", Material.FABRIC, shade, (0.0, 0.0, -hz), (0.0, 0.0, hz), r, 0.6 * r, glow=LAMP_GLOW)
    return p.build()


def window(half: Vec3, rng: np.random.Generator, level: int = 0) -> Asset:
    """An open window through a wall: a white frame lining the opening (head, sill, jambs)
    and a mullion and transom; no pane, so what is outside is seen, and labelled, as itself."""
    hz = half[2]
    p = Parts(level)
    white = (0.93, 0.93, 0.91)
    L, T, _, box = _lengthwise(p, half)
    f = 0.06
    transom = -hz + 0.68 * 2 * hz
    for name, lo, hi in (("head", (-L, -T, hz - f), (L, T, hz)), ("sill", (-L, -T, -hz), (L, T, -hz + f)),
                         ("jamb_l", (-L, -T, -hz), (-L + f, T, hz)), ("jamb_r", (L - f, -T, -hz), (L, T, hz)),
                         ("mullion", (-0.025, -0.03, -hz), (0.025, 0.03, hz)),
                         ("transom", (-L, -0.03, transom - 0.025), (L, 0.03, transom + 0.025))):  # fmt: skip
        box(name, "window", Material.PLASTIC, white, lo, hi)
    return p.build()


#: A room's skirting board: its height and how far it stands proud of the wall (m); the
#: wall's surface is set back this far into its box so the board stays inside it.
SKIRTING_M = (0.1, 0.012)


def wall_look(rng: np.random.Generator) -> tuple[Material, tuple[float, float, float]]:
    """A room's walls: painted (two rooms in three; emulsion is flat, unlike a facade's
    render) or papered."""
    if float(rng.random()) < 0.35:
        return Material.WALLPAPER, pick(looks.WALLPAPERS, rng)
    return Material.PLAIN, pick(looks.WALL_PAINTS, rng)


def room_wall(half: Vec3, rng: np.random.Generator, level: int = 0, *, inside: Axis, openings: list[Opening],
              look: tuple[Material, tuple[float, float, float]]) -> Asset:  # fmt: skip
    """A room's wall filling its box: the face towards ``inside`` (an axis of the box's
    frame) in ``look`` above a painted skirting board, the face away from it rendered, both
    cut around ``openings`` (along the inner face from its left end seen from the room, up
    from the box's bottom; their frames, a window's or a door's own collider, line them)."""
    hz = half[2]
    p = Parts(level)
    q = Quads()
    faces = box_faces(half)
    inner = next(f for f in faces if float(f.normal[:2] @ np.array(inside)) > 0.5)
    outer = next(f for f in faces if float(f.normal[:2] @ np.array(inside)) < -0.5)
    material, colour = look
    skirt_h, proud = SKIRTING_M
    holed(q, inner, openings, "wall", "misc", material, colour, z_base=skirt_h, depth=proud)
    board = (0.93, 0.92, 0.89)
    doors = sorted((o.s0, o.s1) for o in openings if o.z0 < skirt_h)
    s = 0.0
    for s0, s1 in [*doors, (inner.width, inner.width)]:
        rect(q, inner, "skirting", "misc", Material.WOOD, board, s, s0, 0.0, skirt_h)
        if s0 - s > 1e-9:
            a, b = inner.at(s, skirt_h), inner.at(s0, skirt_h)
            q.add("skirting", "misc", Material.WOOD, board, [a, b, b - proud * inner.normal, a - proud * inner.normal],
                  (0.0, 0.0, 1.0))  # fmt: skip
        s = max(s, s1)
    mirrored = [Opening(outer.width - o.s1, outer.width - o.s0, o.z0, o.z1) for o in openings]
    holed(q, outer, mirrored, "outside", "misc", Material.PLASTER, (0.86, 0.84, 0.80))
    for f in faces:
        if f is not inner and f is not outer:  # the ends, under the walls across them
            rect(q, f, "end", "misc", Material.PLASTER, colour, 0.0, f.width, 0.0, f.height)
    hx, hy = half[0], half[1]
    q.add("top", "misc", Material.PLASTER, colour, level_rect(-hx, -hy, hx, hy, hz), (0.0, 0.0, 1.0))
    q.into(p)
    return p.build()


def ceiling(half: Vec3, rng: np.random.Generator, level: int = 0) -> Asset:
    """A ceiling slab filling its box, in white paint (its underside is what the room sees)."""
    p = Parts(level)
    p.box("slab", "ceiling", Material.PLASTER, (0.92, 0.92, 0.90), (0.0, 0.0, 0.0), tuple(half))
    return p.build()


def door(half: Vec3, rng: np.random.Generator, level: int = 0) -> Asset:
    """A door in its frame: a panelled wooden leaf, a frame and a handle on each face."""
    hz = half[2]
    p = Parts(level)
    wood = pick(WOODS, rng)
    L, T, _, box = _lengthwise(p, half)
    f = 0.07
    leaf = T - 0.02  # the leaf fills the box's depth: the box runs through a thinner wall
    box("leaf", "door", Material.WOOD, wood, (-L + f, -leaf, -hz), (L - f, leaf, hz - f))
    for name, lo, hi in (("head", (-L, -T, hz - f), (L, T, hz)), ("jamb_l", (-L, -T, -hz), (-L + f, T, hz)),
                         ("jamb_r", (L - f, -T, -hz), (L, T, hz))):  # fmt: skip
        box(name, "door", Material.WOOD, (0.9, 0.9, 0.88), lo, hi)
    if p.fine:
        for sgn in (-1.0, 1.0):
            y0, y1 = sorted((sgn * leaf, sgn * (leaf + 0.008)))
            for k, (z0, z1) in enumerate(((-hz + 0.15, -0.05), (0.1, hz - f - 0.15))):
                box(f"panel{k}{sgn:+.0f}", "door", Material.WOOD, wood, (-L + f + 0.1, y0, z0), (L - f - 0.1, y1, z1))
            y0, y1 = sorted((sgn * leaf, sgn * T))
            box(
                f"handle{sgn:+.0f}",
                "door",
                Material.CHROME,
                (0.8, 0.78, 0.7),
                (L - f - 0.14, y0, -0.02),
                (L - f - 0.06, y1, 0.0),
            )
    return p.build()


def curtain(half: Vec3, rng: np.random.Generator, level: int = 0) -> Asset:
    """A curtain hanging in folds: pleats of fabric turned alternately, filling the box."""
    hz = half[2]
    p = Parts(level)
    cloth = pick(FABRICS, rng)
    L, T, along_x, _ = _lengthwise(p, half)
    folds = 8 if p.fine else 4
    width = 2 * L / folds
    angle = math.atan2(2 * T * 0.8, width)
    for k in range(folds):
        a = -L + (k + 0.5) * width
        tilt = angle if k % 2 == 0 else -angle
        seg = width / 2 / math.cos(angle)
        centre, yaw = ((a, 0.0, 0.0), tilt) if along_x else ((0.0, a, 0.0), math.pi / 2 + tilt)
        p.box(f"fold{k}", "curtain", Material.FABRIC, cloth, centre, (seg, 0.008, hz), rot=rotation(yaw))
    return p.build()


def step(half: Vec3, rng: np.random.Generator, level: int = 0, *, indoor: bool = True) -> Asset:
    """A step of a flight (its box stands on the floor): a wooden or stone tread on a
    painted or concrete riser block, both filling the box (it is what a foot stands on)."""
    hx, hy, hz = half
    p = Parts(level)
    tread, riser = ((Material.WOOD, WOODS[0]), (Material.PLAIN, (0.9, 0.9, 0.88))) if indoor else \
        ((Material.CONCRETE, (0.62, 0.61, 0.58)), (Material.CONCRETE, (0.55, 0.54, 0.52)))  # fmt: skip
    p.span("block", "stairs", riser[0], riser[1], (-hx, -hy, -hz), (hx, hy, hz - 0.03))
    p.span("tread", "stairs", tread[0], tread[1], (-hx, -hy, hz - 0.03), (hx, hy, hz))
    return p.build()


def chair_back(half: Vec3, rng: np.random.Generator, level: int = 0) -> Asset:
    """A chair's back standing on its seat: two uprights and rails, filling a thin box along
    its longer horizontal axis."""
    hz = half[2]
    p = Parts(level)
    wood = pick(WOODS, rng)
    L, T, _, box = _lengthwise(p, half)
    leg = 0.022
    for a in (-L + leg, L - leg):
        box(f"upright{a:+.2f}", "chair", Material.WOOD, wood, (a - leg, -T, -hz), (a + leg, T, hz))
    for k in range(3 if p.fine else 1):
        z = hz - 0.02 - k * 0.12
        box(f"rail{k}", "chair", Material.WOOD, wood, (-L + leg, -0.6 * T, z - 0.06), (L - leg, 0.6 * T, z))
    return p.build()
