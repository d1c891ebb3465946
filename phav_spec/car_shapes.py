"""The shapes of car bodies: each body type's proportions, the side profile it is drawn from
and the convex hulls a car collides as, so that the car people meet and the car the
renderer draws are one shape (``phav_generator.world.vehicles`` draws from these profiles).

The frame is the car's box: origin at its centre, +x forward, +z up, half extents
``half``; the ground is ``below`` metres under the box's bottom (a box lifted for its
clearance, as the car of ``car_hit`` is).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from itertools import pairwise

import numpy as np

#: A point or half extents (x, y, z) in metres (as ``phav_spec.scene``'s, which builds on this module).
Vec3 = tuple[float, float, float]

#: The body types a car is drawn as.
CAR_BODIES: tuple[str, ...] = ("hatchback", "sedan", "suv", "van")
#: How far (m) a bumper stands proud of the body's front and rear.
BUMPER_M = 0.07
#: How far (m) the roof panel overhangs the glass's top edge on each side.
ROOF_OVERHANG_M = 0.005
#: The body's corners seen from above, rounded at these radii (m) at the front and rear: a
#: car's plan is a rounded oblong, not a box (a box-cornered car reads as a van or a bus).
CORNER_FRONT_M = 0.35
CORNER_REAR_M = 0.25
#: How far (m) a bumper reaches round its corner, beyond the flat of the body's end.
BUMPER_WRAP_M = 0.12

Point2 = tuple[float, float]


@dataclass(frozen=True)
class CarShape:
    """A body type's proportions, as fractions of the box's length and height."""

    hood_front: float  # height of the hood's front edge / total height
    belt: float  # height of the beltline (bottom of the side windows) / total height
    hood: float  # hood length / length
    trunk: float  # trunk-deck length / length (0: a hatch or van back)
    windshield: float  # windshield's run / length
    rear_window: float  # rear window's run / length
    wheelbase: float  # / length


CAR_SHAPES: dict[str, CarShape] = {
    "hatchback": CarShape(0.50, 0.62, 0.22, 0.02, 0.16, 0.08, 0.64),
    "sedan": CarShape(0.50, 0.64, 0.24, 0.17, 0.15, 0.13, 0.60),
    "suv": CarShape(0.56, 0.60, 0.20, 0.02, 0.12, 0.05, 0.62),
    "van": CarShape(0.48, 0.50, 0.10, 0.0, 0.12, 0.01, 0.64),
}


def car_body(rng: np.random.Generator) -> str:
    """A body type drawn from ``rng`` (one integer draw)."""
    return CAR_BODIES[int(rng.integers(0, len(CAR_BODIES)))]


@dataclass(frozen=True)
class CarProfile:
    """A car's side profile in its box's frame (metres): heights up its front and the
    stations along it where the hood, glass and roof begin and end."""

    kind: str
    half: Vec3
    ground: float  # the ground's height
    bottom: float  # the body's underside
    hood_front: float  # the hood's front edge
    belt: float  # the beltline, where the side windows begin
    roof: float  # the roof's top (the box's top)
    front: float  # the body's front face, behind the bumper
    rear: float  # the body's rear face, behind the bumper
    windscreen: float  # where the windscreen meets the hood
    rear_window: float  # where the rear window meets the trunk or hatch
    roof_front: float  # the windscreen's top
    roof_rear: float  # the rear window's top
    side: float  # the body's half width
    lean: float  # the share of the half width the glass leans in from the beltline to the roof

    @property
    def roof_half_width(self) -> float:
        """The roof's half width: the sides lean in over the glass."""
        return self.side * (1.0 - self.lean)

    @property
    def roof_panel_half_width(self) -> float:
        """The roof panel's half width: the roof's, overhanging the glass's top edge."""
        return self.roof_half_width + ROOF_OVERHANG_M

    def lower(self) -> tuple[Point2, ...]:
        """The body's outline below the beltline, counter-clockwise in (x, z)."""
        z0, zh, zb, front, rear = self.bottom, self.hood_front, self.belt, self.front, self.rear
        if self.kind == "van":
            return ((rear + 0.04, z0), (front - 0.06, z0), (front, z0 + 0.12), (front, zh - 0.05),
                    (front - 0.06, zh), (self.windscreen, zb), (rear, zb), (rear, z0 + 0.04))  # fmt: skip
        return ((rear + 0.06, z0), (front - 0.06, z0), (front, z0 + 0.12), (front, zh - 0.06), (front - 0.08, zh),
                (self.windscreen, zb), (self.rear_window, zb), (rear, zb - 0.08), (rear, z0 + 0.10))  # fmt: skip

    def tuck(self, z: float) -> float:
        """How far in (a fraction of the half width) the body's side is at height z: tucked
        under the sill and rounded over the shoulder line below the belt."""
        sill = 0.07 * max(0.0, (self.bottom + 0.1 - z) / 0.1)
        return sill + 0.05 * max(0.0, (z - self.belt + 0.15) / 0.15)

    def plan_half_width(self, x: float) -> float:
        """The body's half width (m) at station x seen from above: ``side``, less round each
        end's corner of ``CORNER_FRONT_M`` / ``CORNER_REAR_M``."""
        for end, r, sign in ((self.front, CORNER_FRONT_M, 1.0), (self.rear, CORNER_REAR_M, -1.0)):
            into = sign * (x - end) + r  # how far past the corner's start, towards the end
            if into > 0.0:
                return self.side - r + math.sqrt(max(r * r - into * into, 0.0))
        return self.side

    def section_heights(self, x: float) -> tuple[float, ...]:
        """The heights of a body section's points at station x: the outline's span there, at
        ``SECTION_HEIGHTS`` of it (one point near the sill, one near the shoulder)."""
        lo, hi = _vertical_span(self.lower(), x)
        return tuple(lo + (hi - lo) * t for t in SECTION_HEIGHTS)

    def surface_half_width(self, x: float, z: float) -> float:
        """How far (m) from the middle the body's side is at station x and height z, as its
        sections draw it: straight between a section's points."""
        heights = self.section_heights(x)
        tucks = [self.tuck(h) for h in heights]
        z = min(max(z, heights[0]), heights[-1])
        for (h0, t0), (h1, t1) in pairwise(zip(heights, tucks, strict=True)):
            if z <= h1:
                tuck = t0 + (t1 - t0) * (z - h0) / max(h1 - h0, 1e-12)
                break
        return self.plan_half_width(x) * (1.0 - tuck)

    def body_sections(self, per_corner: int) -> tuple[tuple[Vec3, ...], ...]:
        """The body below the belt as cross-sections from rear to front, each a loop of eight
        points counter-clockwise as seen from behind (``Parts.loft``): at the outline's
        stations and ``per_corner`` more round each rounded end, the outline's height span
        (``section_heights``), as wide as the plan and the tuck allow there."""
        outline = self.lower()
        xs = {x for x, _ in outline}
        turns = [0.5 * math.pi * k / per_corner for k in range(per_corner + 1)] if per_corner else [0.0, 0.5 * math.pi]
        for end, r, sign in ((self.front, CORNER_FRONT_M, 1.0), (self.rear, CORNER_REAR_M, -1.0)):
            xs.update(end - sign * r * (1.0 - math.sin(a)) for a in turns)
        x_lo, x_hi = min(x for x, _ in outline), max(x for x, _ in outline)
        sections = []
        for x in sorted(v for v in xs if x_lo <= v <= x_hi):
            heights = self.section_heights(x)
            if heights[-1] - heights[0] < 1e-4:
                continue
            right = [(x, -self.plan_half_width(x) * (1.0 - self.tuck(z)), z) for z in heights]
            sections.append(tuple(right + [(x, -y, z) for x, y, z in reversed(right)]))
        return tuple(sections)

    def cabin(self) -> tuple[Point2, ...]:
        """The greenhouse's outline (windscreen, roof line, rear window), up to 5 cm under the
        roof's top, which the roof panel covers."""
        zt = self.roof - 0.05
        return (
            (self.windscreen, self.belt),
            (self.roof_front, zt),
            (self.roof_rear, zt),
            (self.rear_window, self.belt),
        )

    def roof_panel(self) -> tuple[Point2, ...]:
        """The roof panel's outline over the greenhouse, its edges bevelled."""
        zt, front, rear = self.roof, self.roof_front, self.roof_rear
        return ((front + 0.03, zt - 0.06), (front - 0.02, zt), (rear + 0.02, zt), (rear - 0.03, zt - 0.06))

    def bumpers(self) -> tuple[tuple[Vec3, Vec3], ...]:
        """The front and rear bumpers as boxes: (centre, half extents), across the flat of the
        body's end and ``BUMPER_WRAP_M`` round each corner."""
        hx, hy = self.half[0], self.half[1]
        out = []
        for x, r in ((hx - BUMPER_M / 2 - 0.005, CORNER_FRONT_M), (-hx + BUMPER_M / 2 + 0.005, CORNER_REAR_M)):
            half = (BUMPER_M / 2 + 0.005, min(hy - 0.08, self.side - r + BUMPER_WRAP_M), 0.12)
            out.append(((x, 0.0, self.bottom + 0.14), half))
        return tuple(out)


