"""Arm IK of the two-handed swings: solved once per keyframe, on first use."""

from __future__ import annotations

from phav_generator.motion.catalogue import SPECS
from phav_generator.motion.ik import PosedArms, _fit_keys
from phav_generator.motion.postures import STAND, golf_swing


def test_posed_arms_solve_on_first_use_and_give_the_fitted_keys():
    keys = ((0.0, STAND), *golf_swing(1.5))
    posed = PosedArms(keys)
    assert posed._solved is None and len(posed) == len(keys)  # reading the catalogue fits nothing
    assert tuple(posed) == _fit_keys(keys)
    assert posed[1] == posed._solved[1] and all("l_arm" not in k or k["l_arm"] == 0.0 for _, k in posed)


def test_the_catalogue_swings_are_posed_lazily():
    swings = [s for s in SPECS.values() if isinstance(s.keys, PosedArms)]
    assert len(swings) == 5
