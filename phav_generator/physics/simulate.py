"""``simulate(recipe) -> Trajectory``: run the planned scene in MuJoCo, frame by frame.

Each physics step sets the pins (driven pelvis poses) and servo targets from the plan, the servo
gains and gravity compensation from the muscle strengths, the perturbation pulls and the
camera anchor; grips switch on and off at their times; a car's touch releases the
protagonist. After each frame the poses and the physics signals are recorded. A step that
produces NaN or a runaway velocity stops the simulation: the frame is marked, the last good
state is held for the rest of the clip, and nothing in the output is NaN.
"""

from __future__ import annotations

import copy
import math
from dataclasses import dataclass

import mujoco
import numpy as np

from phav_generator.motion.rotations import look_at, matrix_to_quat, relative_rotation_vectors
from phav_generator.motion.skeleton import BONE_INDEX, BONES, DOF_BODY, LOWER, UPPER, forward_kinematics
from phav_generator.physics.model import PIN_MASS, PIN_TIMECONST, SERVO_OMEGA, SERVO_ZETA, SceneModel, build_model
from phav_generator.physics.plan import RELEASE_RAMP_S, RELEASED_STRENGTH, ScenePlan, plan_scene
from phav_generator.physics.traffic import Traffic, footprint_points
from phav_generator.physics.trajectory import PersonTrack, PropTrack, Trajectory
from phav_spec.recipe import Recipe
from phav_spec.seeding import stream
from phav_spec.vocab import OBJECTS

#: Above this joint speed (rad/s or m/s) a state counts as exploded.
MAX_SPEED = 500.0
#: Perturbation pull stiffness, as an angular frequency of the pulled body (rad/s).
PERTURBATION_OMEGA = 40.0
#: Indoors camera: time constant (s) of the pan that follows the protagonist.
PAN_TIMECONST = 0.6
_FULL = mujoco.mjtState.mjSTATE_FULLPHYSICS


def intrinsics(recipe: Recipe) -> tuple[float, float, float, float]:
    """Pinhole intrinsics (fx, fy, cx, cy) in pixels; ``fov_deg`` is the vertical field of view."""
    w, h = recipe.video.width, recipe.video.height
    fy = (h / 2.0) / math.tan(math.radians(recipe.camera.fov_deg) / 2.0)
    return fy, fy, w / 2.0, h / 2.0


def _backward_difference(x: np.ndarray, dt: float) -> np.ndarray:
    """(x[k] − x[k−1]) / dt along axis 0; the forward difference at k = 0."""
    v = np.empty_like(x)
    v[1:] = (x[1:] - x[:-1]) / dt
    v[0] = v[1] if len(x) > 1 else 0.0
    return v


def _second_difference(x: np.ndarray, dt: float) -> np.ndarray:
    """(x[k+1] − 2x[k] + x[k−1]) / dt² along axis 0; zero at both ends."""
    a = np.zeros_like(x)
    a[1:-1] = (x[2:] - 2.0 * x[1:-1] + x[:-2]) / dt**2
    return a


@dataclass(frozen=True)
class _Reference:
    """A person's animation as the physics step sees it, per plan step k.

    Semi-implicit Euler moves a state (x[k], v[k]) with an acceleration a[k] to
    v[k+1] = v[k] + a·dt, x[k+1] = x[k] + v[k+1]·dt, so velocities are backward
    differences and accelerations second differences: a body that follows them exactly
    lands on the animation at every step, whatever the timestep.
    """

    root_pos: np.ndarray  # (S, 3)
    root_quat: np.ndarray  # (S, 4)
    root_vel: np.ndarray  # (S, 3) world
    root_acc: np.ndarray  # (S, 3)
    root_omega: np.ndarray  # (S, 3) in the pelvis's own axes, as a free joint stores it
    root_alpha: np.ndarray  # (S, 3)
    q: np.ndarray  # (S, 30)
    qvel: np.ndarray
    qacc: np.ndarray

    @classmethod
    def of(cls, targets, dt: float) -> _Reference:
        quat = targets.root_quat
        turns = relative_rotation_vectors(quat[:-1], quat[1:]) / dt  # over [k, k+1]
        omega = np.zeros((len(quat), 3))
        alpha = np.zeros((len(quat), 3))
        if len(quat) > 1:
            # A turn's rotation vector lies on its axis, so it reads the same in either frame.
            omega[1:] = turns
            omega[0] = turns[0]
            alpha[1:-1] = (turns[1:] - turns[:-1]) / dt
        return cls(
            root_pos=targets.root_pos,
            root_quat=quat,
            root_vel=_backward_difference(targets.root_pos, dt),
            root_acc=_second_difference(targets.root_pos, dt),
            root_omega=omega,
            root_alpha=alpha,
            q=targets.q,
            qvel=_backward_difference(targets.q, dt),
            qacc=_second_difference(targets.q, dt),
        )


