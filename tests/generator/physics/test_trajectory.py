"""The trajectory: saved and loaded unchanged, a broken file named in the error."""

from __future__ import annotations

import pytest

from phav_generator.physics import Trajectory, compare
from phav_generator.physics.simulate import simulate
from phav_spec.errors import PhavUserError
from tests.generator.physics.support import recipe_for


def test_trajectory_round_trip(tmp_path) -> None:
    tr = simulate(recipe_for("pour", seconds=0.4))
    path = tmp_path / "t.npz"
    tr.save(path)
    back = Trajectory.load(path)
    assert back.content_hash() == tr.content_hash()
    assert max(compare(tr, back).values()) == 0.0
    path.write_bytes(b"not a trajectory")
    with pytest.raises(PhavUserError, match=r"t\.npz"):
        Trajectory.load(path)
