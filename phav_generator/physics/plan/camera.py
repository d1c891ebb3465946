"""Where the camera starts: the recipe's C_xyz and T_xyz, put on the protagonist's actual
first pose, moved out of the environment's walls and turned to see past what stands between
it and the protagonist; what a spring camera's target holds on to."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from phav_generator.motion.rotations import quat_to_matrix
from phav_generator.motion.skeleton import BONE_INDEX
from phav_spec.recipe import Recipe
from phav_spec.scene import ENVIRONMENT_SCENES, Collider

if TYPE_CHECKING:
    from phav_generator.physics.plan.scene_plan import PropPlan, StaticBox

#: Where on the protagonist a spring camera's target is tied, per camera, as weights of body
#: origins: the kite films the whole body around the pelvis; the close-up aims two thirds of
#: the way from the chest's origin to the head's (the neck), about 0.77 of the body's height
#: standing, so that the head, the hand brushing it and the hand hanging by the hip share the frame.
ANCHOR_WEIGHTS: dict[str, dict[str, float]] = {"kite": {"pelvis": 1.0}, "closeup": {"chest": 1 / 3, "head": 2 / 3}}


def anchor_point(kind: str, body_pos: np.ndarray) -> np.ndarray:
    """The point a ``kind`` camera's target spring holds on to, from world body origins (…, 15, 3)."""
    weights = ANCHOR_WEIGHTS[kind]
    body_pos = np.asarray(body_pos)
    return sum(w * body_pos[..., BONE_INDEX[b], :] for b, w in weights.items())


#: How far towards the partner's anchor (a share of the way) the camera's target is held.
PARTNER_PULL = 0.5


def camera_anchor(kind: str, protagonist_pos: np.ndarray, partner_pos: np.ndarray | None = None) -> np.ndarray:
    """The point a ``kind`` camera's target holds on to: the protagonist's anchor, or, for
    two people walking into each other (``partner_pos`` given), ``PARTNER_PULL`` of the way
    from it to the partner's, so that the camera frames the pair (on the protagonist alone,
    a partner 4–8 m off is out of the frame until they meet, and beside it at arm's length
    after). The view still keeps the protagonist's own anchor in the frame (``keep_in_view``)."""
    anchor = anchor_point(kind, protagonist_pos)
    if partner_pos is None:
        return anchor
    return anchor + PARTNER_PULL * (anchor_point(kind, partner_pos) - anchor)


def framed_partner(recipe: Recipe) -> bool:
    """Whether the camera frames the protagonist's partner with it (``camera_anchor``)."""
    return bool(recipe.supporting_characters) and recipe.supporting_characters[0].placement == "facing"


#: How far (m) a camera start inside something is first lifted to clear it.
LIFT_M = 1.0


def _inside(colliders, point: np.ndarray, clearance: float, floor: float = -np.inf) -> bool:
    x, y, z = (float(v) for v in point)
    return z < floor + clearance or any(
        c.xy_distance(x, y) < clearance and c.bottom - clearance < z < c.top + clearance for c in colliders
    )


