"""Scene plan → MuJoCo model, built with ``MjSpec`` (structure); ``simulate`` owns the state.

The only module that compiles MuJoCo models. People become active ragdolls (free pelvis,
one hinge per skeleton DOF with its limits, a servo per hinge, a driven pin body welded to
the pelvis); props become free bodies (weld constraints grip them), bodies driven
along a path (cars) or static geoms; the environment's colliders, the action's boxes (stairs, chair) and the
ground plane are static; the kite camera is a pair of sliding bodies tied by tendon springs.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import mujoco
import numpy as np

from phav_generator.motion.rotations import matrix_to_quat, yaw_matrix
from phav_generator.motion.skeleton import BONES, DOFS
from phav_generator.physics.plan.scene_plan import PersonPlan, PropPlan, ScenePlan
from phav_spec.scene import ENVIRONMENT_SCENES, Collider

# Collision bits: world geometry, the camera, props, and one bit per physical person so a
# person never collides with itself but does with everyone else.
WORLD_BIT = 1
CAMERA_BIT = 2
PROP_BIT = 4
#: Name prefix of the boxes only the camera collides with (``ScenePlan.camera_walls``).
CAMERA_WALL = "camera_wall_"
#: Sliding friction of a vehicle's hulls against whatever touches them (cloth on paint).
HULL_FRICTION = 0.3
#: A vehicle's contacts are softer than MuJoCo's default 0.02 s: a bumper's foam and the leg
#: it strikes give, so the body follows its swept legs instead of whipping their feet
#: faster than 30 m/s (docs/physics.md has the trade against how deep limbs press in).
HULL_CONTACT_TIMECONST = 0.04
_PERSON_BITS = (8, 16, 32, 64)

#: Servo natural frequency (rad/s) and damping ratio at full strength. A servo is a soft
#: joint equality constraint (MuJoCo's direct stiffness and damping, in acceleration units),
#: solved with the pin, contacts and ties in one problem: an actuator's explicit torque
#: reached the pelvis only after the weld was solved, so the pinned pelvis rocked with the
#: stride by an amount first order in the timestep.
SERVO_OMEGA = 40.0
SERVO_ZETA = 1.0
SERVO_SOLIMP = (0.95, 0.95, 0.001, 0.5, 2.0)
#: A constraint servo lets 1 − d of an outside push through at once and stiffens against
#: the rest by d / (1 − d); the random perturbation's muscles yield more (d = 0.8) so its
#: orbiting pull moves them as far as it moved the earlier torque servos (up to ~0.7 rad).
PERTURBED_SOLIMP = (0.8, 0.8, 0.001, 0.5, 2.0)
CAMERA_RADIUS_M = 0.12
CAMERA_MARGIN_M = 0.1
#: Stiff camera contacts (MuJoCo clamps the time constant to at least two steps).
CAMERA_CONTACT_TIMECONST = 0.004
#: The root pin: a weld from a driven body (the animated pelvis) to the pelvis. Time constant
#: (s) at full pin weight, and a flat impedance.
#: 0.01 s keeps a sprinting pelvis within ~3° of its animation (0.02 s let it swing 15°);
#: MuJoCo raises it to two physics steps where that is larger.
PIN_TIMECONST = 0.01
PIN_SOLIMP = (0.95, 0.95, 0.001, 0.5, 2.0)
#: Mass (kg) and inertia (kg m²) of the pin body: heavy enough that the weld moves the pelvis.
PIN_MASS = 1.0e5
#: Hinge damping of a pushed door (N m s / rad): a heavy door that stops when let go.
DOOR_DAMPING = 15.0


@dataclass
class PersonHandles:
    """Where one ragdoll lives in the model's arrays."""

    person_id: int
    bodies: np.ndarray  # (15,) body ids
    qpos_root: int  # address of the free joint's 7 qpos
    qvel_root: int
    qpos_dofs: np.ndarray  # (30,) qpos addresses of the hinges
    qvel_dofs: np.ndarray
    servo_eqs: np.ndarray  # (30,) joint equality (servo) ids
    pin_qpos: int  # the pin body's free joint
    pin_qvel: int
    pin_eq: int
    geoms: np.ndarray
    lower: np.ndarray
    upper: np.ndarray


