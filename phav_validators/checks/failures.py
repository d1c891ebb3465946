"""The paper's failure cases, recomputed from poses, cameras and the environment geometry.

Nothing here trusts a flag the generator wrote (``penetration_m``, ``joint_limit_excess``,
``visible``): every measure is taken again from the 3-D joints in ``people.parquet``, the
camera poses in ``cameras.parquet`` and the environment's collision boxes rebuilt from each
recipe (``phav_spec.scene``); the base motion for the perturbation test is re-planned from
the recipe (``phav_generator.physics.plan``: kinematics only, no physics, no GL).

A video fails when any measure crosses its threshold; the dataset fails when the share of
failed videos exceeds the budget (default 10 %, the paper's estimate of its failure rate).
A non-finite pose, a table the check cannot read (``tables``), and rows that break the
contract (a frame twice or outside the clip, a frame without its camera) are a broken file
rather than a failure case and always fail.
"""

from __future__ import annotations

import copy
import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Any

import numpy as np
from scipy.spatial import ConvexHull

from phav_generator.motion.skeleton import BONES, JOINT_BODIES, forward_kinematics
from phav_generator.physics.plan.scene import plan_scene
from phav_generator.physics.plan.scene_plan import ScenePlan
from phav_spec.errors import PhavUserError
from phav_spec.metadata import JOINT_ORDER
from phav_spec.recipe import Recipe
from phav_spec.scene import ACTION_SCENES, ENVIRONMENT_SCENES, WALKABLE_PIXEL_CLASSES, Collider
from phav_validators import tables
from phav_validators.findings import CheckResult, Finding, Reason, Report

if TYPE_CHECKING:
    import pyarrow as pa

#: The paper's estimate of its failure rate: the default budget.
DEFAULT_BUDGET = 0.10

_J = {name: i for i, name in enumerate(JOINT_ORDER)}
#: Joint pairs on one rigid body or across one hinge: their distance never changes.
RIGID_PAIRS: tuple[tuple[int, int], ...] = tuple(
    (_J[a], _J[b])
    for a, b in (
        ("neck", "left_shoulder"), ("neck", "right_shoulder"), ("left_shoulder", "right_shoulder"),
        ("left_shoulder", "left_elbow"), ("left_elbow", "left_wrist"),
        ("right_shoulder", "right_elbow"), ("right_elbow", "right_wrist"),
        ("left_hip", "right_hip"), ("left_hip", "left_knee"), ("left_knee", "left_ankle"),
        ("right_hip", "right_knee"), ("right_knee", "right_ankle"),
    )
)  # fmt: skip
#: Limbs whose midpoints are tested against the geometry along with the joints.
_LIMBS = RIGID_PAIRS[3:7] + RIGID_PAIRS[8:] + ((_J["neck"], _J["left_hip"]), (_J["neck"], _J["right_hip"]))


def probe_points(joints: np.ndarray) -> np.ndarray:
    """The points tested against the geometry: the joints (..., 13, 3) and the midpoints of
    the limbs between them, (..., 13 + limbs, 3)."""
    mid = 0.5 * (joints[..., [a for a, _ in _LIMBS], :] + joints[..., [b for _, b in _LIMBS], :])
    return np.concatenate([joints, mid], axis=-2)


#: How a measure reports a failure: its reason and a message saying what crossed which threshold.
_Fail = Callable[[Reason, str], None]

#: An ankle this close (m) above its support is planted; a neck this far above the hips, upright.
PLANTED_M = 0.15
UPRIGHT_M = 0.35


@dataclass(frozen=True)
class Thresholds:
    """Where a measure becomes a failure (metres, seconds, radians; docs/validation.md)."""

    max_speed_m_s: float = 30.0  # a joint faster than this between frames, the pins holding the body: explosion
    max_thrown_speed_m_s: float = 45.0  # the same once a car's touch threw it (its hit throws limbs faster)
    max_stretch_m: float = 0.03  # a rigid joint pair longer or shorter than its median by this
    penetration_m: float = 0.08  # a joint or limb midpoint this deep inside a box or the ground
    knee_hyperextension_m: float = 0.08  # knee this far behind the hip–ankle line
    on_screen_fraction: float = 0.5  # protagonist in view in fewer frames than this: off-screen
    min_instance_pixels: int = 30  # fewer protagonist pixels than this: hidden
    camera_inside_m: float = 0.02  # the camera this deep inside geometry
    perturbation_m: float = 0.30  # necessary-muscle joints this far from the base motion (mean)
    slide_m_s: float = 0.5  # the slowest planted foot's mean horizontal speed above this


@dataclass
class PersonSeries:
    """One person's 3-D joints over the frames of a video."""

    person_id: int
    role: str
    frames: np.ndarray  # (T,) frame numbers, sorted
    joints: np.ndarray  # (T, 13, 3)
    pinned: np.ndarray  # (T,) root pin ≥ 0.5: the body follows its animation, physics does not own it
    #: (T,) let go by a touch the plan allows (car_hit's protagonist after the hit), or None
    thrown: np.ndarray | None = None


@dataclass
class CameraSeries:
    frames: np.ndarray  # (T,)
    poses: np.ndarray  # (T, 4, 4) camera to world
    intrinsics: np.ndarray  # (T, 4) fx, fy, cx, cy


