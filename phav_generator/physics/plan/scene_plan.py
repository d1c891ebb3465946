"""The scene plan's data: everything ``plan_scene`` decides and the simulation reads.

Frozen dataclasses of numpy arrays, one row per physics step (background people: per
frame): the people with their animated targets and control schedules, the props, the
action's static boxes, the hand ties, the annotated manipulations and the traffic.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from phav_generator.motion.animation import MotionParams, Pose
from phav_generator.motion.skeleton import BodyDims
from phav_generator.physics.traffic import Vehicle
from phav_spec.recipe import Recipe


@dataclass(frozen=True)
class PersonPlan:
    """One person: who, the animation targets per physics step and the control schedules."""

    person_id: int
    role: str  # protagonist, supporting, background
    dims: BodyDims
    params: MotionParams
    motion: str
    targets: Pose  # at every physics step (physical people) or every frame (background)
    strengths: np.ndarray  # (S, 15) servo strength per muscle, 1 = nominal
    pin: np.ndarray  # (S,) root pin weight, 1 = held to the animation, 0 = released
    physical: bool
    perturbed: tuple[str, ...] = ()  # muscles pulled by orbiting bodies
    perturbation_radius_m: float = 0.0
    perturbation_period_s: float = 1.0
    release_on_contact_with: str | None = None  # prop name whose touch releases the pins
    sole_friction: float = 1.0  # the feet's friction on the floor (the motion's)


@dataclass(frozen=True)
class Manipulation:
    """An object manipulation annotated in the trajectory: hold, throw, catch or kick."""

    object: str
    person_id: int
    body: str
    kind: str
    start_s: float
    end_s: float


@dataclass(frozen=True)
class PropPlan:
    """A prop or vehicle: its shape, mass and how it moves."""

    name: str
    object: str  # OBJECTS name
    pixel_class: str
    shape: str  # box, capsule, sphere
    size: tuple[float, ...]  # MuJoCo geom size
    mass: float
    pos: np.ndarray  # initial position (3,)
    quat: np.ndarray  # initial orientation (4,)
    vel: np.ndarray = field(default_factory=lambda: np.zeros(3))
    dynamic: bool = True  # free body; False: static (chair, bar, stairs) or kinematic path
    path: np.ndarray | None = None  # (S, 3) kinematic positions (cars, pushed loads)
    hinge: tuple[float, float] | None = None  # a door: (lower, upper) angle (rad) about its vertical axis at pos
    offset: tuple[float, float, float] = (0.0, 0.0, 0.0)  # geom centre in the body frame (a door's leaf)
    grips: tuple[
        tuple[int, str, float, float, np.ndarray, np.ndarray], ...
    ] = ()  # (person, body, t0, t1, rel pos, rel quat)
    # Convex solids (their corners, in the shape's frame) it collides as instead of its
    # shape, which then only carries its mass and pose: a car's body, greenhouse and bumpers.
    hulls: tuple[tuple[tuple[float, float, float], ...], ...] = ()
    # The last step of ``path`` the prop can reach once it has touched someone (a car braking
    # from its touch stops short of its path's end; one that touches no one drives it all);
    # None: the whole path.
    lane_end: int | None = None


@dataclass(frozen=True)
class StaticBox:
    """Scene geometry an action needs (stairs, a chair seat): a box with its pixel class."""

    pixel_class: str
    center: tuple[float, float, float]
    half_size: tuple[float, float, float]
    yaw_deg: float = 0.0


@dataclass(frozen=True)
class HandTie:
    """A soft connect constraint between two people's bodies (holding hands, hugging)."""

    person_a: int
    body_a: str
    person_b: int
    body_b: str
    anchor_a: tuple[float, float, float]  # the tied point in body_a's frame
    anchor_b: tuple[float, float, float]  # the same point in body_b's frame


@dataclass(frozen=True)
class ScenePlan:
    """The whole plan of one video."""

    recipe: Recipe
    fps: int
    substeps: int
    n_frames: int  # frames written; the plan covers n_frames + 1 (forward flow of the last)
    people: tuple[PersonPlan, ...]
    props: tuple[PropPlan, ...]
    boxes: tuple[StaticBox, ...]
    ties: tuple[HandTie, ...]
    manipulations: tuple[Manipulation, ...]
    stand_offset_z: float = 0.0  # protagonist raised onto a landing (going down stairs)
    camera_start: tuple[float, float, float] | None = None  # recipe's C_xyz moved out of walls
    #: A spring camera's target start: its anchor on the protagonist (the recipe's C_xyz and
    #: T_xyz are moved together by the same offset), None for other cameras.
    camera_target: tuple[float, float, float] | None = None
    traffic: tuple[Vehicle, ...] = ()  # background vehicles on the environment's lanes
    #: Boxes (centre, half sizes, yaw in degrees) only a spring camera collides with: the
    #: lanes of the cars it started clear of, which it then keeps out of.
    camera_walls: tuple[tuple[tuple[float, float, float], tuple[float, float, float], float], ...] = ()

    @property
    def timestep(self) -> float:
        return 1.0 / (self.fps * self.substeps)

    @property
    def n_steps(self) -> int:
        return self.n_frames * self.substeps

    @property
    def step_times(self) -> np.ndarray:
        return np.arange(self.n_steps + 1) * self.timestep