@dataclass
class PropHandles:
    """Where one prop lives in the model's arrays, and how it moves."""

    name: str
    body: int
    geom: int
    qpos: int | None  # free joint address (dynamic props), first slide (driven props)
    qvel: int | None
    driven: bool = False  # moves along the plan's path (cars): x, y, z slides from its start
    hinged: bool = False  # turns on a hinge (a door): one qpos, from its closed position
    grip_eqs: list[int] = field(default_factory=list)
    touching: tuple[int, ...] = ()  # the geoms that collide: its own, or its hulls


@dataclass
class CameraHandles:
    """Where the kite camera's bodies, anchor and slides live in the model's arrays."""

    camera_body: int
    target_body: int
    anchor_mocap: int
    camera_geom: int
    camera_qpos: np.ndarray  # (3,) slide joints
    target_qpos: np.ndarray
    camera_qvel: np.ndarray
    target_qvel: np.ndarray


@dataclass
class SceneModel:
    """A compiled scene and where each part of it lives in MuJoCo's arrays."""

    model: mujoco.MjModel
    people: list[PersonHandles]
    props: list[PropHandles]
    camera: CameraHandles | None
    tie_eqs: list[int]
    world_geoms: np.ndarray  # static geoms (ground, colliders, boxes)


def _add_geom_shape(geom, shape: str, size: tuple[float, ...]) -> None:
    if shape == "sphere":
        geom.type = mujoco.mjtGeom.mjGEOM_SPHERE
        geom.size = [size[0], 0, 0]
    elif shape == "capsule":
        geom.type = mujoco.mjtGeom.mjGEOM_CAPSULE
        geom.size = [size[0], size[1], 0]
    elif shape == "box":
        geom.type = mujoco.mjtGeom.mjGEOM_BOX
        geom.size = list(size)
    else:
        raise ValueError(f"unknown prop shape {shape!r}")


def _box(parent, name: str, center, half, yaw_deg: float) -> mujoco.MjsGeom:
    """A static box geom of world geometry (collides with everything that moves)."""
    g = parent.add_geom()
    g.name = name
    g.type = mujoco.mjtGeom.mjGEOM_BOX
    g.size = list(half)
    g.pos = list(center)
    g.quat = list(matrix_to_quat(yaw_matrix(math.radians(yaw_deg))[None])[0])
    g.contype = WORLD_BIT
    g.conaffinity = 0
    return g


def _hull_geom(spec: mujoco.MjSpec, parent, name: str, corners, pos, quat) -> mujoco.MjsGeom:
    """One convex hull of a car as a mesh geom at ``pos``, ``quat``, with a car's contacts:
    clothes slide on paint and glass (a body a car carries slides off as it brakes)."""
    mesh = spec.add_mesh()
    mesh.name = name
    mesh.uservert = np.asarray(corners, dtype=np.float64).ravel().tolist()
    g = parent.add_geom()
    g.name = name
    g.type = mujoco.mjtGeom.mjGEOM_MESH
    g.meshname = name
    g.pos, g.quat = list(pos), list(quat)
    g.friction = [HULL_FRICTION, 0.005, 0.0001]
    g.solref = [HULL_CONTACT_TIMECONST, 1.0]
    g.priority = 2  # over a person's feet: its friction and softness decide
    return g


def _static_hulls(spec: mujoco.MjSpec, name: str, collider: Collider) -> None:
    """A collider's convex hulls (a parked car's) as static mesh geoms of world geometry,
    posed as its box."""
    quat = matrix_to_quat(yaw_matrix(math.radians(collider.yaw_deg))[None])[0]
    for k, corners in enumerate(collider.hulls):
        g = _hull_geom(spec, spec.worldbody, f"{name}_hull{k}", corners, collider.center, quat)
        g.contype = WORLD_BIT
        g.conaffinity = 0