@dataclass
class VideoFailures:
    """The measures of one video and the failures they amount to."""

    video_id: str
    measures: dict[str, float] = field(default_factory=dict)
    failures: list[tuple[Reason, str]] = field(default_factory=list)

    @property
    def failed(self) -> bool:
        return bool(self.failures)


def _runs(keys: Sequence[np.ndarray]) -> list[np.ndarray]:
    """The rows of each distinct key (the last array the first sort key), each run's rows
    ordered by the first array (its frames): one sort, one pass."""
    order = np.lexsort(keys)
    if len(order) == 0:
        return []
    cut = np.zeros(len(order), dtype=bool)
    cut[0] = True
    for key in keys[1:]:
        sorted_key = key[order]
        cut[1:] |= sorted_key[1:] != sorted_key[:-1]
    return np.split(order, np.flatnonzero(cut)[1:])


def people_series(table: pa.Table, source: str = "people.parquet") -> dict[str, list[PersonSeries]]:
    """``people.parquet`` → per video, per person, the joints ordered by frame; a
    ``PhavUserError`` naming the column where one the check reads is missing or malformed."""
    vids = tables.keys(table, "video_id", source)
    frames = tables.numbers(table, "frame", source, key=True)
    pids = tables.numbers(table, "person_id", source, key=True)
    roles = tables.keys(table, "role", source)
    joints = tables.fixed_lists(table, "joints3d", 39, source).reshape(-1, 13, 3)
    weights = tables.fixed_lists(table, "pin_weight", 15, source)
    unknown = ~np.isfinite(weights).all(axis=1)
    if unknown.any():  # NaN ≥ 0.5 is False: read as released, the pinned measures went unjudged
        raise PhavUserError(f"{int(unknown.sum())} rows with a weight that is not a number", source=source,
                            field="pin_weight")  # fmt: skip
    pinned = weights[:, 0] >= 0.5
    out: dict[str, list[PersonSeries]] = {}
    for rows in _runs((frames, pids, vids)):
        i0 = rows[0]
        out.setdefault(str(vids[i0]), []).append(
            PersonSeries(int(pids[i0]), str(roles[i0]), frames[rows].astype(int), joints[rows], pinned[rows])
        )
    return out


def camera_series(table: pa.Table, source: str = "cameras.parquet") -> dict[str, CameraSeries]:
    """``cameras.parquet`` → per video the camera poses ordered by frame; a
    ``PhavUserError`` naming the column where one the check reads is missing or malformed."""
    vids = tables.keys(table, "video_id", source)
    frames = tables.numbers(table, "frame", source, key=True)
    poses = tables.fixed_lists(table, "cam_to_world", 16, source).reshape(-1, 4, 4)
    intr = np.stack([tables.numbers(table, c, source) for c in ("fx", "fy", "cx", "cy")], axis=1)
    return {str(vids[rows[0]]): CameraSeries(frames[rows].astype(int), poses[rows], intr[rows])
            for rows in _runs((frames, vids))}  # fmt: skip


