"""One simulation run: MuJoCo data and the control that drives it, step by step.

Each physics step sets the pins (driven pelvis poses) and servo targets from the plan, the
servo gains and gravity compensation from the muscle strengths, the inverse-dynamics
feed-forward, the perturbation pulls, the camera anchor, the push that keeps a spring
camera out of the people it films and the lift that raises it over a driven prop in its
line; grips switch on and off at their times; a car's touch
releases the protagonist. A step that produces NaN or a runaway velocity stops the
physics: the frame is marked and the last good state is held.
"""

from __future__ import annotations

import copy
import math
from dataclasses import dataclass

import mujoco
import numpy as np

from phav_generator.motion.rotations import relative_rotation_vectors
from phav_generator.motion.skeleton import BONE_INDEX, DOF_BODY, forward_kinematics
from phav_generator.physics.model import PIN_MASS, PIN_TIMECONST, SERVO_OMEGA, SERVO_ZETA, SceneModel
from phav_generator.physics.plan.camera import (
    Blocker,
    camera_anchor,
    framed_partner,
    sight_boxes,
    sight_lift,
    sight_plants,
)
from phav_generator.physics.plan.car_hit import CAR_BRAKING_MPS2
from phav_generator.physics.plan.people import RELEASE_RAMP_S, RELEASED_STRENGTH
from phav_generator.physics.plan.scene_plan import ScenePlan
from phav_spec.scene import ENVIRONMENT_SCENES
from phav_spec.seeding import stream

#: Above this joint speed (rad/s or m/s) a state counts as exploded.
MAX_SPEED = 500.0
#: Perturbation pull stiffness, as an angular frequency of the pulled body (rad/s).
PERTURBATION_OMEGA = 40.0
#: A spring camera keeps this far (m) from every body origin of every person (background
#: walkers as animated): within it a push on the camera alone (people feel nothing) springs
#: it back, as an operator steps back from someone coming at them. Body origins are joint
#: centres, so a limb's surface stays about 0.7 m away; a close-up films from 1.3 m or more.
CAMERA_ROOM_M = 0.8
#: The push's stiffness, as an angular frequency of the camera's mass (rad/s).
CAMERA_ROOM_OMEGA = 12.0
#: A spring camera whose line to its anchor passes through a driven prop (the car of
#: `car_hit` stopped between it and the thrown body, a pushed load) or a low plant (a hedge,
#: a reed bed) is lifted, as an operator raises the camera over a car's roof, till the line
#: clears it by this (m).
CAMERA_SIGHT_MARGIN_M = 0.2
#: The lift's stiffness, as an angular frequency of the camera's mass (rad/s), critically
#: damped.
CAMERA_SIGHT_OMEGA = 8.0
#: The most (m) one step's lift may ask for.
CAMERA_SIGHT_MAX_M = 1.5
#: What MuJoCo state is saved and restored: all of it.
FULL_STATE = mujoco.mjtState.mjSTATE_FULLPHYSICS


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


