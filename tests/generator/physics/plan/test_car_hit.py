"""Car hit: the car touches the protagonist, the pins let go and the ragdoll falls."""

from __future__ import annotations

import numpy as np
import pytest

from phav_generator.motion.skeleton import BONE_INDEX
from phav_generator.physics import Trajectory
from phav_generator.physics.simulate import simulate
from tests.generator.physics.support import assert_healthy, recipe_for

PELVIS = BONE_INDEX["pelvis"]


@pytest.fixture(scope="module")
def car_hit() -> Trajectory:
    # No variation: a weakened muscle is meant to lag its animation.
    return simulate(recipe_for("car_hit", seconds=3.0, variation="none"))


def test_car_hit_contact_then_fall(car_hit: Trajectory) -> None:
    assert_healthy(car_hit)
    touched = np.flatnonzero(car_hit.contacts["car_protagonist"])
    assert touched.size, "the car never touched the protagonist"
    after = car_hit.people[0].body_pos[touched[0] :, PELVIS, 2]
    ground = recipe_for("car_hit", seconds=3.0, variation="none").protagonist.position[2]
    assert np.min(after - ground) < 0.5


def test_released_ragdoll_is_simulated(car_hit: Trajectory) -> None:
    p = car_hit.people[0]
    touched = np.flatnonzero(car_hit.contacts["car_protagonist"])[0]
    assert p.pin[-1] == 0.0 and p.pin[0] == 1.0
    divergence = np.linalg.norm(p.body_pos - p.target_pos, axis=-1).max(axis=1)
    assert divergence[: max(touched - 2, 1)].max() < 0.15
    assert divergence[touched:].max() > 0.5
    # After the release, something other than a foot rests on the ground.
    rest = [BONE_INDEX[b] for b in ("pelvis", "chest", "head", "left_hand", "right_hand")]
    ground = recipe_for("car_hit", seconds=3.0, variation="none").protagonist.position[2]
    assert (p.body_pos[-1, rest, 2] - ground).min() < 0.3
