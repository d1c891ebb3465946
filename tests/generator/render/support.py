"""Rendering a recipe in tests: physics first (the renderer never simulates), then frames."""

from __future__ import annotations

from collections.abc import Iterator

import moderngl

from phav_generator.physics.simulate import simulate
from phav_generator.render.video import RenderedFrame, render_video
from phav_spec.recipe import Recipe


def render_recipe(recipe: Recipe, ctx: moderngl.Context) -> Iterator[RenderedFrame]:
    """The frames of ``recipe``'s simulated trajectory, rendered in ``ctx``."""
    return render_video(recipe, simulate(recipe, keep_state=False), ctx=ctx)
