"""Recipe → scene plan: everything the simulation needs, decided before MuJoCo runs.

Pure numpy on the recipe (STYLE.md "plan, then execute"): the animated targets of every
person at every physics step, the muscle-strength and pin schedules (variations, limp,
stagger, releases), the props with their grips and manipulation intervals, the action
rules of the paper's synthetic actions, and the camera's parameters. Run-time random
choices (car speed, release moments, …) come from the recipe's physics seed through named
streams, so a plan depends on the recipe alone.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from phav_generator.motion.animation import (
    MotionParams,
    Pose,
    animate,
    blend,
    gaussian_smooth,
    motion_params,
    placement,
    smooth_targets,
)
from phav_generator.motion.gait import STAIR_RISE, STAIR_RUN, STAIR_START, stair_height
from phav_generator.motion.library import get_motion
from phav_generator.motion.rotations import matrix_to_quat, yaw_matrix
from phav_generator.motion.skeleton import (
    BONE_INDEX,
    BONES,
    DOF_INDEX,
    BodyDims,
    capsule_points,
    dims_for,
    forward_kinematics,
    lowest_point,
)
from phav_generator.physics.traffic import Vehicle, footprint_points, plan_traffic
from phav_spec.motions import MOTIONS
from phav_spec.recipe import Recipe
from phav_spec.scene import ACTION_SCENES, ENVIRONMENT_SCENES, MAX_STEP_M, walkable_heights
from phav_spec.seeding import stream
from phav_spec.vocab import MUSCLES, OBJECTS

#: Physics steps per second unless a stiff spring needs more (``phav bench`` chose it).
DEFAULT_PHYSICS_HZ = 240
#: Largest ω·dt allowed for the kite springs (semi-implicit Euler is stable below 2).
MAX_SPRING_OMEGA_DT = 0.5
#: Largest distance the thrown camera may travel in one physics step (half its contact margin).
MAX_CAMERA_STEP_M = 0.05
#: Strength of muscles once a ragdoll is released: a little tone, gravity does the rest.
RELEASED_STRENGTH = 0.15
#: Seconds over which a release lets the pins and muscles go.
RELEASE_RAMP_S = 0.1

HANDS = ("right_hand", "left_hand")
#: Servo strength of an arm whose hand is tied to someone else's body.
TIED_ARM_STRENGTH = 0.4
#: Half the thickness of the posts that hold a pull-up bar's ends (m).
POST_HALF_WIDTH_M = 0.04
#: Gap between the fingertips and the face of what they push (m): touching, not pressing.
PUSH_GAP_M = 0.01
#: A pushed door's leaf (m): wide enough for both hands and a walker's shoulders.
DOOR_WIDTH_M = 1.0
DOOR_HEIGHT_M = 2.0


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
    traffic: tuple[Vehicle, ...] = ()  # background vehicles on the environment's lanes

    @property
    def timestep(self) -> float:
        return 1.0 / (self.fps * self.substeps)

    @property
    def n_steps(self) -> int:
        return self.n_frames * self.substeps

    @property
    def step_times(self) -> np.ndarray:
        return np.arange(self.n_steps + 1) * self.timestep


def choose_substeps(recipe: Recipe, physics_hz: int = DEFAULT_PHYSICS_HZ) -> int:
    """Physics steps per frame: ``physics_hz / fps``, more when a kite spring is stiff.

    The springs are integrated explicitly in position, so the step must keep ω·dt small
    for the stiffest spring–mass pair (ω² = k/m; the target feels both springs).
    """
    fps = recipe.video.fps
    substeps = max(1, math.ceil(physics_hz / fps))
    springs = recipe.camera.springs
    if springs is not None and recipe.camera.kind in ("kite", "closeup"):
        omega2 = max(
            springs.ct_spring_strength / springs.camera_mass,
            (springs.ct_spring_strength + springs.tp_spring_strength) / springs.target_mass,
        )
        needed = math.ceil(math.sqrt(omega2) / (fps * MAX_SPRING_OMEGA_DT))
        substeps = max(substeps, needed)
        impulse = recipe.camera.impulse
        if impulse is not None:
            # A thrown camera must not cross its contact margin in one step (no tunnelling).
            speed = abs(impulse.strength) / springs.camera_mass
            substeps = max(substeps, math.ceil(speed / (fps * MAX_CAMERA_STEP_M)))
    return substeps


def _inside(colliders, point: np.ndarray, clearance: float) -> bool:
    x, y, z = (float(v) for v in point)
    return any(c.xy_distance(x, y) < clearance and c.bottom - clearance < z < c.top + clearance for c in colliders)


def clear_camera_start(recipe: Recipe, clearance: float = 0.25) -> tuple[float, float, float]:
    """The camera's start, slid towards its target until it is clear of the environment's walls.

    The sampler places C_xyz around the protagonist without looking at the geometry, so a
    start inside a building or behind a wall is moved, deterministically, to the first
    point on the segment to the target (5 cm steps) with ``clearance`` metres of room.
    """
    colliders = ENVIRONMENT_SCENES[recipe.environment.name].colliders
    start = np.array(recipe.camera.position, dtype=np.float64)
    target = np.array(recipe.camera.target, dtype=np.float64)
    length = float(np.linalg.norm(target - start))
    steps = max(1, int(length / 0.05))
    for k in range(steps + 1):
        point = start + (target - start) * (k / steps)
        if not _inside(colliders, point, clearance):
            return (float(point[0]), float(point[1]), float(point[2]))
    return tuple(float(v) for v in target)  # type: ignore[return-value]


def _uniform(rng: np.random.Generator, lo: float, hi: float) -> float:
    return lo + (hi - lo) * rng.random()


def _animate_person(
    motion: str, start_s: float, params: MotionParams, dims: BodyDims, position, heading: float, times: np.ndarray
) -> Pose:
    """The pins' and servos' targets: the motion placed in the world, smoothed (continuous
    velocities) so every physics timestep follows the same function of time."""
    clip = get_motion(motion)
    return smooth_targets(lambda t: animate(clip, t, start_s, params, dims, tuple(position), heading), times)


def _body_poses(dims: BodyDims, pose: Pose) -> tuple[np.ndarray, np.ndarray]:
    return forward_kinematics(dims, pose.root_pos, pose.root_quat, pose.q)


def _free_hand(necessary: tuple[str, ...]) -> str:
    return "left_hand" if "right_hand" in necessary else "right_hand"


# Props held in the hand: shape, size, mass and the grip offset in the hand frame.
_HANDHELD_SHAPES: dict[str, tuple[str, tuple[float, ...], float, tuple[float, float, float]]] = {
    "ball": ("sphere", (0.11,), 0.45, (0.0, 0.0, -0.15)),
    "cup": ("capsule", (0.04, 0.04), 0.25, (0.04, 0.0, -0.09)),
    "bottle": ("capsule", (0.035, 0.1), 0.6, (0.04, 0.0, -0.09)),
    "hair_brush": ("capsule", (0.02, 0.1), 0.2, (0.0, 0.0, -0.14)),
    "gun": ("box", (0.11, 0.02, 0.06), 1.0, (0.05, 0.0, -0.08)),
    "golf_club": ("capsule", (0.015, 0.5), 0.4, (0.0, 0.0, -0.55)),
    "baseball_bat": ("capsule", (0.03, 0.42), 0.9, (0.0, 0.0, -0.45)),
    "bow": ("capsule", (0.015, 0.7), 0.8, (0.0, 0.0, -0.06)),
}


def _grip(rel: tuple[float, float, float], scale: float) -> tuple[np.ndarray, np.ndarray]:
    return np.array(rel) * np.array([1.0, 1.0, scale]), np.array([1.0, 0.0, 0.0, 0.0])


def _world_grip(body_pos: np.ndarray, body_rot: np.ndarray, rel: np.ndarray) -> np.ndarray:
    return body_pos + body_rot @ rel


def _rot_to_quat(m: np.ndarray) -> np.ndarray:
    return matrix_to_quat(m[None])[0]


class _Builder:
    """Accumulates the plan's parts while the rules of the action run."""

    def __init__(self, recipe: Recipe, substeps: int):
        self.recipe = recipe
        self.fps = recipe.video.fps
        self.substeps = substeps
        self.n_frames = recipe.n_frames
        self.times = np.arange(recipe.n_frames * substeps + 1) / (self.fps * substeps)
        self.rng = stream(recipe.seeds.physics, "plan")
        self.props: list[PropPlan] = []
        self.boxes: list[StaticBox] = []
        self.ties: list[HandTie] = []
        self.manipulations: list[Manipulation] = []
        self.stand_offset_z = 0.0


