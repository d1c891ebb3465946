"""A person whose animated path runs into an obstacle is let go as its body reaches it.

The pins and muscles follow the motion wherever it goes; where it goes through a building
or a planter, they drive the body into the box until MuJoCo throws it out (a joint at 20 to
40 m/s, the body a metre inside a wall, the camera chasing it). Let go at the obstacle, the
body meets it as a ragdoll: it hits or trips, falls and stays outside.
"""

from __future__ import annotations

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