def _inverse_dynamics(scene: SceneModel, refs: list[_Reference]) -> list[np.ndarray]:
    """Generalised forces (S, 6 + 30) per physical person, root wrench then joint torques,
    that make the animation happen in free space.

    Computed-torque feed-forward: MuJoCo's inverse dynamics of the reference motion (pose,
    velocity, acceleration, root included) with gravity, contacts and equality constraints
    switched off, since gravity compensation and the pin carry the weight. The servos then
    only correct the residual, so fast motions (a sprint's knee swings at 2000 rad/s²) are
    tracked without stiffer, less stable gains.
    """
    m = copy.copy(scene.model)
    off = mujoco.mjtDisableBit
    m.opt.disableflags |= int(off.mjDSBL_GRAVITY | off.mjDSBL_CONSTRAINT)
    d = mujoco.MjData(m)
    steps = len(refs[0].q) if refs else 0
    qpos = np.tile(m.qpos0, (steps, 1))
    qvel = np.zeros((steps, m.nv))
    qacc = np.zeros((steps, m.nv))
    for ref, h in zip(refs, scene.people, strict=True):
        qpos[:, h.qpos_root : h.qpos_root + 3] = ref.root_pos
        qpos[:, h.qpos_root + 3 : h.qpos_root + 7] = ref.root_quat
        qpos[:, h.qpos_dofs] = ref.q
        qvel[:, h.qvel_root : h.qvel_root + 3] = ref.root_vel
        qvel[:, h.qvel_root + 3 : h.qvel_root + 6] = ref.root_omega
        qvel[:, h.qvel_dofs] = ref.qvel
        qacc[:, h.qvel_root : h.qvel_root + 3] = ref.root_acc
        qacc[:, h.qvel_root + 3 : h.qvel_root + 6] = ref.root_alpha
        qacc[:, h.qvel_dofs] = ref.qacc
    out = [np.zeros((steps, 6 + len(h.qvel_dofs))) for h in scene.people]
    for k in range(steps):
        d.qpos[:] = qpos[k]
        d.qvel[:] = qvel[k]
        d.qacc[:] = qacc[k]
        mujoco.mj_inverse(m, d)
        for i, h in enumerate(scene.people):
            out[i][k, :6] = d.qfrc_inverse[h.qvel_root : h.qvel_root + 6]
            out[i][k, 6:] = d.qfrc_inverse[h.qvel_dofs]
    return out


def _perturbation_offsets(plan: ScenePlan) -> dict[tuple[int, int], np.ndarray]:
    """(person, body) → orbit offsets (S, 3): circles of the recipe's radius and period."""
    out = {}
    rng = stream(plan.recipe.seeds.perturbation, "orbits")
    t = plan.step_times
    for p in plan.people:
        for m in p.perturbed:
            axis = rng.normal(size=3)
            axis /= np.linalg.norm(axis)
            u = np.cross(axis, [0.0, 0.0, 1.0] if abs(axis[2]) < 0.9 else [1.0, 0.0, 0.0])
            u /= np.linalg.norm(u)
            v = np.cross(axis, u)
            phase = 2 * math.pi * rng.random()
            angle = 2 * math.pi * t / p.perturbation_period_s + phase
            out[(p.person_id, BONE_INDEX[m])] = p.perturbation_radius_m * (
                np.cos(angle)[:, None] * u + np.sin(angle)[:, None] * v
            )
    return out


