"""What stands in the way: a person whose animated path runs into an obstacle is let go as
its body reaches it, and a driven box (a car, a pushed load) slides only as far as it is clear.

The pins and muscles follow the motion wherever it goes; where it goes through a building
or a planter, they drive the body into the box until MuJoCo throws it out (a joint at 20 to
40 m/s, the body a metre inside a wall, the camera chasing it). Let go at the obstacle, the
body meets it as a ragdoll: it hits or trips, falls and stays outside.
"""

from __future__ import annotations

import math

import numpy as np

from phav_generator.physics.plan.builder import PlanBuilder
from phav_generator.physics.plan.people import release
from phav_generator.physics.plan.scene_plan import PersonPlan
from phav_spec.scene import ENVIRONMENT_SCENES, WALKABLE_PIXEL_CLASSES, Collider

#: The body as a column round the animated pelvis: from the feet (the pelvis's standing
#: height below it) to the chest, and how near an obstacle's face (m) its axis may come
#: before the body is let go (about a torso's half depth).
CHEST_ABOVE_PELVIS_M = 0.3
REACH_M = 0.25
#: What a foot steps over or onto: a box whose top is at most this far above the feet (a
#: kerb, a terrace's edge) is no obstacle, and walkable classes never are.
STEP_OVER_M = 0.3
#: How long before the body reaches an obstacle it is let go (s): the release ramps over
#: ``people.RELEASE_RAMP_S``, done by the time of contact.
LEAD_S = 0.1
#: Colliders whose top lies within this (m) of the ground a driven prop moves on carry it.
SUPPORT_TOLERANCE_M = 0.02


def obstacles(environment: str) -> list[Collider]:
    """The colliders of ``environment`` a body can run into: every one but the walkable."""
    return [c for c in ENVIRONMENT_SCENES[environment].colliders if c.pixel_class not in WALKABLE_PIXEL_CLASSES]


def first_contact(b: PlanBuilder, p: PersonPlan) -> int | None:
    """The first physics step at which ``p``'s animated body column comes within
    ``REACH_M`` of an obstacle taller than a step over its feet (None if it never does, or
    starts there: placement keeps waypoints clear)."""
    root = p.targets.root_pos
    feet = root[:, 2] - p.dims.standing_pelvis_height
    chest = root[:, 2] + CHEST_ABOVE_PELVIS_M
    near = np.zeros(len(root), dtype=bool)
    for c in obstacles(b.recipe.environment.name):
        # squared distances (the box's frame from math's cos and sin): no CPU-dispatched
        # transcendental decides a step
        gx, gy = c.xy_gaps(root[:, 0], root[:, 1])
        near |= (gx * gx + gy * gy <= REACH_M**2) & (c.bottom < chest) & (c.top > feet + STEP_OVER_M)
    hits = np.flatnonzero(near)
    if hits.size == 0 or hits[0] == 0:
        return None
    return int(hits[0])


def let_go_at_obstacles(b: PlanBuilder, p: PersonPlan) -> PersonPlan:
    """``p`` released ``LEAD_S`` before its body first reaches an obstacle; unchanged if it
    never does (or is not simulated)."""
    if not p.physical:
        return p
    step = first_contact(b, p)
    if step is None:
        return p
    return release(p, b.times, max(float(b.times[step]) - LEAD_S, 0.0))


def clear_run(
    colliders: tuple[Collider, ...], centre: tuple[float, float], travel: tuple[float, float],
    half: tuple[float, float, float], bottom: float, ground: float, *, raised: bool,
) -> tuple[float, float]:  # fmt: skip
    """How far (m) a box of ``half`` extents, its bottom at height ``bottom`` and centred on
    ``centre`` seen from above, can slide back against the unit ``travel`` direction and on
    along it before it meets a collider (or, on ``raised`` ground, leaves the walkable
    colliders whose top is ``ground``, as ``support_height`` finds ground); −inf both ways
    where it meets one where it stands. In Python floats: a driven prop's way (a car's, a
    pushed load's) cannot depend on the machine's vector kernels."""
    hx, hy, hz = (float(h) for h in half)
    top = bottom + 2.0 * hz
    back = ahead = math.inf
    carried: list[tuple[list[tuple[float, float]], ...]] = []
    for c in colliders:
        corners = [_along(p, centre, travel) for p in c.footprint()]
        if raised and c.pixel_class in WALKABLE_PIXEL_CLASSES and abs(c.top - ground) <= SUPPORT_TOLERANCE_M:
            carried.append(tuple(_band(corners, w - 1e-6, w + 1e-6) for w in (-hy, 0.0, hy)))
        if c.top <= bottom or c.bottom >= top:
            continue
        inside = _band(corners, -hy, hy)
        if not inside:
            continue
        lo, hi = min(u for u, _ in inside), max(u for u, _ in inside)
        if lo < hx and hi > -hx:
            return -math.inf, -math.inf
        if hi <= -hx:
            back = min(back, -hi - hx)
        else:
            ahead = min(ahead, lo - hx)
    if raised:
        # Each of the car's sides and its middle line stays over the ground it drives on.
        for line in range(3):
            spans = sorted(
                (min(u for u, _ in part), max(u for u, _ in part)) for parts in carried if (part := parts[line])
            )
            merged: list[list[float]] = []
            for a, b in spans:
                if merged and a <= merged[-1][1] + SUPPORT_TOLERANCE_M:
                    merged[-1][1] = max(merged[-1][1], b)
                else:
                    merged.append([a, b])
            under = [(a, b) for a, b in merged if a <= -hx and b >= hx]
            if not under:
                return -math.inf, -math.inf
            back, ahead = min(back, -under[0][0] - hx), min(ahead, under[0][1] - hx)
    return back, ahead


def _along(point: tuple[float, float], centre: tuple[float, float], travel: tuple[float, float]) -> tuple[float, float]:
    """``point`` in the sliding box's frame seen from above: (along ``travel``, across it to the left)."""
    dx, dy = point[0] - centre[0], point[1] - centre[1]
    return dx * travel[0] + dy * travel[1], -dx * travel[1] + dy * travel[0]


def _band(polygon: list[tuple[float, float]], lo: float, hi: float) -> list[tuple[float, float]]:
    """The convex ``polygon`` clipped to the band lo ≤ across ≤ hi (Sutherland–Hodgman)."""
    out = polygon
    for bound, keep in ((lo, 1.0), (hi, -1.0)):
        points, out = out, []
        for k, (u, w) in enumerate(points):
            pu, pw = points[k - 1]
            now, before = keep * (w - bound) >= 0.0, keep * (pw - bound) >= 0.0
            if now != before:
                f = (bound - pw) / (w - pw)
                out.append((pu + f * (u - pu), bound))
            if now:
                out.append((u, w))
        if not out:
            return []
    return out
