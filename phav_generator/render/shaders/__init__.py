"""The renderer's GLSL, one ``.glsl`` file per shader stage, read from package data.

A line ``#include "name.glsl"`` is replaced by that file's text (GLSL 3.30 has no include);
a file already included in the same shader is left out, so the pieces several shaders share
are written once:

- ``outputs.glsl``: the five render targets in attachment order (scene and sky shaders);
- ``hash.glsl``: the integer hash behind the materials' and the clouds' noise;
- ``tone.glsl``: the tone curve ``1 − exp(−exposure·c)`` and display gamma;
- ``sky.glsl``: the sky's colour along a direction, seen through the fog;
- ``models.glsl``: every drawable's model matrices at t and t + 1, one texture row per
  drawable (texels 0–3: the columns at t, 4–7: at t + 1), written once per frame.

The stages: ``scene_vertex`` / ``scene_fragment`` (the labelled geometry pass and the
supersampled colour passes), ``fullscreen_vertex`` (a triangle covering the viewport, for
the sky, resolve and post passes), ``sky_fragment`` (the background in every target),
``shadow_*`` (the sun's depth maps), ``rain_*`` (streaks), ``resolve_fragment`` (the mean of
the colour samples) and ``post_fragment`` (the RGB modality's post-processing).

``scene_fragment`` and ``post_fragment`` carry no ``#version``: ``with_features`` puts it
first, followed by the renderer's feature switches (``SHADOWS``, ``STILL_SHADOWS``,
``LAMPS``, ``WET``; ``MOTION_BLUR``, ``SSR``, ``AO``, ``BLOOM``): llvmpipe runs both sides of
a branch, so work a scene lacks is compiled out rather than skipped at run time.
"""

from __future__ import annotations

import re
from functools import cache
from importlib.resources import files

_INCLUDE = re.compile(r'^#include "([a-z_]+\.glsl)"\n', re.MULTILINE)


@cache
def shader_source(name: str) -> str:
    """The GLSL of ``name`` (a ``.glsl`` file of this package) with its includes expanded,
    each file once (where it is first included)."""
    return _expanded(name, set())


def _expanded(name: str, seen: set[str]) -> str:
    seen.add(name)
    text = files(__name__).joinpath(name).read_text(encoding="utf-8")
    return _INCLUDE.sub(lambda m: "" if m.group(1) in seen else _expanded(m.group(1), seen), text)


def with_features(source: str, flags: dict[str, bool]) -> str:
    """A shader's source with its feature switches defined (sorted: the text is deterministic)."""
    defines = "".join(f"#define {name} {int(on)}\n" for name, on in sorted(flags.items()))
    return "#version 330\n" + defines + source


__all__ = ["shader_source", "with_features"]