def _add_person(spec: mujoco.MjSpec, p: PersonPlan, bit: int) -> None:
    """An active ragdoll: its bodies, the pin welded to its pelvis, a servo per hinge."""
    _add_ragdoll_bodies(spec, p, bit)
    _add_pin(spec, p)
    _add_servos(spec, p)


def _add_ragdoll_bodies(spec: mujoco.MjSpec, p: PersonPlan, bit: int) -> None:
    """The skeleton's bodies: a free pelvis, one limited hinge per DOF, a capsule per bone."""
    pre = f"p{p.person_id}_"
    dims = p.dims
    others = sum(_PERSON_BITS) & ~bit
    bodies = {}
    for k, bone in enumerate(BONES):
        parent = spec.worldbody if bone.parent is None else bodies[bone.parent]
        body = parent.add_body()
        body.name = pre + bone.name
        body.pos = [0.0, 0.0, 0.0] if bone.parent is None else list(dims.offsets[k])
        body.gravcomp = 1.0
        if bone.parent is None:
            j = body.add_freejoint()
            j.name = pre + "root"
        for d in DOFS:
            if d.body != bone.name:
                continue
            j = body.add_joint()
            j.name = pre + d.name
            j.type = mujoco.mjtJoint.mjJNT_HINGE
            j.axis = list(d.axis)
            j.range = [d.lower, d.upper]
            j.limited = mujoco.mjtLimited.mjLIMITED_TRUE
            j.armature = 0.01
            j.damping = [0.5, 0.0, 0.0]
        cap = dims.capsules[k]
        g = body.add_geom()
        g.name = pre + bone.name
        if cap.a == cap.b:
            g.type = mujoco.mjtGeom.mjGEOM_SPHERE
            g.size = [cap.radius, 0, 0]
            g.pos = list(cap.a)
        else:
            g.type = mujoco.mjtGeom.mjGEOM_CAPSULE
            g.fromto = [*cap.a, *cap.b]
            g.size = [cap.radius, 0, 0]
        g.mass = float(dims.masses[k])
        g.contype = bit
        g.conaffinity = WORLD_BIT | PROP_BIT | others
        g.friction = [1.0, 0.005, 0.0001]
        if bone.name.endswith("_foot") and p.sole_friction != 1.0:
            # MuJoCo takes the larger friction of a pair unless one geom has priority.
            g.friction = [p.sole_friction, 0.005, 0.0001]
            g.priority = 1
        bodies[bone.name] = body


def _add_pin(spec: mujoco.MjSpec, p: PersonPlan) -> None:
    """The root pin: a driven body welded to the pelvis."""
    pre = f"p{p.person_id}_"
    pin = spec.worldbody.add_body()
    pin.name = pre + "pin"
    # A heavy free body whose pose and velocity the simulation sets every step: unlike a
    # mocap body it moves with a velocity, so the weld damps the pelvis's velocity *error*.
    pin.add_freejoint().name = pre + "pin"
    pin.mass = PIN_MASS
    pin.inertia = [PIN_MASS, PIN_MASS, PIN_MASS]
    pin.explicitinertial = True
    pin.gravcomp = 1.0
    eq = spec.add_equality()
    eq.name = pre + "pin"
    eq.type = mujoco.mjtEq.mjEQ_WELD
    eq.objtype = mujoco.mjtObj.mjOBJ_BODY
    eq.name1 = pre + "pin"
    eq.name2 = pre + "pelvis"
    eq.solref = [PIN_TIMECONST, 1.0]
    eq.solimp = list(PIN_SOLIMP)
    eq.data = np.array([0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 1, 0], dtype=np.float64)


