"""``plan_scene(recipe) -> ScenePlan``: the planning steps of one video, in order.

The protagonist (standing on a built flight for climb_stairs), the rules of the action
and its variation, the props the action uses, the supporting characters and their ties,
the background pedestrians, the camera's start and the traffic. Each step lives in the
module named for what it plans; this one only calls them in order.
"""

from __future__ import annotations

import math

import numpy as np

from phav_generator.motion.skeleton import forward_kinematics
from phav_generator.physics.plan.background import background_people
from phav_generator.physics.plan.builder import PlanBuilder
from phav_generator.physics.plan.camera import (
    LANE_MARGIN_MIN_M,
    anchor_point,
    camera_anchor,
    clear_camera_start,
    driven_lanes,
    framed_partner,
    view_blockers,
)
from phav_generator.physics.plan.car_hit import car_hit
from phav_generator.physics.plan.furniture import chair_under_pelvis, pull_up_bar
from phav_generator.physics.plan.handheld import catch, free_hand, hands, hold, kick, pick, throw
from phav_generator.physics.plan.obstacles import let_go_at_obstacles
from phav_generator.physics.plan.people import plan_person
from phav_generator.physics.plan.push import push_target
from phav_generator.physics.plan.ragdoll_rules import dive_floor, limp, stagger
from phav_generator.physics.plan.scene_plan import PersonPlan, PropPlan, ScenePlan, StaticBox
from phav_generator.physics.plan.stairs import build_stairs
from phav_generator.physics.plan.supporting import arm_pose_for_tie, loosen_tied_arms, supporting_people
from phav_generator.physics.plan.timestep import DEFAULT_PHYSICS_HZ, choose_substeps
from phav_generator.physics.plan.variations import apply_variation
from phav_generator.physics.traffic import box_footprints, footprint_points, plan_traffic
from phav_spec.recipe import Recipe
from phav_spec.scene import ACTION_SCENES, ENVIRONMENT_SCENES
from phav_spec.seeding import stream


def plan_scene(recipe: Recipe, *, physics_hz: int = DEFAULT_PHYSICS_HZ) -> ScenePlan:
    """The simulation plan of a recipe (deterministic, pure)."""
    substeps = choose_substeps(recipe, physics_hz)
    b = PlanBuilder(recipe, substeps)
    b.walkers = tuple(background_people(b))
    protagonist = _action_props(b, _protagonist_rules(b, _protagonist(b)))
    people = loosen_tied_arms(supporting_people(b, protagonist), b.ties)
    people = [let_go_at_obstacles(b, person) for person in people]
    people = (*people, *b.walkers)
    camera_target = _camera_target(recipe, people[0], people[1] if framed_partner(recipe) else None)
    shift = None if camera_target is None else np.array(camera_target) - np.array(recipe.camera.target)
    anchors = _view_anchors(recipe, people[0], substeps)
    blockers = () if not anchors else view_blockers(
        ENVIRONMENT_SCENES[recipe.environment.name].colliders, b.boxes, b.props)  # fmt: skip
    wide, narrow = driven_lanes(b.props), driven_lanes(b.props, LANE_MARGIN_MIN_M)
    camera_start = clear_camera_start(
        recipe, shift=shift, blockers=blockers, anchors=anchors, keep_out=wide if anchors else ()
    )
    if anchors and any(lane.holds(camera_start) for lane in wide):  # no turn clears the wide lane
        camera_start = clear_camera_start(recipe, shift=shift, blockers=blockers, anchors=anchors, keep_out=narrow)
    # A spring camera started clear of a car's lane keeps out of it: it films the hit from
    # beside the road instead of following the thrown body into the car's way. The wide
    # lane where the start is clear of it, else the narrow one.
    cars = [p for p in b.props if p.object == "car"]
    walls = tuple(
        (lane.center, lane.half, math.degrees(math.atan2(lane.axes[0][1], lane.axes[0][0])))
        for lane in (
            next((lane for lane in ways if not lane.holds(camera_start)), None)
            for ways in zip(driven_lanes(cars), driven_lanes(cars, LANE_MARGIN_MIN_M), strict=True)
        )
        if lane is not None
    )
    return ScenePlan(
        recipe=recipe,
        fps=recipe.video.fps,
        substeps=substeps,
        n_frames=recipe.n_frames,
        people=people,
        props=tuple(b.props),
        boxes=tuple(b.boxes),
        ties=tuple(b.ties),
        manipulations=tuple(b.manipulations),
        stand_offset_z=b.stand_offset_z,
        camera_start=camera_start,
        camera_target=camera_target,
        traffic=plan_traffic(recipe, _planned_obstacles(people, b.props, b.boxes, substeps), camera_start),
        camera_walls=walls if recipe.camera.kind in ("kite", "closeup") else (),
    )


def _camera_target(
    recipe: Recipe, protagonist: PersonPlan, partner: PersonPlan | None = None
) -> tuple[float, float, float] | None:
    """A spring camera's target start: its anchor (``camera_anchor``) on the first animated
    poses (the sampler's T_xyz assumes a standing protagonist alone; a seated or raised one,
    or a partner framed with it, moves the rig)."""
    if recipe.camera.springs is None:
        return None
    first = [forward_kinematics(p.dims, p.targets.root_pos[:1], p.targets.root_quat[:1], p.targets.q[:1])[0][0]
             for p in (protagonist, partner) if p is not None]  # fmt: skip
    return tuple(float(v) for v in camera_anchor(recipe.camera.kind, *first))  # type: ignore[return-value]


