"""Action variations: they move the complementary muscles only, and blending never sinks a body."""

from __future__ import annotations

import numpy as np
import pytest

import phav_generator.physics.plan.variations as variations
from phav_generator.motion.animation import blend, muscle_dof_mask
from phav_generator.motion.skeleton import forward_kinematics, lowest_point
from phav_generator.physics.plan.scene import plan_scene
from phav_generator.physics.simulate import simulate
from phav_spec.scene import ACTION_SCENES
from phav_validators.checks.failures import video_failures
from tests.generator.physics.support import recipe_for, short_recipe, simulated_people

#: How far (joint angle) a variation may move the action's necessary muscles.
NECESSARY_TOLERANCE_RAD = 0.1


@pytest.mark.parametrize("kind", ["random_perturbation", "action_blending"])
def test_variations_change_complementary_muscles_only(kind: str) -> None:
    base = recipe_for("wave", seconds=2.0)
    scene = ACTION_SCENES["wave"]
    muscles = scene.complementary_muscles[:6]
    if kind == "random_perturbation":
        variation = {"kind": kind, "muscles": muscles, "radius_m": 0.3, "period_s": 0.8}
    else:
        variation = {
            "kind": kind,
            "muscles": muscles,
            "blend_motion": "jumping_jacks_01",
            "blend_start_s": 1.0,
            "weight": 0.8,
        }
    varied = base.model_copy(
        update={"variation": base.model_validate({**base.model_dump(), "variation": variation}).variation}
    )
    plain = base.model_copy(
        update={"variation": base.model_validate({**base.model_dump(), "variation": {"kind": "none"}}).variation}
    )
    a, b = simulate(plain).people[0], simulate(varied).people[0]
    necessary = muscle_dof_mask(scene.necessary_muscles)
    varied_dofs = muscle_dof_mask(muscles)
    change = np.abs(a.q - b.q).max(axis=0)
    assert change[varied_dofs].max() > 0.2, f"varied muscles moved {np.round(change[varied_dofs], 3)}"
    assert change[necessary].max() < NECESSARY_TOLERANCE_RAD, (
        f"necessary muscles moved {np.round(change[necessary], 3)}"
    )


def test_blending_keeps_a_lying_body_above_ground() -> None:
    """A true failure of the 100-video phav-v1-short measurement: a dive clip whose blended
    leg (a standing one, onto a body lying on the floor) started 71 cm into the ground. The
    blend weight now drops where it would sink a body."""
    dive, run = short_recipe("v000035"), short_recipe("v000005")
    assert dive.action == "dive_floor" and dive.variation.kind == run.variation.kind == "action_blending"
    result = video_failures(dive, simulated_people(dive), None)
    assert not result.failed, (dive.video_id, result.failures)

    def targets(recipe, weight):
        variation = recipe.variation.model_copy(update={"weight": weight})
        return plan_scene(recipe.model_copy(update={"variation": variation})).people[0].targets

    # The dive's body lies on the floor: its standing blended leg never sinks it (it is let
    # in only where the body stays above the ground). The targets are the reference body's
    # angles on an anny body, whose capsules may reach 5 cm lower lying down; contacts
    # lift them (the simulated clip above does not fail).
    plan = plan_scene(dive)
    me = plan.people[0]
    t = me.targets
    pos, rot = forward_kinematics(me.dims, t.root_pos, t.root_quat, t.q)
    ground = dive.protagonist.position[2]
    assert lowest_point(me.dims, pos, rot).min() > ground - 0.05
    # A runner's blended arms sink nothing: blended at the recipe's full weight.
    weight = run.variation.weight
    full = blend(targets(run, 0.0), targets(run, 1.0), run.variation.muscles, weight)
    np.testing.assert_allclose(targets(run, weight).q, full.q, atol=1e-12)


def test_a_stairs_take_blends_its_level_strides(monkeypatch: pytest.MonkeyPatch) -> None:
    """Blended into a standing action's legs, a stairs take strides on level ground: the
    climbing version reached for treads that are not there, sank a foot and had its weight
    cut to a third (the legs moved a third as far from the action's own)."""
    base = recipe_for("wave", seconds=3.0)
    legs = [m for m in ACTION_SCENES["wave"].complementary_muscles if m.endswith(("_leg", "_foot"))]
    variation = {"kind": "action_blending", "muscles": legs, "blend_motion": "climb_up_stairs_01",
                 "blend_start_s": 1.0, "weight": 0.8}  # fmt: skip

    def legs_moved() -> float:
        plans = [base.model_validate({**base.model_dump(), "variation": v}) for v in ({"kind": "none"}, variation)]
        plain, blended = (plan_scene(r).people[0].targets for r in plans)
        return float(np.abs(blended.q - plain.q)[:, muscle_dof_mask(legs)].mean())

    level = legs_moved()
    climbing = variations.animate_person
    monkeypatch.setattr(variations, "animate_person", lambda *a, **k: climbing(*a, **{**k, "flight": True}))
    assert level > 2.0 * legs_moved() and level > 0.05