def _add_servos(spec: mujoco.MjSpec, p: PersonPlan) -> None:
    """A soft joint-equality servo per hinge (the perturbed muscles' ones more yielding)."""
    pre = f"p{p.person_id}_"
    for d in DOFS:
        # Stiffness and damping are set per step from the muscle's strength.
        eq = spec.add_equality()
        eq.name = pre + "servo_" + d.name
        eq.type = mujoco.mjtEq.mjEQ_JOINT
        eq.objtype = mujoco.mjtObj.mjOBJ_JOINT
        eq.name1 = pre + d.name
        eq.solref = [-(SERVO_OMEGA**2), -2.0 * SERVO_ZETA * SERVO_OMEGA]
        eq.solimp = list(PERTURBED_SOLIMP if d.body in p.perturbed else SERVO_SOLIMP)


def _add_prop(spec: mujoco.MjSpec, prop: PropPlan) -> None:
    if prop.path is not None or prop.dynamic:
        body = spec.worldbody.add_body()
        body.name = "prop_" + prop.name
        body.pos = list(prop.pos)
        body.quat = list(prop.quat) if prop.path is None else [1.0, 0.0, 0.0, 0.0]
        if prop.hinge is not None:
            # A door: turns about the vertical axis through its body origin, heavily damped.
            j = body.add_joint()
            j.name = "prop_" + prop.name
            j.type = mujoco.mjtJoint.mjJNT_HINGE
            j.axis = [0.0, 0.0, 1.0]
            j.range = list(prop.hinge)
            j.limited = mujoco.mjtLimited.mjLIMITED_TRUE
            j.damping = [DOOR_DAMPING, 0.0, 0.0]
        elif prop.path is not None:
            # Driven along its path through three slides: unlike a mocap body it has a
            # velocity, so a contact sees the car coming instead of a teleporting wall.
            body.gravcomp = 1.0
            for axis, name in zip(np.eye(3), "xyz", strict=True):
                j = body.add_joint()
                j.name = f"prop_{prop.name}_{name}"
                j.type = mujoco.mjtJoint.mjJNT_SLIDE
                j.axis = list(axis)
        else:
            j = body.add_freejoint()
            j.name = "prop_" + prop.name
        parent = body
    else:
        parent = spec.worldbody
    g = parent.add_geom()
    g.name = "prop_" + prop.name
    _add_geom_shape(g, prop.shape, prop.size)
    g.pos = list(prop.offset)
    if parent is spec.worldbody:
        g.pos = list(prop.pos)
    if parent is spec.worldbody or prop.path is not None:
        g.quat = list(prop.quat)  # a driven body slides along world axes; its shape turns
    g.mass = prop.mass
    g.contype = 0 if prop.hulls else PROP_BIT
    g.conaffinity = 0 if prop.hulls else WORLD_BIT | PROP_BIT | sum(_PERSON_BITS)
    _add_hulls(spec, parent, prop, g)
    for k, (person, body_name, _t0, _t1, rel_pos, rel_quat) in enumerate(prop.grips):
        eq = spec.add_equality()
        eq.name = f"grip_{prop.name}_{k}"
        eq.type = mujoco.mjtEq.mjEQ_WELD
        eq.objtype = mujoco.mjtObj.mjOBJ_BODY
        eq.name1 = f"p{person}_{body_name}"
        eq.name2 = "prop_" + prop.name
        eq.active = False
        eq.solref = [0.02, 1.0]
        eq.data = np.array([0, 0, 0, *rel_pos, *rel_quat, 1.0, 0.0], dtype=np.float64)


def _add_hulls(spec: mujoco.MjSpec, parent, prop: PropPlan, shape) -> None:
    """A prop's convex hulls as mesh geoms beside its ``shape`` geom, posed as it is: what
    collides in its place (a car's body, greenhouse and bumpers)."""
    for k, corners in enumerate(prop.hulls):
        g = _hull_geom(spec, parent, f"prop_{prop.name}_hull{k}", corners, shape.pos, shape.quat)
        g.density = 0.0  # the shape geom carries the mass
        g.contype = PROP_BIT
        # The camera collides with a vehicle's hulls too: a car that meets it pushes it
        # aside instead of passing through it.
        g.conaffinity = WORLD_BIT | CAMERA_BIT | PROP_BIT | sum(_PERSON_BITS)