#: The cameras whose start turns to see the protagonist: those whose azimuth θ draws round
#: the whole circle (a close-up's is drawn in front of the protagonist; turned, it would
#: film its back), with how long (s) of the planned path each must see: the kite follows
#: after its first seconds in its springs' dead zones, a fixed mount sees the whole clip.
VIEW_CHECK_S = {"kite": 3.0, "indoors": math.inf, "static": math.inf}
#: Every how many frames of the planned path the view is checked.
VIEW_CHECK_EVERY = 5


def _view_anchors(recipe: Recipe, protagonist: PersonPlan, substeps: int) -> tuple[tuple[float, float, float], ...]:
    """The protagonist's planned pelvis every ``VIEW_CHECK_EVERY`` frames of the span its
    camera must see (``VIEW_CHECK_S``); none for a camera that is not turned."""
    seconds = VIEW_CHECK_S.get(recipe.camera.kind)
    if seconds is None:
        return ()
    t = protagonist.targets
    last = len(t.root_pos) - 1 if math.isinf(seconds) else round(seconds * recipe.video.fps) * substeps
    steps = slice(0, min(last, len(t.root_pos) - 1) + 1, VIEW_CHECK_EVERY * substeps)
    pos, _ = forward_kinematics(protagonist.dims, t.root_pos[steps], t.root_quat[steps], t.q[steps])
    return tuple(tuple(float(v) for v in anchor_point("kite", p)) for p in pos)  # type: ignore[misc]


def _protagonist(b: PlanBuilder) -> PersonPlan:
    """The protagonist's animated targets, standing where the recipe says (climb_stairs:
    on the flight built for the clip, raised onto its landing going down)."""
    r = b.recipe
    start = np.array(r.protagonist.position, dtype=np.float64)
    if r.action == "climb_stairs":
        probe = plan_person(
            b, 0, "protagonist", r.protagonist.human, r.motion.base_motion, r.motion.start_s, r.motion.speed,
            r.motion.mirror, tuple(start), r.protagonist.heading_deg,
        )  # fmt: skip
        start = build_stairs(b, probe, start)
    position = tuple(start + np.array([0.0, 0.0, b.stand_offset_z]))
    return plan_person(
        b, 0, "protagonist", r.protagonist.human, r.motion.base_motion, r.motion.start_s, r.motion.speed,
        r.motion.mirror, position, r.protagonist.heading_deg,
    )  # fmt: skip


def _protagonist_rules(b: PlanBuilder, p: PersonPlan) -> PersonPlan:
    """The arm reaching to a partner, the recipe's variation, then the action's own rule
    (car hit, dive floor, stagger, limp) on the protagonist's schedules."""
    action = b.recipe.action
    p = arm_pose_for_tie(p, action)
    p = apply_variation(b, p)
    if action == "car_hit":
        p = car_hit(b, p)
    elif action == "dive_floor":
        p = dive_floor(b, p)
    elif action == "stagger":
        p = stagger(b, p)
    elif action == "limp":
        p = limp(p, rng=stream(b.recipe.seeds.physics, "rules"))
    return p


def _action_props(b: PlanBuilder, p: PersonPlan) -> PersonPlan:
    """The props the action itself uses, what a push pushes, and the objects variation's
    prop; the protagonist as planned, halted where a pushed load stops."""
    r = b.recipe
    action = r.action
    scene = ACTION_SCENES[action]
    right, left = hands(r.motion.base_motion, r.motion.mirror)  # a right-handed take's right hand, and left
    for obj in scene.objects:
        if obj in ("hair_brush", "gun", "golf_club", "baseball_bat"):
            hold(b, p, obj, right)
        elif obj == "bow":
            hold(b, p, obj, left)
        elif obj == "bottle" and action == "pour":
            hold(b, p, "bottle", right)
        elif obj == "cup" and action == "pour":
            hold(b, p, "cup", left)
        elif obj == "bottle" and action == "pick":
            pick(b, p, right)
        elif obj == "ball" and action == "catch":
            catch(b, p, right)
        elif obj == "ball" and action in ("throw", "shoot_ball"):
            throw(b, p, "ball", right, "throw")
        elif obj == "ball" and action == "kick_ball":
            kick(b, p)
        elif obj == "chair":
            chair_under_pelvis(b, p)
        elif obj == "pull_up_bar":
            pull_up_bar(b, p)
    if action == "push":
        p = push_target(b, p)
    if r.variation.kind == "objects":
        free = free_hand(scene.necessary_muscles, right, left)
        hold(b, p, r.variation.object, free, name=f"{r.variation.object}_variation")
    return p


def _planned_obstacles(
    people: tuple[PersonPlan, ...], props: list[PropPlan], boxes: list[StaticBox], substeps: int
) -> np.ndarray:
    """Every person's bodies, every driven prop's footprint and the action's boxes' (F + 1,
    N, 3) per frame, as planned."""
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
    still = box_footprints(boxes)
    parts.append(np.broadcast_to(still, (len(parts[0]), *still.shape)))
    return np.concatenate(parts, axis=1)
