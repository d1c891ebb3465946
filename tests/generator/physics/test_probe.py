"""The action probe: features that ignore where a clip happens, a deterministic classifier,
and the 35 actions told apart from simulated motion alone (issue: motions, ragdoll)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from phav_generator.motion.rotations import matrix_to_quat, quat_to_matrix, yaw_matrix
from phav_generator.physics.probe import (
    LogisticProbe,
    confusion_matrix,
    evaluate_probe,
    format_confusion,
    motion_features,
    single_action_theta,
)
from phav_generator.physics.simulate import simulate
from phav_generator.sampling import sample_recipes
from phav_spec.theta import load_preset
from phav_spec.vocab import ACTIONS
from tests.generator.physics.support import recipe_for

#: The issue's bar for telling the 35 actions apart from protagonist motion.
MIN_ACCURACY = 0.70


def _moved(track, rot: np.ndarray, shift: np.ndarray):
    """A person track rotated by ``rot`` about the origin and shifted by ``shift``."""
    quat = matrix_to_quat(rot @ quat_to_matrix(track.body_quat))
    return dataclasses.replace(track, body_pos=track.body_pos @ rot.T + shift, body_quat=quat)


def test_features_ignore_where_and_which_way_the_clip_happens() -> None:
    tr = simulate(recipe_for("walk_holding_hands", seconds=1.0), keep_state=False)
    rot = yaw_matrix(math.radians(130.0))
    shift = np.array([12.0, -7.0, 0.5])
    moved = dataclasses.replace(tr, people=tuple(_moved(p, rot, shift) for p in tr.people))
    a, b = motion_features(tr), motion_features(moved)
    assert a.shape == b.shape and np.all(np.isfinite(a))
    np.testing.assert_allclose(a, b, atol=1e-6)


def test_features_see_the_other_person_only_when_there_is_one() -> None:
    alone = motion_features(simulate(recipe_for("walk", seconds=1.0), keep_state=False))
    together = motion_features(simulate(recipe_for("walk_holding_hands", seconds=1.0), keep_state=False))
    assert alone[-4:].min() >= 5.0  # nobody near: the FAR value
    assert together[-1] < 0.1  # hands tied: the closest hands touch (in body heights)


def test_logistic_probe_separates_blobs_deterministically() -> None:
    rng = np.random.default_rng(7)
    centres = {"a": [0.0, 0.0, 5.0], "b": [3.0, 0.0, 5.0], "c": [0.0, 3.0, 5.0]}
    labels = [c for c in centres for _ in range(30)]
    x = np.array([centres[c] for c in labels]) + rng.normal(scale=0.5, size=(90, 3))
    x[:, 2] = 5.0  # a constant column must not divide by zero
    first = LogisticProbe.fit(x, labels)
    again = LogisticProbe.fit(x, labels)
    np.testing.assert_array_equal(first.weights, again.weights)
    test = np.array([[0.1, -0.2, 5.0], [2.9, 0.3, 5.0], [-0.3, 3.2, 5.0]])
    assert first.predict(test) == ["a", "b", "c"]


def test_confusion_matrix_counts_rows_as_truth() -> None:
    m = confusion_matrix(["a", "a", "b", "c"], ["a", "b", "b", "a"], ("a", "b", "c"))
    np.testing.assert_array_equal(m, [[1, 1, 0], [0, 1, 0], [1, 0, 0]])
    text = format_confusion(m, ("a", "b", "c"))
    assert text.splitlines()[1].startswith("a") and "50%" in text.splitlines()[1]


def test_single_action_theta_makes_only_that_action() -> None:
    theta = single_action_theta(load_preset("phav-v1"), "hop", 1.5)
    recipes = list(sample_recipes(theta, n=5, seed=3))
    assert {r.action for r in recipes} == {"hop"}
    assert all(abs(r.duration_s - 1.5) < 1 / 30 for r in recipes)


#: Five actions of unlike body patterns: a gait forwards and backwards, a posture, a cycle on
#: all fours and a two-person action (the partner features).
FEW_ACTIONS = ("walk", "moonwalk", "sit", "crawl", "walking_hug")


def test_a_few_actions_are_recognisable_from_simulated_motion() -> None:
    """The probe's protocol in small (the 35 actions below are marked slow): 3 one-second
    clips per action of seed 0 train it, 2 of seed 1 test it. Chance is 20 %; 8 or more of
    the 10 right by chance has probability below 1e-4."""
    result = evaluate_probe(load_preset("phav-v1"), FEW_ACTIONS, n_train=3, n_test=2, seed=0, seconds=1.0)
    assert result.classes == FEW_ACTIONS and result.confusion.sum() == 2 * len(FEW_ACTIONS)
    assert result.simulate_s > 0 and result.fit_s > 0
    assert result.accuracy >= 0.8, format_confusion(result.confusion, result.classes)


@pytest.mark.slow
def test_the_35_actions_are_recognisable_from_simulated_motion() -> None:
    """Train on seed 0, test on seed 1: 12 + 4 two-second clips per action (~80 s; the
    protocol of docs/physics.md). Slow: the test above runs it on five actions."""
    result = evaluate_probe(load_preset("phav-v1"), ACTIONS.names, n_train=12, n_test=4, seed=0)
    print(f"\naction probe: {result.accuracy:.1%} of {result.confusion.sum()} held-out clips")
    print(format_confusion(result.confusion, result.classes))
    assert result.confusion.sum() == 4 * len(ACTIONS.names)
    assert result.accuracy >= MIN_ACCURACY, format_confusion(result.confusion, result.classes)
