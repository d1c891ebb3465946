"""The synthetic actions whose rule changes the ragdoll's control: dive floor (pins let go),
stagger (the pin goes slack in windows) and limp (one leg's muscles weakened)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from phav_generator.motion.skeleton import BONE_INDEX
from phav_generator.physics.plan.builder import PlanBuilder, uniform
from phav_generator.physics.plan.people import release
from phav_generator.physics.plan.scene_plan import PersonPlan
from phav_spec.seeding import stream


def dive_floor(b: PlanBuilder, p: PersonPlan) -> PersonPlan:
    """Dive floor: pins let go when the dive starts (pelvis below 75 % of standing)."""
    z = p.targets.root_pos[:, 2] - b.recipe.protagonist.position[2]
    low = np.flatnonzero(z < 0.75 * p.dims.standing_pelvis_height)
    rng = stream(b.recipe.seeds.physics, "dive")
    t0 = float(b.times[low[0]]) if low.size else uniform(0.3, 0.6, rng=rng) * b.times[-1]
    return release(p, b.times, t0, strength=0.5)


def stagger(b: PlanBuilder, p: PersonPlan) -> PersonPlan:
    """Stagger: the root pin goes slack for a few short windows; the body stumbles."""
    rng = stream(b.recipe.seeds.physics, "stagger")
    pin = p.pin.copy()
    duration = b.times[-1]
    for _ in range(2 + int(rng.random() * 2)):
        t0 = rng.random() * duration
        length = uniform(0.3, 0.8, rng=rng)
        weight = uniform(0.02, 0.15, rng=rng)
        window = (b.times >= t0) & (b.times < t0 + length)
        pin[window] = np.minimum(pin[window], weight)
    return replace(p, pin=pin)


def limp(p: PersonPlan, *, rng: np.random.Generator) -> PersonPlan:
    """Limp: one leg's knee and ankle muscles disabled (paper: synthetic limp)."""
    side = "right" if rng.random() < 0.5 else "left"
    s = p.strengths.copy()
    s[:, BONE_INDEX[f"{side}_lower_leg"]] *= 0.25
    s[:, BONE_INDEX[f"{side}_foot"]] *= 0.25
    return replace(p, strengths=s)
