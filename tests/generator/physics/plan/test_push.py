"""Push: what a push pushes moves ahead of the hands, a door swings open."""

from __future__ import annotations

import numpy as np

from phav_generator.physics.plan.builder import PlanBuilder
from phav_generator.physics.plan.push import hand_reach
from phav_generator.physics.plan.scene import plan_scene
from phav_generator.physics.simulate import simulate
from phav_generator.sampling import sample_recipes
from tests.generator.physics.support import theta_for


def _push_recipes() -> dict[str, object]:
    """One 5 s push recipe per push motion of phav-v1."""
    out: dict[str, object] = {}
    for r in sample_recipes(theta_for("push", "simple", seconds=5.0, variation="none"), n=60, seed=0):
        out.setdefault(r.motion.base_motion, r)
    return out


def test_push_moves_what_it_pushes() -> None:
    """A pushed box or cart advances ahead of the fingertips without being reached through;
    a pushed door swings open on its hinge, and the pushing is annotated."""
    recipes = _push_recipes()
    assert set(recipes) == {"push_heavy_box_01", "push_shopping_cart_01", "push_open_door_01"}
    for motion, recipe in recipes.items():
        tr = simulate(recipe, keep_state=False)
        assert tr.exploded_at is None and not any(tr.warnings.values()), motion
        obj = {"push_heavy_box_01": "box", "push_shopping_cart_01": "shopping_cart"}.get(motion, "door")
        track = next(p for p in tr.props if p.name == obj)
        assert any(m[0] == obj and m[3] == "push" for m in tr.manipulations), motion
        plan = plan_scene(recipe)
        if obj == "door":
            # The leaf's yaw relative to its closed pose: opened by more than 30°.
            q0, q1 = track.quat[0], track.quat[-1]
            turn = 2 * np.degrees(np.arccos(min(1.0, abs(float(q0 @ q1)))))
            assert turn > 30.0, f"door opened only {turn:.1f}°"
            continue
        x0 = np.array(recipe.protagonist.position)
        heading = np.deg2rad(recipe.protagonist.heading_deg)
        fwd = np.array([np.cos(heading), np.sin(heading), 0.0])
        advance = (track.pos[-1] - track.pos[0]) @ fwd
        assert advance > 1.0, f"{obj} advanced only {advance:.2f} m"
        _, _, tips = hand_reach(PlanBuilder(recipe, plan.substeps), plan.people[0])
        near_face = (track.pos - x0) @ fwd - track.size[0]
        reach = ((tips[:: plan.substeps] - x0) @ fwd).max(axis=1)
        assert np.all(reach <= near_face + 1e-6), f"the hands reach into the {obj}"
