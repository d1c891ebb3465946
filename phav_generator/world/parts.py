"""The asset library's building blocks: parts with a pixel class, a material and a colour,
assembled into one ``Asset`` (triangles in the object's own frame, labels per vertex).

Shapes are made with the arithmetic that gives the same bytes on every CPU: angles from
Python's ``math`` (scalar libm), transforms as element-wise float64 products and sums (no
BLAS, no SIMD-dispatched transcendental), then rounded to float32 once.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from phav_generator.world.materials import Material
from phav_spec.vocab import PIXEL_CLASSES

Vec3 = tuple[float, float, float]
#: What the builders take for a point, for points ((n, 3) or (n, 2)) and for a colour (0–1).
Point = Sequence[float] | np.ndarray
Points = Sequence[Sequence[float]] | np.ndarray
Colour = Sequence[float]

#: What a part's surface gives off: nothing or the lamps' light.
NO_GLOW, LAMP_GLOW = 0, 1
#: Segments round a curved part at each level of detail (0 the finest).
ROUND_SEGMENTS = (16, 10, 6)
LEVELS = len(ROUND_SEGMENTS)


@dataclass(frozen=True)
class Asset:
    """An object's triangles in its own frame (metres, +Z up, standing on z = 0 unless said)
    with, per vertex, its pixel class, material, display colour (0–1) and glow; ``parts``
    gives each part's triangle range, name and whether its surface is closed."""

    positions: np.ndarray  # (N, 3) float32
    normals: np.ndarray  # (N, 3) float32, unit
    triangles: np.ndarray  # (M, 3) uint32, counter-clockwise seen from outside
    class_ids: np.ndarray  # (N,) uint16
    materials: np.ndarray  # (N,) uint8, Material values
    colours: np.ndarray  # (N, 3) float32
    glow: np.ndarray  # (N,) uint8: NO_GLOW or LAMP_GLOW
    parts: tuple[tuple[str, int, int, bool], ...]  # (name, first triangle, end, closed)

    @property
    def n_triangles(self) -> int:
        return len(self.triangles)

    def pixel_classes(self) -> tuple[str, ...]:
        """The classes its vertices carry, in class-id order."""
        return tuple(PIXEL_CLASSES.names[int(i)] for i in np.unique(self.class_ids))

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """Its axis-aligned bounds (lowest, highest corner) in its own frame."""
        p = self.positions.astype(np.float64)
        return p.min(axis=0), p.max(axis=0)

    def digest_bytes(self) -> bytes:
        """Every array's bytes, in a fixed order (what the determinism tests compare)."""
        arrays = (self.positions, self.normals, self.triangles, self.class_ids, self.materials, self.colours, self.glow)
        return b"".join(np.ascontiguousarray(a).tobytes() for a in arrays)


def rotation(yaw: float = 0.0, pitch: float = 0.0, roll: float = 0.0) -> np.ndarray:
    """R = Rz(yaw) · Ry(pitch) · Rx(roll), radians, from scalar trigonometry."""
    cz, sz, cy, sy, cx, sx = (math.cos(yaw), math.sin(yaw), math.cos(pitch), math.sin(pitch),
                              math.cos(roll), math.sin(roll))  # fmt: skip
    return np.array([
        [cz * cy, cz * sy * sx - sz * cx, cz * sy * cx + sz * sx],
        [sz * cy, sz * sy * sx + cz * cx, sz * sy * cx - cz * sx],
        [-sy, cy * sx, cy * cx],
    ])  # fmt: skip


def transform_points(points: np.ndarray, rot: np.ndarray, offset) -> np.ndarray:
    """rot · p + offset for each row of ``points`` (n, 3), element-wise (no BLAS)."""
    p = np.asarray(points, dtype=np.float64)
    out = np.empty_like(p)
    for i in range(3):
        out[:, i] = rot[i, 0] * p[:, 0] + rot[i, 1] * p[:, 1] + rot[i, 2] * p[:, 2] + float(offset[i])
    return out


def _normalised(v: np.ndarray) -> np.ndarray:
    length = np.sqrt(v[:, 0] * v[:, 0] + v[:, 1] * v[:, 1] + v[:, 2] * v[:, 2])
    return v / np.maximum(length, 1e-12)[:, None]


