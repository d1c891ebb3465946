"""Recipes for physics tests: one action in one environment, short clips, from a θ variant;
and the checks and views several physics tests share."""

from __future__ import annotations

import copy
import functools
from typing import Any

import numpy as np

from phav_generator.motion.skeleton import JOINT_BODIES
from phav_generator.physics.simulate import simulate
from phav_generator.physics.trajectory import Trajectory
from phav_generator.sampling import sample_recipes
from phav_spec.recipe import Recipe
from phav_spec.theta import load_preset, load_theta, parse_theta
from phav_spec.vocab import ACTIONS, ENVIRONMENTS
from phav_validators.checks.failures import PersonSeries
from tests.helpers import preset_dict


@functools.cache
def _preset() -> dict[str, Any]:
    """phav-v1's YAML mapping, read once (parsing the YAML cost as much as a short simulation)."""
    return preset_dict()


def theta_for(
    action: str, environment: str | None = None, *, seconds: float = 1.0, variation: str | None = None, **edits: Any
) -> Any:
    """phav-v1 restricted to one action (and environment, and variation), clips of ``seconds``."""
    data = copy.deepcopy(_preset())
    data["theta_a"] = {action: 1}
    if environment is not None:
        data["theta_ae"]["rows"][action] = {environment: 1}
    if variation is not None:
        data["theta_av"] = {"default": {variation: 1}}
    data["durations"] = {"t_min": seconds, "t_max": seconds, "t_mod": seconds}
    for key, value in edits.items():
        data[key] = value
    return parse_theta(data, source="<test θ>")


@functools.cache
def recipe_for(
    action: str,
    environment: str | None = None,
    *,
    seconds: float = 1.0,
    seed: int = 0,
    index: int = 0,
    variation: str | None = None,
) -> Recipe:
    """The ``index``-th recipe of a θ that only makes ``action`` (in ``environment``, ``variation``)."""
    theta = theta_for(action, environment, seconds=seconds, variation=variation)
    return next(iter(sample_recipes(theta, n=1, seed=seed, start=index)))


@functools.cache
def short_recipe(video_id: str) -> Recipe:
    """A recipe of the first 40 of phav-v1-short, seed 0 (the 100-video measurement's clips)."""
    recipes = {r.video_id: r for r in sample_recipes(load_theta("phav-v1-short"), n=40, seed=0)}
    return recipes[video_id]


def possible_pairs() -> list[tuple[str, str]]:
    """Every (action, environment) with non-zero probability under phav-v1."""
    ae = load_preset("phav-v1").arrays.ae
    return [(a, e) for i, a in enumerate(ACTIONS.names) for j, e in enumerate(ENVIRONMENTS.names) if ae[i, j] > 0]


def assert_healthy(tr: Trajectory) -> None:
    """No explosion, no MuJoCo warning, nothing non-finite in the trajectory."""
    assert tr.exploded_at is None, f"{tr.video_id}: exploded at frame {tr.exploded_at}"
    bad = {k: v for k, v in tr.warnings.items() if v}
    assert not bad, f"{tr.video_id}: MuJoCo warnings {bad}"
    for name, array in tr.arrays().items():
        assert np.all(np.isfinite(array)), f"{tr.video_id}: non-finite values in {name}"


def simulated_people(recipe: Recipe) -> list:
    """The recipe's people as the failures check reads them (``PersonSeries``), straight from
    a simulation: joints per written frame (not the last pose, which only the last frame's
    forward flow needs) and whether the pins hold."""
    tr = simulate(recipe, keep_state=False)
    joints, n = list(JOINT_BODIES), recipe.n_frames
    return [
        PersonSeries(p.person_id, p.role, np.arange(n), p.body_pos[:n, joints], p.pin[:n] >= 0.5) for p in tr.people
    ]
