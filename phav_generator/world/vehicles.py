"""Vehicles: cars of four body types (hatchback, sedan, SUV, van), a rigid truck and a city
bus, each fitted into its collision box, with glass, lights, bumpers, plates and wheels
that turn (the wheels are their own asset, placed at ``Vehicle.axles``).

The frame is the box's: origin at its centre, +x forward, +z up; the ground is ``below``
metres under the box's bottom (a car whose box is lifted for its clearance).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from phav_generator.world.materials import (
    CAR_PAINTS,
    CHROME_TINT,
    GLASS_TINT,
    HEADLIGHT,
    PLATE,
    RGB,
    RIM,
    TAIL_LIGHT,
    TRIM,
    TYRE,
    Material,
    pick_weighted,
)  # fmt: skip
from phav_generator.world.parts import LAMP_GLOW, Asset, Parts, Vec3, circle, rotation
from phav_spec.car_shapes import BUMPER_M, CAR_SHAPES, HULL_CORNER_STATIONS, car_body, car_profile

#: Stations round each rounded end of a car's body, per level of detail: the finest as the
#: car of ``car_hit`` collides (``car_hulls``).
BODY_CORNER_STATIONS = (HULL_CORNER_STATIONS, 2, 1)
#: Edges of a car's body sharper than this (degrees) stay sharp; flatter ones shade smooth,
#: so the panels curve round the corners and the shoulder as pressed steel does.
BODY_CREASE_DEG = 40.0
#: A truck's rear axles (m ahead of its back): the overhang behind them leaves the underride
#: bar clear of the tyres.
REAR_AXLES_M = (2.0, 1.0)
#: A bus tyre's clearance to its round wheel arch (m).
BUS_ARCH_GAP_M = 0.12
#: How far (m) a bus's black glazing surround reaches past its side windows, fore and aft.
BUS_GLAZING_SURROUND_M = 0.2
#: A box body's aluminium posts and rails.
RAIL: tuple[float, float, float] = (0.62, 0.63, 0.65)
#: Truck box and cab colours.
_TRUCK_BOXES = ((0.92, 0.92, 0.90), (0.80, 0.80, 0.78), (0.70, 0.12, 0.10), (0.15, 0.30, 0.55))
#: Bus liveries, one drawn per bus: red, yellow, green, white, blue (docs/realism.md gives
#: what the judges name each).
BUS_LIVERIES: tuple[RGB, ...] = (
    (0.85, 0.12, 0.10), (0.92, 0.75, 0.10), (0.15, 0.40, 0.25), (0.90, 0.90, 0.88), (0.12, 0.30, 0.60),
)  # fmt: skip


@dataclass(frozen=True)
class Vehicle:
    """A vehicle's body, one wheel (axle along y, centred on the origin) and where each wheel's
    centre sits in the body's frame."""

    body: Asset
    wheel: Asset
    axles: np.ndarray  # (k, 3) wheel centres
    wheel_radius: float

    @property
    def n_triangles(self) -> int:
        """Its body's triangles and every wheel's."""
        return self.body.n_triangles + len(self.axles) * self.wheel.n_triangles


def _axle_pairs(xs, y: float, z: float) -> np.ndarray:
    """Wheel centres (2·len(xs), 3): a wheel each side (∓y) of every axle at x in ``xs``."""
    return np.array([(x, sgn * y, z) for x in xs for sgn in (-1.0, 1.0)])


def wheel(radius: float, width: float, level: int, cls: str = "car") -> Asset:
    """A tyre with a rim and five spokes on each face (so its turning shows), axle along y,
    labelled with its vehicle's class."""
    p = Parts(level)
    y = width / 2
    p.cylinder("tyre", cls, Material.RUBBER, TYRE, (0.0, -y, 0.0), (0.0, y, 0.0), radius, segments=p.round + 4)
    rim = 0.62 * radius
    for side in (-1.0, 1.0):
        face = side * (y + 0.004)
        p.cylinder(f"rim{side:+.0f}", cls, Material.CHROME, RIM, (0.0, side * (y - 0.01), 0.0), (0.0, face, 0.0),
                   rim, segments=p.round)  # fmt: skip
        if p.fine:
            for k, (c, s) in enumerate(circle(5)):
                centre = (0.55 * rim * c, face + side * 0.006, 0.55 * rim * s)
                p.box(f"spoke{k}{side:+.0f}", cls, Material.METAL, (0.30, 0.30, 0.32), centre,
                      (0.45 * rim, 0.006, 0.035), rot=rotation(pitch=-math.atan2(s, c)))  # fmt: skip
    return p.build()


