"""The skinned meshes against the world on clean clips: standing feet (the ragdoll's foot
capsule resting on the floor) have their mesh soles within 2 cm of it, and no mesh goes
more than 2 cm into the ground or a prop."""

from __future__ import annotations

import numpy as np
import pytest

from phav_generator.physics.simulate import simulate
from phav_generator.render.contact import measure_contact
from tests.generator.physics.support import recipe_for


@pytest.mark.parametrize(
    ("action", "environment"),
    [("walk", "urban"), ("wave", "simple"), ("run", "stadium"), ("sit", "house_interior"), ("climb_stairs", "urban")],
)
def test_standing_soles_are_on_the_floor_and_no_mesh_sinks(action, environment):
    recipe = recipe_for(action, environment, seconds=1.0, variation="none")
    contact = measure_contact(recipe, simulate(recipe, keep_state=False))
    assert len(contact.standing_sole_m) > 5, "some frames have a standing foot"
    assert np.all(np.abs(contact.standing_sole_m) < 0.02), np.round(contact.standing_sole_m, 3)
    assert contact.depth_m.max() < 0.02, contact.depth_m.max()
