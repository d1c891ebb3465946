"""What a simulation writes down: per frame the poses and physics signals, then the ``Trajectory``.

After each frame the simulated people's bodies, joints and control state, the props'
geom poses, penetrations, contacts, kinetic energy, the camera and (optionally) MuJoCo's
full state are recorded. Background people are kinematic: their bodies come from their
animation, all frames at once. The traffic, which nothing simulated touches, is driven
through the recorded frames at the end.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

from phav_generator.motion.rotations import look_at, matrix_to_quat
from phav_generator.motion.skeleton import BONES, LOWER, UPPER
from phav_generator.physics.control import FULL_STATE, SimulationRun
from phav_generator.physics.plan.camera import anchor_point
from phav_generator.physics.plan.scene_plan import ScenePlan
from phav_generator.physics.traffic import FAR_M, Traffic, box_footprints, footprint_points
from phav_generator.physics.trajectory import PersonTrack, PropTrack, Trajectory
from phav_spec.recipe import Recipe
from phav_spec.vocab import OBJECTS

#: Indoors camera: time constant (s) of the pan that follows the protagonist.
PAN_TIMECONST = 0.6
#: A spring camera looks at its target body, which lags the protagonist; where the lag
#: would put its anchor further than this share of half the vertical field of view from
#: the view's centre, the view turns towards the anchor just enough to keep it there.
IN_VIEW_SHARE = 0.75


def intrinsics(recipe: Recipe) -> tuple[float, float, float, float]:
    """Pinhole intrinsics (fx, fy, cx, cy) in pixels; ``fov_deg`` is the vertical field of view."""
    w, h = recipe.video.width, recipe.video.height
    fy = (h / 2.0) / math.tan(math.radians(recipe.camera.fov_deg) / 2.0)
    return fy, fy, w / 2.0, h / 2.0


class FrameRecorder:
    """The trajectory's arrays, filled one frame at a time from the run's MuJoCo state."""

    def __init__(self, plan: ScenePlan, run: SimulationRun, *, keep_state: bool) -> None:
        self.plan = plan
        self.run = run
        n_out = plan.n_frames + 1
        n_phys = len(run.physical)
        self.n_out = n_out
        self.body_pos = np.zeros((n_phys, n_out, len(BONES), 3))
        self.body_quat = np.zeros((n_phys, n_out, len(BONES), 4))
        self.q = np.zeros((n_phys, n_out, 30))
        self.strengths = np.zeros((n_phys, n_out, len(BONES)))
        self.pins = np.zeros((n_phys, n_out))
        self.prop_pos = np.zeros((len(plan.props), n_out, 3))
        self.prop_quat = np.zeros((len(plan.props), n_out, 4))
        self.cam_pos = np.zeros((n_out, 3))
        self.cam_look = np.zeros((n_out, 3))
        self.penetration = np.zeros((n_phys, n_out))
        self.person_excess = np.zeros((n_phys, n_out))
        self.cam_pen = np.zeros(n_out)
        self.energy = np.zeros(n_out)
        self.contacts = {"car_protagonist": np.zeros(n_out, bool), "protagonist_ground": np.zeros(n_out, bool)}
        self.states = np.zeros((n_out, mujoco.mj_stateSize(run.m, FULL_STATE))) if keep_state else None
        self.background, self.background_fk = run.background, run.background_fk  # animated, not simulated
        #: Every body and driven prop's footprint per recorded frame: what traffic yields to.
        self.obstacles: list[np.ndarray] = []
        self._boxes = box_footprints(plan.boxes)  # the action's boxes: it yields to them too

    def record(self, f: int, touched: set[str]) -> None:
        """Write frame f; ``touched`` are the named contacts seen during its physics steps."""
        self._record_obstacles(f)
        self._record_people(f)
        self._record_props(f)
        self._record_contacts_and_energy(f, touched)
        self.cam_pos[f], self.cam_look[f] = _camera_now(self.plan, self.run, f)
        if self.states is not None:
            mujoco.mj_getState(self.run.m, self.run.d, self.states[f], FULL_STATE)

    def _record_obstacles(self, f: int) -> None:
        """Where everyone is now: the simulated and background people's bodies, a driven car."""
        d, scene = self.run.d, self.run.scene
        driven = [
            footprint_points(d.geom_xpos[h.geom], math.atan2(d.geom_xmat[h.geom, 3], d.geom_xmat[h.geom, 0]), prop.size)
            for prop, h in zip(self.plan.props, scene.props, strict=True)
            if h.driven
        ]
        people = [d.xpos[h.bodies] for h in scene.people] + [pos[f] for pos, _ in self.background_fk]
        self.obstacles.append(np.concatenate([*people, *driven, self._boxes]))

    def _record_people(self, f: int) -> None:
        """The simulated people's bodies, joints, control state and joint-limit excess."""
        d, run = self.run.d, self.run
        for i, h in enumerate(run.scene.people):
            self.body_pos[i, f] = d.xpos[h.bodies]
            self.body_quat[i, f] = d.xquat[h.bodies]
            self.q[i, f] = d.qpos[h.qpos_dofs]
            self.strengths[i, f] = run.strength_now[i]
            self.pins[i, f] = run.pin_now[i]
            q = d.qpos[h.qpos_dofs]
            self.person_excess[i, f] = float(np.max(np.maximum(q - h.upper, h.lower - q), initial=0.0))

    def _record_props(self, f: int) -> None:
        """Each prop's geom pose."""
        d = self.run.d
        for j, h in enumerate(self.run.scene.props):
            # The geom's pose, not its body's: a static prop hangs off the world body, a
            # driven one's body only slides while its geom carries the heading.
            self.prop_pos[j, f] = d.geom_xpos[h.geom]
            mujoco.mju_mat2Quat(self.prop_quat[j, f], d.geom_xmat[h.geom])

    def _record_contacts_and_energy(self, f: int, touched: set[str]) -> None:
        """Penetrations of people and camera, the named contacts, and the kinetic energy."""
        pen, cpen, touches = _penetrations(self.run)
        self.penetration[:, f] = pen
        self.cam_pen[f] = cpen
        for name in touches | touched:
            self.contacts[name][f] = True
        self.energy[f] = _kinetic_energy(self.run.m, self.run.d)

    def trajectory(self) -> Trajectory:
        """The finished ``Trajectory``: every frame's poses and the physics signals."""
        plan, run = self.plan, self.run
        d = run.d
        warnings = {
            mujoco.mjtWarning(i).name: int(d.warning[i].number) for i in range(mujoco.mjtWarning.mjNWARNING.value)
        }
        traffic = Traffic.drive(plan.traffic, self.obstacles, 1.0 / plan.fps, cameras=self.cam_pos)
        return Trajectory(
            video_id=plan.recipe.video_id,
            fps=plan.fps,
            timestep=plan.timestep,
            times=np.arange(self.n_out) / plan.fps,
            people=(*self._simulated_tracks(), *self._background_tracks()),
            props=self._prop_tracks(traffic),
            cam_to_world=self._cam_to_world(),
            intrinsics=intrinsics(plan.recipe),
            boxes=tuple((b.pixel_class, b.center, b.half_size, b.yaw_deg) for b in plan.boxes),
            manipulations=tuple(
                (x.object, x.person_id, x.body, x.kind, x.start_s, x.end_s) for x in plan.manipulations
            ),
            penetration_m=np.max(self.penetration, axis=0, initial=0.0),
            camera_penetration_m=self.cam_pen,
            limit_excess_rad=np.max(self.person_excess, axis=0, initial=0.0),
            kinetic_energy_j=self.energy,
            warnings=warnings,
            exploded_at=run.exploded_at,
            contacts=self.contacts,
            mj_state=self.states,
            traffic_clearance_m=traffic.clearances(self.obstacles).min(axis=0, initial=FAR_M),
        )

    def _simulated_tracks(self) -> list[PersonTrack]:
        """One track per simulated person, with the animation it followed."""
        run, substeps = self.run, self.plan.substeps
        return [
            PersonTrack(
                person_id=p.person_id,
                role=p.role,
                body_pos=self.body_pos[i],
                body_quat=self.body_quat[i],
                target_pos=run.target_body_pos[i][::substeps],
                q=self.q[i],
                strengths=self.strengths[i],
                pin=self.pins[i],
                lower=h.lower,
                upper=h.upper,
                height_m=p.dims.height_m,
                penetration_m=self.penetration[i],
                limit_excess_rad=self.person_excess[i],
            )
            for i, (p, h) in enumerate(zip(run.physical, run.scene.people, strict=True))
        ]

    def _background_tracks(self) -> list[PersonTrack]:
        """One track per background person: their animation is their pose."""
        tracks = []
        for p, (pos, rot) in zip(self.background, self.background_fk, strict=True):
            quat = matrix_to_quat(rot)
            excess = np.max(np.maximum(p.targets.q - UPPER, LOWER - p.targets.q), axis=1, initial=0.0)
            # Background actors are kinematic (no MuJoCo bodies): their penetration is not measured.
            unmeasured = np.full(self.n_out, np.nan)
            track = PersonTrack(p.person_id, p.role, pos, quat, pos, p.targets.q, p.strengths, p.pin, LOWER, UPPER,
                                p.dims.height_m, unmeasured, excess)  # fmt: skip
            tracks.append(track)
        return tracks

    def _prop_tracks(self, traffic: Traffic) -> tuple[PropTrack, ...]:
        """The plan's props, then the traffic's vehicles."""
        plan = self.plan
        vehicle_pos, vehicle_quat = traffic.poses()
        return tuple(
            PropTrack(prop.name, prop.object, prop.pixel_class, prop.shape, tuple(prop.size), self.prop_pos[j],
                      self.prop_quat[j])
            for j, prop in enumerate(plan.props)
        ) + tuple(
            PropTrack(v.name, v.kind, OBJECTS[v.kind], "box", v.half_size, vehicle_pos[j],
                      np.repeat(vehicle_quat[j][None], self.n_out, axis=0))
            for j, v in enumerate(traffic.vehicles)
        )  # fmt: skip

    def _cam_to_world(self) -> np.ndarray:
        """Camera-to-world matrices (F, 4, 4), looking from each position at its look point."""
        cam_to_world = np.zeros((self.n_out, 4, 4))
        cam_to_world[:, :3, :3] = look_at(self.cam_pos, self.cam_look)
        cam_to_world[:, :3, 3] = self.cam_pos
        cam_to_world[:, 3, 3] = 1.0
        return cam_to_world