class _Run:
    """The state of one simulation: MuJoCo data plus the precomputed per-step targets."""

    def __init__(self, plan: ScenePlan, scene: SceneModel):
        self.plan = plan
        self.scene = scene
        self.m = scene.model
        self.d = mujoco.MjData(self.m)
        physical = [p for p in plan.people if p.physical]
        self.physical = physical
        self.target_body_pos = []
        for p in physical:
            pos, _ = forward_kinematics(p.dims, p.targets.root_pos, p.targets.root_quat, p.targets.q)
            self.target_body_pos.append(pos)
        index = {p.person_id: i for i, p in enumerate(physical)}
        # (physical person index, body) → orbit offsets, looked up once rather than per step.
        self.orbits = {(index[pid], b): off for (pid, b), off in _perturbation_offsets(plan).items() if pid in index}
        self.refs = [_Reference.of(p.targets, plan.timestep) for p in physical]
        self.torque_ff = _inverse_dynamics(scene, self.refs)
        self.step_times = plan.step_times
        self.released = [False] * len(physical)
        self.release_time = [math.inf] * len(physical)
        self.strength_now = [p.strengths[0].copy() for p in physical]
        self.pin_now = [float(p.pin[0]) for p in physical]
        self.car_geoms = {h.geom for h, prop in zip(scene.props, plan.props, strict=True) if prop.object == "car"}
        self.pan = None

    def initialise(self) -> None:
        d, m = self.d, self.m
        for ref, h in zip(self.refs, self.scene.people, strict=True):
            d.qpos[h.qpos_root : h.qpos_root + 3] = ref.root_pos[0]
            d.qpos[h.qpos_root + 3 : h.qpos_root + 7] = ref.root_quat[0]
            d.qpos[h.qpos_dofs] = ref.q[0]
            d.qvel[h.qvel_root : h.qvel_root + 3] = ref.root_vel[0]
            d.qvel[h.qvel_root + 3 : h.qvel_root + 6] = ref.root_omega[0]
            d.qvel[h.qvel_dofs] = ref.qvel[0]
        for prop, h in zip(self.plan.props, self.scene.props, strict=True):
            if h.qpos is not None and not (h.driven or h.hinged):
                d.qpos[h.qpos : h.qpos + 3] = prop.pos
                d.qpos[h.qpos + 3 : h.qpos + 7] = prop.quat
                d.qvel[h.qvel : h.qvel + 3] = prop.vel
        cam = self.scene.camera
        imp = self.plan.recipe.camera.impulse
        springs = self.plan.recipe.camera.springs
        if cam is not None and imp is not None and springs is not None:
            az, el = math.radians(imp.azimuth_deg), math.radians(imp.elevation_deg)
            direction = np.array([math.cos(el) * math.cos(az), math.cos(el) * math.sin(az), math.sin(el)])
            d.qvel[cam.camera_qvel] = direction * imp.strength / springs.camera_mass
        self._apply_controls(0)
        mujoco.mj_forward(m, d)

    def _apply_controls(self, k: int) -> None:
        """Targets and gains for the step that ends at plan step k (it starts at k − 1)."""
        d, m = self.d, self.m
        t = self.step_times[k]
        j = max(k - 1, 0)
        for i, (p, h) in enumerate(zip(self.physical, self.scene.people, strict=True)):
            strengths = p.strengths[k].copy()
            pin = float(p.pin[k])
            if self.released[i]:
                r = min(1.0, (t - self.release_time[i]) / RELEASE_RAMP_S)
                pin *= 1.0 - r
                strengths = np.minimum(strengths, strengths * (1 - r) + RELEASED_STRENGTH * r)
            self.strength_now[i] = strengths
            self.pin_now[i] = pin
            s_dof = strengths[DOF_BODY]
            stiffness = SERVO_OMEGA**2 * s_dof
            damping = 2.0 * SERVO_ZETA * SERVO_OMEGA * np.sqrt(s_dof)
            ref = self.refs[i]
            # The servo pulls q towards q*, q̇ towards q̇* and adds the animation's acceleration
            # (scaled like the feed-forward): −k(q − q*) − b(q̇ − q̇*) + a* is −k(q − target) − b·q̇.
            m.eq_solref[h.servo_eqs, 0] = -stiffness
            m.eq_solref[h.servo_eqs, 1] = -damping
            active = s_dof > 1e-3
            lead = (damping * ref.qvel[j] + s_dof * pin * ref.qacc[j]) / np.where(active, stiffness, 1.0)
            m.eq_data[h.servo_eqs, 0] = ref.q[j] + lead
            d.eq_active[h.servo_eqs] = active
            # An active muscle carries its body's weight; a released ragdoll feels gravity.
            m.body_gravcomp[h.bodies] = strengths * pin
            d.qfrc_applied[h.qvel_root : h.qvel_root + 6] = self.torque_ff[i][j, :6] * pin
            d.qfrc_applied[h.qvel_dofs] = self.torque_ff[i][j, 6:] * (s_dof * pin)
            d.eq_active[h.pin_eq] = pin > 1e-3
            if pin > 1e-3:
                self._pin_pose(h, ref, j, pin)
        d.xfrc_applied[:] = 0.0
        for (i, b), offsets in self.orbits.items():
            h = self.scene.people[i]
            body = h.bodies[b]
            orbit = self.target_body_pos[i][k, b] + offsets[k]
            mass = m.body_mass[body]
            d.xfrc_applied[body, :3] += mass * PERTURBATION_OMEGA**2 * (orbit - d.xpos[body])
        for prop, h in zip(self.plan.props, self.scene.props, strict=True):
            for (_pid, _body, t0, t1, _rp, _rq), eq in zip(prop.grips, h.grip_eqs, strict=True):
                d.eq_active[eq] = t0 <= t < t1
            if h.driven:
                # Placed and moved along the path each step whatever it hits: infinitely heavy,
                # but with a velocity, so contacts push people at the car's speed.
                start = self._car_position(prop, k - 1)
                d.qpos[h.qpos : h.qpos + 3] = start - prop.path[0]
                d.qvel[h.qvel : h.qvel + 3] = (self._car_position(prop, k) - start) / self.plan.timestep
        cam = self.scene.camera
        if cam is not None:
            body = "head" if self.plan.recipe.camera.kind == "closeup" else "pelvis"
            d.mocap_pos[cam.anchor_mocap] = d.xpos[self.scene.people[0].bodies[BONE_INDEX[body]]]

    def _pin_pose(self, h, ref: _Reference, j: int, weight: float) -> None:
        """Put the pin body on the animated pelvis at plan step j, moving and accelerating
        as it does, so the weld pulls only the pelvis's pose and velocity errors to zero."""
        d, m = self.d, self.m
        m.eq_solref[h.pin_eq, 0] = max(PIN_TIMECONST / math.sqrt(weight), 2.0 * self.plan.timestep)
        d.qpos[h.pin_qpos : h.pin_qpos + 3] = ref.root_pos[j]
        d.qpos[h.pin_qpos + 3 : h.pin_qpos + 7] = ref.root_quat[j]
        d.qvel[h.pin_qvel : h.pin_qvel + 3] = ref.root_vel[j]
        d.qvel[h.pin_qvel + 3 : h.pin_qvel + 6] = ref.root_omega[j]
        # The pin's inertia is isotropic, so its angular acceleration needs no gyroscopic term.
        d.qfrc_applied[h.pin_qvel : h.pin_qvel + 3] = PIN_MASS * ref.root_acc[j]
        d.qfrc_applied[h.pin_qvel + 3 : h.pin_qvel + 6] = PIN_MASS * ref.root_alpha[j]

    def _car_position(self, prop, k: int) -> np.ndarray:
        """Where the car is at plan step k: on its path until it has touched the
        protagonist, then braking at 8 m/s² along the direction it was going."""
        path, dt = prop.path, self.plan.timestep
        k = max(k, 0)
        if not self.released[0]:
            return path[k]
        hit = min(max(round(self.release_time[0] / dt), 1), len(path) - 1)
        if k <= hit:
            return path[k]
        v0 = (path[hit] - path[hit - 1]) / dt
        speed = float(np.linalg.norm(v0))
        t = min((k - hit) * dt, speed / 8.0)
        return path[hit] + v0 / max(speed, 1e-9) * (speed * t - 4.0 * t**2)

    def check_contacts(self, t: float) -> set[str]:
        """Named contacts of this step; a car touching the protagonist releases their pins."""
        d = self.d
        names = set()
        if d.ncon == 0:
            return names
        g1 = d.contact.geom1[: d.ncon]
        g2 = d.contact.geom2[: d.ncon]
        if self.car_geoms:
            protagonist = set(self.scene.people[0].geoms.tolist()) if self.scene.people else set()
            for a, b in zip(g1.tolist(), g2.tolist(), strict=True):
                if (a in self.car_geoms and b in protagonist) or (b in self.car_geoms and a in protagonist):
                    names.add("car_protagonist")
                    if not self.released[0] and self.physical[0].release_on_contact_with == "car":
                        self.released[0] = True
                        self.release_time[0] = t
                    break
        return names


