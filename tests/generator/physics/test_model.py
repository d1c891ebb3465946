"""Plan → MuJoCo model: the compiled ragdoll is the skeleton's kinematics; a parked car collides
as the solids it is drawn from."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from phav_generator.motion.skeleton import LOWER, UPPER, forward_kinematics
from phav_generator.physics.model import build_model
from phav_generator.physics.plan.scene import plan_scene
from tests.generator.physics.support import recipe_for


def test_numpy_kinematics_match_mujoco() -> None:
    recipe = recipe_for("wave")
    plan = plan_scene(recipe)
    scene = build_model(plan)
    m, h = scene.model, scene.people[0]
    d = mujoco.MjData(m)
    rng = np.random.default_rng(0)
    for _ in range(5):
        q = rng.uniform(LOWER, UPPER)
        quat = rng.normal(size=4)
        quat /= np.linalg.norm(quat)
        d.qpos[h.qpos_root : h.qpos_root + 3] = rng.normal(size=3)
        d.qpos[h.qpos_root + 3 : h.qpos_root + 7] = quat
        d.qpos[h.qpos_dofs] = q
        mujoco.mj_kinematics(m, d)
        pos, rot = forward_kinematics(
            plan.people[0].dims, d.qpos[None, h.qpos_root : h.qpos_root + 3], quat[None], q[None]
        )
        np.testing.assert_allclose(pos[0], d.xpos[h.bodies], atol=1e-12)
        np.testing.assert_allclose(rot[0].reshape(-1, 9), d.xmat[h.bodies], atol=1e-12)


def test_a_parked_car_collides_as_the_solids_it_is_drawn_from() -> None:
    """A parked car is its hulls in the world, not its box: a ray down onto its hood meets the
    hood (about 0.9 m up), where the box's top stood at 1.5 m; its roof is the box's top."""
    from phav_spec.car_shapes import car_profile
    from phav_spec.scene import ENVIRONMENT_SCENES

    recipe = recipe_for("walk", "urban")
    m = build_model(plan_scene(recipe)).model
    d = mujoco.MjData(m)
    mujoco.mj_forward(m, d)
    index, parked = next((k, c) for k, c in enumerate(ENVIRONMENT_SCENES["urban"].colliders) if c.hulls)
    assert mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_GEOM, f"collider_{index}_car") == -1  # no box
    outline = car_profile(parked.model, parked.half_size)
    yaw = np.radians(parked.yaw_deg)
    forward = np.array([np.cos(yaw), np.sin(yaw), 0.0])
    geom = np.zeros(1, dtype=np.int32)

    def top_at(x: float) -> float:  # the highest solid under (x, 0) in the car's frame
        start = np.asarray(parked.center) + x * forward + np.array([0.0, 0.0, 3.0])
        return float(start[2] - mujoco.mj_ray(m, d, start, np.array([0.0, 0.0, -1.0]), None, 1, -1, geom))

    hood = top_at(outline.front - 0.2)
    assert hood == pytest.approx(outline.hood_front + parked.center[2], abs=0.03)
    assert hood < parked.top - 0.4
    assert top_at(0.5 * (outline.roof_front + outline.roof_rear)) == pytest.approx(parked.top, abs=0.01)