def car(
    half: Vec3, rng: np.random.Generator, level: int = 0, *, body: str | None = None, below: float = 0.0
) -> Vehicle:
    """A car filling the box of half extents ``half``; ``body`` one of ``CAR_BODIES`` (drawn
    from ``rng`` when None), its paint drawn from ``CAR_PAINTS``."""
    kind = body if body is not None else car_body(rng)
    shape = CAR_SHAPES[kind]
    paint = pick_weighted(CAR_PAINTS, rng)
    outline = car_profile(kind, half, below)
    hx, hy, hz = outline.half
    length, height = 2 * hx, 2 * hz + below
    p = Parts(level)
    g = outline.ground
    radius = min(0.34, 0.22 * height)
    z0, zh, zb, zt = outline.bottom, outline.hood_front, outline.belt, outline.roof
    front, rear = outline.front, outline.rear
    x_ws, x_rw = outline.windscreen, outline.rear_window
    side = outline.side
    # The body: rounded corners seen from above, its sides tucked in under the sills and
    # rounded over the shoulder line (the same sections the car collides as), shaded smooth.
    sections = outline.body_sections(BODY_CORNER_STATIONS[level])
    p.loft("body", "car", Material.PAINT, paint, sections, crease=BODY_CREASE_DEG)
    # The dark underside between the wheels: what shades the road under a car.
    p.span(
        "underbody",
        "car",
        Material.RUBBER,
        TRIM,
        (rear + 0.3, -side + 0.1, g + 0.04),
        (front - 0.3, side - 0.1, z0 + 0.02),
    )
    # The greenhouse: glass leaning in towards the roof, a painted roof and pillars.
    x_roof_front, x_roof_rear = outline.roof_front, outline.roof_rear
    lean = outline.lean
    taper = lambda z: lean * (z - zb) / max(zt - zb, 1e-6)  # noqa: E731
    cabin = list(outline.cabin())
    p.prism("glass", "car", Material.GLASS, GLASS_TINT, cabin, -side + 0.01, side - 0.01, taper=taper)
    overhang = outline.roof_panel_half_width
    p.prism("roof", "car", Material.PAINT, paint, list(outline.roof_panel()), -overhang, overhang)
    tilt = math.atan2(lean * side, zt - zb)
    pillar_x = [(x_ws + x_roof_front) / 2, (x_roof_front + x_roof_rear) / 2, (x_rw + x_roof_rear) / 2]
    pillar_run = [x_ws - x_roof_front, 0.0, x_roof_rear - x_rw]
    for k, (x, run) in enumerate(zip(pillar_x, pillar_run, strict=True)):
        if k == 1 and x_roof_front - x_roof_rear < 1.0:
            continue  # a short cabin has no B pillar
        for sgn in (-1.0, 1.0):
            y = sgn * (side - 0.005 - lean * side / 2)
            pitch = math.atan2(run, zt - zb) * (-1.0 if k == 0 else 1.0)
            p.box(f"pillar{k}{sgn:+.0f}", "car", Material.PAINT, paint, (x, y, (zb + zt) / 2 - 0.02),
                  (0.05, 0.02, (zt - zb) / 2 / max(math.cos(pitch), 0.3)),
                  rot=rotation(pitch=pitch, roll=sgn * tilt))  # fmt: skip
    # Bumpers, lights, grille, plates, wheel arches and mirrors.
    trim = TRIM if rng.random() < 0.5 else paint
    for ((x, _, z), extent), sgn in zip(outline.bumpers(), (1.0, -1.0), strict=True):
        p.box(f"bumper{sgn:+.0f}", "car", Material.PLASTIC, trim, (x, 0.0, z), extent)
        plate_x = x + sgn * (BUMPER_M / 2 + 0.008)
        p.box(f"plate{sgn:+.0f}", "car", Material.PLAIN, PLATE, (plate_x, 0.0, z0 + 0.16), (0.006, 0.26, 0.06))
    lamp_z = zh - 0.10
    # The lights and grille on the flat of each end, inside its rounded corners.
    face_front, face_rear = outline.plan_half_width(front), outline.plan_half_width(rear)
    lamp_half = min(0.14, 0.3 * face_front)
    for sgn in (-1.0, 1.0):
        p.box(f"headlight{sgn:+.0f}", "car", Material.CHROME, HEADLIGHT,
              (front + 0.004, sgn * (face_front - lamp_half - 0.01), lamp_z), (0.01, lamp_half, 0.05),
              glow=LAMP_GLOW)  # fmt: skip
        tail_z = (zb - 0.14) if kind != "van" else (z0 + 0.45)
        tail_half = min(0.13, 0.3 * face_rear)
        p.box(f"taillight{sgn:+.0f}", "car", Material.PLASTIC, TAIL_LIGHT,
              (rear - 0.004, sgn * (face_rear - tail_half - 0.01), tail_z), (0.01, tail_half, 0.05),
              glow=LAMP_GLOW)  # fmt: skip
    grille_half = face_front - 2.0 * lamp_half - 0.04
    p.box("grille", "car", Material.PLASTIC, TRIM, (front + 0.003, 0.0, lamp_z - 0.02), (0.01, grille_half, 0.06))
    base = shape.wheelbase * length
    axle_x = ((front + rear) / 2 + base / 2 - 0.05 * length * (shape.hood - 0.2), 0.0)
    axle_x = (axle_x[0], axle_x[0] - base)
    wheel_w = 0.2
    axles = _axle_pairs(axle_x, hy - wheel_w / 2 - 0.005, g + radius)
    for x in axle_x:
        for sgn in (-1.0, 1.0):
            arch = [(x + (radius + 0.06) * c, g + radius + (radius + 0.06) * s) for c, s in circle(12)[:7]]
            on_side = [(ax, sgn * (outline.surface_half_width(ax, az) + 0.003), az) for ax, az in arch]
            p.panel(f"arch{x:+.1f}{sgn:+.0f}", "car", Material.RUBBER, TRIM, on_side if sgn < 0 else on_side[::-1])
    if p.fine:
        for sgn in (-1.0, 1.0):
            p.box(f"mirror{sgn:+.0f}", "car", Material.PAINT, paint, (x_ws - 0.08, sgn * (side + 0.02), zb + 0.08),
                  (0.05, 0.025, 0.05))  # fmt: skip
            y = sgn * (outline.surface_half_width(x_ws - 0.5, zb - 0.12) + 0.004)
            p.box(f"handle{sgn:+.0f}", "car", Material.CHROME, CHROME_TINT, (x_ws - 0.5, y, zb - 0.12),
                  (0.08, 0.006, 0.015))  # fmt: skip
    return Vehicle(p.build(), wheel(radius, wheel_w, level), axles, radius)