def _penetrations(run: _Run) -> tuple[np.ndarray, float, set[str]]:
    """Deepest world penetration of each simulated person and of the camera now, and which
    world parts touch."""
    d = run.d
    n = d.ncon
    if n == 0:
        return np.zeros(len(run.scene.people)), 0.0, set()
    g1 = d.contact.geom1[:n]
    g2 = d.contact.geom2[:n]
    dist = d.contact.dist[:n]
    world = np.isin(g1, run.scene.world_geoms) | np.isin(g2, run.scene.world_geoms)
    deepest = np.array(
        [float(np.max(-dist[world & (np.isin(g1, h.geoms) | np.isin(g2, h.geoms))], initial=0.0))
         for h in run.scene.people]
    )  # fmt: skip
    cam = 0.0
    touches = set()
    if run.scene.camera is not None:
        cg = run.scene.camera.camera_geom
        sel = world & ((g1 == cg) | (g2 == cg))
        cam = float(np.max(-dist[sel], initial=0.0))
    if run.scene.people:
        ground = np.flatnonzero(run.m.geom_type == mujoco.mjtGeom.mjGEOM_PLANE)
        on_ground = np.isin(g1, ground) | np.isin(g2, ground)
        prot = np.isin(g1, run.scene.people[0].geoms) | np.isin(g2, run.scene.people[0].geoms)
        if np.any(on_ground & prot):
            touches.add("protagonist_ground")
    return np.maximum(deepest, 0.0), max(cam, 0.0), touches