def _add_camera(spec: mujoco.MjSpec, plan: ScenePlan) -> None:
    cam = plan.recipe.camera
    springs = cam.springs
    assert springs is not None
    # The target starts on its anchor (the plan put the rig on the protagonist's first pose).
    target = np.array(plan.camera_target if plan.camera_target is not None else cam.target, dtype=np.float64)
    start = plan.camera_start or cam.position
    for name, pos, mass, drag, collide in (
        ("camera", start, springs.camera_mass, springs.camera_drag, True),
        ("camera_target", tuple(target), springs.target_mass, springs.target_drag, False),
    ):
        body = spec.worldbody.add_body()
        body.name = name
        body.pos = list(pos)
        body.gravcomp = 1.0
        for axis_name, axis in (("x", (1, 0, 0)), ("y", (0, 1, 0)), ("z", (0, 0, 1))):
            j = body.add_joint()
            j.name = f"{name}_{axis_name}"
            j.type = mujoco.mjtJoint.mjJNT_SLIDE
            j.axis = list(axis)
            j.damping = [drag * mass, 0.0, 0.0]
        g = body.add_geom()
        g.name = name
        g.type = mujoco.mjtGeom.mjGEOM_SPHERE
        g.size = [CAMERA_RADIUS_M if collide else 0.05, 0, 0]
        g.mass = mass
        g.contype = CAMERA_BIT if collide else 0
        g.conaffinity = WORLD_BIT if collide else 0
        # Contacts switch on CAMERA_MARGIN_M before the surface, so the soft contact has
        # room to stop the camera before the sphere itself reaches the wall.
        g.margin = CAMERA_MARGIN_M if collide else 0.0
        g.solref = [CAMERA_CONTACT_TIMECONST, 1.0]
        if collide:
            # Frictionless (its condim wins by priority over the world's and a vehicle's
            # hulls'): pulled against a hedge or a wall, the camera slides along it and round
            # its end, as an operator steps round it, instead of sticking to it while the
            # protagonist walks away.
            g.condim = 1
            g.priority = 3
        s = body.add_site()
        s.name = name
    anchor = spec.worldbody.add_body()
    anchor.name = "camera_anchor"
    anchor.mocap = True
    anchor.pos = list(target)
    s = anchor.add_site()
    s.name = "camera_anchor"
    d_ct = float(np.linalg.norm(np.array(start) - target))
    d_tp = 0.0  # the target rests on its anchor
    for name, a, b, k, rest, slack in (
        ("ct_spring", "camera", "camera_target", springs.ct_spring_strength, d_ct, springs.ct_min_distance_m),
        ("tp_spring", "camera_target", "camera_anchor", springs.tp_spring_strength, d_tp, springs.tp_min_distance_m),
    ):
        t = spec.add_tendon()
        t.name = name
        t.wrap_site(a)
        t.wrap_site(b)
        stiffness = np.zeros_like(np.asarray(t.stiffness))
        stiffness[0] = k
        t.stiffness = stiffness
        # The paper's minimum-distance tolerance zone: no force within ±slack of the rest length.
        t.springlength = [max(0.0, rest - slack), rest + slack]


