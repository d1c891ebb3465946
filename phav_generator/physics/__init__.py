"""Recipe → trajectory: the scene plan, the MuJoCo model and the simulation (paper: physics).

Read in the order the data flows:

- ``plan/``: recipe → ``ScenePlan`` (``plan.scene.plan_scene``), pure numpy, one module per
  thing planned (stairs, variations, car hit, props, supporting and background people, …).
- ``model``: ``ScenePlan`` → compiled MuJoCo model (``build_model``), the only module that
  compiles one.
- ``control``: one simulation run: the per-step pins, servos, feed-forward and releases.
- ``recording``: what each frame records, and the ``Trajectory`` built from it.
- ``simulate``: ``simulate(recipe)`` / ``simulate_plan(plan)``, the steps above in order.
- ``trajectory``: the output (``Trajectory``), saveable and comparable without MuJoCo.
- ``traffic``: background vehicles, planned, then driven through the simulated frames.
- ``probe``: the action probe, a benchmark of how recognisable the simulated motions are.
"""

from phav_generator.physics.trajectory import PersonTrack, PropTrack, Trajectory, compare

__all__ = ["PersonTrack", "PropTrack", "Trajectory", "compare"]
