"""Plan → MuJoCo model: the compiled ragdoll is the skeleton's kinematics (issue: ragdoll)."""

from __future__ import annotations

import mujoco
import numpy as np

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