def build_model(plan: ScenePlan) -> SceneModel:
    """Compile the plan's scene. Raises ``RuntimeError`` if MuJoCo refuses the model."""
    spec = mujoco.MjSpec()
    spec.modelname = plan.recipe.video_id
    spec.compiler.degree = False  # joint ranges are in radians, as in the skeleton
    spec.option.timestep = plan.timestep
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    spec.option.cone = mujoco.mjtCone.mjCONE_PYRAMIDAL
    env = ENVIRONMENT_SCENES[plan.recipe.environment.name]
    ground = spec.worldbody.add_geom()
    ground.name = "ground"
    ground.type = mujoco.mjtGeom.mjGEOM_PLANE
    ground.size = [0.0, 0.0, 1.0]
    ground.pos = [0.0, 0.0, float(getattr(env, "ground_z", 0.0))]
    ground.contype = WORLD_BIT
    ground.conaffinity = 0
    for k, c in enumerate(getattr(env, "colliders", ())):
        if c.hulls:
            _static_hulls(spec, f"collider_{k}_{c.pixel_class}", c)
        else:
            _box(spec.worldbody, f"collider_{k}_{c.pixel_class}", c.center, c.half_size, c.yaw_deg)
    for k, bx in enumerate(plan.boxes):
        _box(spec.worldbody, f"box_{k}_{bx.pixel_class}", bx.center, bx.half_size, bx.yaw_deg)
    for k, (center, half, yaw) in enumerate(plan.camera_walls):
        wall = _box(spec.worldbody, f"{CAMERA_WALL}{k}", center, half, yaw)
        wall.contype, wall.conaffinity = 0, CAMERA_BIT  # the camera's alone: people walk through
    physical = [p for p in plan.people if p.physical]
    if len(physical) > len(_PERSON_BITS):
        raise ValueError(f"at most {len(_PERSON_BITS)} simulated people per scene")
    for p, bit in zip(physical, _PERSON_BITS, strict=False):
        _add_person(spec, p, bit)
    for prop in plan.props:
        _add_prop(spec, prop)
    for k, tie in enumerate(plan.ties):
        eq = spec.add_equality()
        eq.name = f"tie_{k}"
        eq.type = mujoco.mjtEq.mjEQ_CONNECT
        eq.objtype = mujoco.mjtObj.mjOBJ_BODY
        eq.name1 = f"p{tie.person_a}_{tie.body_a}"
        eq.name2 = f"p{tie.person_b}_{tie.body_b}"
        eq.solref = [0.01, 1.0]
        eq.data = np.array([*tie.anchor_a, *([0.0] * 9)], dtype=np.float64)
    if plan.recipe.camera.kind in ("kite", "closeup") and plan.recipe.camera.springs is not None:
        _add_camera(spec, plan)
    model = spec.compile()
    for k, tie in enumerate(plan.ties):
        # MuJoCo derives the second anchor from the reference pose; the plan states it.
        model.eq_data[mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_EQUALITY, f"tie_{k}"), 3:6] = tie.anchor_b
    return _handles(model, plan, physical)


def _handles(model: mujoco.MjModel, plan: ScenePlan, physical: list[PersonPlan]) -> SceneModel:
    """Where each part of the plan landed in the compiled model's arrays."""
    return SceneModel(
        model=model,
        people=[_person_handles(model, p) for p in physical],
        props=[_prop_handles(model, prop) for prop in plan.props],
        camera=_camera_handles(model),
        tie_eqs=[_id(model, mujoco.mjtObj.mjOBJ_EQUALITY, f"tie_{k}") for k in range(len(plan.ties))],
        world_geoms=np.array([g for g in np.flatnonzero(model.geom_bodyid == 0) if not _is_camera_wall(model, g)]),
    )


def _is_camera_wall(model: mujoco.MjModel, geom: int) -> bool:
    """Whether a geom is one of the plan's camera walls (not world geometry: the camera
    pressed against one is not in anything)."""
    return (mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_GEOM, int(geom)) or "").startswith(CAMERA_WALL)


def _id(model: mujoco.MjModel, kind: mujoco.mjtObj, name: str) -> int:
    return mujoco.mj_name2id(model, kind, name)


