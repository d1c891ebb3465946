"""The shapes of car bodies: each body type's proportions, the side profile it is drawn from
and the convex hulls a car collides as, so that the car people meet and the car the
renderer draws are one shape (``phav_generator.world.vehicles`` draws from these profiles).

The frame is the car's box: origin at its centre, +x forward, +z up, half extents
``half``; the ground is ``below`` metres under the box's bottom (a box lifted for its
clearance, as the car of ``car_hit`` is).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from phav_spec.scene import Vec3

#: The body types a car is drawn as.
CAR_BODIES: tuple[str, ...] = ("hatchback", "sedan", "suv", "van")
#: How far (m) a bumper stands proud of the body's front and rear.
BUMPER_M = 0.07
#: How far (m) the roof panel overhangs the glass's top edge on each side.
ROOF_OVERHANG_M = 0.005

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
    lean: float  # how far (m) the glass leans in from the beltline to the roof

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
        """The front and rear bumpers as boxes: (centre, half extents)."""
        hx, hy = self.half[0], self.half[1]
        half = (BUMPER_M / 2 + 0.005, hy - 0.08, 0.12)
        return tuple(
            ((x, 0.0, self.bottom + 0.14), half) for x in (hx - BUMPER_M / 2 - 0.005, -hx + BUMPER_M / 2 + 0.005)
        )


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


def car_hulls(profile: CarProfile) -> tuple[tuple[Vec3, ...], ...]:
    """The convex solids a car collides as, each as its corners: the body below the belt,
    the greenhouse from the belt to the roof panel (its sides leaning in as the glass does)
    and the two bumpers. Only the mirrors (9 cm), the pillars' trim (5.5 cm) and the dark
    underside between the wheels are drawn outside them; the wheels do not collide."""
    side, top = profile.side, profile.roof_panel_half_width
    body = tuple((x, s * side, z) for x, z in profile.lower() for s in (-1.0, 1.0))
    glass = (profile.cabin()[0], profile.cabin()[-1])  # where the glass meets the belt
    cabin = tuple((x, s * side, z) for x, z in glass for s in (-1.0, 1.0)) + tuple(
        (x, s * top, z) for x, z in profile.roof_panel() for s in (-1.0, 1.0)
    )
    bumpers = tuple(
        tuple((cx + i * hx, i2 * hy, cz + i3 * hz) for i in (-1, 1) for i2 in (-1, 1) for i3 in (-1, 1))
        for (cx, _, cz), (hx, hy, hz) in profile.bumpers()
    )
    return (body, cabin, *bumpers)
