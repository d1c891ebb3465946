"""The motion library: the built-ins are every catalogue motion and cannot be changed; users'
clips are registered beside them, found by ``get_motion`` and removed again."""

from __future__ import annotations

import dataclasses

import pytest

from phav_generator.motion.catalogue import SPECS
from phav_generator.motion.library import (
    BUILTIN_MOTIONS,
    MotionLibrary,
    get_motion,
    register_motion,
    unregister_motion,
    user_motions,
)
from phav_spec.motions import MOTIONS

NAMES = list(MOTIONS.names)


def test_every_catalogue_motion_is_built_in_with_its_length_and_description():
    assert list(BUILTIN_MOTIONS) == NAMES and len(SPECS) == len(NAMES) == 128
    for name in NAMES:
        m = BUILTIN_MOTIONS[name]
        assert get_motion(name) is m
        assert m.length_s == MOTIONS[name].length_s and m.description == MOTIONS[name].description
        assert callable(m.fn)
        assert m.stairs == (SPECS[name].gait.stairs if SPECS[name].gait is not None else 0)


def test_the_built_in_library_is_immutable():
    walk = BUILTIN_MOTIONS["walk_forward_01"]
    with pytest.raises(TypeError):
        BUILTIN_MOTIONS["walk_forward_01"] = walk  # type: ignore[index]
    with pytest.raises(TypeError):
        del BUILTIN_MOTIONS["walk_forward_01"]  # type: ignore[attr-defined]
    with pytest.raises(AttributeError):
        BUILTIN_MOTIONS._motions = {}  # type: ignore[misc]
    with pytest.raises(AttributeError):
        BUILTIN_MOTIONS.update({})  # type: ignore[attr-defined]
    with pytest.raises(TypeError):
        SPECS["walk_forward_01"] = SPECS["run_forward_01"]  # type: ignore[index]
    assert BUILTIN_MOTIONS["walk_forward_01"] is walk and len(BUILTIN_MOTIONS) == 128


def test_unknown_names_and_duplicates_say_so():
    with pytest.raises(KeyError, match="unknown motion 'no_such_motion'"):
        get_motion("no_such_motion")
    walk = BUILTIN_MOTIONS["walk_forward_01"]
    with pytest.raises(ValueError, match="motion 'walk_forward_01' is already registered"):
        MotionLibrary([walk, walk])


def test_a_registered_user_clip_is_found_and_leaves_the_built_ins_alone():
    clip = dataclasses.replace(BUILTIN_MOTIONS["walk_forward_01"], name="test_user_clip")
    assert register_motion(clip) is clip
    try:
        assert get_motion("test_user_clip") is clip
        assert "test_user_clip" in user_motions() and "test_user_clip" not in BUILTIN_MOTIONS
        assert len(BUILTIN_MOTIONS) == 128
        with pytest.raises(ValueError, match="motion 'test_user_clip' is already registered"):
            register_motion(clip)
        other = dataclasses.replace(clip, length_s=2.0)
        assert register_motion(other, replace=True) is other and get_motion("test_user_clip") is other
    finally:
        unregister_motion("test_user_clip")
    assert "test_user_clip" not in user_motions()
    with pytest.raises(KeyError, match="unknown motion 'test_user_clip'"):
        get_motion("test_user_clip")
    with pytest.raises(KeyError, match="no registered user clip 'test_user_clip'"):
        unregister_motion("test_user_clip")


def test_a_user_clip_replaces_a_built_in_only_when_asked():
    walk = BUILTIN_MOTIONS["walk_forward_01"]
    mine = dataclasses.replace(walk, description="my own walk")
    with pytest.raises(ValueError, match="motion 'walk_forward_01' is already registered"):
        register_motion(mine)
    register_motion(mine, replace=True)
    try:
        assert get_motion("walk_forward_01") is mine
        assert BUILTIN_MOTIONS["walk_forward_01"] is walk  # the built-in itself is untouched
    finally:
        unregister_motion("walk_forward_01")
    assert get_motion("walk_forward_01") is walk


@pytest.mark.parametrize("length", [0.0, -1.0, float("nan"), float("inf")])
def test_a_clip_needs_a_finite_positive_length(length):
    clip = dataclasses.replace(BUILTIN_MOTIONS["walk_forward_01"], name="test_bad_length", length_s=length)
    with pytest.raises(ValueError, match="length must be finite and > 0"):
        register_motion(clip)
    assert "test_bad_length" not in user_motions()


def test_get_motion_reads_the_library_it_is_given():
    walk = BUILTIN_MOTIONS["walk_forward_01"]
    small = MotionLibrary([walk])
    assert get_motion("walk_forward_01", small) is walk
    with pytest.raises(KeyError, match="unknown motion 'run_forward_01'"):
        get_motion("run_forward_01", small)