def _person_handles(model: mujoco.MjModel, p: PersonPlan) -> PersonHandles:
    """A ragdoll's bodies, joint addresses, servos, pin and geoms."""
    obj = mujoco.mjtObj
    pre = f"p{p.person_id}_"
    root = _id(model, obj.mjOBJ_JOINT, pre + "root")
    joints = [_id(model, obj.mjOBJ_JOINT, pre + d.name) for d in DOFS]
    pin = _id(model, obj.mjOBJ_JOINT, pre + "pin")
    return PersonHandles(
        person_id=p.person_id,
        bodies=np.array([_id(model, obj.mjOBJ_BODY, pre + b.name) for b in BONES]),
        qpos_root=int(model.jnt_qposadr[root]),
        qvel_root=int(model.jnt_dofadr[root]),
        qpos_dofs=model.jnt_qposadr[joints].copy(),
        qvel_dofs=model.jnt_dofadr[joints].copy(),
        servo_eqs=np.array([_id(model, obj.mjOBJ_EQUALITY, pre + "servo_" + d.name) for d in DOFS]),
        pin_qpos=int(model.jnt_qposadr[pin]),
        pin_qvel=int(model.jnt_dofadr[pin]),
        pin_eq=_id(model, obj.mjOBJ_EQUALITY, pre + "pin"),
        geoms=np.array([_id(model, obj.mjOBJ_GEOM, pre + b.name) for b in BONES]),
        lower=model.jnt_range[joints, 0].copy(),
        upper=model.jnt_range[joints, 1].copy(),
    )


def _prop_handles(model: mujoco.MjModel, prop: PropPlan) -> PropHandles:
    """A prop's body and geom, its joint addresses (driven, free or hinged) and grips."""
    obj = mujoco.mjtObj
    g = _id(model, obj.mjOBJ_GEOM, "prop_" + prop.name)
    body = int(model.geom_bodyid[g])
    hulls = tuple(_id(model, obj.mjOBJ_GEOM, f"prop_{prop.name}_hull{k}") for k in range(len(prop.hulls)))
    handle = PropHandles(prop.name, body, g, None, None, touching=hulls or (g,))
    if prop.path is not None:
        j = _id(model, obj.mjOBJ_JOINT, f"prop_{prop.name}_x")
        handle.qpos, handle.qvel, handle.driven = int(model.jnt_qposadr[j]), int(model.jnt_dofadr[j]), True
    elif prop.dynamic:
        j = _id(model, obj.mjOBJ_JOINT, "prop_" + prop.name)
        handle.qpos = int(model.jnt_qposadr[j])
        handle.qvel = int(model.jnt_dofadr[j])
        handle.hinged = prop.hinge is not None
    handle.grip_eqs = [_id(model, obj.mjOBJ_EQUALITY, f"grip_{prop.name}_{k}") for k in range(len(prop.grips))]
    return handle


def _camera_handles(model: mujoco.MjModel) -> CameraHandles | None:
    """The kite camera's bodies, anchor, geom and slide joints; None without a kite camera."""
    obj = mujoco.mjtObj
    if _id(model, obj.mjOBJ_BODY, "camera") < 0:
        return None
    cj = [_id(model, obj.mjOBJ_JOINT, f"camera_{a}") for a in "xyz"]
    tj = [_id(model, obj.mjOBJ_JOINT, f"camera_target_{a}") for a in "xyz"]
    return CameraHandles(
        camera_body=_id(model, obj.mjOBJ_BODY, "camera"),
        target_body=_id(model, obj.mjOBJ_BODY, "camera_target"),
        anchor_mocap=int(model.body_mocapid[_id(model, obj.mjOBJ_BODY, "camera_anchor")]),
        camera_geom=_id(model, obj.mjOBJ_GEOM, "camera"),
        camera_qpos=model.jnt_qposadr[cj].copy(),
        target_qpos=model.jnt_qposadr[tj].copy(),
        camera_qvel=model.jnt_dofadr[cj].copy(),
        target_qvel=model.jnt_dofadr[tj].copy(),
    )
