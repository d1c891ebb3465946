"""What a simulation records: the camera's intrinsics and the props' poses where the model has them."""

from __future__ import annotations

import numpy as np

from phav_generator.physics.plan.scene import plan_scene
from phav_generator.physics.recording import intrinsics
from phav_generator.physics.simulate import simulate
from tests.generator.physics.support import recipe_for


def test_intrinsics_from_the_vertical_field_of_view() -> None:
    recipe = recipe_for("wave")
    _, fy, cx, cy = intrinsics(recipe)
    assert (cx, cy) == (recipe.video.width / 2, recipe.video.height / 2)
    assert np.isclose(2 * np.degrees(np.arctan(cy / fy)), recipe.camera.fov_deg)


def test_props_are_recorded_where_the_model_has_them() -> None:
    """A trajectory carries each prop's geom pose: a static bar where the plan put it, a
    driven car turned to its heading (its body only slides)."""
    for action, name in (("pull_up", "pull_up_bar"), ("car_hit", "car")):
        recipe = recipe_for(action, seconds=0.5, variation="none")
        planned = next(p for p in plan_scene(recipe).props if p.name == name)
        track = next(p for p in simulate(recipe, keep_state=False).props if p.name == name)
        np.testing.assert_allclose(track.pos[0], planned.pos, atol=1e-6)
        np.testing.assert_allclose(np.abs(track.quat[0] @ planned.quat), 1.0, atol=1e-6)
