"""A person whose motion runs into a building is let go as it reaches the wall: it hits and
falls outside the wall instead of being driven through it; a path that meets nothing and
steps over a kerb is not touched."""

from __future__ import annotations

import numpy as np

from phav_generator.physics.plan.builder import PlanBuilder
from phav_generator.physics.plan.obstacles import LEAD_S, REACH_M, first_contact, let_go_at_obstacles, obstacles
from phav_generator.physics.plan.scene import _protagonist
from phav_generator.physics.plan.timestep import DEFAULT_PHYSICS_HZ, choose_substeps
from phav_generator.physics.simulate import simulate
from phav_spec.scene import ENVIRONMENT_SCENES, WALKABLE_PIXEL_CLASSES
from tests.generator.physics.support import assert_healthy, recipe_for


def _running_at(heading_deg: float):
    """A 3 s run in the urban street from waypoint (-8, 6) facing ``heading_deg``: 143° takes
    it across the pavement into the planter and the building on its north side."""
    base = recipe_for("run", "urban", seconds=3.0, variation="none")
    env = base.environment.model_copy(update={"waypoint_index": 3, "waypoint": (-8.0, 6.0, 0.0)})
    protagonist = base.protagonist.model_copy(update={"position": (-8.0, 6.0, 0.0), "heading_deg": heading_deg})
    return base.model_copy(update={"environment": env, "protagonist": protagonist})


def _plan(recipe):
    b = PlanBuilder(recipe, choose_substeps(recipe, DEFAULT_PHYSICS_HZ))
    return b, _protagonist(b)


def test_the_body_is_let_go_just_before_its_path_reaches_an_obstacle():
    b, p = _plan(_running_at(143.0))
    step = first_contact(b, p)
    assert step is not None and step > 0
    where = p.targets.root_pos[step]
    gaps = [c.xy_distance(where[0], where[1]) for c in obstacles("urban")]
    assert min(gaps) <= REACH_M + 1e-9  # at the obstacle's face, not inside it
    before = p.targets.root_pos[: step - 1]
    assert all(c.xy_distance(x, y) > REACH_M for x, y, _ in before for c in obstacles("urban") if c.top > 0.4)
    let_go = let_go_at_obstacles(b, p)
    released = np.flatnonzero(let_go.pin < 1.0)
    assert b.times[released[0]] >= b.times[step] - LEAD_S - 1e-9 and let_go.pin[-1] == 0.0


def test_a_path_that_meets_nothing_is_left_as_it_was():
    b, p = _plan(_running_at(-90.0))  # south, down the open street
    assert first_contact(b, p) is None
    assert let_go_at_obstacles(b, p) is p


def test_running_into_a_building_no_longer_drives_the_body_through_it():
    tr = simulate(_running_at(143.0), keep_state=False)
    assert_healthy(tr)
    body = tr.people[0].body_pos
    speed = np.linalg.norm(np.diff(body, axis=0), axis=-1) * 30.0
    assert speed.max() < 15.0  # a fall, not an explosion
    solid = [c for c in ENVIRONMENT_SCENES["urban"].colliders if c.pixel_class not in WALKABLE_PIXEL_CLASSES]
    deepest = 0.0
    for c in solid:
        inside = np.array([c.contains_xy(x, y) and c.bottom < z < c.top for x, y, z in body.reshape(-1, 3)])
        if inside.any():
            pts = body.reshape(-1, 3)[inside]
            depth = [min(c.half_size[0] - abs(c.to_local(x, y)[0]), c.half_size[1] - abs(c.to_local(x, y)[1]))
                     for x, y, _ in pts]  # fmt: skip
            deepest = max(deepest, max(depth))
    assert deepest < 0.15  # a body's parts may press into a box a little, never a metre