class BoxSet:
    """An environment's collision boxes as arrays, for vectorised inside / crossing tests; a
    collider with hulls (a parked car) is its hulls, as it collides."""

    def __init__(self, colliders: Sequence[Collider], ground_z: float = -np.inf):
        self.colliders = tuple(colliders)
        self.ground_z = ground_z
        self.center = np.array([c.center for c in colliders], dtype=float).reshape(-1, 3)
        self.half = np.array([c.half_size for c in colliders], dtype=float).reshape(-1, 3)
        # A box standing on the ground (a raised plaza, a bank, a step) is solid down to it
        # and below: a point sunk into it is as deep as it is under its top, not nearer the
        # buried bottom face the deeper it goes.
        self.grounded = self.center[:, 2] - self.half[:, 2] <= ground_z + GROUNDED_TOLERANCE_M
        # math's cos and sin, not numpy's CPU-dispatched kernels: a point on a box's face is
        # inside or out by the same bits on every machine.
        yaw = [math.radians(c.yaw_deg) for c in colliders]
        self.cos = np.array([math.cos(a) for a in yaw], dtype=float)
        self.sin = np.array([math.sin(a) for a in yaw], dtype=float)
        # Each hull as its faces' planes (n, d) in its box's frame: n·p + d ≤ 0 inside.
        self.planes = {i: [ConvexHull(np.asarray(h)).equations for h in c.hulls]
                       for i, c in enumerate(colliders) if c.hulls}  # fmt: skip

    def plus(self, extra: Sequence[Collider]) -> BoxSet:
        """These boxes and ``extra`` after them, on the same ground: these boxes' arrays and
        hulls' planes are reused, not computed again (an action's few boxes beside an
        environment's many, per video)."""
        more = BoxSet(extra, self.ground_z)
        both = copy.copy(self)
        both.colliders = self.colliders + more.colliders
        for name in ("center", "half", "grounded", "cos", "sin"):
            setattr(both, name, np.concatenate([getattr(self, name), getattr(more, name)]))
        n = len(self.colliders)
        both.planes = {**self.planes, **{n + i: e for i, e in more.planes.items()}}
        return both

    def support(self, points: np.ndarray, reach: float) -> np.ndarray:
        """What each point (..., 3) stands on: the top of the highest walkable box (a road,
        a terrace, a stair of the action's flight) whose footprint holds it and whose top is
        at most ``reach`` above it, else the ground (``walkable_heights`` over these boxes)."""
        local = self.local(points)
        tops = self.center[:, 2] + self.half[:, 2]
        walkable = np.array([c.pixel_class in WALKABLE_PIXEL_CLASSES for c in self.colliders], dtype=bool)
        holds = (np.abs(local[..., 0]) <= self.half[:, 0]) & (np.abs(local[..., 1]) <= self.half[:, 1])
        under = walkable & holds & (tops <= points[..., 2:3] + reach)
        return np.maximum(np.where(under, tops, -np.inf).max(axis=-1, initial=-np.inf), self.ground_z)

    def local(self, points: np.ndarray) -> np.ndarray:
        """Points (..., 3) in every box's frame: (..., B, 3)."""
        d = points[..., None, :] - self.center
        x = d[..., 0] * self.cos + d[..., 1] * self.sin
        y = -d[..., 0] * self.sin + d[..., 1] * self.cos
        return np.stack([x, y, d[..., 2]], axis=-1)

    def depth_inside(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """How deep each point (..., 3) is inside its deepest box (negative: outside all) and
        which box (..., ); with no boxes, −inf and −1."""
        if len(self.colliders) == 0:
            shape = points.shape[:-1]
            return np.full(shape, -np.inf), np.full(shape, -1)
        local = self.local(points)
        room = self.half - np.abs(local)
        room[..., 2] = np.where(self.grounded, self.half[:, 2] - local[..., 2], room[..., 2])
        depth = room.min(axis=-1)  # (..., B)
        for i, hulls in self.planes.items():
            depth[..., i] = _union_depth(local[..., i, :], hulls)
        which = depth.argmax(axis=-1)
        return np.take_along_axis(depth, which[..., None], axis=-1)[..., 0], which

    def crossed(self, a: np.ndarray, b: np.ndarray, min_height: float = 1.0) -> np.ndarray:
        """For segments a→b (T, 3), the index of a box at least ``min_height`` tall whose
        interior the segment passes through (slab test; each hull of a collider that has
        them, clipped), −1 when none."""
        out = np.full(len(a), -1)
        if len(self.colliders) == 0:
            return out
        la, lb = self.local(a), self.local(b)  # (T, B, 3)
        d = lb - la
        with np.errstate(divide="ignore", invalid="ignore"):
            t0 = (-self.half - la) / d
            t1 = (self.half - la) / d
        lo = np.where(d == 0, np.where(np.abs(la) < self.half, -np.inf, np.inf), np.minimum(t0, t1))
        hi = np.where(d == 0, np.where(np.abs(la) < self.half, np.inf, -np.inf), np.maximum(t0, t1))
        enter, leave = lo.max(axis=-1), hi.min(axis=-1)
        hit = (enter < leave) & (leave > 0) & (enter < 1)
        for i, hulls in self.planes.items():
            hit[:, i] = np.any([_through_hull(la[:, i], lb[:, i], e) for e in hulls], axis=0)
        hit &= 2 * self.half[:, 2] >= min_height
        any_hit = hit.any(axis=-1)
        out[any_hit] = hit[any_hit].argmax(axis=-1)
        return out


def _plane_distances(points: np.ndarray, planes: np.ndarray) -> np.ndarray:
    """Signed distances (..., F) of points (..., 3) from face planes (F, 4) (n·p + d, > 0
    outside), as products and sums of elements (no BLAS kernel): the same bits on every CPU."""
    p = points[..., None, :]
    return p[..., 0] * planes[:, 0] + p[..., 1] * planes[:, 1] + p[..., 2] * planes[:, 2] + planes[:, 3]


#: Directions a point's way out of a union of hulls is sought along besides the hulls' own
#: face normals: the 26 of a cube's faces, edges and corners (an edge of the union nearest a
#: point is read at most about 10 % too deep).
_WAYS_OUT = np.array([(x, y, z) for x in (-1, 0, 1) for y in (-1, 0, 1) for z in (-1, 0, 1) if (x, y, z) != (0, 0, 0)],
                     dtype=float)  # fmt: skip
_WAYS_OUT /= np.sqrt((_WAYS_OUT * _WAYS_OUT).sum(axis=1))[:, None]
#: Hulls whose faces lie within this (m) of each other along a way out are joined: a car's
#: body and its greenhouse share the belt's plane.
_SEAM_M = 1e-4


def _union_depth(points: np.ndarray, hulls: Sequence[np.ndarray]) -> np.ndarray:
    """How deep points (..., 3) are inside the union of convex hulls (each its face planes
    (F, 4)), negative outside: how far the nearest way out is, the hulls joined where they
    touch or overlap. The deepest single hull reads a point 1 cm below the seam between a
    car's body and its greenhouse as 1 cm deep."""
    single = np.max([-_plane_distances(points, e).max(axis=-1) for e in hulls], axis=0)
    inside = single > 0
    if len(hulls) < 2 or not inside.any():
        return single
    p = points[inside]  # (M, 3)
    ways = np.concatenate([_WAYS_OUT, *(e[:, :3] for e in hulls)])  # (K, 3): the face normals' ways exact
    spans = [_ray_spans(p, ways, e) for e in hulls]  # each (M, K) entering and leaving distances
    out = np.zeros((len(p), len(ways)))
    for _ in hulls:  # each pass may carry the way on into one more hull
        for enter, leave in spans:
            carries = (enter <= out + _SEAM_M) & (leave > out) & (enter < leave)
            out = np.where(carries, leave, out)
    depth = single.copy()
    depth[inside] = np.maximum(single[inside], out.min(axis=1))
    return depth


def _ray_spans(points: np.ndarray, ways: np.ndarray, planes: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Where rays from points (M, 3) along unit ``ways`` (K, 3) enter and leave the convex
    hull of face ``planes`` (F, 4): (M, K) distances each, enter ≥ leave where they miss."""
    start = _plane_distances(points, planes)[:, None, :]  # (M, 1, F): > 0 outside that face
    rate = (ways[:, None, 0] * planes[:, 0] + ways[:, None, 1] * planes[:, 1]
            + ways[:, None, 2] * planes[:, 2])[None]  # (1, K, F)  # fmt: skip
    with np.errstate(divide="ignore", invalid="ignore"):
        t = -start / rate
    enter = np.where(rate < 0, t, -np.inf).max(axis=-1)
    leave = np.where(rate > 0, t, np.inf).min(axis=-1)
    parallel_outside = ((rate == 0) & (start >= 0)).any(axis=-1)
    return enter, np.where(parallel_outside, -np.inf, leave)


def _through_hull(a: np.ndarray, b: np.ndarray, planes: np.ndarray) -> np.ndarray:
    """For segments a→b (T, 3), whether each passes through the interior of the convex hull
    of face ``planes`` (F, 4): clipped against every face (Cyrus–Beck)."""
    outside_a = _plane_distances(a, planes)  # (T, F): > 0 outside that face at a
    toward = _plane_distances(b, planes) - outside_a  # how fast the segment moves out through each face
    with np.errstate(divide="ignore", invalid="ignore"):
        t = -outside_a / toward
    enter = np.where(toward < 0, t, -np.inf).max(axis=1)
    leave = np.where(toward > 0, t, np.inf).min(axis=1)
    parallel_outside = ((toward == 0) & (outside_a >= 0)).any(axis=1)
    return (enter < leave) & (leave > 0) & (enter < 1) & ~parallel_outside


#: How far (m) above the ground a box's bottom may lie and the box still stand on it.
GROUNDED_TOLERANCE_M = 0.02

_BOXES: dict[str, BoxSet] = {}


def boxes(environment: str) -> BoxSet:
    """The environment's collision boxes (cached per process)."""
    if environment not in _BOXES:
        scene = ENVIRONMENT_SCENES[environment]
        _BOXES[environment] = BoxSet(scene.colliders, scene.ground_z)
    return _BOXES[environment]


def clip_boxes(recipe: Recipe, plan: ScenePlan | None = None) -> BoxSet:
    """The environment's boxes and those the recipe's action builds (stairs, a chair, a door's
    frame, a pull-up bar), from its ``plan`` (re-planned from the recipe when not given)."""
    built = (plan if plan is not None else plan_scene(recipe)).boxes
    if not built:
        return boxes(recipe.environment.name)
    return boxes(recipe.environment.name).plus([Collider(b.pixel_class, b.center, b.half_size, b.yaw_deg)
                                                for b in built])  # fmt: skip


def _project(joints: np.ndarray, cams: CameraSeries, index: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Pixel coordinates (T, 13, 2) and camera depths (T, 13) of joints at the given camera rows."""
    pose = cams.poses[index]
    r = pose[:, :3, :3]
    t = pose[:, :3, 3]
    cam = np.einsum("tji,tkj->tki", r, joints - t[:, None, :])  # R^T (p − t)
    z = -cam[..., 2]
    fx, fy, cx, cy = (cams.intrinsics[index, i][:, None] for i in range(4))
    with np.errstate(divide="ignore", invalid="ignore"):
        uv = np.stack([cx + fx * cam[..., 0] / z, cy - fy * cam[..., 1] / z], axis=-1)
    return uv, z


def base_motion_joints(recipe: Recipe, plan: ScenePlan | None = None) -> tuple[np.ndarray, np.ndarray] | None:
    """The protagonist's animated (unperturbed) joints per frame (T, 13, 3) and whether the
    pins hold the body to the animation then (T,), from its ``plan`` (re-planned from the
    recipe when not given)."""

    plan = plan if plan is not None else plan_scene(recipe)
    person = next((p for p in plan.people if p.person_id == recipe.protagonist.person_id), None)
    if person is None:
        return None
    steps = np.arange(recipe.n_frames) * plan.substeps
    t = person.targets
    pos, _ = forward_kinematics(person.dims, t.root_pos[steps], t.root_quat[steps], t.q[steps])
    return pos[:, list(JOINT_BODIES)], person.pin[steps] >= 0.5


def necessary_joints(action: str) -> list[int]:
    """Joints moved by the action's necessary muscles (a joint is its body's origin, so it
    moves with its parent body)."""

    necessary = set(ACTION_SCENES[action].necessary_muscles)
    return [j for j, b in enumerate(JOINT_BODIES) if BONES[b].parent in necessary]


def video_failures(
    recipe: Recipe,
    people: Sequence[PersonSeries],
    cams: CameraSeries | None,
    *,
    instance_pixels: Mapping[int, Sequence[int]] | None = None,
    thresholds: Thresholds = Thresholds(),
) -> VideoFailures:
    """Every failure measure of one video; ``failures`` lists those over their threshold.

    Each person's pose first, then the protagonist's: in view, the camera outside geometry,
    the perturbation and the feet.
    """
    th = thresholds
    out = VideoFailures(recipe.video_id)
    m = out.measures

    def fail(reason: Reason, message: str) -> None:
        out.failures.append((reason, message))

    plan = plan_scene(recipe)  # once: the action's boxes and, for a perturbation, its base motion
    box = clip_boxes(recipe, plan)
    framed = [_frames_valid(recipe, person, fail) for person in people]
    people = [_held_as_planned(person, plan) if ok else person for person, ok in zip(people, framed, strict=True)]
    valid = {id(person) for person, ok in zip(people, framed, strict=True) if ok}
    for person in people:
        if id(person) in valid:
            _pose(recipe, person, box, th, m, fail)
    protagonist = next((p for p in people if p.person_id == recipe.protagonist.person_id), None)
    if protagonist is None:  # a broken table, not a protagonist out of view
        fail(Reason.METADATA_INVALID,
             f"people.parquet: no rows for the protagonist (person_id {recipe.protagonist.person_id})")  # fmt: skip
        return out
    if id(protagonist) not in valid or not np.isfinite(protagonist.joints).all():
        return out
    if _cameras_valid(recipe, protagonist, cams, fail):
        _off_screen(recipe, protagonist, cams, instance_pixels, th, m, fail)
        _camera_in_geometry(recipe, cams, box, th, m, fail)
    _perturbation(recipe, protagonist, plan, th, m, fail)
    _sliding(recipe, protagonist, box, th, m, fail)
    _physics_stopped(recipe, protagonist, plan, fail)
    return out


def _held_as_planned(person: PersonSeries, plan: ScenePlan) -> PersonSeries:
    """The person with the pins the plan holds them by, not the ones the table records: a
    written weight of 0 would switch off the knee, perturbation and sliding measures. Only
    a body the plan lets a touch release (the protagonist of ``car_hit``) may be let go
    earlier than planned, as the table records it."""
    planned = next((p for p in plan.people if p.person_id == person.person_id), None)
    if planned is None:
        return person
    # A physical body's plan runs on the physics steps, a kinematic walker's on the frames.
    held = planned.pin[person.frames * (plan.substeps if planned.physical else 1)] >= 0.5
    if planned.release_on_contact_with is None:
        return replace(person, pinned=held)
    return replace(person, pinned=held & person.pinned, thrown=held & ~person.pinned)


def _frames_valid(recipe: Recipe, person: PersonSeries, fail: _Fail) -> bool:
    """A person's rows name each frame of the clip at most once (a gap is measured across)."""
    frames = person.frames
    who = f"{person.role} {person.person_id}"
    if len(frames) and (frames[0] < 0 or frames[-1] >= recipe.n_frames):
        outside = int(frames[0] if frames[0] < 0 else frames[-1])
        fail(Reason.METADATA_INVALID,
             f"people.parquet: {who} has a row for frame {outside}, outside the clip's {recipe.n_frames}")  # fmt: skip
        return False
    if (np.diff(frames) == 0).any():
        twice = int(frames[1:][np.diff(frames) == 0][0])
        fail(Reason.METADATA_INVALID, f"people.parquet: {who} has two rows for frame {twice}")
        return False
    return True


def _cameras_valid(recipe: Recipe, protagonist: PersonSeries, cams: CameraSeries | None, fail: _Fail) -> bool:
    """The video's camera rows (None: none given, its measures not taken): one per frame of
    the protagonist's, none outside the clip, finite. Where they are not, the camera's
    measures cannot be taken, and that is a broken file."""
    if cams is None:
        return False
    if len(cams.frames) and (cams.frames[0] < 0 or cams.frames[-1] >= recipe.n_frames):
        outside = int(cams.frames[0] if cams.frames[0] < 0 else cams.frames[-1])
        fail(Reason.METADATA_INVALID,
             f"cameras.parquet: a row for frame {outside}, outside the clip's {recipe.n_frames}")  # fmt: skip
        return False
    missing = ~np.isin(protagonist.frames, cams.frames)
    if missing.any():
        fail(Reason.METADATA_INVALID, f"cameras.parquet: no row for {int(missing.sum())} of the protagonist's "
             f"{len(missing)} frames (first {int(protagonist.frames[missing][0])})")  # fmt: skip
        return False
    if (np.diff(cams.frames) == 0).any():
        fail(
            Reason.METADATA_INVALID,
            f"cameras.parquet: two rows for frame {int(cams.frames[1:][np.diff(cams.frames) == 0][0])}",
        )
        return False
    for name, values in (
        ("cam_to_world", cams.poses.reshape(len(cams.poses), -1)),
        ("fx, fy, cx, cy", cams.intrinsics),
    ):
        bad = ~np.isfinite(values).all(axis=1)
        if bad.any():
            fail(Reason.NAN_POSE, f"cameras.parquet: {name} not finite in {int(bad.sum())} frames "
                 f"(first {int(cams.frames[bad][0])})")  # fmt: skip
            return False
    return True


def _pose(recipe: Recipe, person: PersonSeries, box: BoxSet, th: Thresholds, m: dict[str, float], fail: _Fail) -> None:
    """One person's joints: finite, no explosion, no interpenetration, knees (not for the
    background actors, who only walk)."""
    j = person.joints
    who = f"{person.role} {person.person_id}"
    if not np.isfinite(j).all():
        bad = np.flatnonzero(~np.isfinite(j).all(axis=(1, 2)))
        fail(Reason.NAN_POSE, f"{who}: non-finite joints in {len(bad)} frames (first {int(person.frames[bad[0]])})")
        return
    _explosion(person, recipe.video.fps, who, th, m, fail)
    _interpenetration(person, recipe.environment.name, box, who, th, m, fail)
    if person.role != "background":
        _knees(j, person.pinned, who, th, m, fail, person.person_id)


def _explosion(person: PersonSeries, fps: int, who: str, th: Thresholds, m: dict[str, float], fail: _Fail) -> None:
    """A joint faster than any body moves, or a rigid pair of joints changing its distance."""
    j = person.joints
    if len(j) > 1:
        # Over each gap between rows, not per row: a missing frame is not a jump.
        spacing = np.diff(person.frames) / fps
        speeds = np.linalg.norm(np.diff(j, axis=0), axis=-1).max(axis=1) / spacing
        m[f"max_joint_speed_m_s/{person.person_id}"] = float(speeds.max())
        # Faster once a touch has thrown the body (a car's hit), not wherever the pins are slack.
        thrown = np.zeros(len(speeds), dtype=bool) if person.thrown is None else person.thrown[1:]
        limit = np.where(thrown, th.max_thrown_speed_m_s, th.max_speed_m_s)
        if (speeds > limit).any():
            k = int(np.argmax(speeds - limit))
            fail(Reason.ENERGY_EXPLOSION, f"{who}: a joint moves at {speeds[k]:.1f} m/s (> {limit[k]:g}"
                 f"{', thrown' if thrown[k] else ''}) at frame {int(person.frames[k + 1])}")  # fmt: skip
    lengths = np.stack([np.linalg.norm(j[:, a] - j[:, b], axis=-1) for a, b in RIGID_PAIRS], axis=1)
    stretch = float(np.abs(lengths - np.median(lengths, axis=0)).max())
    m[f"max_limb_stretch_m/{person.person_id}"] = stretch
    if stretch > th.max_stretch_m:
        fail(Reason.ENERGY_EXPLOSION, f"{who}: a limb changes length by {stretch * 100:.1f} cm")


def _interpenetration(
    person: PersonSeries, environment: str, box: BoxSet, who: str, th: Thresholds, m: dict[str, float], fail: _Fail
) -> None:
    """Joints and limb midpoints deep inside a box (``box``: the environment's and the
    action's) or the ground; else hips passing through a box."""
    j = person.joints
    ground = ENVIRONMENT_SCENES[environment].ground_z
    points = probe_points(j)
    depth, which = box.depth_inside(points)
    below = ground - points[..., 2]
    deepest = float(max(depth.max(), below.max()))
    m[f"penetration_m/{person.person_id}"] = deepest
    if deepest > th.penetration_m:
        t, k = np.unravel_index(int(np.argmax(np.maximum(depth, below))), depth.shape)
        where = f"a {box.colliders[which[t, k]].pixel_class} box" if depth[t, k] >= below[t, k] else "the ground"
        fail(Reason.INTERPENETRATION,
             f"{who}: {deepest * 100:.0f} cm inside {where} at frame {int(person.frames[t])}")  # fmt: skip
        return
    hips = 0.5 * (j[:, _J["left_hip"]] + j[:, _J["right_hip"]])
    crossed = box.crossed(hips[:-1], hips[1:])
    if (crossed >= 0).any():
        t = int(np.flatnonzero(crossed >= 0)[0])
        fail(Reason.INTERPENETRATION, f"{who}: passes through a {box.colliders[crossed[t]].pixel_class} "
             f"box between frames {int(person.frames[t])} and {int(person.frames[t + 1])}")  # fmt: skip


def _off_screen(
    recipe: Recipe,
    protagonist: PersonSeries,
    cams: CameraSeries,
    instance_pixels: Mapping[int, Sequence[int]] | None,
    th: Thresholds,
    m: dict[str, float],
    fail: _Fail,
) -> None:
    """The protagonist in view (four joints in the frame, and enough instance pixels where
    they are known: a count of −1 is a frame the scan never read) in too few frames."""
    index = np.searchsorted(cams.frames, protagonist.frames)  # every frame has its row (_cameras_valid)
    uv, z = _project(protagonist.joints, cams, index)
    w, h = recipe.video.width, recipe.video.height
    inside = (z > 0.05) & (uv[..., 0] >= 0) & (uv[..., 0] < w) & (uv[..., 1] >= 0) & (uv[..., 1] < h)
    seen = inside.sum(axis=1) >= 4
    if instance_pixels is not None and recipe.protagonist.person_id in instance_pixels:
        counts = np.asarray(instance_pixels[recipe.protagonist.person_id])
        # Frames the scan never read (−1: a truncated shard, or past a manifest at odds with
        # the recipe, which the integrity check reports) are judged by the joints alone.
        held = protagonist.frames < len(counts)
        pixels = np.full(len(held), -1, dtype=counts.dtype)
        pixels[held] = counts[protagonist.frames[held]]
        seen &= (pixels < 0) | (pixels >= th.min_instance_pixels)
    share = float(seen.mean())
    m["protagonist_on_screen"] = share
    if share < th.on_screen_fraction:
        fail(Reason.OFF_SCREEN, f"the protagonist is in view in {share:.0%} of frames")


def _camera_in_geometry(
    recipe: Recipe, cams: CameraSeries, box: BoxSet, th: Thresholds, m: dict[str, float], fail: _Fail
) -> None:
    """The camera inside a box (the environment's and the action's) or below the ground."""
    env = recipe.environment.name
    ground = ENVIRONMENT_SCENES[env].ground_z
    cam_pos = cams.poses[:, :3, 3]
    depth, _ = box.depth_inside(cam_pos)
    inside_m = float(max(depth.max(), (ground - cam_pos[:, 2]).max()))
    m["camera_inside_m"] = inside_m
    if inside_m > th.camera_inside_m:
        t = int(np.argmax(np.maximum(depth, ground - cam_pos[:, 2])))
        fail(Reason.CAMERA_IN_GEOMETRY,
             f"the camera is {inside_m * 100:.0f} cm inside geometry at frame {int(cams.frames[t])}")  # fmt: skip


def _knees(
    j: np.ndarray, pinned: np.ndarray, who: str, th: Thresholds, m: dict[str, float], fail: _Fail, pid: int
) -> None:
    """Knees bent backwards: the knee behind the hip–ankle line, 'behind' from the torso.

    Judged while the pins hold the body. The torso's forward stands in for the knee's own
    bending direction, which only holds while the hips are near their rest twist; a released
    ragdoll tumbling after a car hit twists hip and waist together, and its knees (MuJoCo
    hinges, limited to 0–155°) measured up to 35 cm "behind" with every knee angle ≥ 0.
    """
    hips_mid = 0.5 * (j[:, _J["left_hip"]] + j[:, _J["right_hip"]])
    up = j[:, _J["neck"]] - hips_mid
    right = j[:, _J["right_hip"]] - j[:, _J["left_hip"]]
    forward = np.cross(up, right)
    forward /= np.maximum(np.linalg.norm(forward, axis=-1, keepdims=True), 1e-9)
    worst = 0.0
    for side in ("left", "right"):
        hip, knee, ankle = (j[:, _J[f"{side}_{n}"]] for n in ("hip", "knee", "ankle"))
        axis = ankle - hip
        axis /= np.maximum(np.linalg.norm(axis, axis=-1, keepdims=True), 1e-9)
        off = (knee - hip) - np.sum((knee - hip) * axis, axis=-1, keepdims=True) * axis
        # "Behind" is the torso's forward made perpendicular to the leg, so a seated leg
        # (hip–ankle line pointing forward) is judged in its own plane; where forward runs
        # almost along the leg (< 17°) the side is undefined and the frame is not judged.
        back = forward - np.sum(forward * axis, axis=-1, keepdims=True) * axis
        norm = np.linalg.norm(back, axis=-1)
        behind = -np.sum(off * back, axis=-1) / np.maximum(norm, 1e-9)
        worst = max(worst, float(np.where((norm > 0.3) & pinned, behind, 0.0).max(initial=0.0)))
    m[f"knee_hyperextension_m/{pid}"] = worst
    if worst > th.knee_hyperextension_m:
        fail(Reason.JOINT_LIMIT, f"{who}: a knee bends backwards ({worst * 100:.0f} cm behind the hip–ankle line)")


def _perturbation(
    recipe: Recipe, person: PersonSeries, plan: ScenePlan, th: Thresholds, m: dict[str, float], fail: _Fail
) -> None:
    """A random perturbation that moves the action's necessary muscles far from the motion,
    judged while the pins hold the body."""
    if recipe.variation.kind != "random_perturbation":
        return
    base = base_motion_joints(recipe, plan)
    if base is None:
        return
    target, pinned = base
    frames = person.frames[person.frames < len(target)]
    # While the plan pins the body and the recorded pins still hold it: a body released by
    # a hit (the car of car_hit) leaves its motion because of the hit, not the perturbation.
    keep = pinned[frames] & person.pinned[: len(frames)]
    if not keep.any():
        return
    hips = [_J["left_hip"], _J["right_hip"]]
    # Pelvis-relative: the hips are the reference, so they are not among the joints measured.
    joints = [j for j in necessary_joints(recipe.action) if j not in hips]
    if not joints:
        return
    got = person.joints[: len(frames)][keep]
    want = target[frames][keep]
    got = got[:, joints] - got[:, hips].mean(axis=1, keepdims=True)
    want = want[:, joints] - want[:, hips].mean(axis=1, keepdims=True)
    distance = float(np.linalg.norm(got - want, axis=-1).mean())
    m["perturbation_m"] = distance
    if distance > th.perturbation_m:
        fail(Reason.PERTURBATION_TOO_STRONG,
             f"the necessary muscles are {distance * 100:.0f} cm from the base motion on average")  # fmt: skip


#: How far (m) the protagonist's planned motion must move while its recorded joints hold
#: still, bit for bit, to the clip's end, for the physics to count as stopped.
STOPPED_MOTION_M = 0.05


def _physics_stopped(recipe: Recipe, person: PersonSeries, plan: ScenePlan, fail: _Fail) -> None:
    """The generator stops a clip's physics where a step explodes and holds the last good
    state to the end: every joint still, bit for bit, while the pins should still move the
    body along its motion. A body at rest is never so still under the servos, and a
    released ragdoll's frames are not judged (only those the pins hold)."""
    j = person.joints
    if len(j) < 3:
        return
    same = np.all(j[1:] == j[:-1], axis=(1, 2))
    if not same[-1]:
        return
    still = len(same) - int(np.argmin(same[::-1])) if not same.all() else 0  # first row of the still tail
    base = base_motion_joints(recipe, plan)
    if base is None:
        return
    target, _ = base
    rows = np.arange(still, len(j))
    rows = rows[person.pinned[rows] & (person.frames[rows] < len(target))]
    if len(rows) < 2:
        return
    moved = float(np.linalg.norm(target[person.frames[rows]] - target[person.frames[rows[0]]], axis=-1).max())
    if moved > STOPPED_MOTION_M:
        fail(Reason.ENERGY_EXPLOSION,
             f"the physics stopped at frame {int(person.frames[still])}: every joint of the protagonist still to the "
             f"clip's end while its motion moves {moved:.2f} m")  # fmt: skip


def _sliding(
    recipe: Recipe, person: PersonSeries, box: BoxSet, th: Thresholds, m: dict[str, float], fail: _Fail
) -> None:
    """Feet on the ground that move: mean horizontal speed of the slowest planted ankle
    (not for an action whose feet slide on purpose: the moonwalk). A foot stands on the
    environment's walkable boxes and the action's (a flight of stairs)."""
    if len(person.frames) < 3 or ACTION_SCENES[recipe.action].slides_feet:
        return
    ankles = person.joints[:, [_J["left_ankle"], _J["right_ankle"]]]  # (T, 2, 3)
    support = box.support(ankles, 0.05)
    height = ankles[..., 2] - support
    step = np.diff(ankles, axis=0) * recipe.video.fps / np.diff(person.frames)[:, None, None]
    horizontal = np.linalg.norm(step[..., :2], axis=-1)
    vertical = np.abs(step[..., 2])
    # Only while upright: a released ragdoll sliding along the ground after a fall is physics.
    hips = 0.5 * (person.joints[:, _J["left_hip"], 2] + person.joints[:, _J["right_hip"], 2])
    upright = person.joints[:, _J["neck"], 2] - hips > UPRIGHT_M
    # And while pinned: a released ragdoll (car hit, dive) is thrown, not walking.
    owned = (upright & person.pinned)[:-1, None]
    planted = (height[:-1] < PLANTED_M) & (height[1:] < PLANTED_M) & (vertical < 0.3) & owned
    # A low foot may be swinging (mid-swing clearance is a few cm), but a walker always has
    # one foot that stays put: per frame, the slowest low foot is the one that must not move.
    some = planted.any(axis=1)
    if some.sum() < 3:
        return
    speed = float(np.where(planted, horizontal, np.inf)[some].min(axis=1).mean())
    m["planted_foot_speed_m_s"] = speed
    if speed > th.slide_m_s:
        fail(Reason.FOOT_SLIDING, f"planted feet slide at {speed:.2f} m/s on average")


def check_failures(
    recipes: Mapping[str, Recipe],
    people: pa.Table,
    cameras: pa.Table,
    *,
    instance_pixels: Mapping[str, Mapping[int, Sequence[int]]] | None = None,
    budget: float = DEFAULT_BUDGET,
    thresholds: Thresholds = Thresholds(),
    source: str = "people.parquet",
    progress: Any = None,
) -> tuple[CheckResult, list[VideoFailures]]:
    """The failures check over every video with a recipe and metadata rows; a table it
    cannot read fails it with one finding naming the file and the column."""
    report = Report()
    try:
        series = people_series(people, source)
        cams = camera_series(cameras)
    except PhavUserError as e:
        report.add(Finding(Reason.METADATA_INVALID, str(e), file=e.source))
        return CheckResult.from_report("failures", report, f"cannot read the tables: {e}", {}), []
    results: list[VideoFailures] = []
    for vid in sorted(recipes):
        recipe = recipes[vid]
        rows = series.get(vid)
        if not rows:
            report.add(Finding(Reason.MISSING_FILE, "no rows in people.parquet", file=source, video_id=vid))
            continue
        pixels = instance_pixels.get(vid) if instance_pixels is not None else None
        if vid not in cams:
            report.add(Finding(Reason.METADATA_INVALID, "no rows in cameras.parquet", file="cameras.parquet",
                               video_id=vid))  # fmt: skip
        result = video_failures(recipe, rows, cams.get(vid), instance_pixels=pixels, thresholds=thresholds)
        results.append(result)
        for reason, message in result.failures:
            hard = reason in (Reason.NAN_POSE, Reason.METADATA_INVALID)
            # A camera's failure is the cameras table's; every other one is the people table's.
            camera = reason == Reason.CAMERA_IN_GEOMETRY or message.startswith("cameras.parquet:")
            where = "cameras.parquet" if camera else source
            report.add(Finding(reason, message, file=where, video_id=vid, numbers=dict(result.measures),
                               severity="fail" if hard else "warn"))  # fmt: skip
        if progress is not None:
            progress(1)
    failed = sum(r.failed for r in results)
    rate = failed / len(results) if results else 0.0
    if rate > budget:
        report.add(Finding(
            Reason.FAILURE_BUDGET,
            f"{failed} of {len(results)} videos ({rate:.1%}) show failure cases; the budget is {budget:.0%}",
            file=source, numbers={"failed": failed, "videos": len(results), "rate": rate, "budget": budget,
                                  "failed_videos": [r.video_id for r in results if r.failed]},
        ))  # fmt: skip
    by_reason: dict[str, int] = {}
    for r in results:
        for reason in dict.fromkeys(reason for reason, _ in r.failures):
            by_reason[reason.value] = by_reason.get(reason.value, 0) + 1
    numbers = {"videos": len(results), "failed": failed, "rate": rate, "budget": budget, "by_reason": by_reason}
    summary = f"{failed}/{len(results)} videos with failure cases ({rate:.1%}, budget {budget:.0%})"
    return CheckResult.from_report("failures", report, summary, numbers), results
