"""Recipe + trajectory → drawables → frames: labels come from the palette, people keep their
instance ids, the environment's surfaces carry their classes."""

from __future__ import annotations

import numpy as np
import pytest

from phav_generator.physics.simulate import simulate
from phav_generator.render import gl
from phav_generator.render.gl import GROUND, WATER, FrameRenderer
from phav_generator.render.meshes import box
from phav_generator.render.scene import _static, build_drawables, class_id
from phav_generator.world.materials import Material
from phav_spec.vocab import PIXEL_CLASSES
from tests.generator.physics.support import recipe_for

PALETTE_IDS = {PIXEL_CLASSES[n].class_id for n in PIXEL_CLASSES.names}
PERSON_CLASSES = {
    PIXEL_CLASSES[n].class_id for n in PIXEL_CLASSES.names if PIXEL_CLASSES[n].group.name.startswith("HUMAN")
}


@pytest.mark.parametrize(("action", "environment"), [("walk", "urban"), ("walk_holding_hands", "simple")])
def test_frames_of_a_simulated_video(ctx, action: str, environment: str):
    recipe = recipe_for(action, environment, seconds=1.0, variation="none")
    tr = simulate(recipe, keep_state=False)
    renderer = FrameRenderer(
        ctx, recipe.video.width, recipe.video.height, build_drawables(recipe, tr), sky_class=class_id("sky")
    )
    people = {p.person_id + 1 for p in tr.people}
    try:
        for f in (0, tr.n_frames // 2, tr.n_frames - 1):
            frame = renderer.render(f, tr.cam_to_world[f], tr.cam_to_world[f + 1], tr.intrinsics)
            assert set(np.unique(frame.class_id).tolist()) <= PALETTE_IDS
            assert set(np.unique(frame.instance).tolist()) <= people | {0}
            assert (frame.instance == 1).sum() > 50, "the protagonist is on screen"
            # Person pixels are exactly the pixels with a body-part or joint class.
            assert np.array_equal(frame.instance > 0, np.isin(frame.class_id, list(PERSON_CLASSES)))
            ground = frame.class_id == class_id("terrain")
            assert ground.any() and np.all(np.isfinite(frame.depth_m[ground]))
    finally:
        renderer.release()


def test_the_world_s_objects_are_assets_unless_asked_for_their_boxes():
    recipe = recipe_for("car_hit", "urban", seconds=1.0, variation="none")
    tr = simulate(recipe, keep_state=False)
    drawn = build_drawables(recipe, tr)
    boxes = build_drawables(recipe, tr, assets=False)
    car = class_id("car")
    # Every parked and hitting car, as a body and its wheels; as boxes, one box each.
    cars_as_assets = [d for d in drawn if d.part_look is not None and car in d.part_look.class_ids]
    cars_as_boxes = [d for d in boxes if d.class_id == car]
    assert len(cars_as_assets) == 2 * len(cars_as_boxes) > 0
    assert all(d.part_look is None for d in boxes)
    assert sum(d.mesh.n_triangles for d in drawn) > sum(d.mesh.n_triangles for d in boxes)
    # The people and the ground are the same either way.
    assert sum(d.instance_id > 0 for d in drawn) == sum(d.instance_id > 0 for d in boxes)


def test_moving_things_are_drawn_as_finely_as_their_nearest_approach_asks():
    from phav_generator.render.scene import _bounding_radius, _level_along

    eyes = np.zeros((30, 3))
    far = np.tile([100.0, 0.0, 0.0], (30, 1))
    assert _level_along(far, 2.0, eyes, 300.0) == 2  # a car 100 m away all along: 6 px
    passing = far.copy()
    passing[17] = (4.0, 0.0, 0.0)
    assert _level_along(passing, 2.0, eyes, 300.0) == 0  # ... until it passes 4 m from the camera
    assert _level_along(np.array([[30.0, 0.0, 0.0]]), 2.0, eyes, 300.0) == 1  # a box 30 m off: 21 px
    assert _bounding_radius("box", (3.0, 4.0, 0.0)) == 5.0
    assert _bounding_radius("capsule", (0.1, 0.4)) == pytest.approx(0.5)
    assert _bounding_radius("sphere", (0.11,)) == 0.11


def test_each_colour_program_holds_only_the_materials_of_its_draws_and_no_pixel_changes(ctx, monkeypatch):
    """The colour passes draw the near drawables, then the large slabs, each with a program
    compiled with only the materials they show; every program holding every material gives
    the same bytes."""
    recipe = recipe_for("walk", "middle", seconds=0.2, variation="none")  # grass, asphalt, houses, trees
    tr = simulate(recipe, keep_state=False)
    drawables = build_drawables(recipe, tr)

    def frame_and_flags():
        with FrameRenderer(ctx, 170, 128, drawables, sky_class=class_id("sky")) as r:
            near = gl._material_flags(d for d, large in zip(drawables, r._large, strict=True) if not large)
            far = gl._material_flags(d for d, large in zip(drawables, r._large, strict=True) if large)
            return r.render(0, tr.cam_to_world[0], tr.cam_to_world[1], tr.intrinsics), near, far

    split, near, far = frame_and_flags()
    assert f"MATERIAL_{Material.GRASS.value}" in far and f"MATERIAL_{Material.LEAVES.value}" not in far
    assert f"MATERIAL_{Material.LEAVES.value}" in near and f"MATERIAL_{Material.PLASTER.value}" in near
    every = {f"MATERIAL_{m.value}": True for m in Material if m.value >= gl.FIRST_MATERIAL}
    monkeypatch.setattr(gl, "_material_flags", lambda _: every)
    whole, _, _ = frame_and_flags()
    np.testing.assert_array_equal(split.rgb, whole.rgb)
    np.testing.assert_array_equal(split.colour, whole.colour)


def test_a_static_draw_of_wet_ground_takes_the_grounds_material_whatever_it_is_given():
    wet = _static(box((1.0, 1.0, 0.1)), np.eye(4), "road", 1, material=WATER)
    dry = _static(box((1.0, 1.0, 0.1)), np.eye(4), "misc", 1, material=WATER)
    assert (wet.material, dry.material) == (GROUND, WATER)