def _person(
    b: _Builder,
    person_id: int,
    role: str,
    human,
    motion: str,
    start_s: float,
    speed: float,
    mirror: bool,
    position,
    heading: float,
) -> PersonPlan:
    dims = dims_for(human)
    params = motion_params(speed, mirror, b.recipe.seeds.physics, f"{role}/{person_id}")
    targets = _animate_person(motion, start_s, params, dims, position, heading, b.times)
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


def _with(person: PersonPlan, **changes) -> PersonPlan:
    return replace(person, **changes)


def _ramp(times: np.ndarray, t0: float, duration: float) -> np.ndarray:
    """0 before t0, 1 after t0 + duration, linear in between."""
    return np.clip((times - t0) / max(duration, 1e-9), 0.0, 1.0)


def _release(person: PersonPlan, times: np.ndarray, t0: float, strength: float = RELEASED_STRENGTH) -> PersonPlan:
    """Pins off and muscles slack from t0 on (over 0.1 s): physics takes over."""
    r = _ramp(times, t0, RELEASE_RAMP_S)
    pin = person.pin * (1.0 - r)
    strengths = person.strengths * (1.0 - r[:, None]) + strength * r[:, None]
    return _with(person, pin=pin, strengths=np.minimum(person.strengths, strengths))


def _variation(b: _Builder, p: PersonPlan) -> PersonPlan:
    """The paper's four variations applied to the protagonist (Section "Action variations")."""
    v = b.recipe.variation
    if v.kind == "muscle_weakening":
        s = p.strengths.copy()
        for m, strength in zip(v.muscles, v.strengths, strict=True):
            s[:, BONE_INDEX[m]] = strength
        return _with(p, strengths=s)
    if v.kind == "random_perturbation":
        return _with(p, perturbed=tuple(v.muscles), perturbation_radius_m=v.radius_m, perturbation_period_s=v.period_s)
    if v.kind == "action_blending":
        other_params = motion_params(p.params.speed, p.params.mirror, b.recipe.seeds.physics, f"blend/{p.person_id}")
        other = _animate_person(v.blend_motion, v.blend_start_s, other_params, p.dims, (0.0, 0.0, 0.0), 0.0, b.times)
        return _with(p, targets=blend(p.targets, other, v.muscles, _grounded_weight(b, p, other, v.muscles, v.weight)))
    return p


#: Blend weights tried per step, as fractions of the recipe's, when blending would sink a body.
_BLEND_LEVELS = np.linspace(1.0, 0.0, 9)
#: Time constant (s) over which a lowered blend weight recovers: slow enough for the servos.
BLEND_SMOOTHING_S = 0.1


