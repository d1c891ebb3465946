"""Recipe → trajectory → every frame's six modalities and metadata, with content hashes.

``render_video`` is the pure core of ``phav generate`` and ``phav regenerate``: given the
recipe's trajectory (physics is the stage before: ``physics.simulate.simulate``) and a GL
context (``render.context.gl_context``), it builds the scene once, renders each frame with
its flow towards the next and yields the encoded arrays with the frame's camera and people rows;
``phav_spec.encoding.VideoHashes`` accumulates one content hash per modality over the frames
(arrays named by zero-padded frame number). Nothing here touches files.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

import moderngl
import numpy as np

from phav_generator.physics.trajectory import Trajectory
from phav_generator.render.annotations import MetadataBuilder
from phav_generator.render.gl import Drawable, FrameRenderer, PostSettings
from phav_generator.render.lighting import Lighting, lighting_for
from phav_generator.render.modalities import encode_frame
from phav_generator.render.scene import build_drawables, class_id, lamp_positions
from phav_spec.recipe import Recipe
from phav_spec.scene import ENVIRONMENT_SCENES


@dataclass(frozen=True)
class RenderedFrame:
    """One frame of a video: the modality arrays (``MODALITIES`` names) and metadata rows."""

    index: int
    modalities: dict[str, np.ndarray]
    camera: dict[str, Any]
    people: list[dict[str, Any]]


@dataclass(frozen=True)
class SceneInputs:
    """Everything a video's renderer is given, computed on the CPU from its recipe and
    trajectory: the last stage before GL (``dataset.reference`` hashes it)."""

    width: int
    height: int
    drawables: list[Drawable]
    lighting: Lighting
    lamps: np.ndarray  # (L, 3) lamp positions, nearest the action first
    focus: np.ndarray  # (3,) the protagonist's mean position
    supersample: int
    post: PostSettings
    rain_seed: int
    fps: int


def scene_inputs(
    recipe: Recipe,
    trajectory: Trajectory,
    *,
    supersample: int | None = None,
    post: PostSettings | None = None,
    people: bool = True,
    assets: bool = True,
) -> SceneInputs:
    """One video's world, light and weather, focused on the protagonist, with the recipe's
    render settings (θ's ``render``: supersampling of the RGB modality and its post effects)
    unless ``supersample`` or ``post`` override them (the bench does); ``people=False``:
    without the people, ``assets=False``: the objects and places as their colliders' boxes
    (and a plain ground), for the bench."""
    env = ENVIRONMENT_SCENES[recipe.environment.name]
    lighting = lighting_for(recipe.world, indoor=env.indoor)
    protagonist = trajectory.person(recipe.protagonist.person_id)
    lamps = lamp_positions(recipe.environment.name)
    focus = protagonist.body_pos[:, 0].mean(axis=0)
    if len(lamps):  # the lamps nearest the action light it
        lamps = lamps[np.argsort(np.linalg.norm(lamps - focus, axis=1), kind="stable")]
    drawables = build_drawables(recipe, trajectory, lighting, people=people, assets=assets)
    return SceneInputs(
        recipe.video.width, recipe.video.height, drawables,
        lighting, lamps, focus, recipe.render.supersampling if supersample is None else supersample,
        PostSettings.from_render(recipe.render) if post is None else post, recipe.seeds.render, recipe.video.fps,
    )  # fmt: skip


def scene_renderer(
    recipe: Recipe,
    trajectory: Trajectory,
    ctx: moderngl.Context,
    *,
    supersample: int | None = None,
    post: PostSettings | None = None,
    people: bool = True,
    assets: bool = True,
) -> FrameRenderer:
    """A renderer for one video in ``ctx``: ``scene_inputs`` (same arguments) drawn by a
    ``FrameRenderer``."""
    s = scene_inputs(recipe, trajectory, supersample=supersample, post=post, people=people, assets=assets)
    return inputs_renderer(s, ctx)


def inputs_renderer(s: SceneInputs, ctx: moderngl.Context) -> FrameRenderer:
    """A ``FrameRenderer`` in ``ctx`` drawing scene inputs ``s`` (changed ones too: another
    lighting, say)."""
    return FrameRenderer(
        ctx, s.width, s.height, s.drawables, sky_class=class_id("sky"), lighting=s.lighting, lamps=s.lamps,
        focus=s.focus, supersample=s.supersample, post=s.post, rain_seed=s.rain_seed, fps=s.fps,
    )  # fmt: skip


def render_video(
    recipe: Recipe,
    trajectory: Trajectory,
    *,
    ctx: moderngl.Context,
    supersample: int | None = None,
    post: PostSettings | None = None,
) -> Iterator[RenderedFrame]:
    """Frames 0 … n_frames − 1 of a recipe's simulated ``trajectory``, rendered and measured
    in ``ctx`` (the caller's: it stays open), with the recipe's render settings unless
    ``supersample`` or ``post`` override them (``scene_renderer``)."""
    tr = trajectory
    with scene_renderer(recipe, tr, ctx, supersample=supersample, post=post) as renderer:
        meta = MetadataBuilder(recipe, tr)
        for f in range(tr.n_frames):
            frame = renderer.render(f, tr.cam_to_world[f], tr.cam_to_world[f + 1], tr.intrinsics)
            yield RenderedFrame(f, encode_frame(frame), meta.camera_row(f), meta.people_rows(f, frame))
