"""The places, each fitted into its collision box (the box's frame: origin at its centre,
+z up): buildings from a facade grammar, trees, hedges and reeds, roads with their
markings, pavements, grass terraces and the ground, a stand's tiers and a goal's bars.

A building's walls lie on its box's faces, its windows recessed into them; a tree's trunk
fills its trunk box and its crown its crown box; a slab's top face is its box's top, the
markings a few millimetres above it. Nothing stands out of its box by more than that, so
physics and the failures check keep reading the boxes of ``phav_spec.scene``.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, field

import numpy as np

from phav_generator.world import materials as looks
from phav_generator.world.materials import Material, pick
from phav_generator.world.parts import Asset, Parts, Vec3, circle, sphere_triangles

Vec = np.ndarray
UP = np.array([0.0, 0.0, 1.0])
#: How far (m) windows are set back into a wall, and road markings stand above their road.
WINDOW_DEPTH_M = 0.18
#: A loggia (a balcony recessed into the block, inside its box): its depth, width, height
#: above its storey's floor and its parapet's height and thickness (m).
LOGGIA_DEPTH_M = 1.2
LOGGIA_WIDTH_M = 2.2
LOGGIA_HEIGHT_M = 2.5
PARAPET_M = 1.0
PARAPET_THICK_M = 0.15
MARKING_M = 0.004
#: Half the width of a house's front door (m).
DOOR_HALF_M = 0.5
#: Building styles: the urban block, the suburban house, the stadium's concrete.
STYLES = ("urban", "suburban", "stadium")
#: Tree species.
SPECIES = ("broadleaf", "conifer", "birch")


@dataclass
class Quads:
    """Flat quads (and triangles) gathered by look, added to an asset as one part per look
    (a facade has hundreds of windows: one part each would be thousands of parts)."""

    groups: dict[tuple[str, str, int, tuple[float, float, float]], list[Vec]] = field(default_factory=dict)

    def add(self, name: str, cls: str, material: Material, colour, corners, facing) -> None:
        """A flat convex polygon (a quad, or a gable's triangle; any winding), wound to face ``facing``."""
        c = np.asarray(corners, dtype=np.float64)
        normal = np.cross(c[1] - c[0], c[2] - c[0])
        if float(normal @ np.asarray(facing, dtype=np.float64)) < 0.0:
            c = c[::-1]
        key = (name, cls, int(material), tuple(float(v) for v in colour))
        self.groups.setdefault(key, []).append(c)

    def into(self, p: Parts) -> None:
        for (name, cls, material, colour), polygons in self.groups.items():
            tri, first = [], 0
            for c in polygons:  # a fan from each polygon's first corner
                tri += [(first, first + k, first + k + 1) for k in range(1, len(c) - 1)]
                first += len(c)
            p.add(name, cls, Material(material), colour, np.concatenate(polygons), tri, closed=False)


@dataclass(frozen=True)
class Face:
    """A vertical wall face of a box: its bottom-left corner seen from outside, the axis
    along it (to the right seen from outside), its outward normal, width and height."""

    corner: Vec
    along: Vec
    normal: Vec
    width: float
    height: float

    def at(self, s: float, z: float, depth: float = 0.0) -> Vec:
        """The point ``s`` along, ``z`` up and ``depth`` in from the face."""
        return self.corner + s * self.along + z * UP - depth * self.normal


def box_faces(half, bottom: float | None = None, top: float | None = None) -> list[Face]:
    """The four vertical faces of a box of half extents ``half`` (between ``bottom`` and
    ``top``, default its own), +x, +y, −x, −y."""
    hx, hy, hz = half
    z0 = -hz if bottom is None else bottom
    z1 = hz if top is None else top
    out = []
    for n, h_n, w in (((1.0, 0.0, 0.0), hx, 2 * hy), ((0.0, 1.0, 0.0), hy, 2 * hx),
                      ((-1.0, 0.0, 0.0), hx, 2 * hy), ((0.0, -1.0, 0.0), hy, 2 * hx)):  # fmt: skip
        normal = np.array(n)
        along = np.cross(UP, normal)
        corner = normal * h_n - along * (w / 2) + UP * z0
        out.append(Face(corner, along, normal, w, z1 - z0))
    return out


def level_rect(x0: float, y0: float, x1: float, y1: float, z: float) -> list[tuple[float, float, float]]:
    """The corners of a level rectangle at height ``z``."""
    return [(x0, y0, z), (x1, y0, z), (x1, y1, z), (x0, y1, z)]


def rect(q: Quads, face: Face, name: str, cls: str, material: Material, colour, s0, s1, z0, z1, depth=0.0) -> None:
    """A rectangle on ``face`` from ``s0`` to ``s1`` along and ``z0`` to ``z1`` up, ``depth``
    in from it (nothing where it has no area: a row of openings flush with the wall's end)."""
    if s1 - s0 <= 1e-9 or z1 - z0 <= 1e-9:
        return
    q.add(name, cls, material, colour, [face.at(s0, z0, depth), face.at(s1, z0, depth), face.at(s1, z1, depth),
                                        face.at(s0, z1, depth)], face.normal)  # fmt: skip


@dataclass(frozen=True)
class Opening:
    """A window or shop front in a face: from ``s0`` to ``s1`` along it, ``z0`` to ``z1`` up,
    its pane ``depth`` in; a loggia is one ``LOGGIA_DEPTH_M`` deep behind a ``parapet``."""

    s0: float
    s1: float
    z0: float
    z1: float
    depth: float = WINDOW_DEPTH_M
    #: The height of a parapet across its front (m), 0 for none.
    parapet: float = 0.0
    #: What its glass shows behind it: a room's (dark, blinds, curtains) or a lit shop's.
    tints: tuple[looks.RGB, ...] = looks.WINDOW_TINTS


def holed(q: Quads, face: Face, openings: list[Opening], name: str, cls: str, material: Material, colour,
          *, z_base: float = 0.0, depth: float = 0.0) -> None:  # fmt: skip
    """``face`` from ``z_base`` up, ``depth`` in from it, with ``openings`` (which may overlap
    in height, as a door beside a window does) left open: the face cut into bands at every
    opening's top and bottom, each band's runs between openings one rectangle."""
    zs = sorted({z_base, face.height, *(min(max(z, z_base), face.height) for o in openings for z in (o.z0, o.z1))})
    for z0, z1 in itertools.pairwise(zs):
        cut = sorted((o.s0, o.s1) for o in openings if o.z0 < z1 - 1e-9 and o.z1 > z0 + 1e-9)
        s = 0.0
        for s0, s1 in cut:
            rect(q, face, name, cls, material, colour, s, s0, z0, z1, depth)
            s = max(s, s1)
        rect(q, face, name, cls, material, colour, s, face.width, z0, z1, depth)


def _columns(width: float, bay: float, opening: float, margin: float) -> list[tuple[float, float]]:
    """Openings ``opening`` wide, one per bay of about ``bay`` metres, centred across a
    face of ``width`` with ``margin`` clear at each end."""
    n = max(int((width - 2 * margin) // bay), 0)
    if n == 0:
        return []
    step = (width - 2 * margin) / n
    return [(margin + (k + 0.5) * step - opening / 2, margin + (k + 0.5) * step + opening / 2) for k in range(n)]


def facade(p: Parts, q: Quads, face: Face, openings: list[Opening], wall: tuple[Material, tuple], rng, *, frame,
           recessed: bool, z_base: float = 0.0, parapet: tuple[Material, tuple] | None = None) -> None:  # fmt: skip
    """A wall face with its openings: the wall around them, and in each a pane set back by
    its depth with its reveals, a sill (a loggia: its floor) and a frame's mullion and
    transom (``recessed``; else panes laid on the wall, for far away); across a loggia's
    front its parapet, in the ``parapet`` look (default the wall's). Openings sharing a band
    of height are cut as one row, with the wall between them as piers."""
    material, colour = wall
    ledge = parapet or wall
    rows: dict[tuple[float, float], list[Opening]] = {}
    for o in openings:
        rows.setdefault((o.z0, o.z1), []).append(o)
    holed(q, face, openings if recessed else [], "wall", "building", material, colour, z_base=z_base)
    for _, row in sorted(rows.items()):
        for o in row:
            tint = pick(o.tints, rng)
            depth = o.depth if recessed else -0.01
            rect(q, face, "pane", "building", Material.GLASS, tint, o.s0, o.s1, o.z0, o.z1, depth)
            top = o.z0 + o.parapet
            if not recessed:
                rect(q, face, "parapet", "building", ledge[0], ledge[1], o.s0, o.s1, o.z0, top, -0.02)
                continue
            d = o.depth
            for a, b, facing in ((face.at(o.s0, o.z0), face.at(o.s0, o.z1), face.along),
                                 (face.at(o.s1, o.z0), face.at(o.s1, o.z1), -face.along)):  # fmt: skip
                q.add("reveal", "building", material, colour, [a, b, b - d * face.normal, a - d * face.normal], facing)
            floor = ("balcony" if o.parapet else "sill", o.z0, UP, _SILL)
            for name, zz, facing, look in (floor, ("reveal", o.z1, -UP, wall)):
                a, b = face.at(o.s0, zz), face.at(o.s1, zz)
                q.add(name, "building", look[0], look[1], [a, b, b - d * face.normal, a - d * face.normal], facing)
            if o.parapet:
                _parapet(q, face, o, ledge)
            if p.level == 0:  # a frame just in front of the pane: an upright and a transom
                bar = 0.03
                if o.parapet:  # a balcony door beside a window, whose transom is at the parapet's height
                    upright, t, s0 = o.s0 + 0.9, top, o.s0 + 0.9
                else:
                    upright, t, s0 = (o.s0 + o.s1) / 2, o.z0 + 0.68 * (o.z1 - o.z0), o.s0
                rect(q, face, "frame", "building", Material.PLASTIC, frame, upright - bar, upright + bar, o.z0, o.z1,
                     d - 0.02)  # fmt: skip
                rect(q, face, "frame", "building", Material.PLASTIC, frame, s0, o.s1, t - bar, t + bar, d - 0.02)


def _parapet(q: Quads, face: Face, o: Opening, look: tuple[Material, tuple]) -> None:
    """A loggia's parapet across its front: its face in the wall's plane, its top and its
    inner face ``PARAPET_THICK_M`` behind."""
    top, w = o.z0 + o.parapet, PARAPET_THICK_M
    rect(q, face, "parapet", "building", look[0], look[1], o.s0, o.s1, o.z0, top)
    a, b = face.at(o.s0, top), face.at(o.s1, top)
    q.add("parapet", "building", look[0], look[1], [a, b, b - w * face.normal, a - w * face.normal], UP)
    a, b = face.at(o.s1, o.z0, w), face.at(o.s0, o.z0, w)
    rise = (top - o.z0) * UP
    q.add("parapet", "building", look[0], look[1], [a, b, b + rise, a + rise], -face.normal)


#: A window's sill: the bottom of its opening.
_SILL = (Material.CONCRETE, (0.75, 0.74, 0.71))


def _wall_look(rng, style: str) -> tuple[Material, tuple]:
    if style == "stadium":
        return Material.CONCRETE, (0.66, 0.65, 0.62)
    if float(rng.random()) < (0.35 if style == "urban" else 0.3):
        return Material.BRICK, pick(looks.BRICKS, rng)
    return Material.PLASTER, pick(looks.PLASTERS, rng)


@dataclass(frozen=True)
class Loggias:
    """An urban block's loggias: a stack in every ``period``-th bay, behind parapets in the
    ``parapet`` look (None: the wall's)."""

    period: int
    parapet: tuple[Material, tuple] | None


def loggias_of(rng: np.random.Generator) -> Loggias | None:
    """Half the urban blocks have loggias, in every second or third bay, their parapets in
    the wall's look or painted metal; drawn apart from the block's own stream, so that the
    rest of its look does not depend on it."""
    if float(rng.random()) >= 0.5:
        return None
    period = 2 + int(2 * float(rng.random()))
    return Loggias(period, None if float(rng.random()) < 0.5 else (Material.METAL, pick(looks.FRAMES, rng)))


def building(half: Vec3, rng: np.random.Generator, level: int = 0, *, style: str = "urban",
             street: tuple[float, float] | None = None, loggias: Loggias | None = None) -> Asset:  # fmt: skip
    """A building filling its box: ``urban`` (a ground floor of shop fronts under a sign
    band, storeys of windows, in some bays ``loggias``, a cornice, a flat roof),
    ``suburban`` (two storeys under a gable roof along its longer side, a door towards
    ``street``, a local direction) or ``stadium`` (concrete walls with bands of openings).
    Faces under 4 m wide stay plain."""
    if style not in STYLES:
        raise ValueError(f"building style must be one of {STYLES}, got {style!r}")
    hx, hy, hz = half
    p = Parts(level)
    q = Quads()
    wall = _wall_look(rng, style)
    frame = pick(looks.FRAMES, rng)
    recessed = level < 2
    height = 2 * hz
    period = loggias.period if loggias is not None and style == "urban" else 0
    parapet = loggias.parapet if period else None
    if style == "suburban":
        eaves = min(height - 1.5, 6.2)
        storey = eaves / 2
        faces = box_faces(half, top=-hz + eaves)
    else:
        storey = 3.0 + 0.5 * float(rng.random()) if style == "urban" else 4.0
        faces = box_faces(half)
    for face in faces:
        openings: list[Opening] = []
        front_door = style == "suburban" and street is not None and float(face.normal[:2] @ np.array(street)) > 0.5
        door_mid = face.width / 2 + (face.width / 4 if face.width > 8 else 0.0)
        if face.width >= 4.0 and face.height >= 3.0:
            if style == "urban":
                ground = 4.2
                shop = _columns(face.width, 5.0, 3.4, 0.8)
                openings += [Opening(s0, s1, 0.35, 3.1, tints=looks.SHOP_TINTS) for s0, s1 in shop]
                cols = _columns(face.width, 2.8 + 0.6 * float(rng.random()), 1.3, 0.7)
                k = 0
                while ground + (k + 1) * storey <= height - 1.0:
                    z0 = ground + k * storey + 0.85
                    for j, (s0, s1) in enumerate(cols):
                        if period and j % period == 1:
                            mid, z = (s0 + s1) / 2, ground + k * storey + 0.1
                            openings.append(Opening(mid - LOGGIA_WIDTH_M / 2, mid + LOGGIA_WIDTH_M / 2, z,
                                                    z + LOGGIA_HEIGHT_M, LOGGIA_DEPTH_M, PARAPET_M))  # fmt: skip
                        else:
                            openings.append(Opening(s0, s1, z0, z0 + 1.55))
                    k += 1
            elif style == "suburban":
                cols = _columns(face.width, 3.2, 1.2, 0.9)
                for k in range(2):
                    z0 = k * storey + 0.9
                    # No ground-floor window where the front door is, nor within a frame of it.
                    clear = DOOR_HALF_M + 0.2
                    openings += [
                        Opening(s0, s1, z0, min(z0 + 1.3, (k + 1) * storey - 0.3))
                        for s0, s1 in cols
                        if not (k == 0 and front_door and s0 < door_mid + clear and s1 > door_mid - clear)
                    ]
            else:
                cols = _columns(face.width, 6.0, 4.0, 2.0)
                openings += [Opening(s0, s1, face.height - 2.4, face.height - 1.4) for s0, s1 in cols]
        facade(p, q, face, openings, wall, rng, frame=frame, recessed=recessed, parapet=parapet)
        if style == "urban" and face.width >= 4.0 and face.height >= 6.0:
            sign = (0.35 + 0.6 * float(rng.random()), 0.2 + 0.6 * float(rng.random()), 0.2 + 0.6 * float(rng.random()))
            rect(q, face, "sign", "building", Material.PLASTIC, sign, 0.5, face.width - 0.5, 3.3, 4.0, -0.01)
            rect(q, face, "cornice", "building", Material.CONCRETE, (0.80, 0.79, 0.75), 0.0, face.width,
                  face.height - 0.5, face.height, -0.005)  # fmt: skip
        if front_door:
            door = pick(looks.FRAMES, rng)
            rect(q, face, "door", "building", Material.WOOD, door, door_mid - DOOR_HALF_M, door_mid + DOOR_HALF_M,
                 0.0, 2.1, -0.01)  # fmt: skip
    if style == "suburban":
        _gable_roof(q, half, -hz + 2 * storey, wall, pick(looks.ROOFS, rng))
    else:
        q.add("roof", "building", Material.CONCRETE, (0.42, 0.42, 0.43), level_rect(-hx, -hy, hx, hy, hz), UP)
    q.into(p)
    return p.build()


def _gable_roof(q: Quads, half, eaves_z: float, wall, colour) -> None:
    """A gable roof from the walls' top (``eaves_z``) to a ridge at the box's top along its
    longer horizontal axis, with the wall's triangles closing the ends."""
    hx, hy, hz = half
    long_x = hx >= hy
    L, W = (hx, hy) if long_x else (hy, hx)

    def pt(a: float, b: float, z: float) -> Vec:  # a along the ridge, b across it
        return np.array([a, b, z]) if long_x else np.array([b, a, z])

    for side in (-1.0, 1.0):
        out = pt(0.0, side, 0.0)
        slope = out * (hz - eaves_z) / W + UP
        eave, ridge = [pt(-L, side * W, eaves_z), pt(L, side * W, eaves_z)], [pt(L, 0.0, hz), pt(-L, 0.0, hz)]
        q.add("roof", "building", Material.TILES, colour, eave + ridge, slope)
        q.add("gable", "building", wall[0], wall[1], [pt(side * L, -W, eaves_z), pt(side * L, W, eaves_z),
                                                      pt(side * L, 0.0, hz)], pt(side, 0.0, 0.0))  # fmt: skip
    q.add("soffit", "building", wall[0], wall[1],
          [pt(-L, -W, eaves_z), pt(L, -W, eaves_z), pt(L, W, eaves_z), pt(-L, W, eaves_z)], -UP)  # fmt: skip


def _clump_rings(segments: int) -> int:
    """Rings from pole to pole of a leaf clump of ``segments`` round (its vertices: the two
    poles and ``segments`` on each ring between them)."""
    return max(segments // 2, 3)


def _blob(p: Parts, name: str, cls: str, material: Material, colour, centre, radii, rng, *, segments: int,
          rough: float) -> None:  # fmt: skip
    """A lumpy ellipsoid, flat-shaded (a clump of leaves): each vertex pushed out or in by
    up to ``rough`` of its radius. It draws from ``rng`` as many lumps as the finest level's
    clump has vertices, whatever its ``segments``, so the clumps after it lie where they lie
    at every level of detail."""
    rings = _clump_rings(segments)
    around = circle(segments, float(rng.random()) * 2 * math.pi)
    pts = [(0.0, 0.0, -1.0)]
    for i in range(1, rings):
        lat = -math.pi / 2 + math.pi * i / rings
        pts += [(math.cos(lat) * c, math.cos(lat) * s, math.sin(lat)) for c, s in around]
    pts.append((0.0, 0.0, 1.0))
    unit = np.array(pts)
    finest = _CLUMP_SEGMENTS[0]
    lumps = rng.random(max(len(unit), 2 + (_clump_rings(finest) - 1) * finest))
    scale = 1.0 - rough + rough * lumps[: len(unit)]
    pos = unit * (np.asarray(radii, dtype=np.float64) * scale[:, None])
    p.add(name, cls, material, colour, pos, sphere_triangles(segments, rings), closed=True, offset=centre)


#: Segments round a leaf clump at each level of detail.
_CLUMP_SEGMENTS = (9, 7, 5)


def _bough_tier(p: Parts, name: str, colour, z0: float, top: float, r: float, tips: int, turn: float) -> None:
    """A conifer's tier: a closed cone from ``top`` down to a star-shaped rim of ``tips``
    bough tips at radius ``r`` (drooping below ``z0``) with notches at 0.6 ``r`` between them."""
    h = top - z0
    ring = []
    for i in range(2 * tips):
        a = turn + math.pi * i / tips
        tip = i % 2 == 0
        rad, z = (r, z0 - 0.12 * h) if tip else (0.6 * r, z0 + 0.08 * h)
        ring.append((rad * math.cos(a), rad * math.sin(a), z))
    n = len(ring)
    pos = [*ring, (0.0, 0.0, top), (0.0, 0.0, z0 + 0.05 * h)]
    apex, base = n, n + 1
    tri = [(i, (i + 1) % n, apex) for i in range(n)] + [(base, (i + 1) % n, i) for i in range(n)]
    p.add(name, "tree", Material.LEAVES, colour, pos, tri, closed=True)


def species_of(rng: np.random.Generator) -> str:
    """A tree's species: broadleaf most often."""
    u = float(rng.random())
    return "broadleaf" if u < 0.5 else ("conifer" if u < 0.75 else "birch")


def bark_of(species: str, rng: np.random.Generator) -> tuple[float, float, float]:
    """A tree's bark colour: a birch's white, else one of the browns."""
    return looks.BARKS[2] if species == "birch" else pick(looks.BARKS[:2], rng)


def trunk(half: Vec3, rng: np.random.Generator, level: int = 0, *, species: str = "broadleaf", bark=None) -> Asset:
    """A trunk filling its box's height: tapered, with a root flare, in its species' ``bark``
    (drawn from ``rng`` when not given)."""
    hx, hy, hz = half
    p = Parts(level)
    r = min(hx, hy)
    bark = bark_of(species, rng) if bark is None else bark
    thin = 0.55 if species == "birch" else 0.75
    p.frustum("flare", "tree", Material.BARK, bark, (0.0, 0.0, -hz), (0.0, 0.0, -hz + 0.4), r, thin * r)
    p.frustum("trunk", "tree", Material.BARK, bark, (0.0, 0.0, -hz + 0.4), (0.0, 0.0, hz), thin * r, 0.6 * thin * r)
    return p.build()


def crown(half: Vec3, rng: np.random.Generator, level: int = 0, *, species: str = "broadleaf", bark=None) -> Asset:
    """A tree's crown filling its box: clumps of leaves round the top of the trunk and its
    boughs in its ``bark`` (broadleaf, birch: narrower and lighter) or tiers of needles
    (conifer)."""
    if species not in SPECIES:
        raise ValueError(f"species must be one of {SPECIES}, got {species!r}")
    hx, hy, hz = half
    p = Parts(level)
    segments = _CLUMP_SEGMENTS[level]
    green = looks.LEAF_GREENS[SPECIES.index(species)]
    bark = bark_of(species, rng) if bark is None else bark
    if species == "conifer":
        # Tiers of boughs: each a cone whose rim droops to ragged tips, not a smooth cone (a
        # stack of smooth cones is a roofline's shape).
        tiers, tips = (6, 4, 3)[level], (8, 6, 5)[level]
        step = 2 * hz / (tiers + 0.8)
        for k in range(tiers):
            z0 = -hz + (k + 0.25) * step  # the lowest tips droop to the box's bottom
            r = min(hx, hy) * (1.0 - 0.8 * k / tiers)
            shade = tuple(c * (0.85 + 0.3 * float(rng.random())) for c in green)
            top = hz if k == tiers - 1 else z0 + 2.0 * step
            _bough_tier(p, f"tier{k}", shade, z0, top, r, tips, float(rng.random()) * 2 * math.pi)
        p.cylinder("stem", "tree", Material.BARK, bark, (0.0, 0.0, -hz), (0.0, 0.0, 0.3 * hz), 0.08)
        return p.build()
    narrow = 0.7 if species == "birch" else 1.0
    n = (12, 8, 5)[level]
    p.frustum("stem", "tree", Material.BARK, bark, (0.0, 0.0, -hz), (0.0, 0.0, 0.2 * hz), 0.1, 0.05)
    for k in range(n):
        a = 2 * math.pi * (k / n + 0.15 * float(rng.random()))
        size = 0.42 + 0.18 * float(rng.random())
        rx, ry, rz = size * hx * narrow, size * hy * narrow, size * hz * (1.1 if species == "birch" else 0.9)
        reach = (1.0 - size) * (0.35 + 0.65 * float(rng.random()))
        x, y = reach * hx * narrow * math.cos(a), reach * hy * narrow * math.sin(a)
        z = -hz + rz + (2 * hz - 2 * rz) * (0.25 + 0.75 * float(rng.random()))
        if level < 2 and k % 3 == 0:  # a bough from the stem out to the clump
            p.frustum(f"bough{k}", "tree", Material.BARK, bark, (0.0, 0.0, -0.8 * hz), (0.7 * x, 0.7 * y, z - 0.5 * rz),
                      0.06, 0.03, segments=5)  # fmt: skip
        shade = tuple(c * (0.8 + 0.4 * float(rng.random())) for c in green)
        _blob(p, f"clump{k}", "tree", Material.LEAVES, shade, (x, y, z), (rx, ry, rz), rng, segments=segments,
              rough=0.25)  # fmt: skip
    return p.build()


def shrub(half: Vec3, rng: np.random.Generator, level: int = 0, *, planter: bool = False) -> Asset:
    """A hedge or bush filling its box: a row of leafy mounds over a low core, smaller mounds
    between them on top (a lumpy outline, never a flat-topped box), in a hedge's dark green;
    in a concrete ``planter`` when asked."""
    hx, hy, hz = half
    p = Parts(level)
    bottom = -hz
    if planter:
        top = -hz + 0.45
        p.span("planter", "vegetation", Material.CONCRETE, (0.62, 0.61, 0.58), (-hx, -hy, -hz), (hx, hy, top))
        bottom, hx, hy = top, hx - 0.1, hy - 0.1
    green = pick(looks.HEDGE_GREENS, rng)
    height = hz - bottom
    core = (0.7 * hx, 0.7 * hy, 0.3 * height)
    p.box("core", "vegetation", Material.LEAVES, green, (0.0, 0.0, bottom + core[2]), core)
    long_side = max(hx, hy)
    r_across = min(hx, hy)
    n = max(1, min(round(long_side / r_across), 8 if p.fine else 4))
    along_x = hx >= hy
    segments = _CLUMP_SEGMENTS[level]

    def clump(name: str, a: float, r_along: float, r_side: float, r_z: float, z: float) -> None:
        a = max(min(a, long_side - r_along), -long_side + r_along)
        centre, radii = ((a, 0.0, z), (r_along, r_side, r_z)) if along_x else ((0.0, a, z), (r_side, r_along, r_z))
        shade = tuple(c * (0.85 + 0.3 * float(rng.random())) for c in green)
        _blob(p, name, "vegetation", Material.LEAVES, shade, centre, radii, rng, segments=segments, rough=0.2)

    # A row of mounds from the ground to 85 % of the height, a row of smaller ones between
    # them up to the top: a lumpy outline, never a flat-topped box.
    base_r = min(long_side / n * 1.3, long_side)
    for k in range(n):
        clump(f"clump{k}", -long_side + (k + 0.5) * 2 * long_side / n, base_r, r_across, 0.425 * height,
              bottom + 0.425 * height)  # fmt: skip
    top_r = 0.6 * r_across
    m = max(1, n - 1) if p.fine else max(1, (n - 1) // 2)
    for k in range(m):
        clump(f"top{k}", -long_side + (k + 1) * 2 * long_side / (m + 1), min(0.8 * base_r, long_side), top_r,
              0.3 * height, bottom + 0.7 * height)  # fmt: skip
    return p.build()


#: How tall (m) a stand's seats are, seen on the front of their tier.
SEAT_M = 0.42


def tier(half: Vec3, rng: np.random.Generator, level: int = 0, *, front: tuple[float, float], seats) -> Asset:
    """A stand's tier filling its box: concrete, its front (``front``, an axis of the box's
    frame) topped by a row of seats in ``seats``' colour, drawn as the material of the face's
    top ``SEAT_M`` (a row of shells seen from the pitch; it stays inside the box, and the
    box's class)."""
    hx, hy, hz = half
    p = Parts(level)
    q = Quads()
    concrete = (Material.CONCRETE, (0.62, 0.61, 0.58))
    q.add("top", "stairs", *concrete, level_rect(-hx, -hy, hx, hy, hz), UP)
    for face in box_faces(half):
        if float(face.normal[:2] @ np.array(front)) > 0.5:
            top = min(SEAT_M, face.height)
            rect(q, face, "riser", "stairs", *concrete, 0.0, face.width, 0.0, face.height - top)
            rect(q, face, "seats", "stairs", Material.SEATS, seats, 0.0, face.width, face.height - top, face.height)
        else:
            rect(q, face, "side", "stairs", *concrete, 0.0, face.width, 0.0, face.height)
    q.into(p)
    return p.build()


def goal_frame(half: Vec3, rng: np.random.Generator, level: int = 0) -> Asset:
    """A goal's post or crossbar filling its box: a white round bar along its longest axis."""
    axis = int(np.argmax(half))
    a, b = np.zeros(3), np.zeros(3)
    a[axis], b[axis] = -half[axis], half[axis]
    p = Parts(level)
    p.cylinder("bar", "misc", Material.PAINT, (0.95, 0.95, 0.93), a, b, float(min(half)))
    return p.build()


#: Reed blades a square metre of a bed holds at each level of detail, and their widths at
#: the foot (m): coarser levels have fewer, wider blades covering as much of the view.
REED_DENSITY = (150.0, 60.0, 25.0)
REED_WIDTH_M = (0.035, 0.08, 0.18)
#: Reed greens and last year's straw.
_REED_COLOURS = ((0.26, 0.36, 0.12), (0.34, 0.42, 0.16), (0.58, 0.52, 0.32))


def reeds(half: Vec3, rng: np.random.Generator, level: int = 0) -> Asset:
    """A bed of reeds filling its box from the bottom (the lake bed): thin blades, each one
    tall triangle leaning a little from its foot, their tips kept inside the box."""
    hx, hy, hz = half
    p = Parts(level)
    n = max(int(REED_DENSITY[min(level, len(REED_DENSITY) - 1)] * 4 * hx * hy), 8)
    u = rng.random((n, 8))  # the eighth column is spare, drawn so that a bed keeps its blades
    feet = np.column_stack([(2 * u[:, 0] - 1) * hx * 0.95, (2 * u[:, 1] - 1) * hy * 0.95, np.full(n, -hz)])
    heights = 2 * hz * (0.55 + 0.45 * u[:, 2])
    lean = 0.2 * u[:, 3]
    angle = 2 * math.pi * u[:, 4]
    # math's cos and sin per blade: numpy's are dispatched by CPU feature, and the bytes must not be.
    cos = np.array([math.cos(a) for a in angle])
    sin = np.array([math.sin(a) for a in angle])
    tips = feet + np.column_stack([lean * cos, lean * sin, heights])
    tips[:, 0] = np.clip(tips[:, 0], -hx, hx)
    tips[:, 1] = np.clip(tips[:, 1], -hy, hy)
    width = REED_WIDTH_M[min(level, len(REED_WIDTH_M) - 1)] * (0.7 + 0.6 * u[:, 5])
    side = np.column_stack([-sin, cos, np.zeros(n)])  # across the blade, level
    shade = np.minimum((u[:, 6] * len(_REED_COLOURS)).astype(int), len(_REED_COLOURS) - 1)
    for k, colour in enumerate(_REED_COLOURS):
        blades = np.flatnonzero(shade == k)
        if len(blades) == 0:
            continue
        w = (width[blades] / 2)[:, None] * side[blades]
        corners = np.stack([feet[blades] - w, feet[blades] + w, tips[blades]], axis=1).reshape(-1, 3)
        corners[:, :2] = np.clip(corners[:, :2], [-hx, -hy], [hx, hy])
        tri = [(3 * j, 3 * j + 1, 3 * j + 2) for j in range(len(blades))]
        p.add(f"blades{k}", "vegetation", Material.PLAIN, colour, corners, tri, closed=False)
    return p.build()


#: How wide (m) the strip of shore along a bank's edge on open water is.
SHORE_M = 1.2


def slab(half: Vec3, rng: np.random.Generator, level: int = 0, *, cls: str, look: tuple[Material, tuple],
         markings: list[tuple[float, float, float, float]] = (),
         shores: list[tuple[int, float, float]] = ()) -> Asset:  # fmt: skip
    """A road, pavement or grass slab filling its box (its top face the box's top, its sides
    the box's sides, no bottom: it stands on the ground), with flat ``markings`` (x0, y0, x1,
    y1 rectangles in the box's frame, painted white a few millimetres above the top); ``look``
    is its top's material and colour (``ASPHALT``, ``PAVING``, ``GRASS``). ``shores`` are the
    stretches of its sides on open water (a side of ``box_faces``, from s0 to s1 along it): a
    strip of sand and pebbles runs along the top there, and the side is wet mud."""
    surface, colour = look
    hx, hy, hz = half
    p = Parts(level)
    q = Quads()
    q.add("top", cls, surface, colour, level_rect(-hx, -hy, hx, hy, hz), UP)
    side = Material.CONCRETE if cls == "road" else surface
    side_colour = (0.58, 0.57, 0.55) if cls == "road" else tuple(0.8 * c for c in colour)
    wet = {i: (s0, s1) for i, s0, s1 in shores}
    faces = box_faces(half)
    for i, face in enumerate(faces):
        s0, s1 = wet.get(i, (face.width, face.width))
        rect(q, face, "side", cls, side, side_colour, 0.0, s0, 0.0, face.height)
        rect(q, face, "side", cls, side, side_colour, s1, face.width, 0.0, face.height)
        rect(q, face, "mud", cls, Material.SHORE, looks.MUD, s0, s1, 0.0, face.height)
    z = hz + MARKING_M
    for x0, y0, x1, y1 in markings:
        q.add("marking", cls, Material.CONCRETE, looks.MARKING_WHITE, level_rect(x0, y0, x1, y1, z), UP)
    for i, s0, s1 in shores:
        f = faces[i]
        width = min(SHORE_M, (hx if abs(f.normal[0]) > 0.5 else hy))  # never past the slab's middle
        h = f.height + MARKING_M
        q.add("shore", cls, Material.SHORE, looks.SAND, [f.at(s0, h), f.at(s1, h), f.at(s1, h, width),
                                                          f.at(s0, h, width)], UP)  # fmt: skip
    q.into(p)
    return p.build()


def road_markings(half, lanes_y: list[float], crossings_x: list[float], *, dash: float = 3.0, gap: float = 6.0,
                  width: float = 0.12) -> list[tuple[float, float, float, float]]:  # fmt: skip
    """Markings of a straight carriageway along its box's x: a dashed line between each pair
    of neighbouring lanes (``lanes_y``, their centres across it), solid edge lines, and zebra
    crossings at ``crossings_x``."""
    hx, hy, _ = half
    out: list[tuple[float, float, float, float]] = []
    edge = hy - 0.3
    clear = [(x - 2.5, x + 2.5) for x in crossings_x]

    def runs(x0: float, x1: float) -> list[tuple[float, float]]:
        cuts = sorted(c for c in clear if c[1] > x0 and c[0] < x1)
        out_, x = [], x0
        for a, b in cuts:
            if a > x:
                out_.append((x, a))
            x = max(x, b)
        if x < x1:
            out_.append((x, x1))
        return out_

    for y in (-edge, edge):
        out += [(a, y - width / 2, b, y + width / 2) for a, b in runs(-hx, hx)]
    ys = sorted(lanes_y)
    for y0, y1 in itertools.pairwise(ys):
        y = (y0 + y1) / 2
        x = -hx
        while x + dash <= hx:
            out += [(a, y - width / 2, b, y + width / 2) for a, b in runs(x, x + dash)]
            x += dash + gap
    for cx in crossings_x:
        for k in range(int((2 * edge) // 1.0)):
            y = -edge + 0.25 + k * 1.0
            out.append((cx - 2.0, y, cx + 2.0, y + 0.5))
    return out


#: Looks of the ground slabs: (material, colour) by pixel class and role.
ASPHALT = (Material.ASPHALT, looks.ASPHALT_GREY)
PAVING = (Material.PAVING, looks.PAVING_GREY)
GRASS = (Material.GRASS, looks.GRASS_GREEN)


def ground(half_extent: float, z: float, *, indoor: bool, pitch: tuple[float, float] | None = None,
           tiled: tuple[float, float, float, float] | None = None) -> Asset:  # fmt: skip
    """The ground under an environment, a square of ``half_extent`` at height ``z``: grass
    (``terrain``) outdoors, a wooden floor (``floor``) indoors; with a mown football
    ``pitch`` (length, width) and its lines at the middle, or a ``tiled`` rectangle
    (x0, y0, x1, y1: a kitchen's floor tiles), when asked."""
    p = Parts(0)
    q = Quads()
    h = half_extent
    cls, (material, colour) = ("floor", (Material.WOOD, (0.55, 0.40, 0.26))) if indoor else ("terrain", GRASS)
    # the pitch is mown 3 m past its lines
    zone = (-pitch[0] / 2 - 3.0, -pitch[1] / 2 - 3.0, pitch[0] / 2 + 3.0, pitch[1] / 2 + 3.0) if pitch else tiled
    if zone is None:
        q.add("ground", cls, material, colour, level_rect(-h, -h, h, h, z), UP)
    else:
        x0, y0, x1, y1 = zone
        for rect in ((-h, -h, h, y0), (-h, y1, h, h), (-h, y0, x0, y1), (x1, y0, h, y1)):  # the ground round it
            q.add("ground", cls, material, colour, level_rect(*rect, z), UP)
        if pitch is None:
            q.add("tiles", cls, Material.FLOOR_TILES, looks.FLOOR_TILE, level_rect(*zone, z), UP)
        else:
            q.add("pitch", cls, Material.PITCH, looks.GRASS_GREEN, level_rect(*zone, z), UP)
            for quad in pitch_lines(*pitch):
                q.add("line", cls, Material.PLAIN, looks.MARKING_WHITE, [(x, y, z + MARKING_M) for x, y in quad], UP)
    q.into(p)
    return p.build()


def pitch_lines(length: float, width: float, w: float = 0.12) -> list[tuple[tuple[float, float], ...]]:
    """A football pitch's lines as quads (four (x, y) corners, ``w`` wide) centred on the
    origin, its length along x: touch and goal lines, the halfway line, the centre circle,
    the penalty and goal areas."""
    L, W = length / 2, width / 2
    rects = [(-L, -W, L, -W + w), (-L, W - w, L, W), (-L, -W, -L + w, W), (L - w, -W, L, W), (-w / 2, -W, w / 2, W)]
    for s in (-1.0, 1.0):
        for depth, half_width in ((16.5, min(20.15, W - 1.0)), (5.5, 9.15)):
            x_in = s * (L - depth)
            x0, x1 = sorted((s * L, x_in))
            rects += [(x0, -half_width, x1, -half_width + w), (x0, half_width - w, x1, half_width),
                      (x_in - w / 2, -half_width, x_in + w / 2, half_width)]  # fmt: skip
    out = [((x0, y0), (x1, y0), (x1, y1), (x0, y1)) for x0, y0, x1, y1 in rects]
    r, pieces = 9.15, 48
    ring = circle(pieces)
    for k in range(pieces):
        (ca, sa), (cb, sb) = ring[k], ring[(k + 1) % pieces]
        out.append(((ca * (r - w / 2), sa * (r - w / 2)), (cb * (r - w / 2), sb * (r - w / 2)),
                    (cb * (r + w / 2), sb * (r + w / 2)), (ca * (r + w / 2), sa * (r + w / 2))))  # fmt: skip
    return out