def _grounded_weight(b: _Builder, p: PersonPlan, other: Pose, muscles: tuple[str, ...], weight: float) -> np.ndarray:
    """The blend weight per step: the recipe's, except where blending the second motion's
    limbs in would push a body into the floor (a standing leg blended onto a lying body),
    where it drops to the largest level that keeps every body above it; lowered early and
    smoothly (a moving minimum, then a Gaussian), so the servos see no corner."""
    floor = b.recipe.protagonist.position[2] + b.stand_offset_z
    base_low = lowest_point(p.dims, *_body_poses(p.dims, p.targets))
    limit = np.minimum(base_low, floor) - 0.01

    def above(level: float) -> np.ndarray:
        pose = blend(p.targets, other, muscles, weight * level)
        return lowest_point(p.dims, *_body_poses(p.dims, pose)) >= limit

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


def _hold(b: _Builder, person: PersonPlan, obj: str, body: str, t0: float = 0.0, t1: float | None = None, name=None):
    """A handheld prop gripped by ``body`` from t0 to t1 (None: the whole clip)."""
    rel_pos, rel_quat = _grip(_HANDHELD_SHAPES[obj][3], person.dims.height_m / 1.75)
    pos, rot = _body_poses(person.dims, person.targets.take(slice(0, 1)))
    k = BONE_INDEX[body]
    start = _world_grip(pos[0, k], rot[0, k], rel_pos)
    quat = _rot_to_quat(rot[0, k])
    end = b.times[-1] + 1.0 if t1 is None else t1
    name = name or f"{obj}_{len(b.props)}"
    return _gripped_prop(b, person, obj, body, name, start, quat, "hold", t0, end, (rel_pos, rel_quat))


def _gripped_prop(
    b: _Builder,
    person: PersonPlan,
    obj: str,
    body: str,
    name: str,
    pos: np.ndarray,
    quat: np.ndarray,
    kind: str,
    t0: float,
    t1: float,
    grip: tuple[np.ndarray, np.ndarray],
    vel: np.ndarray | None = None,
) -> PropPlan:
    """Add a handheld prop gripped by ``body`` from t0 to t1 and annotate the manipulation
    (``kind``: hold, catch, pick) from t0 to t1 or the clip's end."""
    shape, size, mass, _ = _HANDHELD_SHAPES[obj]
    prop = PropPlan(
        name=name, object=obj, pixel_class=OBJECTS[obj], shape=shape, size=size, mass=mass, pos=pos, quat=quat,
        vel=np.zeros(3) if vel is None else vel, grips=((person.person_id, body, t0, t1, grip[0], grip[1]),),
    )  # fmt: skip
    b.props.append(prop)
    b.manipulations.append(Manipulation(obj, person.person_id, body, kind, t0, min(t1, float(b.times[-1]))))
    return prop


def _body_speed(person: PersonPlan, body: str) -> np.ndarray:
    """Displacement per physics step of a body's animated origin (proportional to speed)."""
    pos, _ = _body_poses(person.dims, person.targets)
    return np.linalg.norm(np.gradient(pos[:, BONE_INDEX[body]], axis=0), axis=1)


def _place_handheld_event(b: _Builder, p: PersonPlan, obj: str, body: str, kind: str) -> None:
    """Throw / shoot: held until the hand moves fastest, then released in flight."""
    speed = _body_speed(p, body)
    lo = len(b.times) // 5
    i = lo + int(np.argmax(speed[lo:])) if len(speed) > lo else len(speed) - 1
    t_release = float(b.times[i])
    _hold(b, p, obj, body, 0.0, t_release)
    b.manipulations[-1] = Manipulation(obj, p.person_id, body, kind, 0.0, t_release)


def _catch(b: _Builder, p: PersonPlan, body: str) -> None:
    """A ball thrown from 4–6 m in front lands in the hand when it is furthest forward."""
    pos, rot = _body_poses(p.dims, p.targets)
    hand = pos[:, BONE_INDEX[body]]
    forward = yaw_matrix(np.deg2rad(b.recipe.protagonist.heading_deg)) @ np.array([1.0, 0.0, 0.0])
    n = len(b.times)
    lo, hi = n // 4, max(n // 4 + 1, (3 * n) // 4)
    i = lo + int(np.argmax(hand[lo:hi] @ forward))
    t_catch = float(b.times[i])
    distance = _uniform(b.rng, 4.0, 6.0)
    target = hand[i] + rot[i, BONE_INDEX[body]] @ np.array([0.0, 0.0, -0.15])
    start = target + distance * forward + np.array([0.0, 0.0, 0.3])
    g = np.array([0.0, 0.0, -9.81])
    vel = (target - start - 0.5 * g * t_catch**2) / max(t_catch, 1e-3)
    grip = _grip(_HANDHELD_SHAPES["ball"][3], p.dims.height_m / 1.75)
    _gripped_prop(b, p, "ball", body, "ball_catch", start, np.array([1.0, 0.0, 0.0, 0.0]), "catch", t_catch,
                  b.times[-1] + 1.0, grip, vel=vel)  # fmt: skip


def _kick(b: _Builder, p: PersonPlan) -> None:
    """A ball on the ground where a foot moves fastest: the foot's contact kicks it."""
    pos, rot = _body_poses(p.dims, p.targets)
    best = None
    for foot in ("right_foot", "left_foot"):
        f = pos[:, BONE_INDEX[foot]]
        speed = np.linalg.norm(np.gradient(f, axis=0), axis=1)
        i = int(np.argmax(speed))
        if best is None or speed[i] > best[0]:
            best = (speed[i], foot, i)
    _, foot, i = best
    toe = pos[i, BONE_INDEX[foot]] + rot[i, BONE_INDEX[foot]] @ np.array([0.12 * p.dims.height_m, 0.0, 0.0])
    radius = _HANDHELD_SHAPES["ball"][1][0]
    ground = b.recipe.protagonist.position[2] + b.stand_offset_z
    ball = np.array([toe[0], toe[1], ground + radius])
    b.props.append(
        PropPlan("ball_kick", "ball", OBJECTS["ball"], "sphere", (radius,), 0.43, ball, np.array([1.0, 0, 0, 0]))
    )
    t = float(b.times[i])
    b.manipulations.append(Manipulation("ball", p.person_id, foot, "kick", max(0.0, t - 0.1), t + 0.1))