class SimulationRun:
    """The state of one simulation: MuJoCo data plus the precomputed per-step targets."""

    def __init__(self, plan: ScenePlan, scene: SceneModel) -> None:
        self.plan = plan
        self.scene = scene
        self.m = scene.model
        self.d = mujoco.MjData(self.m)
        physical = [p for p in plan.people if p.physical]
        self.physical = physical
        # Background people are animated, not simulated: their bodies at every frame, up front
        # (the camera keeps its room from them too; the recording writes their tracks).
        self.background = [p for p in plan.people if not p.physical]
        self.background_fk = [
            forward_kinematics(p.dims, p.targets.root_pos, p.targets.root_quat, p.targets.q) for p in self.background
        ]
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
        #: The partner the camera frames with the protagonist (``camera_anchor``), if any.
        self.framed = scene.people[1] if framed_partner(plan.recipe) else None
        self.released = [False] * len(physical)
        self.release_time = [math.inf] * len(physical)
        self.strength_now = [p.strengths[0].copy() for p in physical]
        self.pin_now = [float(p.pin[0]) for p in physical]
        self.car_geoms = {
            g for h, prop in zip(scene.props, plan.props, strict=True) if prop.object == "car" for g in h.touching
        }
        self.pan = None
        # Per driven prop, its geom and the boxes (centre, half size in its shape's frame)
        # that can hide the protagonist from a spring camera: each hull's bounds, or the shape.
        self.sight_boxes = [
            (h.geom, sight_boxes(prop)) for prop, h in zip(plan.props, scene.props, strict=True) if h.driven
        ]
        # The low plants a spring camera rises over, each with its extent seen from above.
        self.sight_plants = tuple(
            (plant, plant.ground_extent(CAMERA_SIGHT_MARGIN_M))
            for plant in sight_plants(ENVIRONMENT_SCENES[plan.recipe.environment.name].colliders)
        )
        self.lifting = False  # a sight lift under way: its rise is braked once the line is clear
        # The explosion guard: the frame a step blew up at, and the last good state to hold.
        self.exploded_at: int | None = None
        self.good_state = np.zeros(mujoco.mj_stateSize(self.m, FULL_STATE))

    def initialise(self) -> None:
        """The first frame's state: people on their animation, props placed, the camera thrown."""
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
        mujoco.mj_kinematics(m, d)  # the controls pull bodies from where they now are
        self._apply_controls(0)
        mujoco.mj_forward(m, d)

    def keep_good_state(self) -> None:
        """Remember the state now as the last good one (held if a later step explodes)."""
        mujoco.mj_getState(self.m, self.d, self.good_state, FULL_STATE)

    def step_frame(self, f: int) -> set[str]:
        """Run the physics steps that end at frame f (none once exploded); the named contacts seen.

        A step that leaves NaN or a runaway velocity marks the frame exploded and puts the
        last good state back, at rest, for the rest of the clip.
        """
        m, d, plan = self.m, self.d, self.plan
        touched: set[str] = set()
        if self.exploded_at is not None:
            return touched
        for s in range(plan.substeps):
            k = (f - 1) * plan.substeps + s + 1
            self._apply_controls(k)
            mujoco.mj_step(m, d)
            touched |= self.check_contacts(self.step_times[k])
            if not _healthy(d):
                self.exploded_at = f
                break
        if self.exploded_at is None:
            # mj_step leaves positions, contacts and energies computed for the state
            # *before* its last integration: bring them up to the state being recorded.
            mujoco.mj_forward(m, d)
            self.keep_good_state()
        else:
            mujoco.mj_setState(m, d, self.good_state, FULL_STATE)
            d.qvel[:] = 0.0
            mujoco.mj_forward(m, d)
        return touched

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
            kind = self.plan.recipe.camera.kind
            partner = None if self.framed is None else d.xpos[self.framed.bodies]
            d.mocap_pos[cam.anchor_mocap] = camera_anchor(kind, d.xpos[self.scene.people[0].bodies], partner)
            d.xfrc_applied[cam.camera_body, :3] += self._camera_room_push(k)
            d.xfrc_applied[cam.camera_body, 2] += self._camera_sight_lift()

    def _camera_room_push(self, k: int) -> np.ndarray:
        """The push (N) at plan step k that keeps a spring camera ``CAMERA_ROOM_M`` from each
        person's nearest body origin (a background walker's as animated at the frame the step
        ends at): a spring on the camera alone, away from that origin."""
        d, cam = self.d, self.scene.camera
        at = d.xpos[cam.camera_body]
        f = -(-k // self.plan.substeps)
        people = [d.xpos[h.bodies] for h in self.scene.people]
        people += [pos[min(f, len(pos) - 1)] for pos, _ in self.background_fk]
        push = np.zeros(3)
        for bodies in people:
            away = at - bodies
            dist = np.linalg.norm(away, axis=1)
            b = int(np.argmin(dist))
            if dist[b] < CAMERA_ROOM_M:
                unit = away[b] / dist[b] if dist[b] > 1e-6 else np.array([0.0, 0.0, 1.0])
                push += unit * (CAMERA_ROOM_M - dist[b])
        return push * self.m.body_mass[cam.camera_body] * CAMERA_ROOM_OMEGA**2

    def _camera_sight_lift(self) -> float:
        """The upward push (N) on a spring camera whose line to its anchor passes through a
        driven prop or a low plant now: a critically damped spring on the camera alone
        towards the height that clears it by ``CAMERA_SIGHT_MARGIN_M``; once clear, the
        lift's rise is braked to a stop, so the camera rests there instead of sailing on up."""
        if not self.sight_boxes and not self.sight_plants:
            return 0.0
        d, cam = self.d, self.scene.camera
        eye, anchor = d.xpos[cam.camera_body], d.mocap_pos[cam.anchor_mocap]
        lift = 0.0
        for geom, boxes in self.sight_boxes:
            rot = d.geom_xmat[geom].reshape(3, 3)
            r, pos = rot.tolist(), d.geom_xpos[geom].tolist()
            for c, half in boxes:
                # In Python floats, as Blocker's own sums: the same lift whatever the BLAS.
                at = [pos[i] + r[i][0] * c[0] + r[i][1] * c[1] + r[i][2] * c[2] for i in range(3)]
                box = Blocker.of(at, half, rot)
                lift = max(lift, sight_lift(eye, anchor, box, CAMERA_SIGHT_MARGIN_M))
        (ex, ey, _), (ax, ay, _) = eye.tolist(), anchor.tolist()
        for plant, (x0, y0, x1, y1) in self.sight_plants:
            # Most steps the line passes nowhere near a plant: only those under it are measured.
            if min(ex, ax) <= x1 and max(ex, ax) >= x0 and min(ey, ay) <= y1 and max(ey, ay) >= y0:
                lift = max(lift, sight_lift(eye, anchor, plant, CAMERA_SIGHT_MARGIN_M))
        rise = float(d.qvel[cam.camera_qvel[2]])
        self.lifting = lift > 0.0 or (self.lifting and rise > 0.0)
        if not self.lifting:
            return 0.0
        w = CAMERA_SIGHT_OMEGA
        return self.m.body_mass[cam.camera_body] * (w * w * min(lift, CAMERA_SIGHT_MAX_M) - 2.0 * w * rise)

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
        protagonist, then braking (``CAR_BRAKING_MPS2``) along the direction it was going,
        never past the path's end (where something stands in its way, it stops there)."""
        path, dt = prop.path, self.plan.timestep
        k = max(k, 0)
        if not self.released[0]:
            return path[k]
        hit = min(max(round(self.release_time[0] / dt), 1), len(path) - 1)
        if k <= hit:
            return path[k]
        # In Python floats, not a BLAS dot or norm: the stop cannot depend on the machine's kernels.
        v0 = (path[hit] - path[hit - 1]) / dt
        speed = math.sqrt(sum(float(c) * float(c) for c in v0))
        if speed < 1e-9:
            return path[hit]
        way = v0 / speed
        t = min((k - hit) * dt, speed / CAR_BRAKING_MPS2)
        room = sum(float(e - h) * float(w) for e, h, w in zip(path[-1], path[hit], way, strict=True))
        return path[hit] + way * min(speed * t - 0.5 * CAR_BRAKING_MPS2 * t**2, room)

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


def _healthy(d: mujoco.MjData) -> bool:
    """Finite positions and velocities, no joint faster than ``MAX_SPEED``."""
    return bool(
        np.all(np.isfinite(d.qpos)) and np.all(np.isfinite(d.qvel)) and np.max(np.abs(d.qvel), initial=0) < MAX_SPEED
    )