def _kinetic_energy(m: mujoco.MjModel, d: mujoco.MjData) -> float:
    out = np.zeros(m.nv)
    mujoco.mj_mulM(m, d, out, d.qvel)
    return 0.5 * float(d.qvel @ out)


def _healthy(d: mujoco.MjData) -> bool:
    return bool(
        np.all(np.isfinite(d.qpos)) and np.all(np.isfinite(d.qvel)) and np.max(np.abs(d.qvel), initial=0) < MAX_SPEED
    )


def simulate(recipe: Recipe, *, physics_hz: int | None = None, keep_state: bool = True) -> Trajectory:
    """Simulate a recipe: the world pose of every body, prop and the camera per frame.

    Args:
        recipe: the video's recipe.
        physics_hz: physics steps per second (default: the plan's, 240 Hz or more for
            stiff kite springs).
        keep_state: keep MuJoCo's full physics state per frame (for saving / comparing).
    """
    plan = plan_scene(recipe) if physics_hz is None else plan_scene(recipe, physics_hz=physics_hz)
    return simulate_plan(plan, keep_state=keep_state)


def simulate_plan(plan: ScenePlan, *, keep_state: bool = True) -> Trajectory:
    """Simulate an already planned scene (``plan_scene``)."""
    scene = build_model(plan)
    run = _Run(plan, scene)
    run.initialise()
    m, d = run.m, run.d
    n_out = plan.n_frames + 1
    physical = run.physical
    n_phys = len(physical)
    body_pos = np.zeros((n_phys, n_out, len(BONES), 3))
    body_quat = np.zeros((n_phys, n_out, len(BONES), 4))
    q_out = np.zeros((n_phys, n_out, 30))
    strengths = np.zeros((n_phys, n_out, len(BONES)))
    pins = np.zeros((n_phys, n_out))
    prop_pos = np.zeros((len(plan.props), n_out, 3))
    prop_quat = np.zeros((len(plan.props), n_out, 4))
    cam_pos = np.zeros((n_out, 3))
    cam_look = np.zeros((n_out, 3))
    penetration = np.zeros((n_phys, n_out))
    person_excess = np.zeros((n_phys, n_out))
    cam_pen = np.zeros(n_out)
    energy = np.zeros(n_out)
    contacts = {"car_protagonist": np.zeros(n_out, bool), "protagonist_ground": np.zeros(n_out, bool)}
    nstate = mujoco.mj_stateSize(m, _FULL)
    states = np.zeros((n_out, nstate)) if keep_state else None
    exploded_at = None
    good_state = np.zeros(nstate)
    frame_touch: set[str] = set()
    # Background people are animated, not simulated: their bodies at every frame, up front.
    background = [p for p in plan.people if not p.physical]
    background_fk = [
        forward_kinematics(p.dims, p.targets.root_pos, p.targets.root_quat, p.targets.q) for p in background
    ]
    traffic = Traffic(plan.traffic)
    vehicle_pos = np.zeros((len(plan.traffic), n_out, 3))
    vehicle_quat = np.zeros((len(plan.traffic), n_out, 4))
    clearance = np.zeros(n_out)
    bodies_now = np.zeros((0, 3))

    def record(f: int) -> None:
        nonlocal bodies_now
        bodies_now = np.concatenate(
            [d.xpos[h.bodies] for h in scene.people]
            + [pos[f] for pos, _ in background_fk]
            + [
                footprint_points(
                    d.geom_xpos[h.geom], math.atan2(d.geom_xmat[h.geom, 3], d.geom_xmat[h.geom, 0]), prop.size
                )
                for prop, h in zip(plan.props, scene.props, strict=True)
                if h.driven
            ]
            + [np.zeros((0, 3))]
        )
        vehicle_pos[:, f], vehicle_quat[:, f] = traffic.poses()
        clearance[f] = traffic.clearance(bodies_now)
        for i, h in enumerate(scene.people):
            body_pos[i, f] = d.xpos[h.bodies]
            body_quat[i, f] = d.xquat[h.bodies]
            q_out[i, f] = d.qpos[h.qpos_dofs]
            strengths[i, f] = run.strength_now[i]
            pins[i, f] = run.pin_now[i]
            q = d.qpos[h.qpos_dofs]
            person_excess[i, f] = float(np.max(np.maximum(q - h.upper, h.lower - q), initial=0.0))
        for j, h in enumerate(scene.props):
            # The geom's pose, not its body's: a static prop hangs off the world body, a
            # driven one's body only slides while its geom carries the heading.
            prop_pos[j, f] = d.geom_xpos[h.geom]
            mujoco.mju_mat2Quat(prop_quat[j, f], d.geom_xmat[h.geom])
        pen, cpen, touches = _penetrations(run)
        penetration[:, f] = pen
        cam_pen[f] = cpen
        for name in touches | frame_touch:
            contacts[name][f] = True
        energy[f] = _kinetic_energy(m, d)
        cam_pos[f], cam_look[f] = _camera_now(plan, run, f)
        if states is not None:
            mujoco.mj_getState(m, d, states[f], _FULL)

    record(0)
    mujoco.mj_getState(m, d, good_state, _FULL)
    for f in range(1, n_out):
        frame_touch = set()
        traffic.advance(bodies_now, 1.0 / plan.fps)
        if exploded_at is None:
            for s in range(plan.substeps):
                k = (f - 1) * plan.substeps + s + 1
                run._apply_controls(k)
                mujoco.mj_step(m, d)
                frame_touch |= run.check_contacts(run.step_times[k])
                if not _healthy(d):
                    exploded_at = f
                    break
            if exploded_at is None:
                # mj_step leaves positions, contacts and energies computed for the state
                # *before* its last integration: bring them up to the state being recorded.
                mujoco.mj_forward(m, d)
                mujoco.mj_getState(m, d, good_state, _FULL)
            else:
                mujoco.mj_setState(m, d, good_state, _FULL)
                d.qvel[:] = 0.0
                mujoco.mj_forward(m, d)
        record(f)
    warnings = {mujoco.mjtWarning(i).name: int(d.warning[i].number) for i in range(mujoco.mjtWarning.mjNWARNING.value)}
    tracks = []
    for i, (p, h) in enumerate(zip(physical, scene.people, strict=True)):
        tracks.append(
            PersonTrack(
                person_id=p.person_id,
                role=p.role,
                body_pos=body_pos[i],
                body_quat=body_quat[i],
                target_pos=run.target_body_pos[i][:: plan.substeps],
                q=q_out[i],
                strengths=strengths[i],
                pin=pins[i],
                lower=h.lower,
                upper=h.upper,
                height_m=p.dims.height_m,
                penetration_m=penetration[i],
                limit_excess_rad=person_excess[i],
            )
        )
    for p, (pos, rot) in zip(background, background_fk, strict=True):
        quat = matrix_to_quat(rot)
        excess = np.max(np.maximum(p.targets.q - UPPER, LOWER - p.targets.q), axis=1, initial=0.0)
        # Background actors are kinematic (no MuJoCo bodies): their penetration is not measured.
        unmeasured = np.full(n_out, np.nan)
        track = PersonTrack(p.person_id, p.role, pos, quat, pos, p.targets.q, p.strengths, p.pin, LOWER, UPPER,
                            p.dims.height_m, unmeasured, excess)  # fmt: skip
        tracks.append(track)
    cam_to_world = np.zeros((n_out, 4, 4))
    cam_to_world[:, :3, :3] = look_at(cam_pos, cam_look)
    cam_to_world[:, :3, 3] = cam_pos
    cam_to_world[:, 3, 3] = 1.0
    props = tuple(
        PropTrack(prop.name, prop.object, prop.pixel_class, prop.shape, tuple(prop.size), prop_pos[j], prop_quat[j])
        for j, prop in enumerate(plan.props)
    ) + tuple(
        PropTrack(v.name, v.kind, OBJECTS[v.kind], "box", v.half_size, vehicle_pos[j], vehicle_quat[j])
        for j, v in enumerate(plan.traffic)
    )
    return Trajectory(
        video_id=plan.recipe.video_id,
        fps=plan.fps,
        timestep=plan.timestep,
        times=np.arange(n_out) / plan.fps,
        people=tuple(tracks),
        props=props,
        cam_to_world=cam_to_world,
        intrinsics=intrinsics(plan.recipe),
        boxes=tuple((b.pixel_class, b.center, b.half_size, b.yaw_deg) for b in plan.boxes),
        manipulations=tuple((x.object, x.person_id, x.body, x.kind, x.start_s, x.end_s) for x in plan.manipulations),
        penetration_m=np.max(penetration, axis=0, initial=0.0),
        camera_penetration_m=cam_pen,
        limit_excess_rad=np.max(person_excess, axis=0, initial=0.0),
        kinetic_energy_j=energy,
        warnings=warnings,
        exploded_at=exploded_at,
        contacts=contacts,
        mj_state=states,
        traffic_clearance_m=clearance,
    )


def _camera_now(plan: ScenePlan, run: _Run, f: int) -> tuple[np.ndarray, np.ndarray]:
    """Camera position and the point it looks at, per behaviour."""
    cam = plan.recipe.camera
    d = run.d
    if run.scene.camera is not None:
        return d.xpos[run.scene.camera.camera_body].copy(), d.xpos[run.scene.camera.target_body].copy()
    position = np.array(plan.camera_start or cam.position, dtype=np.float64)
    if cam.kind == "indoors":
        # A fixed mount that pans: the look point follows the pelvis, smoothed.
        pelvis = d.xpos[run.scene.people[0].bodies[0]].copy() if run.scene.people else np.array(cam.target)
        if run.pan is None:
            run.pan = np.array(cam.target, dtype=np.float64)
        else:
            a = 1.0 - math.exp(-1.0 / (plan.fps * PAN_TIMECONST))
            run.pan = run.pan + a * (pelvis - run.pan)
        return position, run.pan.copy()
    return position, np.array(cam.target, dtype=np.float64)