def truck(half: Vec3, rng: np.random.Generator, level: int = 0, *, below: float = 0.0) -> Vehicle:
    """A rigid box truck: a cab with a windscreen and side windows, a cargo box, a chassis and
    three axles."""
    hx, hy, hz = (float(h) for h in half)
    height = 2 * hz + below
    g = -hz - below
    p = Parts(level)
    cab_paint = pick_weighted(CAR_PAINTS, rng)
    box_paint = _TRUCK_BOXES[int(rng.integers(0, len(_TRUCK_BOXES)))]
    radius = min(0.50, 0.14 * height)
    cab_len = min(2.2, 0.3 * 2 * hx)
    front, rear = hx, -hx
    cab_back = front - cab_len
    z_frame = g + radius + 0.25
    p.span(
        "chassis",
        "truck",
        Material.METAL,
        TRIM,
        (rear + 0.3, -hy + 0.35, g + radius * 0.8),
        (front - 0.2, hy - 0.35, z_frame),
    )
    cab_top = g + 0.78 * height
    cab = [(cab_back, z_frame), (front - 0.02, z_frame), (front, z_frame + 0.3), (front, cab_top - 0.55),
           (front - 0.25, cab_top), (cab_back, cab_top)]  # fmt: skip
    p.prism("cab", "truck", Material.PAINT, cab_paint, cab, -hy + 0.02, hy - 0.02)
    ws = [(front + 0.005, -hy + 0.15, cab_top - 0.58), (front + 0.005, hy - 0.15, cab_top - 0.58),
          (front - 0.22, hy - 0.15, cab_top - 0.06), (front - 0.22, -hy + 0.15, cab_top - 0.06)]  # fmt: skip
    p.panel("windscreen", "truck", Material.GLASS, GLASS_TINT, ws)
    for sgn in (-1.0, 1.0):
        y = sgn * (hy - 0.015)
        win = [(cab_back + 0.3, y, cab_top - 0.75), (front - 0.35, y, cab_top - 0.75),
               (front - 0.35, y, cab_top - 0.15), (cab_back + 0.3, y, cab_top - 0.15)]  # fmt: skip
        p.panel(f"side_window{sgn:+.0f}", "truck", Material.GLASS, GLASS_TINT, win if sgn < 0 else win[::-1])
        p.box(f"headlight{sgn:+.0f}", "truck", Material.CHROME, HEADLIGHT,
              (front + 0.005, sgn * (hy - 0.3), z_frame + 0.25), (0.01, 0.15, 0.07), glow=LAMP_GLOW)  # fmt: skip
    p.box("grille", "truck", Material.PLASTIC, TRIM, (front + 0.004, 0.0, z_frame + 0.6), (0.01, hy - 0.5, 0.3))
    p.box("bumper", "truck", Material.PLASTIC, TRIM, (front - 0.08, 0.0, z_frame + 0.05), (0.08, hy - 0.05, 0.15))
    box_front, box_bottom = cab_back - 0.1, z_frame + 0.05
    # A box body is panels between aluminium posts and rails, not one slab: a plain white
    # block is what a street model calls a wall.
    p.span("cargo", "truck", Material.METAL, box_paint, (rear, -hy + 0.03, box_bottom), (box_front, hy - 0.03, hz))
    for sgn in (-1.0, 1.0):
        y = sgn * (hy - 0.02)
        for rail, z0, z1 in (("top", hz - 0.1, hz), ("bottom", box_bottom, box_bottom + 0.2)):
            p.span(f"{rail}_rail{sgn:+.0f}", "truck", Material.METAL, RAIL, (rear, y - 0.02, z0),
                   (box_front, y + 0.02, z1))  # fmt: skip
    if p.fine:
        for sgn in (-1.0, 1.0):
            y = sgn * (hy - 0.02)
            p.box(f"mirror{sgn:+.0f}", "truck", Material.PLASTIC, TRIM, (front - 0.3, sgn * (hy - 0.03), cab_top - 0.5),
                  (0.04, 0.025, 0.2))  # fmt: skip
            n_posts = max(2, round((box_front - rear) / 0.6))
            for k in range(1, n_posts):
                x = rear + (box_front - rear) * k / n_posts
                p.span(f"post{k}{sgn:+.0f}", "truck", Material.METAL, RAIL, (x - 0.03, y - 0.015, box_bottom + 0.2),
                       (x + 0.03, y + 0.015, hz - 0.1))  # fmt: skip
            # The side guard between the front axle and the rear ones, 10 cm inside the box.
            guard_y = sgn * (hy - 0.12)
            for z in (g + 0.45, g + 0.72):
                p.span(f"guard{z:.2f}{sgn:+.0f}", "truck", Material.METAL, RAIL,
                       (rear + REAR_AXLES_M[0] + radius + 0.1, guard_y - 0.02, z - 0.03),
                       (front - cab_len + 0.3, guard_y + 0.02, z + 0.03))  # fmt: skip
            x, z = rear - 0.01, (box_bottom + hz) / 2 + 0.05
            p.box(f"lock_bar{sgn:+.0f}", "truck", Material.CHROME, CHROME_TINT, (x, sgn * 0.35, z),
                  (0.01, 0.02, (hz - box_bottom) / 2 - 0.2))  # fmt: skip
        p.box("rear_door_seam", "truck", Material.METAL, (0.5, 0.5, 0.5), (rear - 0.004, 0.0, (z_frame + hz) / 2),
              (0.006, 0.02, (hz - z_frame) / 2 - 0.1))  # fmt: skip
        p.span("underride_bar", "truck", Material.METAL, TRIM, (rear + 0.05, -hy + 0.15, g + 0.4),
               (rear + 0.2, hy - 0.15, g + 0.55))  # fmt: skip
    for sgn in (-1.0, 1.0):
        p.box(f"tail_light{sgn:+.0f}", "truck", Material.PLASTIC, TAIL_LIGHT,
              (rear - 0.01, sgn * (hy - 0.25), g + 0.75), (0.01, 0.12, 0.06), glow=LAMP_GLOW)  # fmt: skip
    axles = _axle_pairs((front - 0.6 * cab_len, *(rear + x for x in REAR_AXLES_M)), hy - 0.17, g + radius)
    return Vehicle(p.build(), wheel(radius, 0.3, level, "truck"), axles, radius)


