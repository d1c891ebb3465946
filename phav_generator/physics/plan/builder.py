"""The accumulator the planning steps share: the plan's times, its random stream and the
props, boxes, ties and manipulations the action's rules add."""

from __future__ import annotations

import numpy as np

from phav_generator.motion.rotations import matrix_to_quat
from phav_generator.physics.plan.scene_plan import HandTie, Manipulation, PersonPlan, PropPlan, StaticBox
from phav_spec.recipe import Recipe
from phav_spec.seeding import stream


class PlanBuilder:
    """Accumulates the plan's parts while the rules of the action run."""

    def __init__(self, recipe: Recipe, substeps: int) -> None:
        self.recipe = recipe
        self.fps = recipe.video.fps
        self.substeps = substeps
        self.n_frames = recipe.n_frames
        self.times = np.arange(recipe.n_frames * substeps + 1) / (self.fps * substeps)
        self.rng = stream(recipe.seeds.physics, "plan")
        self.props: list[PropPlan] = []
        self.boxes: list[StaticBox] = []
        self.ties: list[HandTie] = []
        self.manipulations: list[Manipulation] = []
        self.stand_offset_z = 0.0
        #: The background walkers, planned first: kinematic, they keep to their ways whatever
        #: comes, so what the action drives (the car of ``car_hit``) keeps clear of them.
        self.walkers: tuple[PersonPlan, ...] = ()


def uniform(lo: float, hi: float, *, rng: np.random.Generator) -> float:
    """A uniform draw in [lo, hi) from one ``rng.random()`` (STYLE: our own inverse CDFs)."""
    return lo + (hi - lo) * rng.random()


def rot_to_quat(m: np.ndarray) -> np.ndarray:
    """The quaternion (w, x, y, z) of one rotation matrix."""
    return matrix_to_quat(m[None])[0]
