"""The paper's action variations applied to the protagonist (Section "Action variations"):
muscle weakening, random perturbation and action blending (the objects variation is a
held prop, planned with the action's props)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from phav_generator.motion.animation import Pose, blend, gaussian_smooth, motion_params
from phav_generator.motion.skeleton import BONE_INDEX, lowest_point
from phav_generator.physics.plan.builder import PlanBuilder
from phav_generator.physics.plan.people import animate_person, body_poses
from phav_generator.physics.plan.scene_plan import PersonPlan


def apply_variation(b: PlanBuilder, p: PersonPlan) -> PersonPlan:
    """The paper's four variations applied to the protagonist (Section "Action variations")."""
    v = b.recipe.variation
    if v.kind == "muscle_weakening":
        s = p.strengths.copy()
        for m, strength in zip(v.muscles, v.strengths, strict=True):
            s[:, BONE_INDEX[m]] = strength
        return replace(p, strengths=s)
    if v.kind == "random_perturbation":
        return replace(
            p, perturbed=tuple(v.muscles), perturbation_radius_m=v.radius_m, perturbation_period_s=v.period_s
        )
    if v.kind == "action_blending":
        other_params = motion_params(p.params.speed, p.params.mirror, b.recipe.seeds.physics, f"blend/{p.person_id}")
        # A stairs take blends its strides on level ground: no flight is built for it.
        other = animate_person(v.blend_motion, v.blend_start_s, other_params, p.dims, (0.0, 0.0, 0.0), 0.0, b.times,
                               flight=False)  # fmt: skip
        return replace(
            p, targets=blend(p.targets, other, v.muscles, _grounded_weight(b, p, other, v.muscles, v.weight))
        )
    return p


#: Blend weights tried per step, as fractions of the recipe's, when blending would sink a body.
_BLEND_LEVELS = np.linspace(1.0, 0.0, 9)
#: Time constant (s) over which a lowered blend weight recovers: slow enough for the servos.
BLEND_SMOOTHING_S = 0.1


def _grounded_weight(b: PlanBuilder, p: PersonPlan, other: Pose, muscles: tuple[str, ...], weight: float) -> np.ndarray:
    """The blend weight per step: the recipe's, except where blending the second motion's
    limbs in would push a body into the floor (a standing leg blended onto a lying body),
    where it drops to the largest level that keeps every body above it; lowered early and
    smoothly (a moving minimum, then a Gaussian), so the servos see no corner."""
    floor = b.recipe.protagonist.position[2] + b.stand_offset_z
    base_low = lowest_point(p.dims, *body_poses(p.dims, p.targets))
    limit = np.minimum(base_low, floor) - 0.01

    def above(level: float) -> np.ndarray:
        pose = blend(p.targets, other, muscles, weight * level)
        return lowest_point(p.dims, *body_poses(p.dims, pose)) >= limit

    if np.all(above(1.0)):  # the usual case: nothing sinks at the recipe's weight
        return np.full(len(b.times), weight)
    allowed = np.zeros(len(b.times))
    for level in _BLEND_LEVELS[::-1]:  # from 0 up: the largest level that stays above wins
        allowed = np.where(above(level), weight * level, allowed)
    rate = b.fps * b.substeps
    half = max(1, round(2 * BLEND_SMOOTHING_S * rate))
    padded = np.pad(allowed, half, mode="edge")
    floor_w = np.lib.stride_tricks.sliding_window_view(padded, 2 * half + 1).min(axis=1)
    return np.clip(gaussian_smooth(floor_w[:, None], BLEND_SMOOTHING_S * rate)[:, 0], 0.0, weight)