@dataclass(frozen=True)
class Blocker:
    """A box that can stand between the camera and the protagonist: centre, half sizes and
    its three axes in world coordinates (a point's k-th local coordinate is axis k · (p −
    centre)), all in plain floats."""

    center: tuple[float, float, float]
    half: tuple[float, float, float]
    axes: tuple[tuple[float, float, float], ...]

    @classmethod
    def of(cls, center: Sequence[float], half: Sequence[float], rotation: np.ndarray) -> Blocker:
        """From a centre, half sizes and a (3, 3) rotation whose columns are the box's axes."""
        r = np.asarray(rotation, dtype=np.float64)
        axes = tuple(tuple(float(v) for v in r[:, k]) for k in range(3))
        return cls(tuple(float(v) for v in center), tuple(float(v) for v in half[:3]), axes)  # type: ignore[arg-type]

    @classmethod
    def turned(cls, center: Sequence[float], half: Sequence[float], yaw_deg: float) -> Blocker:
        """A box turned by ``yaw_deg`` about +z (a collider's or an action's static box)."""
        c, s = math.cos(math.radians(yaw_deg)), math.sin(math.radians(yaw_deg))
        return cls.of(center, half, np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]))

    def crosses(self, a: Sequence[float], b: Sequence[float]) -> bool:
        """Whether the segment a → b passes through the box."""
        return self.span(a, b) is not None

    def span(self, a: Sequence[float], b: Sequence[float]) -> tuple[float, float] | None:
        """Where the segment a → b is inside the box, as the fractions of the way from a
        where it enters and leaves (slab test in the box's frame); None if it misses it.

        Written in Python floats, not numpy products, so the answer cannot depend on the
        machine's BLAS kernels."""
        t0, t1 = 0.0, 1.0
        for axis, h in zip(self.axes, self.half, strict=True):
            pa = sum(r * (x - c) for r, x, c in zip(axis, a, self.center, strict=True))
            pb = sum(r * (x - c) for r, x, c in zip(axis, b, self.center, strict=True))
            d = pb - pa
            if abs(d) < 1e-12:
                if abs(pa) > h:
                    return None
                continue
            u0, u1 = sorted(((-h - pa) / d, (h - pa) / d))
            t0, t1 = max(t0, u0), min(t1, u1)
            if t0 > t1:
                return None
        return t0, t1

    def reach(self, i: int) -> float:
        """How far (m) the box reaches from its centre along world axis ``i``."""
        return sum(abs(axis[i]) * h for axis, h in zip(self.axes, self.half, strict=True))

    @property
    def top(self) -> float:
        """The height (m) of the box's highest corner."""
        return self.center[2] + self.reach(2)

    def ground_extent(self, margin: float) -> tuple[float, float, float, float]:
        """(x0, y0, x1, y1): the box grown by ``margin`` on every side, as seen from above."""
        rx, ry = self.reach(0) + margin, self.reach(1) + margin
        return self.center[0] - rx, self.center[1] - ry, self.center[0] + rx, self.center[1] + ry

    def raised(self, by: float) -> Blocker:
        """The box with its top ``by`` metres higher: the axis nearest the vertical grown by
        ``by`` / 2 each way and its centre moved up as much."""
        k = max(range(3), key=lambda i: abs(self.axes[i][2]))
        up = math.copysign(by / 2.0, self.axes[k][2])
        center = tuple(c + a * up for c, a in zip(self.center, self.axes[k], strict=True))
        half = tuple(h + by / 2.0 if i == k else h for i, h in enumerate(self.half))
        return Blocker(center, half, self.axes)  # type: ignore[arg-type]

    def holds(self, point: Sequence[float], margin: float = 0.0) -> bool:
        """Whether ``point`` lies inside the box grown by ``margin`` on every side."""
        return all(
            abs(sum(r * (x - c) for r, x, c in zip(axis, point, self.center, strict=True))) <= h + margin
            for axis, h in zip(self.axes, self.half, strict=True)
        )


#: A line of sight ends this far (m) short of the anchor: a box the protagonist stands,
#: sits or leans in does not count as standing between.
SIGHT_END_M = 0.3
#: The smallest lever (1 − t) ``sight_lift`` divides by: a box at the line's end.
SIGHT_LEVER_MIN = 0.25
#: The turns (degrees about the vertical through the target) tried for a clear view, nearest
#: first, the opposite view last.
SIGHT_TURNS_DEG = (*(s * 10.0 * k for k in range(1, 18) for s in (1.0, -1.0)), 180.0)


def sees(start: Sequence[float], target: Sequence[float], blockers: Sequence[Blocker]) -> bool:
    """Whether nothing in ``blockers`` stands on the line from ``start`` to ``target``."""
    a, b = [float(x) for x in start], [float(x) for x in target]
    length = math.dist(a, b)
    if length <= SIGHT_END_M:
        return True
    k = (length - SIGHT_END_M) / length
    end = [x + (y - x) * k for x, y in zip(a, b, strict=True)]
    return not any(box.crosses(a, end) for box in blockers)


