"""Recipe + trajectory → drawables → frames: labels come from the palette, people keep their
instance ids, the environment's surfaces carry their classes."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from phav_generator.physics.simulate import simulate
from phav_generator.render.gl import FrameRenderer, gl_context
from phav_generator.render.scene import build_drawables, class_id
from phav_spec.vocab import PIXEL_CLASSES
from tests.generator.physics.support import recipe_for

PALETTE_IDS = {PIXEL_CLASSES[n].class_id for n in PIXEL_CLASSES.names}
PERSON_CLASSES = {
    PIXEL_CLASSES[n].class_id for n in PIXEL_CLASSES.names if PIXEL_CLASSES[n].group.name.startswith("HUMAN")
}


@pytest.fixture(scope="module")
def ctx():
    c = gl_context()
    yield c
    c.release()


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


def test_encoded_modalities_follow_the_spec(ctx):
    from phav_generator.render.modalities import encode_frame
    from phav_spec.encoding import MODALITIES, decode_depth, decode_flow, instance_rgb

    recipe = recipe_for("walk_holding_hands", "simple", seconds=0.5, variation="none")
    tr = simulate(recipe, keep_state=False)
    renderer = FrameRenderer(
        ctx, recipe.video.width, recipe.video.height, build_drawables(recipe, tr), sky_class=class_id("sky")
    )
    try:
        frame = renderer.render(3, tr.cam_to_world[3], tr.cam_to_world[4], tr.intrinsics)
    finally:
        renderer.release()
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
    from phav_spec.encoding import MAX_PERSON_ID, instance_rgb

    colours = [instance_rgb(i) for i in range(MAX_PERSON_ID + 1)]
    assert len(set(colours)) == len(colours) and (0, 0, 0) not in colours
    with pytest.raises(ValueError, match="person id"):
        instance_rgb(MAX_PERSON_ID + 1)


_HASH_SCRIPT = """
import json, sys
from tests.generator.physics.support import recipe_for
from phav_generator.render.video import render_video
from phav_spec.encoding import VideoHashes
r = recipe_for("walk", "urban", seconds=0.3, variation="none")
h = VideoHashes(r.n_frames)
for rf in render_video(r):
    h.add(rf.index, rf.modalities)
print(json.dumps(h.hexdigests()))
"""


def test_a_video_hashes_the_same_in_two_processes():
    """Same recipe, two fresh processes (fresh GL contexts): identical content hashes."""
    import json
    import subprocess
    import sys

    runs = [
        json.loads(
            subprocess.run([sys.executable, "-c", _HASH_SCRIPT], capture_output=True, text=True, check=True).stdout
        )
        for _ in range(2)
    ]
    assert runs[0] == runs[1] and len(runs[0]) == 6


def test_streamed_hashes_equal_the_content_hash_of_all_frames(ctx):
    from phav_generator.render.video import render_video
    from phav_spec.encoding import VideoHashes, content_hash

    recipe = recipe_for("wave", "green", seconds=0.2, variation="none")
    frames = list(render_video(recipe, ctx=ctx))
    h = VideoHashes(len(frames))
    for rf in frames:
        h.add(rf.index, rf.modalities)
    expected = content_hash({f"{rf.index:05d}": rf.modalities["depth"] for rf in frames})
    assert h.hexdigests()["depth"] == expected


def _adjacent(joint: str) -> set[str]:
    """The joint's own class and the parts that meet at it."""
    side, _, kind = joint.partition("_")
    parts = {
        "shoulder": ("chest", f"{side}_upper_arm"),
        "elbow": (f"{side}_upper_arm", f"{side}_lower_arm"),
        "wrist": (f"{side}_lower_arm", f"{side}_hand"),
        "hip": (f"{side}_upper_leg", f"{side}_hip", "chest"),
        "knee": (f"{side}_upper_leg", f"{side}_lower_leg"),
        "ankle": (f"{side}_lower_leg", f"{side}_foot"),
    }
    return {joint, *(("head", "chest") if joint == "neck" else parts[kind])}


def test_visible_2d_joints_land_on_their_joint_or_an_adjacent_part(ctx):
    from phav_generator.render.video import render_video
    from phav_spec.metadata import JOINT_ORDER
    from phav_spec.vocab import PIXEL_CLASSES

    by_colour = {PIXEL_CLASSES[n].rgb: n for n in PIXEL_CLASSES.names}
    visible = 0
    for action, env in (("walk", "urban"), ("wave", "green"), ("sit", "house_interior")):
        for rf in render_video(recipe_for(action, env, seconds=0.3, variation="none"), ctx=ctx):
            semantic = rf.modalities["semantic"]
            for person in rf.people:
                uv = np.array(person["joints2d"]).reshape(13, 2)
                for j, name in enumerate(JOINT_ORDER):
                    if not person["visible"][j]:
                        continue
                    visible += 1
                    seen = by_colour[tuple(int(c) for c in semantic[int(uv[j, 1]), int(uv[j, 0])])]
                    assert seen in _adjacent(name), (action, rf.index, person["person_id"], name, seen)
    assert visible > 100


def test_rgb_warped_by_the_flow_matches_the_next_frame_on_static_pixels(ctx):
    """Raw RGB of frame t+1 sampled where the flow sends each static, unoccluded pixel of
    frame t (same class there, bilinear) equals frame t's colour within a few levels."""
    import cv2

    from phav_generator.render.video import render_video
    from phav_generator.vary import vary
    from phav_spec.encoding import decode_flow
    from tests.generator.physics.support import theta_for

    base = recipe_for("walk", "simple", seconds=0.3, variation="none")
    recipe = vary(base, theta_for("walk", "simple", seconds=0.3, variation="none"),
                  {"weather": "clear", "wet_ground": False, "rain": False, "fog": False})  # fmt: skip
    frames = [rf.modalities for rf in render_video(recipe, ctx=ctx)]
    errors = []
    for a, b in itertools.pairwise(frames):
        flow, valid = decode_flow(a["flow"])
        h, w = valid.shape
        v, u = np.mgrid[0:h, 0:w].astype(np.float32)
        map_x = u + np.nan_to_num(flow[..., 0])
        map_y = v + np.nan_to_num(flow[..., 1])
        warped = cv2.remap(b["raw_rgb"].astype(np.float32), map_x, map_y, cv2.INTER_LINEAR)
        cls_next = cv2.remap(b["semantic"], map_x, map_y, cv2.INTER_NEAREST)
        static = valid & (a["instance"].sum(axis=-1) == 0)
        same = np.all(cls_next == a["semantic"], axis=-1)
        inside = (map_x >= 1) & (map_x < w - 2) & (map_y >= 1) & (map_y < h - 2)
        keep = static & same & inside
        errors.append(np.abs(warped - a["raw_rgb"].astype(np.float32)).mean(axis=-1)[keep])
    err = np.concatenate(errors)
    assert err.size > 10000
    assert np.median(err) < 1.5 and np.percentile(err, 95) < 8.0, (np.median(err), np.percentile(err, 95))