def bus(half: Vec3, rng: np.random.Generator, level: int = 0, *, below: float = 0.0) -> Vehicle:
    """A city bus: a long body in its livery, a band of side windows, a windscreen and doors,
    two axles."""
    hx, hy, hz = (float(h) for h in half)
    height = 2 * hz + below
    g = -hz - below
    p = Parts(level)
    livery = BUS_LIVERIES[int(rng.integers(0, len(BUS_LIVERIES)))]
    radius = min(0.50, 0.16 * height)
    z0 = g + 0.3
    # The body above the wheel arches, and the skirt between them: a bus shows its wheels in
    # arches, which a tram or a wall does not.
    arch_top, arch_half = g + 2 * radius + 0.08, radius + BUS_ARCH_GAP_M
    wheel_xs = (hx - 2.6, -hx + 3.2)
    body = [(-hx, arch_top), (hx, arch_top), (hx, hz - 0.15), (hx - 0.15, hz), (-hx + 0.1, hz), (-hx, hz - 0.1)]
    p.prism("body", "bus", Material.PAINT, livery, body, -hy + 0.02, hy - 0.02)
    edges = (-hx, *(e for x in sorted(wheel_xs) for e in (x - arch_half, x + arch_half)), hx)
    for k, (x0, x1) in enumerate(zip(edges[::2], edges[1::2], strict=True)):
        p.span(f"skirt{k}", "bus", Material.PAINT, livery, (x0, -hy + 0.02, z0), (x1, hy - 0.02, arch_top))
    # Each arch is round over its wheel: the skirt's corners above the arc filled in, as fans
    # from each corner of the well's opening (a tram's skirt is straight).
    axle_z = g + radius
    top_angle = math.asin(min((arch_top - axle_z) / arch_half, 1.0))
    arc = [(math.cos(top_angle * k / 4), math.sin(top_angle * k / 4)) for k in range(5)]
    for x in wheel_xs:
        p.span(f"wheel_well{x:+.1f}", "bus", Material.PLASTIC, TRIM, (x - arch_half, -hy + 0.35, z0),
               (x + arch_half, hy - 0.35, arch_top))  # fmt: skip
        for side in (-1.0, 1.0):  # the well's back corner, then its front one
            corner = (x + side * arch_half, arch_top)
            rim = [(x + side * arch_half * c, axle_z + arch_half * s) for c, s in arc]  # ends on the skirt's top
            for sgn in (-1.0, 1.0):
                y = sgn * (hy - 0.02 + 0.003)
                wound = rim[::-1] if (side > 0) != (sgn < 0) else rim  # counter-clockwise seen from outside
                fan = [(ax, y, az) for ax, az in (corner, *wound)]
                p.panel(f"arch{x:+.1f}{side:+.0f}{sgn:+.0f}", "bus", Material.PAINT, livery, fan)
    belt, top = g + 0.42 * height, hz - 0.3
    ws = [(hx + 0.005, -hy + 0.12, belt - 0.3), (hx + 0.005, hy - 0.12, belt - 0.3),
          (hx + 0.005, hy - 0.12, top + 0.15), (hx + 0.005, -hy + 0.12, top + 0.15)]  # fmt: skip
    p.panel("windscreen", "bus", Material.GLASS, GLASS_TINT, ws)
    for sgn in (-1.0, 1.0):
        # Flush glazing, as a city bus has: the windows in a black surround wider than the
        # glass, black pillars between them (painted pillars in a band of glass read as a
        # tram's side to the Cityscapes judge: docs/realism.md).
        y = sgn * (hy - 0.017)
        x0, x1 = -hx + 0.5 - BUS_GLAZING_SURROUND_M, hx - 0.4 + BUS_GLAZING_SURROUND_M
        z_a, z_b = belt - 0.05, top + 0.08
        surround = [(x0, y, z_a), (x1, y, z_a), (x1, y, z_b), (x0, y, z_b)]
        p.panel(f"glazing_surround{sgn:+.0f}", "bus", Material.PLASTIC, TRIM, surround if sgn < 0 else surround[::-1])
        y = sgn * (hy - 0.015)
        band = [(-hx + 0.5, y, belt), (hx - 0.4, y, belt), (hx - 0.4, y, top), (-hx + 0.5, y, top)]
        p.panel(f"windows{sgn:+.0f}", "bus", Material.GLASS, GLASS_TINT, band if sgn < 0 else band[::-1])
        if p.fine:
            for k in range(1, int((2 * hx - 0.9) / 1.4)):
                x = -hx + 0.5 + 1.4 * k
                p.box(f"mullion{k}{sgn:+.0f}", "bus", Material.PAINT, TRIM, (x, y + sgn * 0.004, (belt + top) / 2),
                      (0.04, 0.006, (top - belt) / 2))  # fmt: skip
        p.box(f"headlight{sgn:+.0f}", "bus", Material.CHROME, HEADLIGHT, (hx + 0.005, sgn * (hy - 0.3), z0 + 0.35),
              (0.01, 0.15, 0.07), glow=LAMP_GLOW)  # fmt: skip
    for x in (hx - 1.4, -0.5):  # doors on the kerb side (right-hand traffic: −y)
        y = -(hy - 0.01)
        door = [(x - 0.6, y, z0 + 0.05), (x + 0.6, y, z0 + 0.05), (x + 0.6, y, top), (x - 0.6, y, top)]
        p.panel(f"door{x:+.1f}", "bus", Material.GLASS, (0.16, 0.18, 0.20), door)
    p.box("bumper", "bus", Material.PLASTIC, TRIM, (hx - 0.06, 0.0, z0 + 0.1), (0.07, hy - 0.04, 0.12))
    back = [(-hx - 0.005, hy - 0.2, belt + 0.3), (-hx - 0.005, -hy + 0.2, belt + 0.3),
            (-hx - 0.005, -hy + 0.2, top), (-hx - 0.005, hy - 0.2, top)]  # fmt: skip
    p.panel("rear_window", "bus", Material.GLASS, GLASS_TINT, back)
    p.box("rear_bumper", "bus", Material.PLASTIC, TRIM, (-hx + 0.06, 0.0, z0 + 0.1), (0.07, hy - 0.04, 0.12))
    for sgn in (-1.0, 1.0):
        p.box(f"tail_light{sgn:+.0f}", "bus", Material.PLASTIC, TAIL_LIGHT, (-hx - 0.005, sgn * (hy - 0.2), z0 + 0.5),
              (0.01, 0.1, 0.2), glow=LAMP_GLOW)  # fmt: skip
    p.box("destination", "bus", Material.PLASTIC, (0.9, 0.6, 0.1), (hx + 0.004, 0.0, top + 0.02), (0.01, hy - 0.4, 0.1),
          glow=LAMP_GLOW)  # fmt: skip
    axles = _axle_pairs(wheel_xs, hy - 0.17, g + radius)
    return Vehicle(p.build(), wheel(radius, 0.3, level, "bus"), axles, radius)
