"""A recipe's video, frame by frame: identical content hashes in fresh processes, streamed
hashes equal to the whole video's, and flow that carries each pixel to its next position."""

from __future__ import annotations

import itertools
import json
import subprocess
import sys

import cv2
import numpy as np

from phav_generator.vary import vary
from phav_spec.encoding import VideoHashes, content_hash, decode_flow
from tests.generator.physics.support import recipe_for, theta_for
from tests.generator.render.support import render_recipe

_HASH_SCRIPT = """
import json
from phav_generator.render.context import gl_context
from phav_spec.encoding import VideoHashes
from tests.generator.physics.support import recipe_for
from tests.generator.render.support import render_recipe
r = recipe_for("walk", "urban", seconds=0.3, variation="none")
h = VideoHashes(r.n_frames)
for rf in render_recipe(r, gl_context()):
    h.add(rf.index, rf.modalities)
print(json.dumps(h.hexdigests()))
"""


def test_a_video_hashes_the_same_in_two_processes():
    """Same recipe, two fresh processes (fresh GL contexts): identical content hashes."""
    runs = [
        json.loads(
            subprocess.run([sys.executable, "-c", _HASH_SCRIPT], capture_output=True, text=True, check=True).stdout
        )
        for _ in range(2)
    ]
    assert runs[0] == runs[1] and len(runs[0]) == 6


def test_streamed_hashes_equal_the_content_hash_of_all_frames(ctx):
    recipe = recipe_for("wave", "green", seconds=0.2, variation="none")
    frames = list(render_recipe(recipe, ctx))
    h = VideoHashes(len(frames))
    for rf in frames:
        h.add(rf.index, rf.modalities)
    expected = content_hash({f"{rf.index:05d}": rf.modalities["depth"] for rf in frames})
    assert h.hexdigests()["depth"] == expected


def test_rgb_warped_by_the_flow_matches_the_next_frame_on_static_pixels(ctx):
    """Raw RGB of frame t+1 sampled where the flow sends each static, unoccluded pixel of
    frame t (same class there, bilinear) equals frame t's colour within a few levels."""
    base = recipe_for("walk", "simple", seconds=0.3, variation="none")
    recipe = vary(base, theta_for("walk", "simple", seconds=0.3, variation="none"),
                  {"weather": "clear", "wet_ground": False, "rain": False, "fog": False})  # fmt: skip
    frames = [rf.modalities for rf in render_recipe(recipe, ctx)]
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


def test_the_recipes_render_settings_reach_the_renderer(ctx):
    """θ's ``render`` section, carried by each recipe, decides the RGB modalities: one sample
    a pixel or every post effect off changes the RGB; the raw RGB (the samples' mean, before
    post) changes with the samples only; labels, depth and flow stay identical to the bit."""
    base = recipe_for("walk", "urban", seconds=0.2, variation="none")
    assert base.render.supersampling == 2
    one_sample = base.model_copy(update={"render": base.render.model_copy(update={"supersampling": 1})})
    plain = base.model_copy(update={"render": base.render.model_copy(update={
        "motion_blur": False, "bloom": False, "ambient_occlusion": False, "screen_space_reflection": False,
        "color_grading": False, "vignette": False})})  # fmt: skip
    runs = {name: [rf.modalities for rf in render_recipe(r, ctx)] for name, r in
            (("base", base), ("one_sample", one_sample), ("plain", plain))}  # fmt: skip
    for name in ("one_sample", "plain"):
        for a, b in zip(runs["base"], runs[name], strict=True):
            for m in ("semantic", "instance", "depth", "flow"):
                assert np.array_equal(a[m], b[m]), (name, m)
        assert not all(np.array_equal(a["rgb"], b["rgb"]) for a, b in zip(runs["base"], runs[name], strict=True))
    pairs = {name: list(zip(runs["base"], runs[name], strict=True)) for name in ("one_sample", "plain")}
    assert all(np.array_equal(a["raw_rgb"], b["raw_rgb"]) for a, b in pairs["plain"])
    # One sample a pixel: the same picture, its edges aliased rather than averaged.
    diffs = [np.abs(a["raw_rgb"].astype(int) - b["raw_rgb"].astype(int)) for a, b in pairs["one_sample"]]
    assert all(d.max() > 0 for d in diffs) and np.mean([d.mean() for d in diffs]) < 3.0