def _penetrations(run: SimulationRun) -> tuple[np.ndarray, float, set[str]]:
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
    """½ q̇ᵀ M q̇ of the whole scene now."""
    out = np.zeros(m.nv)
    mujoco.mj_mulM(m, d, out, d.qvel)
    return 0.5 * float(d.qvel @ out)


def keep_in_view(eye: np.ndarray, look: np.ndarray, anchor: np.ndarray, limit_rad: float) -> np.ndarray:
    """The point to look at from ``eye``: ``look`` itself while ``anchor`` is within
    ``limit_rad`` of the view's axis, else ``look`` turned about ``eye``, in the plane of the
    two directions, until the anchor is at ``limit_rad`` (the view the protagonist would
    otherwise leave: a runner passing close under the kite).

    Python floats throughout, so the answer does not depend on the machine's BLAS kernels;
    an unturned ``look`` is returned as it came, bit for bit."""
    f = [float(a - e) for a, e in zip(look, eye, strict=True)]
    a = [float(p - e) for p, e in zip(anchor, eye, strict=True)]
    nf, na = math.sqrt(sum(v * v for v in f)), math.sqrt(sum(v * v for v in a))
    if nf < 1e-9 or na < 1e-9:
        return look
    f, a = [v / nf for v in f], [v / na for v in a]
    cos = sum(x * y for x, y in zip(f, a, strict=True))
    if cos >= math.cos(limit_rad):
        return look
    # The unit vector in the plane of f and a, orthogonal to a, on f's side.
    u = [x - cos * y for x, y in zip(f, a, strict=True)]
    nu = math.sqrt(sum(v * v for v in u))
    if nu < 1e-12:  # the anchor straight behind: any side will do, keep the view level
        u = [-a[1], a[0], 0.0]
        nu = math.hypot(u[0], u[1]) or 1.0
    c, s = math.cos(limit_rad), math.sin(limit_rad)
    turned = [c * y + s * x / nu for x, y in zip(u, a, strict=True)]
    return np.array([e + nf * t for e, t in zip(eye, turned, strict=True)], dtype=np.float64)


def _camera_now(plan: ScenePlan, run: SimulationRun, f: int) -> tuple[np.ndarray, np.ndarray]:
    """Camera position and the point it looks at, per behaviour."""
    cam = plan.recipe.camera
    d = run.d
    if run.scene.camera is not None:
        eye, look = d.xpos[run.scene.camera.camera_body].copy(), d.xpos[run.scene.camera.target_body].copy()
        anchor = anchor_point(cam.kind, d.xpos[run.scene.people[0].bodies])
        return eye, keep_in_view(eye, look, anchor, IN_VIEW_SHARE * math.radians(cam.fov_deg) / 2.0)
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
