"""The GLSL ships as package data: every shader stage is a ``.glsl`` file of
``phav_generator.render.shaders``, read through ``importlib.resources`` with its includes
expanded, and compiles with every combination of the renderer's feature switches."""

from __future__ import annotations

import itertools
from importlib.resources import files

import pytest

from phav_generator.render.shaders import shader_source, with_features

SNIPPETS = ("hash.glsl", "materials.glsl", "models.glsl", "outputs.glsl", "sky.glsl", "tone.glsl")
#: Each program's stages and the feature switches its fragment stage takes (None: no switches).
PROGRAMS = {
    "scene": ("scene_vertex.glsl", "scene_fragment.glsl", ("LAMPS", "MATERIALS", "SHADOWS", "STILL_SHADOWS", "WET")),
    "sky": ("fullscreen_vertex.glsl", "sky_fragment.glsl", None),
    "shadow": ("shadow_vertex.glsl", "shadow_fragment.glsl", None),
    "rain": ("rain_vertex.glsl", "rain_fragment.glsl", None),
    "resolve": ("fullscreen_vertex.glsl", "resolve_fragment.glsl", None),
    "post": ("fullscreen_vertex.glsl", "post_fragment.glsl", ("AO", "BLOOM", "MOTION_BLUR", "SSR")),
}


def test_every_glsl_file_of_the_package_is_a_stage_or_a_shared_snippet():
    packaged = {p.name for p in files("phav_generator.render.shaders").iterdir() if p.name.endswith(".glsl")}
    stages = {name for vertex, fragment, _ in PROGRAMS.values() for name in (vertex, fragment)}
    assert packaged == stages | set(SNIPPETS)


def test_includes_are_replaced_by_the_snippets_text():
    scene = shader_source("scene_fragment.glsl")
    assert "#include" not in scene
    for snippet in ("sky.glsl", "tone.glsl", "outputs.glsl"):
        assert shader_source(snippet) in scene
    assert shader_source("models.glsl") in shader_source("scene_vertex.glsl")
    # the sky and the materials both include the hash: the scene gets it once, where the sky brings it
    assert scene.count("uint hash_u(") == 1 and shader_source("sky_fragment.glsl").count("uint hash_u(") == 1
    text = files("phav_generator.render.shaders").joinpath("rain_vertex.glsl").read_text(encoding="utf-8")
    assert shader_source("rain_vertex.glsl") == text  # no include: the file as shipped


def test_feature_switches_follow_the_version_line_in_sorted_order():
    source = with_features("void main() {}\n", {"WET": True, "LAMPS": False})
    assert source == "#version 330\n#define LAMPS 0\n#define WET 1\nvoid main() {}\n"


@pytest.mark.parametrize("program", sorted(PROGRAMS))
def test_every_program_compiles_with_every_feature_combination(ctx, program):
    vertex, fragment, switches = PROGRAMS[program]
    if switches is None:
        ctx.program(vertex_shader=shader_source(vertex), fragment_shader=shader_source(fragment)).release()
        return
    for values in itertools.product((False, True), repeat=len(switches)):
        source = with_features(shader_source(fragment), dict(zip(switches, values, strict=True)))
        ctx.program(vertex_shader=shader_source(vertex), fragment_shader=source).release()