def _box_meets_bones(box: StaticBox, dims: BodyDims, rot: np.ndarray, pos: np.ndarray, bones: tuple[str, ...]) -> bool:
    """Whether any of ``bones``' capsules (ends and middle) comes inside ``box`` at any step."""
    turn = yaw_matrix(np.deg2rad(box.yaw_deg))
    half = np.array(box.half_size)
    for name in bones:
        k = BONE_INDEX[name]
        cap = dims.capsules[k]
        for local in (np.array(cap.a), np.array(cap.b), (np.array(cap.a) + np.array(cap.b)) / 2):
            point = pos[:, k] + rot[:, k] @ local
            inside = (point - np.array(box.center)) @ turn
            gap = np.linalg.norm(np.maximum(np.abs(inside) - half, 0.0), axis=-1)
            if np.any(gap < cap.radius):
                return True
    return False


def _chair_under_pelvis(b: _Builder, p: PersonPlan) -> None:
    """A chair whose seat is where the animated pelvis comes lowest (sit / stand up).

    Where the seat would cut through the shins or feet (a crouch rather than a seat, or
    sitting on the floor) the chair stands aside, unused and not annotated.
    """
    pos, rot = _body_poses(p.dims, p.targets)
    pelvis = pos[:, 0]
    i = int(np.argmin(pelvis[:, 2]))
    ground = b.recipe.protagonist.position[2]
    heading = b.recipe.protagonist.heading_deg
    back = yaw_matrix(np.deg2rad(heading)) @ np.array([-1.0, 0.0, 0.0])
    half = 0.22

    def chair(centre: np.ndarray, seat_top: float) -> StaticBox:
        return StaticBox(
            "chair",
            (float(centre[0]), float(centre[1]), (ground + seat_top) / 2),
            (half, half, (seat_top - ground) / 2),
            heading,
        )

    seat_top = pelvis[i, 2] - p.dims.capsules[0].radius * 0.9
    box = chair(pelvis[i] + 0.05 * back, seat_top)
    legs = ("left_lower_leg", "right_lower_leg", "left_foot", "right_foot")
    if seat_top - ground < 0.25 or _box_meets_bones(box, p.dims, rot, pos, legs):
        aside = pelvis[0] + 1.2 * (yaw_matrix(np.deg2rad(heading)) @ np.array([0.0, 1.0, 0.0]))
        b.boxes.append(chair(aside, ground + 0.45))
        return
    b.boxes.append(box)
    b.manipulations.append(
        Manipulation("chair", p.person_id, "pelvis", "hold", float(b.times[i]) - 0.5, float(b.times[i]) + 0.5)
    )


def _pull_up_bar(b: _Builder, p: PersonPlan) -> None:
    """A bar through the hands' highest point; the hands hold it while they are near it."""
    pos, _ = _body_poses(p.dims, p.targets)
    hands = (pos[:, BONE_INDEX["left_hand"]] + pos[:, BONE_INDEX["right_hand"]]) / 2
    i = int(np.argmax(hands[:, 2]))
    top = hands[i]
    heading = np.deg2rad(b.recipe.protagonist.heading_deg)
    # The bar runs left–right, just above the palms.
    half_length = 0.6
    yaw = heading + math.pi / 2
    quat = _rot_to_quat(yaw_matrix(yaw) @ np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]]))
    b.props.append(
        PropPlan(
            "pull_up_bar", "pull_up_bar", OBJECTS["pull_up_bar"], "capsule", (0.02, half_length), 5.0,
            top + np.array([0.0, 0.0, 0.08]), quat, dynamic=False,
        )
    )  # fmt: skip
    # Two posts carry the bar's ends down to the ground, out beside the shoulders.
    across = yaw_matrix(yaw) @ np.array([1.0, 0.0, 0.0])
    ground = b.recipe.protagonist.position[2]
    bar_z = top[2] + 0.08
    for side in (-1.0, 1.0):
        foot = top + side * (half_length + POST_HALF_WIDTH_M) * across
        b.boxes.append(
            StaticBox(OBJECTS["pull_up_bar"], (float(foot[0]), float(foot[1]), (ground + bar_z + 0.04) / 2),
                      (POST_HALF_WIDTH_M, POST_HALF_WIDTH_M, (bar_z + 0.04 - ground) / 2), math.degrees(yaw))
        )  # fmt: skip
    near = np.abs(hands[:, 2] - top[2]) < 0.15
    if near.any():
        idx = np.flatnonzero(near)
        b.manipulations.append(
            Manipulation(
                "pull_up_bar", p.person_id, "right_hand", "hold", float(b.times[idx[0]]), float(b.times[idx[-1]])
            )
        )


def _push_target(b: _Builder, p: PersonPlan) -> None:
    """What a push motion pushes, by its description: a door, a shopping cart, else a box."""
    motion = b.recipe.motion.base_motion
    description = MOTIONS[motion].description if motion in MOTIONS else ""
    if "door" in description:
        _door(b, p)
    else:
        _pushed_load(b, p, "shopping_cart" if "cart" in description else "box")


def _hand_reach(b: _Builder, p: PersonPlan) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Forward axis, left axis and, per plan step, both palms' fingertip points (S, 2, 3)."""
    pos, rot = _body_poses(p.dims, p.targets)
    heading = np.deg2rad(b.recipe.protagonist.heading_deg)
    fwd = yaw_matrix(heading) @ np.array([1.0, 0.0, 0.0])
    left = yaw_matrix(heading) @ np.array([0.0, 1.0, 0.0])
    tips = []
    for hand in HANDS:
        k = BONE_INDEX[hand]
        cap = p.dims.capsules[k]
        tip = pos[:, k] + rot[:, k] @ np.array(cap.b)
        tips.append(tip + cap.radius * fwd)
    return fwd, left, np.stack(tips, axis=1)