def sight_lift(eye: Sequence[float], target: Sequence[float], blocker: Blocker, margin: float) -> float:
    """How far (m) the camera at ``eye`` must rise for its line to ``target`` (ending
    ``SIGHT_END_M`` short of it, as in ``sees``) to pass ``margin`` over ``blocker``'s top;
    0 where the line misses the box raised by ``margin``. The line is lowest inside that box
    where it enters or leaves it; raising the eye alone lifts the point a fraction t of the
    way by 1 − t of it. What a camera spring pulls towards, the camera ceasing to rise once
    the line clears the box by ``margin``."""
    a, b = [float(x) for x in eye], [float(x) for x in target]
    length = math.dist(a, b)
    if length <= SIGHT_END_M:
        return 0.0
    k = (length - SIGHT_END_M) / length
    end = [x + (y - x) * k for x, y in zip(a, b, strict=True)]
    span = blocker.raised(margin).span(a, end)
    if span is None:
        return 0.0
    over = blocker.top + margin
    # A line ending inside the box (the protagonist against it) asks at most a few times
    # its own shortfall of the eye, not an unbounded lift.
    return max((over - (a[2] + t * (end[2] - a[2]))) / max(1.0 - t, SIGHT_LEVER_MIN) for t in span)


def sight_boxes(prop: PropPlan) -> tuple[tuple[tuple[float, float, float], tuple[float, float, float]], ...]:
    """The boxes (centre, half size, in its shape's frame) of a prop that can stand between
    a camera and the protagonist: the bounds of each convex hull it collides as (a car's
    body below the belt, its greenhouse, its bumpers), or its box; a car's one box reaches
    its roof over the hood, where a body thrown onto it is in plain view."""
    if not prop.hulls:
        return (((0.0, 0.0, 0.0), tuple(float(v) for v in prop.size[:3])),)  # type: ignore[return-value]
    return hull_bounds(prop.hulls)


def hull_bounds(
    hulls: Sequence[Sequence[Sequence[float]]],
) -> tuple[tuple[tuple[float, float, float], tuple[float, float, float]], ...]:
    """Each convex hull's bounds (centre, half size) in the frame its corners are given in,
    in Python floats."""
    out = []
    for corners in hulls:
        lo = [min(float(q[k]) for q in corners) for k in range(3)]
        hi = [max(float(q[k]) for q in corners) for k in range(3)]
        centre = tuple((a + b) / 2.0 for a, b in zip(lo, hi, strict=True))
        out.append((centre, tuple((b - a) / 2.0 for a, b in zip(lo, hi, strict=True))))
    return tuple(out)  # type: ignore[arg-type]


def stands_free(prop: PropPlan) -> bool:
    """Whether a prop can stand between camera and protagonist: a box no one holds (a door's
    leaf, a pushed load, a car), not a held tool."""
    return prop.shape == "box" and not prop.grips


def hidden(start: Sequence[float], anchors: Sequence[Sequence[float]], blockers: Sequence[Blocker]) -> int:
    """How many of ``anchors`` (points on the protagonist's planned path) something hides
    from ``start``."""
    return sum(not sees(start, a, blockers) for a in anchors)


