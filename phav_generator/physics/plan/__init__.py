"""Recipe → scene plan: everything the simulation needs, decided before MuJoCo runs.

Pure numpy on the recipe (STYLE.md "plan, then execute"): the animated targets of every
person at every physics step, the muscle-strength and pin schedules (variations, limp,
stagger, releases), the props with their grips and manipulation intervals, the action
rules of the paper's synthetic actions, and the camera's parameters. Run-time random
choices (car speed, release moments, …) come from the recipe's physics seed through named
streams, so a plan depends on the recipe alone.

One module per thing planned; ``scene.plan_scene`` calls them in order:

- ``scene``: ``plan_scene``, the entry point.
- ``scene_plan``: the plan's data (``ScenePlan``, ``PersonPlan``, ``PropPlan``, ``StaticBox``, …).
- ``timestep``: ``DEFAULT_PHYSICS_HZ`` and the physics steps per frame.
- ``builder``: the accumulator the steps share.
- ``people``: a person's animated targets, and the release that hands a body to physics.
- ``stairs``: the flight of climb_stairs.
- ``variations``: muscle weakening, random perturbation, action blending.
- ``car_hit``: the car and its hit; ``ragdoll_rules``: dive floor, stagger, limp.
- ``handheld``: hold, pick, throw, catch, kick; ``furniture``: chair, pull-up bar;
  ``push``: box, cart, door.
- ``supporting``: the partner of two-person actions and the hand ties.
- ``background``: background pedestrians.
- ``camera``: the camera's start, out of the walls.
"""