def _pushed_load(b: _Builder, p: PersonPlan, obj: str) -> None:
    """A box or cart just beyond the fingertips, driven forward as far as they have pushed it."""
    fwd, left, tips = _hand_reach(b, p)
    x0 = np.array(b.recipe.protagonist.position, dtype=np.float64)
    ground = x0[2] + b.stand_offset_z
    # The load never comes back towards the hands: it stays where the furthest push left it.
    reach = np.maximum.accumulate(np.max((tips - x0) @ fwd, axis=1)) + PUSH_GAP_M
    lateral = float(np.mean((tips - x0) @ left))
    hand_z = float(np.median(tips[..., 2])) - ground
    if obj == "box":  # a crate whose top stands just above the hands
        half = (0.3, 0.35, max(0.3, (hand_z + 0.1) / 2))
        bottom = 0.01
    else:  # a cart's basket, its handle end at the hands
        half = (0.45, 0.28, max(0.2, (hand_z - 0.15) / 2))
        bottom = 0.15
    path = x0 + (reach[:, None] + half[0]) * fwd + lateral * left
    path[:, 2] = ground + bottom + half[2]
    quat = _rot_to_quat(yaw_matrix(np.deg2rad(b.recipe.protagonist.heading_deg)))
    b.props.append(PropPlan(obj, obj, OBJECTS[obj], "box", half, 40.0, path[0], quat, dynamic=False, path=path))
    moving = np.flatnonzero(np.diff(reach) > 1e-4)
    if moving.size:
        t0, t1 = float(b.times[moving[0]]), float(b.times[moving[-1] + 1])
        b.manipulations.append(Manipulation(obj, p.person_id, "right_hand", "push", t0, t1))


def _door(b: _Builder, p: PersonPlan) -> None:
    """A hinged door in a frame across the path, where the hands first reach out; the hands
    push its leaf open (contact, no constraint) and the damped hinge resists."""
    fwd, left, tips = _hand_reach(b, p)
    x0 = np.array(b.recipe.protagonist.position, dtype=np.float64)
    ground = x0[2] + b.stand_offset_z
    reach = np.max((tips - x0) @ fwd, axis=1)
    pelvis_reach = (p.targets.root_pos - x0) @ fwd
    # The door stands where the hands are furthest ahead of the pelvis (they meet the leaf).
    i = int(np.argmax(reach - pelvis_reach))
    plane = float(reach[i]) + PUSH_GAP_M
    width, height = DOOR_WIDTH_M, DOOR_HEIGHT_M
    hinge_side = 0.7  # the hinge on the person's left; the leaf spans past their right hand
    hinge = x0 + plane * fwd + hinge_side * left
    hinge[2] = ground + 0.01
    heading = b.recipe.protagonist.heading_deg
    quat = _rot_to_quat(yaw_matrix(np.deg2rad(heading)))
    b.props.append(
        PropPlan("door", "door", OBJECTS["door"], "box", (0.02, width / 2, height / 2), 25.0, hinge, quat,
                 hinge=(0.0, math.radians(100.0)), offset=(0.02, -width / 2, height / 2))
    )  # fmt: skip
    # The frame: two posts beside the leaf and a lintel over it (the leaf opens away from them).
    for y in (hinge_side + 0.06, hinge_side - width - 0.06):  # the hinge post, the latch post
        c = x0 + (plane - 0.05) * fwd + y * left
        b.boxes.append(StaticBox("door", (float(c[0]), float(c[1]), ground + (height + 0.1) / 2),
                                 (0.05, 0.05, (height + 0.1) / 2), heading))  # fmt: skip
    c = x0 + (plane - 0.05) * fwd + (hinge_side - width / 2) * left
    b.boxes.append(StaticBox("door", (float(c[0]), float(c[1]), ground + height + 0.06), (0.05, width / 2 + 0.11, 0.05),
                             heading))  # fmt: skip
    b.manipulations.append(Manipulation("door", p.person_id, "right_hand", "push", float(b.times[i]),
                                        float(b.times[-1])))  # fmt: skip


#: Half width of a built flight of stairs (m).
STAIRS_HALF_WIDTH_M = 0.6


