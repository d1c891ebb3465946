"""The physics timestep of a scene: steps per frame, more where a kite spring is stiff."""

from __future__ import annotations

import math

from phav_spec.recipe import Recipe

#: Physics steps per second unless a stiff spring needs more (``phav bench`` chose it).
DEFAULT_PHYSICS_HZ = 240
#: Largest ω·dt allowed for the kite springs (semi-implicit Euler is stable below 2).
MAX_SPRING_OMEGA_DT = 0.5
#: Largest distance the thrown camera may travel in one physics step (half its contact margin).
MAX_CAMERA_STEP_M = 0.05


def choose_substeps(recipe: Recipe, physics_hz: int = DEFAULT_PHYSICS_HZ) -> int:
    """Physics steps per frame: ``physics_hz / fps``, more when a kite spring is stiff.

    The springs are integrated explicitly in position, so the step must keep ω·dt small
    for the stiffest spring–mass pair (ω² = k/m; the target feels both springs).
    """
    fps = recipe.video.fps
    substeps = max(1, math.ceil(physics_hz / fps))
    springs = recipe.camera.springs
    if springs is not None and recipe.camera.kind in ("kite", "closeup"):
        omega2 = max(
            springs.ct_spring_strength / springs.camera_mass,
            (springs.ct_spring_strength + springs.tp_spring_strength) / springs.target_mass,
        )
        needed = math.ceil(math.sqrt(omega2) / (fps * MAX_SPRING_OMEGA_DT))
        substeps = max(substeps, needed)
        impulse = recipe.camera.impulse
        if impulse is not None:
            # A thrown camera must not cross its contact margin in one step (no tunnelling).
            speed = abs(impulse.strength) / springs.camera_mass
            substeps = max(substeps, math.ceil(speed / (fps * MAX_CAMERA_STEP_M)))
    return substeps