def clear_camera_start(
    recipe: Recipe,
    clearance: float = 0.25,
    *,
    shift: np.ndarray | None = None,
    blockers: Sequence[Blocker] = (),
    anchors: Sequence[Sequence[float]] = (),
    keep_out: Sequence[Blocker] = (),
) -> tuple[float, float, float]:
    """The camera's start, moved clear of the environment's geometry: lifted, or slid
    towards its target; then, if something in ``blockers`` stands between it and the
    protagonist's planned path ``anchors`` (the span its camera must see), or it stands in
    ``keep_out`` (where a driven car or load will pass), turned about the vertical through
    the target to the nearest free view that hides fewest of them.

    The sampler places C_xyz around the protagonist without looking at the geometry, so a
    start inside something is moved, deterministically, up to ``LIFT_M`` straight up (over
    the ground, a bench or a car; never into or over a box above the target's height, a
    ceiling) or else to the first point on the segment to the target (through a wall), in
    5 cm steps, to the first with ``clearance`` metres of room.
    ``shift`` moves camera and target together first (a spring camera's rig put on the
    protagonist's actual first pose): a rig lowered onto a seated or lying body can put the
    camera into the ground, where the slide would end on the body itself.

    The turn keeps the sampled distance and height to the target (only the azimuth
    changes; a start lifted clear keeps its lifted height) and takes, of
    ``SIGHT_TURNS_DEG`` whose start is free, the nearest that hides fewest anchors, if
    fewer than the start does; a start that sees every anchor stays as it is. The recipe
    keeps the sampled C_xyz: the plan departs from it only where it is blocked, as it does
    where a start is inside a wall.
    """
    env = ENVIRONMENT_SCENES[recipe.environment.name]
    colliders, floor = env.colliders, float(getattr(env, "ground_z", 0.0))
    offset = np.zeros(3) if shift is None else np.asarray(shift, dtype=np.float64)
    start = np.array(recipe.camera.position, dtype=np.float64) + offset
    target = np.array(recipe.camera.target, dtype=np.float64) + offset
    cleared = _cleared(colliders, floor, start, target, clearance)
    best, fewest = cleared, hidden(cleared, anchors, blockers)
    in_the_way = any(box.holds(cleared, clearance) for box in keep_out)
    dx, dy = float(start[0] - target[0]), float(start[1] - target[1])
    # A start lifted out of the ground or a bench turns at the height it was lifted to.
    height = max(float(start[2]), float(cleared[2]))
    for turn in SIGHT_TURNS_DEG:
        if fewest == 0 and not in_the_way:
            break
        c, s = math.cos(math.radians(turn)), math.sin(math.radians(turn))
        turned = (float(target[0]) + c * dx - s * dy, float(target[1]) + s * dx + c * dy, height)
        if _inside(colliders, np.array(turned), clearance, floor) or any(b.holds(turned, clearance) for b in keep_out):
            continue
        n = hidden(turned, anchors, blockers)
        if in_the_way or n < fewest:
            best, fewest, in_the_way = turned, n, False
    return best


def _cleared(
    colliders, floor: float, start: np.ndarray, target: np.ndarray, clearance: float
) -> tuple[float, float, float]:
    """``start`` lifted, or slid towards ``target``, to the first point ``clearance`` clear.
    The lift rises out of what holds the start from below (the ground, a bench, a car), not
    into or over a box above the target's height (a ceiling, a lamp, a canopy): there it
    would end on the roof, filming the slab, and the start slides instead."""
    x, y = float(start[0]), float(start[1])
    above = [c.bottom for c in colliders if c.bottom > float(target[2]) and c.xy_distance(x, y) < clearance]
    roof = min(above, default=math.inf) - clearance  # the lift stays below it
    for j in range(round(LIFT_M / 0.05) + 1):
        lifted = start + np.array([0.0, 0.0, 0.05 * j])
        if float(lifted[2]) > roof:  # a start already above it (j = 0) slides too
            break
        if not _inside(colliders, lifted, clearance, floor):
            return (float(lifted[0]), float(lifted[1]), float(lifted[2]))
    length = float(np.linalg.norm(target - start))
    steps = max(1, int(length / 0.05))
    for k in range(steps + 1):
        point = start + (target - start) * (k / steps)
        if not _inside(colliders, point, clearance, floor):
            return (float(point[0]), float(point[1]), float(point[2]))
    return tuple(float(v) for v in target)  # type: ignore[return-value]


#: How far (m) beside a car's path its lane keeps the camera: a car's width and more, as a
#: camera films a stunt from beside the road, so the car passes in view instead of filling
#: the frame with a door at arm's length. Where no turn of the start clears it (a kite as
#: close to its target as this), the narrower ``LANE_MARGIN_MIN_M`` is kept, as it is beside
#: a pushed load.
LANE_MARGIN_M = 2.5
LANE_MARGIN_MIN_M = 0.5