def _stairs(b: _Builder, probe: PersonPlan, start: np.ndarray) -> np.ndarray:
    """Build the flight a climb_stairs clip walks on; return where to stand the protagonist.

    A catalogue stairs motion plants its feet on its own treads (``motion.gait.STAIR_*``,
    in the motion frame): those treads are built in the world through the clip's
    ``Placement``, so every plant lands on a tread whatever the person's height, the
    clip's start in the flight or the handedness. Going up, the tread under the feet at
    the clip's start is the waypoint's floor; going down, the lowest tread the clip reaches
    is, and the person starts on the tread (or landing) above it: ``stand_offset_z``.
    """
    motion = get_motion(probe.motion)
    direction = motion.stairs
    if direction == 0:
        return _stairs_from_rise(b, probe, start)
    r = b.recipe
    pl = placement(motion, r.motion.start_s, probe.params, probe.dims, tuple(start), r.protagonist.heading_deg)
    pos, rot = _body_poses(probe.dims, probe.targets.take(slice(None, None, b.substeps)))
    feet = [BONE_INDEX["left_foot"], BONE_INDEX["right_foot"]]
    ends = np.concatenate(capsule_points(probe.dims, pos, rot), axis=-2)[:, feet + [f + len(BONES) for f in feet]]
    in_motion = pl.to_motion(ends.reshape(-1, 3)).reshape(*ends.shape)
    motion_x = in_motion[..., 0]
    # The tread the clip starts on: the lowest one a sole stands on (within 2 cm) at the
    # first frame. Not the lowest sole: going down, the swing foot is lower, in the air.
    radius = probe.dims.capsules[feet[0]].radius / pl.scale
    under = stair_height(motion_x[0], direction)
    clearance = np.abs(in_motion[0, :, 2] - radius - under)
    standing = clearance < 0.02 / pl.scale
    h0 = float(under[standing].min() if standing.any() else under[np.argmin(clearance)])
    lo, hi = float(motion_x.min()) - 0.3, float(motion_x.max()) + STAIR_RUN
    h_low = float(stair_height(np.array([hi]), direction)[0]) if direction < 0 else h0
    z0 = float(start[2])
    b.stand_offset_z = pl.scale * (h0 - h_low)
    stand = np.array([start[0], start[1], z0 - pl.scale * h0])
    base = z0 - pl.scale * h_low  # the animation's z: the motion's floor in the world
    yaw = math.degrees(pl.heading_rad - pl.yaw0)
    n_lo = max(0, math.floor((lo - STAIR_START) / STAIR_RUN) + 1)
    n_hi = math.floor((hi - STAIR_START) / STAIR_RUN) + 1
    for n in range(n_lo, n_hi + 1):
        # Tread n spans [start + (n − 1)·run, start + n·run) at n rises; tread 0 is the floor
        # (a landing, going down) before the first riser.
        x_from = STAIR_START + (n - 1) * STAIR_RUN if n else min(lo, STAIR_START - STAIR_RUN)
        x_to = STAIR_START + n * STAIR_RUN
        top = base + pl.scale * direction * STAIR_RISE * n
        if top - z0 < 1e-3:
            continue
        centre = pl.to_world(np.array([(x_from + x_to) / 2, 0.0, 0.0]))
        half = (pl.scale * (x_to - x_from) / 2, STAIRS_HALF_WIDTH_M, (top - z0) / 2)
        b.boxes.append(StaticBox("stairs", (float(centre[0]), float(centre[1]), (z0 + top) / 2), half, yaw))
    return stand


def _stairs_from_rise(b: _Builder, probe: PersonPlan, start: np.ndarray) -> np.ndarray:
    """Steps for a stairs motion without its own flight (an imported clip): the clip's
    climb taken out of its start, then steps of 17 cm × 30 cm following the pelvis's rise."""
    climbed = probe.targets.root_pos[0, 2] - start[2] - probe.dims.standing_pelvis_height
    start = start - np.array([0.0, 0.0, climbed])
    pelvis = probe.targets.root_pos
    rise = pelvis[-1, 2] - pelvis[0, 2]
    heading = b.recipe.protagonist.heading_deg
    fwd = yaw_matrix(np.deg2rad(heading)) @ np.array([1.0, 0.0, 0.0])
    x0 = np.array(b.recipe.protagonist.position)
    step_rise, step_run = 0.17, 0.30
    n_steps = max(3, int(abs(rise) / step_rise + 0.999) + 2)
    for k in range(n_steps):
        if rise >= 0:  # up: step k's top at (k + 1)·rise, starting 0.4 m ahead
            top = (k + 1) * step_rise
            along = 0.4 + (k + 0.5) * step_run
            length = step_run
        else:  # down: the person starts on a landing; steps fall ahead of it
            top = (n_steps - k) * step_rise
            along = (k + 0.5) * step_run if k else 0.0
            length = step_run if k else 2.0
        c = x0 + along * fwd
        b.boxes.append(
            StaticBox("stairs", (float(c[0]), float(c[1]), x0[2] + top / 2), (length / 2, 0.6, top / 2), heading)
        )
    if rise < 0:
        b.stand_offset_z = n_steps * step_rise
    return start


def _car(b: _Builder, p: PersonPlan) -> PersonPlan:
    """Car hit: a car crosses the protagonist's path and hits them; contact releases the pins."""
    rng = stream(b.recipe.seeds.physics, "car_hit")
    speed = _uniform(rng, 5.0, 12.0)
    n = len(b.times)
    duration = b.times[-1]
    t_hit = _uniform(rng, 0.35, 0.6) * duration
    side = 1.0 if rng.random() < 0.5 else -1.0
    i_hit = int(np.searchsorted(b.times, t_hit))
    pelvis = p.targets.root_pos[min(i_hit, n - 1)]
    heading = np.deg2rad(b.recipe.protagonist.heading_deg)
    across = yaw_matrix(heading) @ np.array([0.0, side, 0.0])
    half = np.array([2.1, 0.9, 0.7])
    ground = b.recipe.protagonist.position[2]
    # The car's front reaches the pelvis at t_hit; then it brakes once it has touched.
    centre_hit = np.array([pelvis[0], pelvis[1], ground + half[2] + 0.15]) + across * (half[0] + 0.15)
    path = centre_hit[None, :] - across[None, :] * speed * (b.times - t_hit)[:, None]
    yaw = heading + side * math.pi / 2 + math.pi
    quat = _rot_to_quat(yaw_matrix(yaw))
    b.props.append(
        PropPlan("car", "car", OBJECTS["car"], "box", tuple(half), 1200.0, path[0], quat, dynamic=False, path=path)
    )
    b.manipulations.append(Manipulation("car", p.person_id, "pelvis", "hit", t_hit, float(b.times[-1])))
    return _with(p, release_on_contact_with="car")


def _dive(b: _Builder, p: PersonPlan) -> PersonPlan:
    """Dive floor: pins let go when the dive starts (pelvis below 75 % of standing)."""
    z = p.targets.root_pos[:, 2] - b.recipe.protagonist.position[2]
    low = np.flatnonzero(z < 0.75 * p.dims.standing_pelvis_height)
    rng = stream(b.recipe.seeds.physics, "dive")
    t0 = float(b.times[low[0]]) if low.size else _uniform(rng, 0.3, 0.6) * b.times[-1]
    return _release(p, b.times, t0, strength=0.5)


