"""The ragdoll rules of the synthetic actions: a limp is asymmetric."""

from __future__ import annotations

from phav_generator.motion.skeleton import DOF_INDEX
from phav_generator.physics.simulate import simulate
from tests.generator.physics.support import recipe_for


def test_limp_is_asymmetric() -> None:
    recipe = recipe_for("limp", seconds=4.0)
    tr = simulate(recipe)
    p = tr.people[0]
    knees = p.q[:, [DOF_INDEX["left_knee_flex"], DOF_INDEX["right_knee_flex"]]]
    swing = knees.max(axis=0) - knees.min(axis=0)
    assert abs(swing[0] - swing[1]) / swing.max() > 0.15, f"knee ranges {swing}"
