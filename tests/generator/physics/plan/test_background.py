"""Background pedestrians: walkers step up onto kerbs on their way."""

from __future__ import annotations

from phav_validators.checks.failures import video_failures
from tests.generator.physics.support import short_recipe, simulated_people


def test_background_walkers_step_onto_kerbs() -> None:
    """A true failure of the 100-video phav-v1-short measurement: a background walker's
    front foot 19 cm inside a raised road (its pelvis stepped up only once over it).
    Walkers now rise for the highest surface within a stride."""
    walkers = short_recipe("v000027")
    assert walkers.background_actors and walkers.environment.name == "urban"
    result = video_failures(walkers, simulated_people(walkers), None)
    assert not result.failed, (walkers.video_id, result.failures)
