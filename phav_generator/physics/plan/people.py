"""A simulated person's plan: the animated targets per physics step, full strength and a
held pin, and the release that hands a body over to physics."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from phav_generator.body.model import rest_body
from phav_generator.motion.animation import MotionParams, Pose, animate, motion_params, resample, smooth_targets
from phav_generator.motion.library import get_motion
from phav_generator.motion.skeleton import BONE_INDEX, BodyDims, forward_kinematics
from phav_generator.physics.plan.builder import PlanBuilder
from phav_generator.physics.plan.scene_plan import PersonPlan
from phav_spec.recipe import HumanSpec
from phav_spec.vocab import MUSCLES

#: Strength of muscles once a ragdoll is released: a little tone, gravity does the rest.
RELEASED_STRENGTH = 0.15
#: Seconds over which a release lets the pins and muscles go.
RELEASE_RAMP_S = 0.1
#: Seconds over which a halted motion slows from its pace to a standstill.
HALT_RAMP_S = 0.5
#: How far back (s) a halt looks for both feet down (about a stride), and how near (m) each
#: foot's lower end (heel or toe) must then be to its lowest in that time.
HALT_LOOKBACK_S = 1.2
PLANTED_M = 0.01
#: How much higher (m) the feet's raised ends (a back heel) may be than the lowest they come
#: to while both stand.
PLANTED_RAISE_M = 0.02


def animate_person(
    motion: str,
    start_s: float,
    params: MotionParams,
    dims: BodyDims,
    position: tuple[float, float, float],
    heading: float,
    times: np.ndarray,
    *,
    flight: bool,
) -> Pose:
    """The pins' and servos' targets: the motion placed in the world, smoothed (continuous
    velocities) so every physics timestep follows the same function of time; a stairs take
    climbs only with a ``flight`` built under it (``get_motion``), and strides on level ground
    without."""
    clip = get_motion(motion, flight=flight)
    return smooth_targets(lambda t: animate(clip, t, start_s, params, dims, tuple(position), heading), times)


def body_poses(dims: BodyDims, pose: Pose) -> tuple[np.ndarray, np.ndarray]:
    """World positions and rotations of every body of ``pose`` (forward kinematics)."""
    return forward_kinematics(dims, pose.root_pos, pose.root_quat, pose.q)


def plan_person(
    b: PlanBuilder,
    person_id: int,
    role: str,
    human: HumanSpec,
    motion: str,
    start_s: float,
    speed: float,
    mirror: bool,
    position: tuple[float, float, float],
    heading: float,
) -> PersonPlan:
    """A simulated person doing ``motion`` from ``position``: targets at every physics step,
    full strength, pinned; the motion's parameters drawn from the physics seed per role and
    id. Only the protagonist of ``climb_stairs`` has a flight built under a stairs take."""
    dims = rest_body(human.phenotype).dims
    params = motion_params(speed, mirror, b.recipe.seeds.physics, f"{role}/{person_id}")
    flight = b.recipe.action == "climb_stairs" and role == "protagonist"
    targets = animate_person(motion, start_s, params, dims, position, heading, b.times, flight=flight)
    n = len(b.times)
    return PersonPlan(
        person_id=person_id,
        role=role,
        dims=dims,
        params=params,
        motion=motion,
        targets=targets,
        strengths=np.ones((n, len(MUSCLES))),
        pin=np.ones(n),
        physical=True,
        sole_friction=get_motion(motion).sole_friction,
    )


def _ramp(times: np.ndarray, t0: float, duration: float) -> np.ndarray:
    """0 before t0, 1 after t0 + duration, linear in between."""
    return np.clip((times - t0) / max(duration, 1e-9), 0.0, 1.0)


def release(person: PersonPlan, times: np.ndarray, t0: float, strength: float = RELEASED_STRENGTH) -> PersonPlan:
    """Pins off and muscles slack from t0 on (over 0.1 s): physics takes over."""
    r = _ramp(times, t0, RELEASE_RAMP_S)
    pin = person.pin * (1.0 - r)
    strengths = person.strengths * (1.0 - r[:, None]) + strength * r[:, None]
    return replace(person, pin=pin, strengths=np.minimum(person.strengths, strengths))


def halt(person: PersonPlan, times: np.ndarray, t_stop: float) -> PersonPlan:
    """``person``'s motion slowing evenly to a standstill (over ``HALT_RAMP_S``, less where
    it stops sooner) so that it holds the pose it had at ``t_stop`` from then on: its
    targets replayed on a clock whose pace falls from 1 to 0 (velocities stay continuous)."""
    ramp = min(HALT_RAMP_S, 2.0 * t_stop)
    if ramp <= 0.0:
        clock = np.full_like(times, t_stop)
    else:
        t0 = t_stop - ramp / 2.0  # slowing down costs half the ramp's length of motion time
        u = np.clip(times - t0, 0.0, ramp)
        clock = np.where(times < t0, times, t0 + u - u * u / (2.0 * ramp))
    return replace(person, targets=resample(person.targets, times, clock))


def planted_before(person: PersonPlan, times: np.ndarray, step: int) -> int:
    """The latest physics step at or before ``step`` (and at most ``HALT_LOOKBACK_S`` before
    it) at which both feet stand, the heel or toe of each within ``PLANTED_M`` of its lowest
    in that time, and their raised ends are about as low as they come while both stand (the
    back heel of a stride lifted, not a foot on its tip); where both never stand, where they
    come nearest: a pose to hold standing, not on one leg."""
    first = max(0, step - round(HALT_LOOKBACK_S / float(times[1] - times[0])))
    pos, rot = body_poses(person.dims, person.targets.take(slice(first, step + 1)))
    low, high = [], []
    for foot in ("left_foot", "right_foot"):
        k = BONE_INDEX[foot]
        cap = person.dims.capsules[k]
        z = np.stack([(pos[:, k] + rot[:, k] @ np.array(end))[:, 2] for end in (cap.a, cap.b)], axis=1)
        low.append(z.min(axis=1) - z.min())
        high.append(z.max(axis=1) - z.min())
    lift, raised = np.max(low, axis=0), np.max(high, axis=0)
    standing = lift <= PLANTED_M
    if standing.any():
        chosen = standing & (raised <= raised[standing].min() + PLANTED_RAISE_M)
    else:
        chosen = lift <= lift.min() + PLANTED_M
    return first + int(np.flatnonzero(chosen)[-1])
