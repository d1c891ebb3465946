"""``simulate(recipe) -> Trajectory``: run the planned scene in MuJoCo, frame by frame.

The steps: plan the scene (``plan.scene``), compile it (``model``), put everyone at their
first pose (``control``), then per frame run the frame's physics steps and record the frame
(``recording``); the recorded frames become the ``Trajectory``, the traffic driven through
them. A step that produces NaN or a runaway velocity stops the physics: the frame is
marked, the last good state is held for the rest of the clip, and nothing in the output is
NaN.
"""

from __future__ import annotations

from phav_generator.physics.control import SimulationRun
from phav_generator.physics.model import build_model
from phav_generator.physics.plan.scene import plan_scene
from phav_generator.physics.plan.scene_plan import ScenePlan
from phav_generator.physics.recording import FrameRecorder
from phav_generator.physics.trajectory import Trajectory
from phav_spec.recipe import Recipe


def simulate(recipe: Recipe, *, physics_hz: int | None = None, keep_state: bool = True) -> Trajectory:
    """Simulate a recipe: the world pose of every body, prop and the camera per frame.

    Args:
        recipe: the video's recipe.
        physics_hz: physics steps per second (default: the plan's, 240 Hz or more for
            stiff kite springs).
        keep_state: keep MuJoCo's full physics state per frame (for saving / comparing).
    """
    plan = plan_scene(recipe) if physics_hz is None else plan_scene(recipe, physics_hz=physics_hz)
    return simulate_plan(plan, keep_state=keep_state)


def simulate_plan(plan: ScenePlan, *, keep_state: bool = True) -> Trajectory:
    """Simulate an already planned scene (``plan_scene``)."""
    run = SimulationRun(plan, build_model(plan))
    run.initialise()
    frames = FrameRecorder(plan, run, keep_state=keep_state)
    frames.record(0, touched=set())
    run.keep_good_state()
    for f in range(1, frames.n_out):
        frames.record(f, run.step_frame(f))
    return frames.trajectory()
