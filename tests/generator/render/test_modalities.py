"""A rendered frame → the six modality arrays of the encoding spec: dtypes and shapes, palette
colours, instance colours, the depth sky code and the flow quantum."""

from __future__ import annotations

import numpy as np
import pytest

from phav_generator.physics.simulate import simulate
from phav_generator.render.gl import FrameRenderer
from phav_generator.render.modalities import encode_frame
from phav_generator.render.scene import build_drawables, class_id
from phav_spec.encoding import MAX_PERSON_ID, MODALITIES, decode_depth, decode_flow, instance_rgb
from phav_spec.vocab import PIXEL_CLASSES
from tests.generator.physics.support import recipe_for


def test_encoded_modalities_follow_the_spec(ctx):
    recipe = recipe_for("walk_holding_hands", "simple", seconds=0.5, variation="none")
    tr = simulate(recipe, keep_state=False)
    drawables = build_drawables(recipe, tr)
    with FrameRenderer(ctx, recipe.video.width, recipe.video.height, drawables, sky_class=class_id("sky")) as r:
        frame = r.render(3, tr.cam_to_world[3], tr.cam_to_world[4], tr.intrinsics)
    out = encode_frame(frame)
    assert list(out) == [m.name for m in MODALITIES]
    for m in MODALITIES:
        a = out[m.name]
        assert a.dtype == np.dtype(m.dtype) and a.shape[:2] == (recipe.video.height, recipe.video.width)
        assert a.shape[2:] == ((3,) if m.channels == 3 else ())
    palette = {PIXEL_CLASSES[n].rgb for n in PIXEL_CLASSES.names}
    assert {tuple(c) for c in np.unique(out["semantic"].reshape(-1, 3), axis=0)} <= palette
    for p in tr.people:
        mask = frame.instance == p.person_id + 1
        assert np.all(out["instance"][mask] == instance_rgb(p.person_id))
    assert np.all(out["instance"][frame.instance == 0] == 0)
    sky = frame.class_id == class_id("sky")
    assert sky.any() and np.all(out["depth"][sky] == 65535) and np.all(out["flow"][sky] == 0)
    flow, valid = decode_flow(out["flow"])
    assert np.abs(flow[valid] - frame.flow[valid]).max() <= 1 / 128 + 1e-6  # the 1/64 px quantum
    assert np.abs(decode_depth(out["depth"])[~sky] - frame.depth_m[~sky]).max() <= 0.005 + 1e-6


def test_instance_colours_are_distinct_and_never_black():
    colours = [instance_rgb(i) for i in range(MAX_PERSON_ID + 1)]
    assert len(set(colours)) == len(colours) and (0, 0, 0) not in colours
    with pytest.raises(ValueError, match="person id"):
        instance_rgb(MAX_PERSON_ID + 1)