def _stagger(b: _Builder, p: PersonPlan) -> PersonPlan:
    """Stagger: the root pin goes slack for a few short windows; the body stumbles."""
    rng = stream(b.recipe.seeds.physics, "stagger")
    pin = p.pin.copy()
    duration = b.times[-1]
    for _ in range(2 + int(rng.random() * 2)):
        t0 = rng.random() * duration
        length = _uniform(rng, 0.3, 0.8)
        weight = _uniform(rng, 0.02, 0.15)
        window = (b.times >= t0) & (b.times < t0 + length)
        pin[window] = np.minimum(pin[window], weight)
    return _with(p, pin=pin)


def _limp(p: PersonPlan, rng: np.random.Generator) -> PersonPlan:
    """Limp: one leg's knee and ankle muscles disabled (paper: synthetic limp)."""
    side = "right" if rng.random() < 0.5 else "left"
    s = p.strengths.copy()
    s[:, BONE_INDEX[f"{side}_lower_leg"]] *= 0.25
    s[:, BONE_INDEX[f"{side}_foot"]] *= 0.25
    return _with(p, strengths=s)


def _supporting_people(b: _Builder, protagonist: PersonPlan) -> list[PersonPlan]:
    r = b.recipe
    out = []
    for s in r.supporting_characters:
        person = _person(
            b, s.person_id, "supporting", s.human, r.motion.base_motion, r.motion.start_s, r.motion.speed,
            r.motion.mirror, s.position, s.heading_deg,
        )  # fmt: skip
        out.append(person)
    if not out:
        return out
    partner = out[0]
    scale = protagonist.dims.height_m / 1.75
    if r.action == "walk_holding_hands":
        # The partner is on the protagonist's right: right hand holds left hand.
        palm = -0.08 * scale
        b.ties.append(HandTie(0, "right_hand", partner.person_id, "left_hand", (0.0, -0.01, palm), (0.0, 0.01, palm)))
        b.manipulations.append(Manipulation("hand", 0, "right_hand", "hold", 0.0, float(b.times[-1])))
    elif r.action == "walking_hug":
        shoulder = (0.0, -0.12 * scale, 0.17 * scale)  # the partner's far (right) shoulder
        b.ties.append(HandTie(0, "right_hand", partner.person_id, "chest", (0.0, 0.0, -0.08 * scale), shoulder))
        b.manipulations.append(Manipulation("hug", 0, "right_hand", "hold", 0.0, float(b.times[-1])))
    return out


def _arm_pose_for_tie(p: PersonPlan, action: str) -> PersonPlan:
    """Two-person rules: reach the arm to the partner (holding hands low, hug around shoulders)."""
    q = p.targets.q.copy()
    if action == "walk_holding_hands":
        q[:, DOF_INDEX["right_shoulder_abd"]] = 0.35
        q[:, DOF_INDEX["right_shoulder_flex"]] = 0.1
        q[:, DOF_INDEX["right_elbow_flex"]] = 0.25
    elif action == "walking_hug":
        q[:, DOF_INDEX["right_shoulder_abd"]] = 1.45
        q[:, DOF_INDEX["right_shoulder_flex"]] = 0.35
        q[:, DOF_INDEX["right_elbow_flex"]] = 0.9
    else:
        return p
    return _with(p, targets=Pose(p.targets.root_pos, p.targets.root_quat, q))


#: How far ahead of and behind its pelvis a background walker's feet reach (m).
BACKGROUND_REACH_M = 0.5


def _background(b: _Builder) -> list[PersonPlan]:
    """Background pedestrians: kinematic walkers between waypoints, posed at frame times only."""
    r = b.recipe
    frame_times = np.arange(r.n_frames + 1) / r.video.fps
    walk = get_motion("walk_forward_01")
    ends = walk.fn(np.array([0.0, walk.length_s]), MotionParams())
    nominal = float(np.linalg.norm(ends.root_pos[1, :2] - ends.root_pos[0, :2])) / walk.length_s
    out = []
    for actor in r.background_actors:
        dims = dims_for(actor.human)
        start = np.array(actor.start)
        dest = np.array(actor.destination)
        delta = dest - start
        dist = float(np.linalg.norm(delta[:2]))
        heading = math.degrees(math.atan2(delta[1], delta[0])) if dist > 1e-6 else 0.0
        scale = dims.height_m / 1.75
        speed = actor.speed_mps / max(nominal * scale, 1e-6)
        params = motion_params(speed, False, r.seeds.background, f"background/{actor.person_id}")
        pose = animate(walk, frame_times, params.phase * walk.length_s, params, dims, (0.0, 0.0, 0.0), heading)
        # Progress along the path, clamped at the destination; the gait's own advance is
        # replaced by the straight segment so the actor arrives where the recipe says.
        travelled = np.minimum(actor.speed_mps * frame_times, dist)
        along = delta / max(dist, 1e-9)
        root = start[None, :] + travelled[:, None] * along[None, :]
        # Walkers step up onto kerbs and terraces on their way instead of wading through them:
        # the highest surface within a stride ahead of or behind the pelvis, where the feet
        # reach (the pelvis alone stepped up only once the front foot was in the kerb).
        reach = max(start[2], dest[2]) + MAX_STEP_M
        root[:, 2] = np.max(
            [
                walkable_heights(r.environment.name, *(root[:, :2] + o * along[:2]).T, reach)
                for o in (-BACKGROUND_REACH_M, -BACKGROUND_REACH_M / 2, 0.0, BACKGROUND_REACH_M / 2, BACKGROUND_REACH_M)
            ],
            axis=0,
        )
        root[:, 2] += pose.root_pos[:, 2]  # the gait's own bob and standing height
        arrived = travelled >= dist
        q = pose.q.copy()
        q[arrived] = 0.0
        n = len(frame_times)
        out.append(
            PersonPlan(
                person_id=actor.person_id,
                role="background",
                dims=dims,
                params=params,
                motion="walk_forward_01",
                targets=Pose(root, pose.root_quat, q),
                strengths=np.ones((n, len(MUSCLES))),
                pin=np.ones(n),
                physical=False,
            )
        )
    return out


