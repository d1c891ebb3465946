"""Supporting characters: tied hands stay together while the two walk."""

from __future__ import annotations

import numpy as np

from phav_generator.motion.rotations import quat_to_matrix
from phav_generator.motion.skeleton import BONE_INDEX
from phav_generator.physics.simulate import simulate
from tests.generator.physics.support import assert_healthy, recipe_for


def test_walk_holding_hands_keeps_hands_tied() -> None:
    tr = simulate(recipe_for("walk_holding_hands", seconds=2.0))
    assert_healthy(tr)
    a, b = tr.people[0], tr.person(1)
    palm = np.array([0.0, 0.0, -0.08 * a.height_m / 1.75])
    pa = a.body_pos[:, BONE_INDEX["right_hand"]] + quat_to_matrix(a.body_quat[:, BONE_INDEX["right_hand"]]) @ palm
    pb = b.body_pos[:, BONE_INDEX["left_hand"]] + quat_to_matrix(b.body_quat[:, BONE_INDEX["left_hand"]]) @ palm
    gap = np.linalg.norm(pa - pb, axis=-1)
    assert gap[10:].max() < 0.05, f"palms {np.round(gap, 3)} m apart"