def car_profile(kind: str, half: Vec3, below: float = 0.0) -> CarProfile:
    """The profile of a ``kind`` car filling a box of half extents ``half`` whose bottom is
    ``below`` metres above the ground."""
    if kind not in CAR_SHAPES:
        raise ValueError(f"{kind!r} is not a car body ({', '.join(CAR_BODIES)})")
    shape = CAR_SHAPES[kind]
    hx, hy, hz = (float(h) for h in half)
    length, height = 2 * hx, 2 * hz + below
    g = -hz - below
    front, rear = hx - BUMPER_M, -hx + BUMPER_M
    windscreen = front - shape.hood * length
    rear_window = rear + shape.trunk * length
    return CarProfile(
        kind=kind,
        half=(hx, hy, hz),
        ground=g,
        bottom=g + max(0.17, below + 0.02),
        hood_front=g + shape.hood_front * height,
        belt=g + shape.belt * height,
        roof=hz,
        front=front,
        rear=rear,
        windscreen=windscreen,
        rear_window=rear_window,
        roof_front=windscreen - shape.windshield * length,
        roof_rear=rear_window + shape.rear_window * length,
        side=hy - 0.05,
        lean=0.10 if kind != "van" else 0.04,
    )


def _vertical_span(outline: tuple[Point2, ...], x: float) -> tuple[float, float]:
    """The lowest and highest z at which the vertical line at x meets a convex outline."""
    zs = []
    for (x0, z0), (x1, z1) in zip(outline, outline[1:] + outline[:1], strict=True):
        if min(x0, x1) - 1e-9 <= x <= max(x0, x1) + 1e-9:
            if abs(x1 - x0) < 1e-9:
                zs += [z0, z1]
            else:
                zs.append(z0 + (z1 - z0) * (x - x0) / (x1 - x0))
    return min(zs), max(zs)