def plan_scene(recipe: Recipe, *, physics_hz: int = DEFAULT_PHYSICS_HZ) -> ScenePlan:
    """The simulation plan of a recipe (deterministic, pure)."""
    substeps = choose_substeps(recipe, physics_hz)
    b = _Builder(recipe, substeps)
    r = recipe
    action = r.action
    scene = ACTION_SCENES[action]
    start = np.array(r.protagonist.position, dtype=np.float64)
    if action == "climb_stairs":
        probe = _person(
            b, 0, "protagonist", r.protagonist.human, r.motion.base_motion, r.motion.start_s, r.motion.speed,
            r.motion.mirror, tuple(start), r.protagonist.heading_deg,
        )  # fmt: skip
        start = _stairs(b, probe, start)
    position = tuple(start + np.array([0.0, 0.0, b.stand_offset_z]))
    p = _person(
        b, 0, "protagonist", r.protagonist.human, r.motion.base_motion, r.motion.start_s, r.motion.speed,
        r.motion.mirror, position, r.protagonist.heading_deg,
    )  # fmt: skip
    rule_rng = stream(r.seeds.physics, "rules")
    p = _arm_pose_for_tie(p, action)
    p = _variation(b, p)
    if action == "car_hit":
        p = _car(b, p)
    elif action == "dive_floor":
        p = _dive(b, p)
    elif action == "stagger":
        p = _stagger(b, p)
    elif action == "limp":
        p = _limp(p, rule_rng)
    # Props the action itself uses.
    right = "left_hand" if r.motion.mirror else "right_hand"
    left = "right_hand" if r.motion.mirror else "left_hand"
    for obj in scene.objects:
        if obj in ("hair_brush", "gun", "golf_club", "baseball_bat"):
            _hold(b, p, obj, right)
        elif obj == "bow":
            _hold(b, p, obj, left)
        elif obj == "bottle" and action == "pour":
            _hold(b, p, "bottle", right)
        elif obj == "cup" and action == "pour":
            _hold(b, p, "cup", left)
        elif obj == "bottle" and action == "pick":
            _pick(b, p, right)
        elif obj == "ball" and action == "catch":
            _catch(b, p, right)
        elif obj == "ball" and action in ("throw", "shoot_ball"):
            _place_handheld_event(b, p, "ball", right, "throw")
        elif obj == "ball" and action == "kick_ball":
            _kick(b, p)
        elif obj == "chair":
            _chair_under_pelvis(b, p)
        elif obj == "pull_up_bar":
            _pull_up_bar(b, p)
    if action == "push":
        _push_target(b, p)
    if r.variation.kind == "objects":
        _hold(b, p, r.variation.object, _free_hand(scene.necessary_muscles), name=f"{r.variation.object}_variation")
    supporting = _supporting_people(b, p)
    people = [p, *supporting]
    for tie in b.ties:
        # Tied arms go compliant so the tie, not the servos, decides where the hands meet.
        for side, body in ((tie.person_a, tie.body_a), (tie.person_b, tie.body_b)):
            if body.endswith("_hand"):
                arm = [f"{body[: -len('hand')]}{part}" for part in ("upper_arm", "lower_arm", "hand")]
                k = next(i for i, x in enumerate(people) if x.person_id == side)
                s = people[k].strengths.copy()
                s[:, [BONE_INDEX[m] for m in arm]] *= TIED_ARM_STRENGTH
                people[k] = _with(people[k], strengths=s)
    people = (*people, *_background(b))
    return ScenePlan(
        recipe=r,
        fps=r.video.fps,
        substeps=substeps,
        n_frames=r.n_frames,
        people=people,
        props=tuple(b.props),
        boxes=tuple(b.boxes),
        ties=tuple(b.ties),
        manipulations=tuple(b.manipulations),
        stand_offset_z=b.stand_offset_z,
        camera_start=clear_camera_start(r),
        traffic=plan_traffic(r, _planned_obstacles(people, b.props, substeps)),
    )


def _planned_obstacles(people: tuple[PersonPlan, ...], props: list[PropPlan], substeps: int) -> np.ndarray:
    """Every person's bodies and every driven prop's footprint (F + 1, N, 3) per frame, as planned."""
    parts = []
    for p in people:
        step = substeps if p.physical else 1
        pos, _ = forward_kinematics(
            p.dims, *(a[::step] for a in (p.targets.root_pos, p.targets.root_quat, p.targets.q))
        )
        parts.append(pos)
    for prop in props:
        if prop.path is not None:
            yaw = 2.0 * math.atan2(prop.quat[3], prop.quat[0])
            parts.append(footprint_points(prop.path[::substeps], yaw, prop.size))
    return np.concatenate(parts, axis=1)


def _pick(b: _Builder, p: PersonPlan, hand: str) -> None:
    """Pick up: the object rests on the ground under the hand's lowest point; held after."""
    pos, rot = _body_poses(p.dims, p.targets)
    h = pos[:, BONE_INDEX[hand]]
    i = int(np.argmin(h[:, 2]))
    _, size, _, rel = _HANDHELD_SHAPES["bottle"]
    ground = b.recipe.protagonist.position[2]
    grip = _grip(rel, p.dims.height_m / 1.75)
    grip_world = _world_grip(h[i], rot[i, BONE_INDEX[hand]], grip[0])
    start = np.array([grip_world[0], grip_world[1], ground + size[0] + size[1] + 0.005])
    t_pick = float(b.times[i])
    _gripped_prop(b, p, "bottle", hand, "bottle_pick", start, np.array([1.0, 0, 0, 0]), "pick", t_pick,
                  b.times[-1] + 1.0, grip)  # fmt: skip