def _area_normals(p: np.ndarray, tri: np.ndarray) -> np.ndarray:
    """Each triangle's normal, twice its area long."""
    a, b, c = p[tri[:, 0]], p[tri[:, 1]], p[tri[:, 2]]
    u, v = b - a, c - a
    return np.stack([u[:, 1] * v[:, 2] - u[:, 2] * v[:, 1], u[:, 2] * v[:, 0] - u[:, 0] * v[:, 2],
                     u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]], axis=1)  # fmt: skip


def _face_normals(p: np.ndarray, tri: np.ndarray) -> np.ndarray:
    return _normalised(_area_normals(p, tri))


def crease_normals(p: np.ndarray, tri: np.ndarray, crease_deg: float, polygons: np.ndarray | None = None) -> np.ndarray:
    """A normal per triangle corner (m·3, 3): the area-weighted mean of the polygons round the
    corner's vertex that turn less than ``crease_deg`` from the corner's own, so that a curved
    panel shades smooth and an edge sharper than the crease stays sharp. ``polygons`` names
    each triangle's polygon (a quad's two triangles one polygon, so that how it was split
    does not tilt the normal); each triangle its own by default. Summed in a fixed order with
    elementwise arithmetic only (no BLAS, no SIMD-dispatched functions): the same on every CPU."""
    raw = _area_normals(p, tri)
    poly = np.arange(len(tri)) if polygons is None else np.asarray(polygons, dtype=np.int64)
    if poly.shape != (len(tri),) or (poly < 0).any():
        raise ValueError(f"polygons: one non-negative id per triangle ({len(tri)}), got shape {poly.shape}")
    poly_raw = np.zeros((int(poly.max()) + 1, 3))
    np.add.at(poly_raw, poly, raw)  # in triangle order
    poly_unit = _normalised(poly_raw)
    cos_crease = math.cos(math.radians(crease_deg))
    corners = tri.reshape(-1)
    order = np.argsort(corners, kind="stable")  # corners grouped by vertex, each group in corner order
    out = np.repeat(_normalised(raw), 3, axis=0)
    for group in np.split(order, np.flatnonzero(np.diff(corners[order])) + 1):
        own = poly[group // 3]
        round_vertex = np.unique(own)  # each polygon once, in id order
        pu, pr = poly_unit[own], poly_unit[round_vertex]
        turn = pu[:, None, 0] * pr[None, :, 0] + pu[:, None, 1] * pr[None, :, 1] + pu[:, None, 2] * pr[None, :, 2]
        acc = np.zeros((len(group), 3))
        for j, q in enumerate(round_vertex):
            acc += (turn[:, j] > cos_crease)[:, None] * poly_raw[q]
        length = np.sqrt(acc[:, 0] * acc[:, 0] + acc[:, 1] * acc[:, 1] + acc[:, 2] * acc[:, 2])
        keep = length > 1e-12  # a polygon of no area keeps its (zero) face normal
        out[group[keep]] = acc[keep] / length[keep, None]
    return out


def circle(segments: int, phase: float = 0.0) -> list[tuple[float, float]]:
    """(cos, sin) of ``segments`` angles evenly round the circle from ``phase`` radians."""
    return [(math.cos(phase + 2 * math.pi * k / segments), math.sin(phase + 2 * math.pi * k / segments))
            for k in range(segments)]  # fmt: skip


def sphere_triangles(segments: int, rings: int) -> list[tuple[int, int, int]]:
    """The triangles of a sphere's grid, counter-clockwise from outside: vertex 0 the bottom
    pole, then ``rings`` − 1 rings of ``segments`` vertices from the bottom up, then the top."""
    top = 1 + (rings - 1) * segments

    def ring(r: int, k: int) -> int:
        return 1 + r * segments + k % segments

    tri = [(0, ring(0, k + 1), ring(0, k)) for k in range(segments)]
    for r in range(rings - 2):
        for k in range(segments):
            tri += [(ring(r, k), ring(r, k + 1), ring(r + 1, k + 1)), (ring(r, k), ring(r + 1, k + 1), ring(r + 1, k))]
    tri += [(ring(rings - 2, k), ring(rings - 2, k + 1), top) for k in range(segments)]
    return tri


@dataclass
class Parts:
    """Parts being assembled into one asset, at level of detail ``level`` (0 the finest)."""

    level: int = 0
    _positions: list[np.ndarray] = field(default_factory=list)
    _normals: list[np.ndarray] = field(default_factory=list)
    _triangles: list[np.ndarray] = field(default_factory=list)
    _labels: list[tuple[int, int, tuple[float, float, float], int, int]] = field(default_factory=list)
    _parts: list[tuple[str, int, int, bool]] = field(default_factory=list)
    _n_vertices: int = 0
    _n_triangles: int = 0

    def __post_init__(self) -> None:
        if not 0 <= self.level < LEVELS:
            raise ValueError(f"level of detail must be 0–{LEVELS - 1}, got {self.level}")

    @property
    def round(self) -> int:
        """Segments round a curved part at this level."""
        return ROUND_SEGMENTS[self.level]

    @property
    def fine(self) -> bool:
        """Whether small details (books, slats, handles) are modelled at this level."""
        return self.level < 2

    def add(self, name: str, cls: str, material: Material, colour: Colour, positions: Points,
            triangles: Sequence[Sequence[int]] | np.ndarray, *, normals: Points | None = None, closed: bool,
            glow: int = NO_GLOW, rot: np.ndarray | None = None, offset: Point = (0.0, 0.0, 0.0),
            crease: float | None = None, polygons: np.ndarray | None = None) -> None:  # fmt: skip
        """One part: ``positions`` (n, 3) and counter-clockwise ``triangles`` (m, 3) in the
        part's frame, placed by ``rot`` and ``offset``; flat-shaded unless ``normals`` given,
        or smooth across edges whose faces turn less than ``crease`` degrees
        (``crease_normals``, with ``polygons``)."""
        p = np.asarray(positions, dtype=np.float64)
        tri = np.asarray(triangles, dtype=np.int64).reshape(-1, 3)
        r = np.eye(3) if rot is None else np.asarray(rot, dtype=np.float64)
        p = transform_points(p, r, offset)
        if normals is None:  # three vertices of its own per triangle
            if crease is None:
                n = np.repeat(_face_normals(p, tri), 3, axis=0)
            else:
                n = crease_normals(p, tri, crease, polygons)
            p, tri = p[tri.reshape(-1)], np.arange(3 * len(tri)).reshape(-1, 3)
        else:
            n = _normalised(transform_points(np.asarray(normals, dtype=np.float64), r, (0.0, 0.0, 0.0)))
        self._positions.append(p)
        self._normals.append(n)
        self._triangles.append(tri + self._n_vertices)
        rgb = tuple(float(c) for c in colour)
        self._labels.append((len(p), PIXEL_CLASSES[cls].class_id, rgb, int(material), glow))
        self._parts.append((name, self._n_triangles, self._n_triangles + len(tri), closed))
        self._n_vertices += len(p)
        self._n_triangles += len(tri)

    def box(
        self, name: str, cls: str, material: Material, colour: Colour, centre: Point, half: Point, *,
        rot: np.ndarray | None = None, glow: int = NO_GLOW,
    ) -> None:  # fmt: skip
        """A box of half extents ``half`` around ``centre``, turned by ``rot``."""
        hx, hy, hz = (float(h) for h in half)
        corners = [(sx * hx, sy * hy, sz * hz) for sz in (-1, 1) for sy in (-1, 1) for sx in (-1, 1)]
        faces = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
        tri = [t for a, b, c, d in faces for t in ((a, b, c), (a, c, d))]
        self.add(name, cls, material, colour, corners, tri, closed=True, glow=glow, rot=rot, offset=centre)

    def span(
        self, name: str, cls: str, material: Material, colour: Colour, lo: Point, hi: Point, *, glow: int = NO_GLOW
    ) -> None:
        """An axis-aligned box between corners ``lo`` and ``hi``."""
        lo_, hi_ = np.asarray(lo, dtype=np.float64), np.asarray(hi, dtype=np.float64)
        self.box(name, cls, material, colour, (lo_ + hi_) / 2, (hi_ - lo_) / 2, glow=glow)

    def frustum(self, name: str, cls: str, material: Material, colour: Colour, a: Point, b: Point, r_a: float,
                r_b: float, *, segments: int | None = None, caps: bool = True, glow: int = NO_GLOW,
                phase: float = 0.0) -> None:  # fmt: skip
        """A truncated cone (a cylinder where the radii agree) from ``a`` to ``b``, smooth
        sides, flat caps (a point where a radius is 0)."""
        s = segments or self.round
        a_, b_ = np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64)
        axis = b_ - a_
        length = math.sqrt(float(axis @ axis))
        axis = axis / length
        helper = np.array([1.0, 0.0, 0.0]) if abs(axis[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
        u = np.cross(axis, helper)
        u = u / math.sqrt(float(u @ u))
        v = np.cross(axis, u)
        ring = circle(s, phase)
        slope = (r_a - r_b) / length
        pos, nrm, tri = [], [], []
        for c, sn in ring:
            radial = c * u + sn * v
            side_n = radial + slope * axis
            pos += [a_ + r_a * radial, b_ + r_b * radial]
            nrm += [side_n, side_n]
        for k in range(s):
            i0, i1, j0, j1 = 2 * k, 2 * k + 1, 2 * ((k + 1) % s), 2 * ((k + 1) % s) + 1
            if r_a > 0 and r_b > 0:
                tri += [(i0, j0, j1), (i0, j1, i1)]
            elif r_a > 0:
                tri += [(i0, j0, i1)]
            else:
                tri += [(i0, j1, i1)]
        if caps:
            for end, radius, sign in ((a_, r_a, -1.0), (b_, r_b, 1.0)):
                if radius <= 0:
                    continue
                centre = len(pos)
                pos.append(end)
                nrm.append(sign * axis)
                first = len(pos)
                for c, sn in ring:
                    pos.append(end + radius * (c * u + sn * v))
                    nrm.append(sign * axis)
                for k in range(s):
                    i, j = first + k, first + (k + 1) % s
                    tri.append((centre, j, i) if sign < 0 else (centre, i, j))
        self.add(name, cls, material, colour, pos, tri, normals=nrm, closed=caps, glow=glow)

    def cylinder(
        self, name: str, cls: str, material: Material, colour: Colour, a: Point, b: Point, radius: float, **kw: Any
    ) -> None:
        """A cylinder from ``a`` to ``b`` (``frustum``'s keywords)."""
        self.frustum(name, cls, material, colour, a, b, radius, radius, **kw)

    def ellipsoid(self, name: str, cls: str, material: Material, colour: Colour, centre: Point, radii: Point, *,
                  segments: int | None = None, rot: np.ndarray | None = None, glow: int = NO_GLOW,
                  squareness: float = 1.0) -> None:  # fmt: skip
        """An ellipsoid (a sphere where the radii agree): smooth, one vertex at each pole.
        ``squareness`` below 1 flattens it towards its box (a superellipsoid: a cushion at
        about 0.3, a box at 0)."""
        s = segments or self.round
        rings = max(s // 2, 3)
        rx, ry, rz = (float(r) for r in radii)
        e = float(squareness)

        def shape(w: float) -> float:  # sign(w)·|w|^e, exactly w for the plain ellipsoid
            return w if e == 1.0 else math.copysign(abs(w) ** e, w)

        def slope(w: float) -> float:  # the normal's factor: sign(w)·|w|^(2 − e)
            return w if e == 1.0 else math.copysign(abs(w) ** (2.0 - e), w)

        pos, nrm = [(0.0, 0.0, -rz)], [(0.0, 0.0, -1.0)]
        around = circle(s)
        for i in range(1, rings):
            lat = -math.pi / 2 + math.pi * i / rings
            cl, sl = math.cos(lat), math.sin(lat)
            for c, sn in around:
                pos.append((rx * shape(cl) * shape(c), ry * shape(cl) * shape(sn), rz * shape(sl)))
                nrm.append((slope(cl) * slope(c) / rx, slope(cl) * slope(sn) / ry, slope(sl) / rz))
        pos.append((0.0, 0.0, rz))
        nrm.append((0.0, 0.0, 1.0))
        tri = sphere_triangles(s, rings)
        self.add(name, cls, material, colour, pos, tri, normals=nrm, closed=True, glow=glow, rot=rot, offset=centre)

    def prism(self, name: str, cls: str, material: Material, colour: Colour, profile: Points, y0: float, y1: float,
              *, taper: Callable[[float], float] | None = None, glow: int = NO_GLOW, rot: np.ndarray | None = None,
              offset: Point = (0.0, 0.0, 0.0)) -> None:  # fmt: skip
        """A convex ``profile`` of (x, z) points, counter-clockwise seen from −y, extruded from
        y0 to y1; ``taper(z)`` (0–1) pulls a vertex at height z towards y's middle (a car's
        cabin narrowing to its roof)."""
        pts = [(float(x), float(z)) for x, z in profile]
        n = len(pts)
        mid, half = (y0 + y1) / 2, (y1 - y0) / 2
        pos = []
        for side in (-1.0, 1.0):
            for x, z in pts:
                w = half * (1.0 - (taper(z) if taper is not None else 0.0))
                pos.append((x, mid + side * w, z))
        tri = []
        for k in range(1, n - 1):  # the caps: fans, facing −y then +y
            tri += [(0, k, k + 1), (n, n + k + 1, n + k)]
        for k in range(n):  # the sides round the profile
            j = (k + 1) % n
            tri += [(k, n + k, n + j), (k, n + j, j)]
        self.add(name, cls, material, colour, pos, tri, closed=True, glow=glow, rot=rot, offset=offset)

    def loft(
        self, name: str, cls: str, material: Material, colour: Colour, sections: Sequence[Points], *,
        glow: int = NO_GLOW, crease: float | None = None,
    ) -> None:  # fmt: skip
        """A closed solid through ``sections``: cross-sections of equally many (x, y, z) points
        each, in order along the solid, each loop counter-clockwise as seen looking from the
        first section towards the last; joined by quads, capped at both ends; flat-shaded, or
        smooth within ``crease`` degrees (``Parts.add``)."""
        loops = [[tuple(float(c) for c in q) for q in loop] for loop in sections]
        m = len(loops[0])
        if len(loops) < 2 or m < 3 or any(len(loop) != m for loop in loops):
            raise ValueError(f"{name}: a loft needs two or more sections of one size (at least 3 points)")
        pos = [q for loop in loops for q in loop]
        tri = []
        for i in range(len(loops) - 1):
            a, b = i * m, (i + 1) * m
            for k in range(m):
                j = (k + 1) % m
                tri += [(a + k, b + j, a + j), (a + k, b + k, b + j)]
        # The caps: fans from each end's centroid (a loop may have collinear points, which
        # a fan from its first point would join into triangles of no area), facing out.
        last = (len(loops) - 1) * m
        for end, first, facing in ((len(pos), 0, -1), (len(pos) + 1, last, 1)):
            for k in range(m):
                a, b = first + k, first + (k + 1) % m
                tri.append((end, a, b) if facing < 0 else (end, b, a))
        pos += [tuple(sum(c) / m for c in zip(*loop, strict=True)) for loop in (loops[0], loops[-1])]
        quads = (len(loops) - 1) * m
        polygons = np.concatenate([np.arange(2 * quads) // 2, np.repeat([quads, quads + 1], m)])  # quads, two caps
        self.add(name, cls, material, colour, pos, tri, closed=True, glow=glow, crease=crease, polygons=polygons)

    def panel(
        self, name: str, cls: str, material: Material, colour: Colour, corners: Points, *, glow: int = NO_GLOW
    ) -> None:
        """A flat convex polygon (one-sided, counter-clockwise seen from its front): glass,
        screens, plates laid on a surface."""
        n = len(corners)
        self.add(
            name, cls, material, colour, corners, [(0, k, k + 1) for k in range(1, n - 1)], closed=False, glow=glow
        )

    def build(self) -> Asset:
        """The parts as one asset."""
        if not self._positions:
            raise ValueError("an asset needs at least one part")
        positions = np.concatenate(self._positions).astype(np.float32)
        normals = np.concatenate(self._normals).astype(np.float32)
        triangles = np.concatenate(self._triangles).astype(np.uint32)
        counts = [n for n, *_ in self._labels]
        class_ids = np.repeat(np.array([c for _, c, *_ in self._labels], dtype=np.uint16), counts)
        materials = np.repeat(np.array([m for *_, m, _ in self._labels], dtype=np.uint8), counts)
        colours = np.repeat(np.array([rgb for _, _, rgb, *_ in self._labels], dtype=np.float32), counts, axis=0)
        glow = np.repeat(np.array([g for *_, g in self._labels], dtype=np.uint8), counts)
        return Asset(positions, normals, triangles, class_ids, materials, colours, glow, tuple(self._parts))