def driven_lanes(props: Sequence[PropPlan], margin: float | None = None) -> tuple[Blocker, ...]:
    """Where each driven prop (a car, a pushed load) passes over the clip: a box round its
    path, from its first position to the last it can reach (``PropPlan.lane_end``), as wide
    and tall as the prop plus ``margin`` each side, which a camera should not start in
    (by default ``LANE_MARGIN_M`` for a car, ``LANE_MARGIN_MIN_M`` for a pushed load)."""
    out = []
    for prop in props:
        if prop.path is None or prop.shape != "box":
            continue
        last = -1 if prop.lane_end is None else prop.lane_end
        (x0, y0, z0), (x1, y1, z1) = (tuple(float(v) for v in prop.path[k]) for k in (0, last))
        run = math.hypot(x1 - x0, y1 - y0)
        heading = math.atan2(y1 - y0, x1 - x0) if run > 1e-9 else 0.0
        rot = quat_to_matrix(np.asarray(prop.quat, dtype=np.float64)).tolist()
        # How far the prop reaches along, across and up its path (Python floats, as `crosses`).
        directions = (
            (math.cos(heading), math.sin(heading), 0.0),
            (-math.sin(heading), math.cos(heading), 0.0),
            (0.0, 0.0, 1.0),
        )
        reach = [
            sum(abs(sum(u[i] * rot[i][k] for i in range(3))) * float(prop.size[k]) for k in range(3))
            for u in directions
        ]
        room = margin if margin is not None else LANE_MARGIN_M if prop.object == "car" else LANE_MARGIN_MIN_M
        half = (run / 2 + reach[0] + room, reach[1] + room, reach[2] + room)
        out.append(Blocker.turned(((x0 + x1) / 2, (y0 + y1) / 2, (z0 + z1) / 2), half, math.degrees(heading)))
    return tuple(out)


def sight_plants(colliders: Sequence[Collider]) -> tuple[Blocker, ...]:
    """The low plants among an environment's colliders (hedges, shrubs, a reed bed: its
    ``vegetation`` boxes, none as tall as a person), which a spring camera rises over as
    over a car where they stand between it and its anchor."""
    return tuple(Blocker.turned(c.center, c.half_size, c.yaw_deg) for c in colliders if c.pixel_class == "vegetation")


def collider_blockers(c: Collider | StaticBox) -> tuple[Blocker, ...]:
    """What of a static collider or an action's box can hide the protagonist: the bounds of
    each hull it collides as (a parked car's body below the belt, its greenhouse, its
    bumpers: not the air over its hood), or its box."""
    hulls = getattr(c, "hulls", ())
    if not hulls:
        return (Blocker.turned(c.center, c.half_size, c.yaw_deg),)
    cos, sin = math.cos(math.radians(c.yaw_deg)), math.sin(math.radians(c.yaw_deg))
    out = []
    for (lx, ly, lz), half in hull_bounds(hulls):
        centre = (c.center[0] + lx * cos - ly * sin, c.center[1] + lx * sin + ly * cos, c.center[2] + lz)
        out.append(Blocker.turned(centre, half, c.yaw_deg))
    return tuple(out)


def view_blockers(
    colliders: Sequence[Collider], boxes: Sequence[StaticBox], props: Sequence[PropPlan]
) -> tuple[Blocker, ...]:
    """What can hide the protagonist from a camera's start: the environment's colliders (a
    parked car as its hulls, ``collider_blockers``), the action's static boxes and every
    prop no one holds (a door's leaf, a pushed load, a car) at its first pose, as the boxes
    a spring camera rises over (``sight_boxes``)."""
    out = [blocker for c in (*colliders, *boxes) for blocker in collider_blockers(c)]
    for prop in filter(stands_free, props):
        rot = quat_to_matrix(np.asarray(prop.quat, dtype=np.float64))
        for c, half in sight_boxes(prop):
            local = [float(o) + float(v) for o, v in zip(prop.offset, c, strict=True)]
            centre = [float(p) + sum(float(r) * o for r, o in zip(row, local, strict=True))
                      for p, row in zip(prop.pos, rot, strict=True)]  # fmt: skip
            out.append(Blocker.of(centre, half, rot))
    return tuple(out)
