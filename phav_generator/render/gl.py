"""One geometry pass, five render targets: colour, semantic class, instance id, linear
depth and forward flow, all from one shader (the paper's multiple-render-target idea);
then the RGB modality's post-processing.

Every drawable is a rigid mesh with a world transform at frame t and at t + 1. The vertex
shader places each vertex at both times; the fragment shader writes the depth along the
camera axis at t and the flow as where the same surface point lands in frame t + 1
(camera and object motion together), exact for rigid parts because clip coordinates are
affine in the vertex position and interpolate perspective-correctly. Labels, depth and
flow come from one sample per pixel and are never blended.

Per frame: a sun shadow map (depth only), the labelled pass at 1×, then ``supersample``
fully shaded colour samples per pixel with rain streaks in colour only (SSAA: one jittered
colour-only pass per sample, side by side in one wide target, averaged by a resolve pass:
the raw RGB; at one sample the labelled pass shades it itself), and a full-screen post pass
(motion blur along the flow, screen-space reflections on water and wet ground, ambient
occlusion from depth, bloom, colour grading, vignette). ``FrameRenderer.render`` is
``render_labels`` (everything up to the labelled targets' read-back) then ``render_rgb``
(supersampling and post): ``phav bench`` times them apart. The GLSL lives in
``render/shaders``; the GL context comes from ``render.context``.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass, replace

import moderngl
import numpy as np

from phav_generator.motion.rotations import look_at
from phav_generator.render.camera import FAR_M, NEAR_M, projection, view
from phav_generator.render.lighting import MAX_LAMPS, Lighting
from phav_generator.render.meshes import Mesh
from phav_generator.render.shaders import shader_source, with_features
from phav_spec.seeding import seeded_rng
from phav_spec.theta import RenderSettings

#: Surface kinds the shader treats differently (``Drawable.material``).
MATTE, GROUND, WATER, EMISSIVE = 0, 1, 2, 3
#: Patterns of the shader (``Drawable.pattern``): plain colour, speckled by world position
#: (the ground's grain), and a texture image (a ``VertexLook``'s, set by it).
PLAIN, SPECKLE, TEXTURED = 0, 3, 4
#: Patterns from this one on are the asset library's materials (``materials.glsl``).
FIRST_MATERIAL = 5
#: The coarsest mip level of texture images (texels 2^level wide).
MAX_MIP_LEVEL = 3
#: Shadow map: texels per side and the half extent (m) of the square it covers.
SHADOW_SIZE = 1024
SHADOW_HALF_M = 30.0
#: Supersampling patterns: sub-pixel offsets (image convention, pixels from the centre) of
#: the colour samples per pixel. 2: diagonal pair; 4: rotated grid; 8: sparse n-rooks;
#: 16: 4 × 4 ordered grid (the bench's reference).
SAMPLE_PATTERNS: dict[int, tuple[tuple[float, float], ...]] = {
    1: ((0.0, 0.0),),
    2: ((-0.25, -0.25), (0.25, 0.25)),
    4: ((-0.125, -0.375), (0.375, -0.125), (-0.375, 0.125), (0.125, 0.375)),
    8: tuple((x / 16.0, y / 16.0) for x, y in ((1, -3), (-1, 3), (5, 1), (-3, -5), (-5, 5), (-7, -1), (3, 7), (7, -7))),
    16: tuple(((i + 0.5) / 4.0 - 0.5, (j + 0.5) / 4.0 - 0.5) for j in range(4) for i in range(4)),
}
#: Drawables with a bounding radius beyond this (m) are drawn after the rest of the scene.
LARGE_M = 15.0
#: A skinned mesh's rest bounding sphere, followed by its root bone, is widened this much
#: so that limbs swinging away from the rest pose stay inside it (frustum culling).
SKINNED_REACH = 1.6
#: Rain streaks at rain intensity 1, and how far around the camera they fall (m).
RAIN_STREAKS = 1800
RAIN_BOX_M = 12.0
RAIN_SPEED_MPS = 9.0


@dataclass(frozen=True)
class VertexLook:
    """Labels and look that vary over a mesh (a person's parts and clothes): pixel classes
    per vertex (a triangle takes its last vertex's, OpenGL's provoking vertex: flat) and a
    texture image over it, mipmapped; they override the drawable's class and colour."""

    class_ids: np.ndarray  # (N,) pixel classes
    uvs: np.ndarray  # (N, 2) texture coordinates, (0, 0) the texture's first texel
    texture: np.ndarray  # (H, W, 3) float16 linear colours, row 0 at v = 0; drawables
    # sharing one array share its texture layer


@dataclass(frozen=True)
class PartLook:
    """Labels and look that vary over an asset's parts (``phav_generator.world``): per vertex a
    pixel class, a material (the shader's pattern code, computed from the vertex's position in
    the mesh's own frame, shifted where it stands still: ``material_coordinates``), a surface
    kind (MATTE, GROUND, EMISSIVE), a display colour and a linear emission; they override the
    drawable's."""

    class_ids: np.ndarray  # (N,)
    patterns: np.ndarray  # (N,) world.materials.Material values
    surfaces: np.ndarray  # (N,) MATTE, GROUND or EMISSIVE
    colours: np.ndarray  # (N, 3) display colours, 0–1
    emission: np.ndarray  # (N, 3) linear


@dataclass(frozen=True)
class Drawable:
    """A mesh with its labels, look and world transforms per frame: (F, 4, 4) for a rigid
    mesh, (F, K, 4, 4) for a mesh skinned to K bones (``mesh.bones`` index them)."""

    mesh: Mesh
    transforms: np.ndarray
    class_id: int
    instance_id: int = 0  # 0: not a person
    colour: tuple[float, float, float] = (0.6, 0.6, 0.6)
    material: int = MATTE
    emission: tuple[float, float, float] = (0.0, 0.0, 0.0)
    pattern: int = PLAIN  # PLAIN or SPECKLE (a vertex look is TEXTURED)
    casts_shadow: bool = True
    vertex_look: VertexLook | None = None
    part_look: PartLook | None = None

    @property
    def n_bones(self) -> int:
        """Rows of the models texture this drawable uses: 1 when rigid."""
        return 1 if self.transforms.ndim == 3 else self.transforms.shape[1]


@dataclass(frozen=True)
class Frame:
    """One rendered frame: image rows top to bottom, columns left to right."""

    colour: np.ndarray | None  # (H, W, 3) uint8: raw RGB, before post-processing (the samples' mean)
    class_id: np.ndarray  # (H, W) uint16 pixel-class ids
    instance: np.ndarray  # (H, W) uint16 person ids + 1, 0 for no person
    depth_m: np.ndarray  # (H, W) float32, +inf for sky
    flow: np.ndarray  # (H, W, 2) float32 pixels, t → t + 1
    flow_valid: np.ndarray  # (H, W) bool
    rgb: np.ndarray | None = None  # (H, W, 3) uint8 after post-processing


@dataclass(frozen=True)
class PostSettings:
    """The RGB modality's post-processing: each effect's strength, 0 (or False) for off."""

    motion_blur: float = 0.5
    ambient_occlusion: float = 0.45
    bloom: float = 0.6
    vignette: float = 0.16
    grade_gain: tuple[float, float, float] = (1.02, 1.0, 0.98)
    grade_lift: float = 0.01
    saturation: float = 1.08
    #: Screen-space reflections on water and wet ground (where the scene has them).
    reflections: bool = True
    #: Colour grading: the gain, lift and saturation above and a gentle S-curve.
    grading: bool = True

    @classmethod
    def from_render(cls, settings: RenderSettings) -> PostSettings:
        """The effects a recipe's render settings (θ's ``render`` section) switch on, at
        their default strengths."""
        on = cls()
        return cls(
            motion_blur=on.motion_blur if settings.motion_blur else 0.0,
            ambient_occlusion=on.ambient_occlusion if settings.ambient_occlusion else 0.0,
            bloom=on.bloom if settings.bloom else 0.0,
            vignette=on.vignette if settings.vignette else 0.0,
            reflections=settings.screen_space_reflection,
            grading=settings.color_grading,
        )


def _default_lighting() -> Lighting:
    """A plain grey day without fog, rain or lamps, for drawables rendered without a recipe."""
    grey = np.array([0.55, 0.75, 0.95])
    return Lighting(
        sun_dir=np.array([0.3, -0.4, 0.87]) / np.linalg.norm([0.3, -0.4, 0.87]),
        sun_colour=np.full(3, 0.65), sky_ambient=np.full(3, 0.35), ground_ambient=np.full(3, 0.35),
        sky_zenith=grey, sky_horizon=grey, fog_colour=grey, fog_per_m=0.0, wetness=0.0, rain=0.0,
        lamp_intensity=0.0, daylight=1.0,
    )  # fmt: skip


def _write(prog: moderngl.Program, name: str, data: bytes) -> None:
    """Write a uniform's raw bytes if the program uses it."""
    if name in prog:
        prog[name].write(data)


def _set(prog: moderngl.Program, name: str, value) -> None:
    """Set a uniform if the program uses it (GLSL drops unused ones)."""
    if name in prog:
        member = prog[name]
        if isinstance(value, np.ndarray):
            value = tuple(float(x) for x in value)
        member.value = value


@dataclass
class _ShadowMap:
    """One of the sun's depth maps: of the casters that move (drawn every frame), or of those
    that hold still for the whole video (drawn once: neither they nor the sun move)."""

    uniform: str  # the scene shader's sampler
    location: int  # its texture unit
    casters: list[int]  # indices into the drawables
    every_frame: bool
    texture: moderngl.Texture
    framebuffer: moderngl.Framebuffer
    vao: moderngl.VertexArray | None = None
    drawn: bool = False


@dataclass(frozen=True)
class _LabelledPass:
    """What the RGB passes need of the labelled pass they finish (``render_labels``)."""

    labels: Frame
    n_indices: int  # the frame's visible triangles' indices, in the index buffer
    n_near: int  # how many of them, first, are not large slabs
    intrinsics: tuple[float, float, float, float]
    cam_to_world: np.ndarray
    rain: np.ndarray | None  # streak end points (2N, 3), or None without rain


class FrameRenderer:
    """Draws a set of drawables frame by frame: labelled targets, raw and post-processed RGB.

    Use it as a context manager (``with FrameRenderer(...) as r:``) or call ``release``: its
    GL objects are freed on exit, the context stays.
    """

    def __init__(
        self,
        ctx: moderngl.Context,
        width: int,
        height: int,
        drawables: list[Drawable],
        *,
        sky_class: int,
        lighting: Lighting | None = None,
        lamps: np.ndarray | None = None,
        focus: np.ndarray | None = None,
        supersample: int = 2,
        post: PostSettings | None = None,
        rain_seed: int = 0,
        fps: float = 30.0,
    ):
        if supersample not in SAMPLE_PATTERNS:
            choices = sorted(SAMPLE_PATTERNS)
            raise ValueError(f"supersample must be one of {choices} samples per pixel, got {supersample}")
        self.ctx = ctx
        self.size = (width, height)
        self.drawables = drawables
        self.lighting = lighting if lighting is not None else _default_lighting()
        self.post_settings = post if post is not None else PostSettings()
        self.fps = fps  # the clip's: rain falls by its time, not its frame count
        self.supersample = supersample
        lamps = np.zeros((0, 3)) if lamps is None else np.asarray(lamps, dtype=np.float64).reshape(-1, 3)
        self.lamps = lamps[:MAX_LAMPS] if self.lighting.lamp_intensity > 0.01 else np.zeros((0, 3))
        self.focus = np.zeros(3) if focus is None else np.asarray(focus, dtype=np.float64)
        self.sky_class = sky_class
        casters = [i for i, d in enumerate(drawables) if d.casts_shadow] if self.lighting.shadows else []
        still = [_holds_still(drawables[i]) for i in casters]
        self._still_casters = [i for i, s in zip(casters, still, strict=True) if s]
        self._moving_casters = [i for i, s in zip(casters, still, strict=True) if not s]
        self.use_shadow = bool(casters)
        #: The GL objects this renderer made, and its programs: ``release`` frees both.
        self._objects: list = []
        self._programs: list[moderngl.Program] = []
        self._labelled: _LabelledPass | None = None
        try:  # GL objects are made in this order: programs, targets, geometry, rain
            self._build_bounds()
            self._build_programs()
            self._build_label_targets()
            self._build_colour_targets()
            self._build_shadow_map()
            self._build_geometry()
            self._build_rain(rain_seed)
            self._set_static_uniforms()
        except BaseException:
            self.release()  # what was made so far: a failed renderer leaks nothing
            raise

    def __enter__(self) -> FrameRenderer:
        return self

    def __exit__(self, *exc: object) -> None:
        self.release()

    def _build_programs(self) -> None:
        """The shader programs, each compiled with only the features this scene uses, and
        the full-screen triangle the sky and post passes draw."""
        ctx, ps = self.ctx, self.post_settings
        wet = self.lighting.wetness > 0.0 or any(d.material == WATER for d in self.drawables)
        materials = any(d.part_look is not None for d in self.drawables)
        features = {"SHADOWS": bool(self._moving_casters), "STILL_SHADOWS": bool(self._still_casters),
                    "LAMPS": len(self.lamps) > 0, "WET": wet, "MATERIALS": materials}  # fmt: skip
        # Two builds of the scene program: the labelled pass places each vertex at t + 1 too
        # (its flow); the colour passes skip that work (llvmpipe runs both sides of a branch).
        # Supersampled, the raw colour is the samples' mean: the labelled pass does not shade.
        vertex = shader_source("scene_vertex.glsl").replace("#version 330\n", "", 1)
        fragment = shader_source("scene_fragment.glsl")
        # The colour passes draw the scene nearest first, then the large slabs (ground,
        # terrain, roads), each with a program holding only the materials it shows: llvmpipe
        # pays for every material a program holds, on every pixel it shades.
        near = _material_flags(d for d, large in zip(self.drawables, self._large, strict=True) if not large)
        far = _material_flags(d for d, large in zip(self.drawables, self._large, strict=True) if large)
        self.program = ctx.program(
            vertex_shader=with_features(vertex, {"FLOW": True}),
            fragment_shader=with_features(fragment, {**features, "COLOUR": self.supersample == 1, **near, **far}),
        )
        self.colour_program, self.colour_program_far = (
            ctx.program(
                vertex_shader=with_features(vertex, {"FLOW": False}),
                fragment_shader=with_features(fragment, {**features, "COLOUR": True, **shown}),
            )
            for shown in (near, far)
        )
        fullscreen = shader_source("fullscreen_vertex.glsl")
        self.sky = ctx.program(vertex_shader=fullscreen, fragment_shader=shader_source("sky_fragment.glsl"))
        self.shadow_prog = ctx.program(
            vertex_shader=shader_source("shadow_vertex.glsl"), fragment_shader=shader_source("shadow_fragment.glsl")
        )
        self.rain_prog = ctx.program(
            vertex_shader=shader_source("rain_vertex.glsl"), fragment_shader=shader_source("rain_fragment.glsl")
        )
        post_features = {"MOTION_BLUR": ps.motion_blur > 0.0, "SSR": wet and ps.reflections,
                         "AO": ps.ambient_occlusion > 0.0, "BLOOM": ps.bloom > 0.0, "GRADING": ps.grading}  # fmt: skip
        self.post_prog = ctx.program(
            vertex_shader=fullscreen, fragment_shader=with_features(shader_source("post_fragment.glsl"), post_features)
        )
        self._scene_programs = (self.program, self.colour_program, self.colour_program_far)
        self._programs += [*self._scene_programs, self.sky, self.shadow_prog, self.rain_prog, self.post_prog]
        tri = np.array([-1.0, -1.0, 3.0, -1.0, -1.0, 3.0], dtype=np.float32)
        self._tri = ctx.buffer(tri.tobytes())
        self.sky_vao = ctx.vertex_array(self.sky, [(self._tri, "2f", "in_xy")])
        self.post_vao = ctx.vertex_array(self.post_prog, [(self._tri, "2f", "in_xy")])
        self._objects += [self._tri, self.sky_vao, self.post_vao]

    def _build_label_targets(self) -> None:
        """The labelled 1× pass's five targets: textures where the post pass reads them."""
        ctx, (width, height) = self.ctx, self.size
        self.colour_1x = ctx.texture((width, height), 4, dtype="f1")
        self.class_rb = ctx.renderbuffer((width, height), 1, dtype="u2")
        self.instance_rb = ctx.renderbuffer((width, height), 1, dtype="u2")
        self.depth_tex = ctx.texture((width, height), 1, dtype="f4")
        self.flow_tex = ctx.texture((width, height), 4, dtype="f4")
        for t in (self.colour_1x, self.depth_tex, self.flow_tex):
            t.filter = (moderngl.NEAREST, moderngl.NEAREST)
            t.repeat_x = t.repeat_y = False
        self.zbuffer = ctx.depth_renderbuffer((width, height))
        self.fbo = ctx.framebuffer(
            color_attachments=[self.colour_1x, self.class_rb, self.instance_rb, self.depth_tex, self.flow_tex],
            depth_attachment=self.zbuffer,
        )
        self.colour_fbo = ctx.framebuffer(color_attachments=[self.colour_1x], depth_attachment=self.zbuffer)
        self._objects += [self.colour_1x, self.class_rb, self.instance_rb, self.depth_tex, self.flow_tex,
                          self.zbuffer, self.fbo, self.colour_fbo]  # fmt: skip

    def _build_colour_targets(self) -> None:
        """Supersampled colour (the samples side by side with their own depth buffer, resolved
        to 1×; the 1× colour itself without supersampling) and the post pass's output."""
        ctx, (width, height), s = self.ctx, self.size, self.supersample
        if s > 1:
            self.samples_tex = ctx.texture((width * s, height), 4, dtype="f1")
            self.zbuffer_ss = ctx.depth_renderbuffer((width * s, height))
            self.fbo_ss = ctx.framebuffer(color_attachments=[self.samples_tex], depth_attachment=self.zbuffer_ss)
            self.colour_ss = ctx.texture((width, height), 4, dtype="f1")
            self.resolve_fbo = ctx.framebuffer(color_attachments=[self.colour_ss])
            self.resolve_prog = ctx.program(
                vertex_shader=shader_source("fullscreen_vertex.glsl"),
                fragment_shader=shader_source("resolve_fragment.glsl"),
            )
            self.resolve_vao = ctx.vertex_array(self.resolve_prog, [(self._tri, "2f", "in_xy")])
            _set(self.resolve_prog, "samples", 5)
            _set(self.resolve_prog, "count", s)
            _set(self.resolve_prog, "width", width)
            self._objects += [self.samples_tex, self.zbuffer_ss, self.fbo_ss, self.colour_ss, self.resolve_fbo,
                              self.resolve_vao]  # fmt: skip
            self._programs.append(self.resolve_prog)
        else:
            self.colour_ss, self.fbo_ss = self.colour_1x, None
        # Read at pixel centres and, for blur, bloom and reflections, between them.
        self.colour_ss.filter = (moderngl.LINEAR, moderngl.LINEAR)
        self.colour_ss.repeat_x = self.colour_ss.repeat_y = False
        self.out_rb = ctx.renderbuffer((width, height), 4, dtype="f1")
        self.out_fbo = ctx.framebuffer(color_attachments=[self.out_rb])
        self._objects += [self.out_rb, self.out_fbo]

    def _build_shadow_map(self) -> None:
        """The sun's depth maps around the focus, where the scene casts shadows: one of the
        casters that move, one of those that hold still (the shader takes the darker)."""
        self._shadow_maps: list[_ShadowMap] = []
        self.light_vp = _sun_matrix(self.lighting.sun_dir, self.focus) if self.use_shadow else np.eye(4)
        maps = (("shadow_map", 0, self._moving_casters, True), ("still_shadow_map", 2, self._still_casters, False))
        for uniform, location, casters, every_frame in maps:
            if not casters:
                continue
            texture = self.ctx.depth_texture((SHADOW_SIZE, SHADOW_SIZE))
            texture.compare_func = "<="
            texture.filter = (moderngl.LINEAR, moderngl.LINEAR)
            framebuffer = self.ctx.framebuffer(depth_attachment=texture)
            self._objects += [texture, framebuffer]
            self._shadow_maps.append(_ShadowMap(uniform, location, casters, every_frame, texture, framebuffer))

    def _build_geometry(self) -> None:
        """Every drawable in one vertex buffer, drawn with one call per pass through a
        per-frame index buffer (the visible drawables, nearest first); the models texture."""
        ctx, drawables = self.ctx, self.drawables
        vertices, self._indices, textures = _pack(drawables)
        self._n_indices = np.array([len(i) for i in self._indices], dtype=np.int64)
        self._world = _stack_transforms(drawables)  # (L, rows, 4, 4) world transforms per frame
        rows = self._world.shape[1]
        #: Each drawable's first row: a rigid drawable's transform, a skinned one's root bone.
        self._rows = np.cumsum([0] + [d.n_bones for d in drawables])[:-1].astype(np.int64)
        # The models texture's rows: each bone's matrix columns (column-major, as GLSL).
        self._columns = np.ascontiguousarray(self._world.transpose(0, 1, 3, 2).reshape(-1, rows, 16), dtype=np.float32)
        self.models_tex = ctx.texture((8, max(rows, 1)), 4, dtype="f4")
        self.models_tex.filter = (moderngl.NEAREST, moderngl.NEAREST)
        self.vbo = ctx.buffer(vertices.tobytes() if drawables else bytes(_VERTEX_DTYPE.itemsize))
        total = sum(len(i) for i in self._indices)
        self.index_buffer = ctx.buffer(reserve=max(total, 3) * 4, dynamic=True)
        self.vao = ctx.vertex_array(self.program, _layout(self.vbo, self.program), self.index_buffer,
                                    index_element_size=4)  # fmt: skip
        self.colour_vaos = tuple(
            ctx.vertex_array(p, _layout(self.vbo, p), self.index_buffer, index_element_size=4)
            for p in (self.colour_program, self.colour_program_far)
        )
        self._objects += [self.models_tex, self.vbo, self.index_buffer, self.vao, *self.colour_vaos]
        self.textures = _texture_array(ctx, textures)
        self._objects.append(self.textures)
        for shadow in self._shadow_maps:
            ibo = ctx.buffer(np.concatenate([self._indices[i] for i in shadow.casters]).tobytes())
            shadow.vao = ctx.vertex_array(self.shadow_prog, _layout(self.vbo, self.shadow_prog), ibo,
                                          index_element_size=4)  # fmt: skip
            self._objects += [ibo, shadow.vao]

    def _build_bounds(self) -> None:
        """Bounding spheres (local centre, radius) for frustum culling of the camera passes,
        and the triangle counts the bench reports."""
        drawables, n = self.drawables, len(self.drawables)
        self._centres = np.zeros((n, 3))
        self._radii = np.zeros(n)
        for i, d in enumerate(drawables):
            lo, hi = d.mesh.positions.min(axis=0), d.mesh.positions.max(axis=0)
            centre = (lo + hi) / 2.0
            radius = float(np.linalg.norm(d.mesh.positions - centre, axis=1).max())
            # Transforms are rigid up to a fixed scale (static slabs may be stretched).
            first = d.transforms[0] if d.n_bones == 1 else d.transforms[0, 0]
            scale = float(np.linalg.svd(first[:3, :3], compute_uv=False).max())
            # A skinned mesh is followed by its root bone; its limbs may reach further.
            reach = 1.0 if d.n_bones == 1 else SKINNED_REACH
            self._centres[i], self._radii[i] = centre, radius * scale * reach
        self._large = self._radii > LARGE_M
        self._n_triangles = np.array([d.mesh.n_triangles for d in drawables], dtype=np.int64)
        self.triangles_built = int(self._n_triangles.sum())
        self.triangles_drawn = 0  # summed over the labelled passes of every frame

    def _build_rain(self, rain_seed: int) -> None:
        """Rain: streak origins in a box around the camera, from the recipe's render seed."""
        ctx = self.ctx
        n_rain = round(RAIN_STREAKS * self.lighting.rain)
        rng = seeded_rng(rain_seed)
        self.rain_origin = rng.random((n_rain, 3)) * 2.0 * RAIN_BOX_M - RAIN_BOX_M
        self.rain_buffer = ctx.buffer(reserve=max(n_rain, 1) * 2 * 3 * 4, dynamic=True) if n_rain else None
        self.rain_vao = (
            ctx.vertex_array(self.rain_prog, [(self.rain_buffer, "3f", "in_pos")]) if self.rain_buffer else None
        )
        if self.rain_vao is not None:
            self._objects += [self.rain_buffer, self.rain_vao]

    def _set_static_uniforms(self) -> None:
        lt, w, h = self.lighting, *self.size
        for prog in (*self._scene_programs, self.sky):
            for name in ("sky_zenith", "sky_horizon", "sky_glow", "sky_tint", "sun_dir", "sun_colour", "fog_colour"):
                _set(prog, name, getattr(lt, name))
            _set(prog, "fog_per_m", float(lt.fog_per_m))
            _set(prog, "cloud_cover", float(lt.cloud_cover))
            _set(prog, "exposure", float(lt.exposure))
        for p in self._scene_programs:
            _set(p, "sky_ambient", lt.sky_ambient)
            _set(p, "ground_ambient", lt.ground_ambient)
            _set(p, "wetness", float(lt.wetness))
            _set(p, "lamp_count", len(self.lamps))
            _set(p, "lamp_colour", tuple(float(x) * lt.lamp_intensity for x in (1.0, 0.78, 0.5)))
            if len(self.lamps):
                padded = np.zeros((MAX_LAMPS, 3), dtype=np.float32)
                padded[: len(self.lamps)] = self.lamps
                _write(p, "lamp_pos", padded.tobytes())
            _set(p, "models", 6)
            _set(p, "textures", 7)
            for shadow in self._shadow_maps:
                _set(p, shadow.uniform, shadow.location)
            if self.use_shadow:
                _write(p, "light_vp", _gl(self.light_vp))
        _set(self.shadow_prog, "models", 6)
        if self.use_shadow:
            self.shadow_prog["light_vp"].write(_gl(self.light_vp))
        _set(self.rain_prog, "rain_colour", (0.78, 0.8, 0.84))
        _set(self.rain_prog, "rain_alpha", 0.35)
        ps = self.post_settings
        q = self.post_prog
        _set(q, "motion_blur", float(ps.motion_blur))
        _set(q, "ao_strength", float(ps.ambient_occlusion))
        _set(q, "fog_per_m", float(self.lighting.fog_per_m))
        _set(q, "bloom", float(ps.bloom))
        _set(q, "vignette", float(ps.vignette))
        _set(q, "grade_gain", tuple(float(x) for x in ps.grade_gain))
        _set(q, "grade_lift", float(ps.grade_lift))
        _set(q, "saturation", float(ps.saturation))
        _set(q, "size", (float(w), float(h)))
        _set(self.sky, "sky_class", self.sky_class)

    def render(
        self,
        frame: int,
        cam_to_world: np.ndarray,
        cam_to_world_next: np.ndarray,
        intrinsics: tuple[float, float, float, float],
    ) -> Frame:
        """Frame ``frame`` seen from ``cam_to_world``, with flow towards frame + 1."""
        return self.render_rgb(self.render_labels(frame, cam_to_world, cam_to_world_next, intrinsics))

    def render_labels(
        self,
        frame: int,
        cam_to_world: np.ndarray,
        cam_to_world_next: np.ndarray,
        intrinsics: tuple[float, float, float, float],
    ) -> Frame:
        """The labelled 1× pass of a frame, read back: classes, instances, depth and flow, and
        unsupersampled its raw RGB (``rgb``, and supersampled ``colour``, are None until
        ``render_rgb`` adds them)."""
        ctx, p = self.ctx, self.program
        ctx.disable(moderngl.CULL_FACE | moderngl.BLEND)
        last = len(self._columns) - 1
        at, nxt = min(frame, last), min(frame + 1, last)
        self.models_tex.write(np.concatenate([self._columns[at], self._columns[nxt]], axis=1).tobytes())
        self.models_tex.use(location=6)
        self.textures.use(location=7)
        self._shadow_pass()
        world_to_cam = view(cam_to_world)
        order = self._draw_order(at, world_to_cam, intrinsics)  # the same at every supersampling
        indices = np.concatenate([self._indices[i] for i in order]) if len(order) else np.zeros(0, np.uint32)
        n_near = int(self._n_indices[order][~self._large[order]].sum())  # the large slabs come last
        self.index_buffer.write(indices.tobytes())
        self.triangles_drawn += int(self._n_triangles[order].sum())
        for prog in self._scene_programs:
            _write(prog, "view_t", _gl(world_to_cam))
            _set(prog, "eye", tuple(float(x) for x in cam_to_world[:3, 3]))
        p["view_t1"].write(_gl(view(cam_to_world_next)))
        self.rain_prog["view_t"].write(_gl(world_to_cam))
        rain = self._rain_lines(frame, cam_to_world[:3, 3]) if self.rain_vao is not None else None
        rot = tuple(float(x) for x in cam_to_world[:3, :3].T.reshape(9))  # column-major mat3
        _set(self.sky, "cam_rot", rot)
        # Labelled pass at 1×; unsupersampled, it shades the raw colour too, and rain goes
        # into that colour only.
        self.fbo.use()
        self.fbo.clear(depth=1.0)
        self._scene_pass(n_near, len(indices), intrinsics, 0, labelled=True)
        raw = None
        if self.fbo_ss is None:
            if rain is not None:
                self._rain_pass(self.colour_fbo, rain, intrinsics, 0)
            # Read as the frame keeps them (RGB without alpha): a channel slice would cost a copy.
            raw = self._read(self.fbo, 0, 3, "f1", np.uint8)
        class_id = self._read(self.fbo, 1, 1, "u2", np.uint16)[..., 0]
        instance = self._read(self.fbo, 2, 1, "u2", np.uint16)[..., 0]
        depth = self._read(self.fbo, 3, 1, "f4", np.float32)[..., 0]
        flow = self._read(self.fbo, 4, 4, "f4", np.float32)
        labels = Frame(
            colour=raw,
            class_id=class_id,
            instance=instance,
            depth_m=depth,
            flow=flow[..., :2],  # a view: its readers take strided arrays
            flow_valid=flow[..., 2] > 0.5,
        )
        self._labelled = _LabelledPass(labels, len(indices), n_near, intrinsics, cam_to_world, rain)
        return labels

    def render_rgb(self, labels: Frame) -> Frame:
        """``labels`` (what ``render_labels`` returned last) with its RGB modalities: the
        frame's supersampled colour (raw RGB), post-processed (motion blur, reflections,
        occlusion, grading)."""
        done = self._labelled
        if done is None or done.labels is not labels:
            raise ValueError("render_rgb finishes the frame render_labels returned last")
        raw = labels.colour
        if self.fbo_ss is not None:
            self._supersample(done.n_near, done.n_indices, done.intrinsics, done.rain)
            raw = self._read(self.resolve_fbo, 0, 3, "f1", np.uint8)
        return replace(labels, colour=raw, rgb=self._post(done.intrinsics, done.cam_to_world))

    def _shadow_pass(self) -> None:
        """The sun's depth maps: of this frame's moving casters, and of the still ones at the
        first frame drawn (the models texture holds their one pose at every frame)."""
        ctx = self.ctx
        for shadow in self._shadow_maps:
            if shadow.every_frame or not shadow.drawn:
                shadow.framebuffer.use()
                ctx.viewport = (0, 0, SHADOW_SIZE, SHADOW_SIZE)
                shadow.framebuffer.clear(depth=1.0)
                ctx.enable(moderngl.DEPTH_TEST)
                shadow.vao.render(moderngl.TRIANGLES)
                shadow.drawn = True
            shadow.texture.use(location=shadow.location)

    def _scene_pass(self, n_near: int, n_indices: int, intrinsics, slot: int, *, labelled: bool) -> None:
        """Draw the scene (the first ``n_indices`` of the frame's index buffer, the first
        ``n_near`` of them not large slabs) into the bound framebuffer's ``slot``-th
        frame-sized viewport: the labelled pass in one call, the colour passes in two (the
        same order, a program each)."""
        ctx = self.ctx
        w, h = self.size
        ctx.viewport = (slot * w, 0, w, h)
        ctx.disable(moderngl.BLEND)
        ctx.enable(moderngl.DEPTH_TEST)
        if labelled:
            draws = [(self.program, self.vao, 0, n_indices)]
        else:
            near, far = self.colour_vaos
            draws = [(self.colour_program, near, 0, n_near), (self.colour_program_far, far, n_near, n_indices - n_near)]
        for p, vao, first, count in draws:
            p["proj"].write(_gl(projection(*intrinsics, w, h)))
            _set(p, "size", (float(w), float(h)))
            if count:
                vao.render(moderngl.TRIANGLES, vertices=count, first=first)
        # The sky last, only where no surface was drawn (it sits on the far plane).
        _set(self.sky, "intrinsics", tuple(float(x) for x in intrinsics))
        _set(self.sky, "size", (float(w), float(h)))
        _set(self.sky, "origin", (float(slot * w), 0.0))
        ctx.depth_func = "<="
        self.sky_vao.render(moderngl.TRIANGLES)
        ctx.depth_func = "<"

    def _draw_order(self, at: int, world_to_cam: np.ndarray, intrinsics) -> np.ndarray:
        """The drawables whose bounding spheres reach into the view at frame ``at``, nearest
        first and large slabs (ground, terrain) last, so hidden surfaces fail the depth test
        before they are shaded. The order depends only on the scene: it is deterministic."""
        w, h = self.size
        fx, fy, cx, cy = intrinsics
        # Side planes through the camera centre, as unit normals pointing into the frustum.
        planes = np.array([[fx, 0.0, -cx], [-fx, 0.0, -(w - cx)], [0.0, -fy, -cy], [0.0, fy, -(h - cy)]])
        planes /= np.linalg.norm(planes, axis=1, keepdims=True)
        t = self._world[at][self._rows]
        world = np.einsum("nij,nj->ni", t[:, :3, :3], self._centres) + t[:, :3, 3]
        c = world @ world_to_cam[:3, :3].T + world_to_cam[:3, 3]
        r = self._radii
        seen = np.flatnonzero((-c[:, 2] + r >= NEAR_M) & np.all(c @ planes.T >= -r[:, None], axis=1))
        return seen[np.lexsort((seen, -c[seen, 2], self._large[seen]))]

    def _rain_lines(self, frame: int, eye: np.ndarray) -> np.ndarray:
        """Streak end points (2N, 3) at this frame: falling, wrapped into a box around the eye."""
        t = frame / self.fps
        fall = np.array([0.6, 0.25, -RAIN_SPEED_MPS])
        top = self.rain_origin + fall * t
        top = np.mod(top - eye + RAIN_BOX_M, 2.0 * RAIN_BOX_M) - RAIN_BOX_M + eye
        bottom = top + fall * (0.5 / self.fps)  # half a frame of motion: a streak
        return np.stack([top, bottom], axis=1).reshape(-1, 3).astype(np.float32)

    def _supersample(self, n_near: int, n_indices: int, intrinsics, rain: np.ndarray | None) -> None:
        """One jittered colour-only pass per sample of the pattern, then their mean at 1×."""
        fx, fy, cx, cy = intrinsics
        self.fbo_ss.use()
        self.fbo_ss.clear(depth=1.0)
        for slot, (dx, dy) in enumerate(SAMPLE_PATTERNS[self.supersample]):
            # Pixel centre (u + ½) of this sample's image sees image point u + ½ + dx.
            self._scene_pass(n_near, n_indices, (fx, fy, cx - dx, cy - dy), slot, labelled=False)
        if rain is not None:
            for slot, (dx, dy) in enumerate(SAMPLE_PATTERNS[self.supersample]):
                self._rain_pass(self.fbo_ss, rain, (fx, fy, cx - dx, cy - dy), slot)
        ctx = self.ctx
        self.resolve_fbo.use()
        ctx.viewport = (0, 0, *self.size)
        ctx.disable(moderngl.DEPTH_TEST | moderngl.BLEND)
        self.samples_tex.use(location=5)
        self.resolve_vao.render(moderngl.TRIANGLES)

    def _rain_pass(self, fbo, lines: np.ndarray, intrinsics, slot: int) -> None:
        """Blend the rain streaks into ``fbo``'s ``slot``-th frame-sized viewport."""
        ctx = self.ctx
        w, h = self.size
        fbo.use()
        ctx.viewport = (slot * w, 0, w, h)
        self.rain_prog["proj"].write(_gl(projection(*intrinsics, w, h)))
        self.rain_buffer.write(lines.tobytes())
        ctx.enable(moderngl.DEPTH_TEST | moderngl.BLEND)
        # Streaks blend into the colour; its alpha (the reflectivity) stays.
        ctx.blend_func = moderngl.SRC_ALPHA, moderngl.ONE_MINUS_SRC_ALPHA, moderngl.ZERO, moderngl.ONE
        fbo.depth_mask = False
        self.rain_vao.render(moderngl.LINES)
        fbo.depth_mask = True
        ctx.disable(moderngl.BLEND)

    def _post(self, intrinsics, cam_to_world: np.ndarray) -> np.ndarray:
        ctx, q = self.ctx, self.post_prog
        w, h = self.size
        self.out_fbo.use()
        ctx.viewport = (0, 0, w, h)
        ctx.disable(moderngl.DEPTH_TEST | moderngl.BLEND)
        self.colour_ss.use(location=1)
        self.depth_tex.use(location=3)
        self.flow_tex.use(location=4)
        _set(q, "colour_ss", 1)
        _set(q, "depth_1x", 3)
        _set(q, "flow_1x", 4)
        _set(q, "intrinsics", tuple(float(x) for x in intrinsics))
        _set(q, "cam_rot", tuple(float(x) for x in cam_to_world[:3, :3].T.reshape(9)))
        _set(q, "up_cam", tuple(float(x) for x in cam_to_world[:3, :3].T @ np.array([0.0, 0.0, 1.0])))
        self.post_vao.render(moderngl.TRIANGLES)
        return self._read(self.out_fbo, 0, 3, "f1", np.uint8)

    def _read(self, fbo, attachment: int, components: int, dtype: str, np_dtype) -> np.ndarray:
        w, h = self.size
        raw = fbo.read(components=components, attachment=attachment, dtype=dtype)
        # GL's row 0 is the bottom of the image.
        return np.ascontiguousarray(np.frombuffer(raw, dtype=np_dtype).reshape(h, w, components)[::-1])

    def release(self) -> None:
        """Free the GL objects (the context stays); calling it again does nothing."""
        for obj in self._objects:
            obj.release()
        for prog in self._programs:
            prog.release()
        self._objects, self._programs = [], []


def _sun_matrix(sun_dir: np.ndarray, focus: np.ndarray) -> np.ndarray:
    """Orthographic view-projection of the sun around ``focus`` (shadow map coordinates)."""
    eye = focus + sun_dir * 150.0
    c2w = np.eye(4)
    c2w[:3, :3] = look_at(eye, focus)
    c2w[:3, 3] = eye
    s, near, far = SHADOW_HALF_M, 1.0, 300.0
    ortho = np.diag([1.0 / s, 1.0 / s, -2.0 / (far - near), 1.0])
    ortho[2, 3] = -(far + near) / (far - near)
    return ortho @ view(c2w)


#: One vertex of the shared buffer: geometry, its bones (rows of the models texture) and
#: weights, then its labels and look (texture coordinates and layer where textured).
_VERTEX_DTYPE = np.dtype([("pos", "<f4", 3), ("normal", "<f4", 3), ("ids", "<u4", 4), ("bones", "<u4", 4),
                          ("weights", "<f4", 4), ("colour", "<f4", 3), ("emission", "<f4", 3),
                          ("uv", "<f4", 3)])  # fmt: skip


def _layout(vbo: moderngl.Buffer, program: moderngl.Program) -> list[tuple]:
    """The vertex buffer's layout for ``program``: each ``_VERTEX_DTYPE`` field as its
    ``in_<field>`` attribute, skipped as padding where the program's build does not read it."""
    formats, names = [], []
    for name in _VERTEX_DTYPE.names:
        base, shape = _VERTEX_DTYPE[name].subdtype
        if f"in_{name}" in program:
            formats.append(f"{shape[0]}{'f' if base.kind == 'f' else 'u'}")
            names.append(f"in_{name}")
        else:
            formats.append(f"{base.itemsize * shape[0]}x")
    return [(vbo, " ".join(formats), *names)]


def linear_colour(colour) -> np.ndarray:
    """Display colours (0–1) made linear for shading (vertex colours, texture images).

    Scalar libm's pow over the distinct values, not numpy's CPU-dispatched ``power``, whose
    float64 results change in their last bit with the SIMD level far more often than
    glibc's: its pow picks an FMA or an SSE2 path too, but those agree on every 8-bit value,
    and the float32 the vertex buffers hold rounds away what else they differ on."""
    values = np.asarray(colour, dtype=np.float64)
    distinct, where = np.unique(values, return_inverse=True)
    table = np.array([math.pow(x, 2.2) if x >= 0.0 else math.nan for x in distinct.tolist()], dtype=np.float64)
    return table[where].reshape(values.shape)


def material_coordinates(positions: np.ndarray, transforms: np.ndarray) -> np.ndarray:
    """Where a drawable's materials take their patterns at its vertices: its mesh's own
    frame, so that a moving drawable's pattern moves with it; for one standing still in every
    frame, that frame shifted to where it stands (the world's position turned into the
    drawable's axes), so that still neighbours of one orientation (a park's terraces, a
    road's pieces) continue one pattern across their seams, each still aligned with its own
    edges."""
    first = transforms[0]
    if transforms.ndim != 3 or not (transforms == first).all():
        return positions
    r, t = first[:3, :3], first[:3, 3]
    # Rᵀt as three products and two sums (no BLAS kernel): the same bits on every CPU.
    return positions + (r[0] * t[0] + r[1] * t[1] + r[2] * t[2])


def _pack(drawables: list[Drawable]) -> tuple[np.ndarray, list[np.ndarray], list[np.ndarray]]:
    """Every drawable's vertices in one array (labels and look per vertex; colours made
    linear here, once), each drawable's triangle indices into it and the texture images
    (one layer per distinct array, in order of first use)."""
    parts, indices, textures, offset, row = [], [], [], 0, 0
    for i, d in enumerate(drawables):
        m, look = d.mesh, d.vertex_look
        v = np.zeros(len(m.positions), dtype=_VERTEX_DTYPE)
        v["pos"], v["normal"] = m.positions, m.normals
        v["ids"] = (i, d.class_id, d.instance_id, d.material * 256 + d.pattern)
        if m.bones is not None and m.weights is not None:
            v["bones"], v["weights"] = row + m.bones, m.weights
        else:
            v["bones"], v["weights"] = row, (1.0, 0.0, 0.0, 0.0)
        v["colour"] = linear_colour(d.colour)
        v["emission"] = d.emission
        if look is not None:
            layer = next((k for k, t in enumerate(textures) if t is look.texture), len(textures))
            if layer == len(textures):
                textures.append(look.texture)
            v["ids"][:, 1] = look.class_ids
            v["ids"][:, 3] = d.material * 256 + TEXTURED
            v["uv"][:, :2], v["uv"][:, 2] = look.uvs, layer
        elif d.part_look is not None:
            parts_ = d.part_look
            v["ids"][:, 1] = parts_.class_ids
            v["ids"][:, 3] = parts_.surfaces.astype(np.uint32) * 256 + parts_.patterns
            v["colour"] = linear_colour(parts_.colours)
            v["emission"] = parts_.emission
            v["uv"] = material_coordinates(m.positions, d.transforms)
        parts.append(v)
        indices.append((m.triangles.reshape(-1) + offset).astype(np.uint32))
        offset += len(v)
        row += d.n_bones
    return (np.concatenate(parts) if parts else np.zeros(0, _VERTEX_DTYPE)), indices, textures


def _material_flags(drawables: Iterable[Drawable]) -> dict[str, bool]:
    """``MATERIAL_n`` for each material pattern n the drawables show: the scene shader
    compiles in only those."""
    shown: set[int] = set()
    for d in drawables:
        if d.part_look is not None:
            shown.update(int(n) for n in np.unique(d.part_look.patterns))
        elif d.vertex_look is None:
            shown.add(d.pattern)
    return {f"MATERIAL_{n}": True for n in sorted(shown) if n >= FIRST_MATERIAL}


def _texture_array(ctx: moderngl.Context, textures: list[np.ndarray]) -> moderngl.TextureArray:
    """The texture images as the layers of one mipmapped array (a texel of black without
    any: the sampler must have one), bilinear in the nearest mip level (half the texel reads
    of trilinear filtering), clamped at the edges."""
    if not textures:
        textures = [np.zeros((1, 1, 3), dtype=np.float16)]
    shapes = {t.shape for t in textures}
    if len(shapes) != 1:
        raise ValueError(f"the texture images of one scene must share a size, got {sorted(shapes)}")
    height, width, _ = textures[0].shape
    array = ctx.texture_array((width, height, len(textures)), 3, np.stack(textures).astype(np.float16).tobytes(),
                              dtype="f2")  # fmt: skip
    array.repeat_x = array.repeat_y = False
    # Mip levels up to 8 × 8 texels: coarser ones would average neighbouring islands of an atlas.
    array.build_mipmaps(max_level=MAX_MIP_LEVEL)
    array.filter = (moderngl.LINEAR_MIPMAP_NEAREST, moderngl.LINEAR)  # bilinear in the nearest level
    return array


def _holds_still(drawable: Drawable) -> bool:
    """Whether ``drawable`` has the same world transforms at every frame."""
    return bool((drawable.transforms == drawable.transforms[:1]).all())


def _stack_transforms(drawables: list[Drawable]) -> np.ndarray:
    """World transforms (L, R, 4, 4) of the R bones of all drawables over L frames (a
    shorter track holds its last pose); a rigid drawable is one bone."""
    frames = max((len(d.transforms) for d in drawables), default=1)
    out = np.tile(np.eye(4), (frames, sum(d.n_bones for d in drawables), 1, 1))
    row = 0
    for d in drawables:
        held = d.transforms[np.minimum(np.arange(frames), len(d.transforms) - 1)]
        out[:, row : row + d.n_bones] = held.reshape(frames, d.n_bones, 4, 4)
        row += d.n_bones
    return out


def _gl(m: np.ndarray) -> bytes:
    """A row-major numpy matrix as the column-major float32 bytes GLSL expects."""
    return np.ascontiguousarray(m.T, dtype=np.float32).tobytes()


__all__ = [
    "EMISSIVE",
    "FAR_M",
    "GROUND",
    "MATTE",
    "NEAR_M",
    "PLAIN",
    "SPECKLE",
    "TEXTURED",
    "WATER",
    "Drawable",
    "Frame",
    "FrameRenderer",
    "PartLook",
    "PostSettings",
    "VertexLook",
    "linear_colour",
]