#: Where a body section's points lie up its height span (fractions from its bottom).
SECTION_HEIGHTS = (0.0, 0.13, 0.8, 1.0)
#: Stations round each rounded end of the body hull (as drawn at the finest level).
HULL_CORNER_STATIONS = 4


def car_hulls(profile: CarProfile) -> tuple[tuple[Vec3, ...], ...]:
    """The convex solids a car collides as, each as its corners: the body below the belt,
    the greenhouse from the belt to the roof panel (its sides leaning in as the glass does)
    and the two bumpers. Only the mirrors (9 cm), the pillars' trim (5.5 cm), the plates and
    lamps (under 1.5 cm) and the dark underside between the wheels are drawn outside them;
    the wheels do not collide."""
    side, top = profile.side, profile.roof_panel_half_width
    body = tuple(q for section in profile.body_sections(HULL_CORNER_STATIONS) for q in section)
    glass = (profile.cabin()[0], profile.cabin()[-1])  # where the glass meets the belt
    cabin = tuple((x, s * side, z) for x, z in glass for s in (-1.0, 1.0)) + tuple(
        (x, s * top, z) for x, z in profile.roof_panel() for s in (-1.0, 1.0)
    )
    bumpers = tuple(
        tuple((cx + i * hx, i2 * hy, cz + i3 * hz) for i in (-1, 1) for i2 in (-1, 1) for i3 in (-1, 1))
        for (cx, _, cz), (hx, hy, hz) in profile.bumpers()
    )
    return (body, cabin, *bumpers)
