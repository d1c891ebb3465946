"""One geometry pass, five render targets: colour, semantic class, instance id, linear
depth and forward flow, all from one shader (the paper's multiple-render-target idea).

Every drawable is a rigid mesh with a world transform at frame t and at t + 1. The vertex
shader places each vertex at both times; the fragment shader writes the depth along the
camera axis at t and the flow as where the same surface point lands in frame t + 1
(camera and object motion together), exact for rigid parts because clip coordinates are
affine in the vertex position and interpolate perspective-correctly. Labels, depth and
flow come from one sample per pixel and are never blended.
"""

from __future__ import annotations

from dataclasses import dataclass

import moderngl
import numpy as np

from phav_generator.render.camera import projection, view
from phav_generator.render.meshes import Mesh

#: The five targets, in attachment order, shared by the scene and sky shaders.
_OUTPUTS = """
layout(location = 0) out vec4 out_colour;
layout(location = 1) out uint out_class;
layout(location = 2) out uint out_instance;
layout(location = 3) out float out_depth;
layout(location = 4) out vec4 out_flow;
"""

_VERTEX = """
#version 330
uniform mat4 model_t;
uniform mat4 model_t1;
uniform mat4 view_t;
uniform mat4 view_t1;
uniform mat4 proj;
in vec3 in_pos;
in vec3 in_normal;
out vec3 v_normal;
out float v_depth;
out vec4 v_clip1;
void main() {
    vec4 world = model_t * vec4(in_pos, 1.0);
    vec4 cam = view_t * world;
    v_depth = -cam.z;
    v_normal = mat3(model_t) * in_normal;
    v_clip1 = proj * (view_t1 * (model_t1 * vec4(in_pos, 1.0)));
    gl_Position = proj * cam;
}
"""

_FRAGMENT = (
    """
#version 330
uniform vec3 base_colour;
uniform uint class_id;
uniform uint instance_id;
uniform vec3 sun_dir;
uniform float ambient;
uniform vec2 size;
in vec3 v_normal;
in float v_depth;
in vec4 v_clip1;
"""
    + _OUTPUTS
    + """
void main() {
    vec3 n = normalize(v_normal);
    if (!gl_FrontFacing) n = -n;
    float light = ambient + (1.0 - ambient) * max(dot(n, sun_dir), 0.0);
    out_colour = vec4(base_colour * light, 1.0);
    out_class = class_id;
    out_instance = instance_id;
    out_depth = v_depth;
    if (v_clip1.w > 1e-6) {
        vec2 window1 = (v_clip1.xy / v_clip1.w * 0.5 + 0.5) * size;
        vec2 d = window1 - gl_FragCoord.xy;
        out_flow = vec4(d.x, -d.y, 1.0, 0.0);  // image rows grow downwards
    } else {
        out_flow = vec4(0.0);  // behind the camera at t + 1: invalid
    }
}
"""
)

# The background: a full-screen triangle that writes the sky into every target.
_SKY_VERTEX = """
#version 330
in vec2 in_xy;
void main() { gl_Position = vec4(in_xy, 1.0, 1.0); }
"""

_SKY_FRAGMENT = (
    """
#version 330
uniform vec3 sky_colour;
uniform uint sky_class;
"""
    + _OUTPUTS
    + """
void main() {
    out_colour = vec4(sky_colour, 1.0);
    out_class = sky_class;
    out_instance = 0u;
    out_depth = 1.0 / 0.0;
    out_flow = vec4(0.0);
}
"""
)


@dataclass(frozen=True)
class Drawable:
    """A rigid mesh with its labels, colour and world transforms per frame (F, 4, 4)."""

    mesh: Mesh
    transforms: np.ndarray
    class_id: int
    instance_id: int = 0  # 0: not a person
    colour: tuple[float, float, float] = (0.6, 0.6, 0.6)


@dataclass(frozen=True)
class Frame:
    """One rendered frame: image rows top to bottom, columns left to right."""

    colour: np.ndarray  # (H, W, 3) uint8
    class_id: np.ndarray  # (H, W) uint16 pixel-class ids
    instance: np.ndarray  # (H, W) uint16 person ids + 1, 0 for no person
    depth_m: np.ndarray  # (H, W) float32, +inf for sky
    flow: np.ndarray  # (H, W, 2) float32 pixels, t → t + 1
    flow_valid: np.ndarray  # (H, W) bool


def gl_context() -> moderngl.Context:
    """A headless OpenGL 3.3+ context through EGL (Mesa llvmpipe on CPU machines)."""
    return moderngl.create_standalone_context(backend="egl")


def gl_strings(ctx: moderngl.Context) -> dict[str, str]:
    """The GL vendor, renderer and version: part of the pixels' fingerprint."""
    return {k: str(ctx.info[k]) for k in ("GL_VENDOR", "GL_RENDERER", "GL_VERSION")}


class FrameRenderer:
    """Draws a set of drawables frame by frame into five targets and reads them back."""

    def __init__(
        self,
        ctx: moderngl.Context,
        width: int,
        height: int,
        drawables: list[Drawable],
        *,
        sky_class: int,
        sky_colour: tuple[float, float, float] = (0.55, 0.75, 0.95),
    ):
        self.ctx = ctx
        self.size = (width, height)
        self.drawables = drawables
        self.program = ctx.program(vertex_shader=_VERTEX, fragment_shader=_FRAGMENT)
        self.sky = ctx.program(vertex_shader=_SKY_VERTEX, fragment_shader=_SKY_FRAGMENT)
        self.sky["sky_colour"].value = sky_colour
        self.sky["sky_class"].value = sky_class
        tri = np.array([-1.0, -1.0, 3.0, -1.0, -1.0, 3.0], dtype=np.float32)
        self._sky_buffer = ctx.buffer(tri.tobytes())
        self.sky_vao = ctx.vertex_array(self.sky, [(self._sky_buffer, "2f", "in_xy")])
        self.targets = [
            ctx.renderbuffer((width, height), 4, dtype="f1"),
            ctx.renderbuffer((width, height), 1, dtype="u2"),
            ctx.renderbuffer((width, height), 1, dtype="u2"),
            ctx.renderbuffer((width, height), 1, dtype="f4"),
            ctx.renderbuffer((width, height), 4, dtype="f4"),
        ]
        self.depth = ctx.depth_renderbuffer((width, height))
        self.fbo = ctx.framebuffer(color_attachments=self.targets, depth_attachment=self.depth)
        self._buffers = []
        self.vaos = []
        for d in drawables:
            vbo = ctx.buffer(np.hstack([d.mesh.positions, d.mesh.normals]).astype(np.float32).tobytes())
            ibo = ctx.buffer(d.mesh.triangles.tobytes())
            self._buffers += [vbo, ibo]
            self.vaos.append(ctx.vertex_array(self.program, [(vbo, "3f 3f", "in_pos", "in_normal")], ibo))
        self.program["size"].value = (float(width), float(height))

    def render(
        self,
        frame: int,
        cam_to_world: np.ndarray,
        cam_to_world_next: np.ndarray,
        intrinsics: tuple[float, float, float, float],
        *,
        sun_dir: tuple[float, float, float] = (0.3, -0.4, 0.87),
        ambient: float = 0.35,
    ) -> Frame:
        """Frame ``frame`` seen from ``cam_to_world``, with flow towards frame + 1."""
        ctx, p = self.ctx, self.program
        w, h = self.size
        self.fbo.use()
        ctx.viewport = (0, 0, w, h)
        self.fbo.clear(depth=1.0)
        ctx.disable(moderngl.DEPTH_TEST | moderngl.CULL_FACE | moderngl.BLEND)
        self.sky_vao.render(moderngl.TRIANGLES)
        ctx.enable(moderngl.DEPTH_TEST)
        p["proj"].write(_gl(projection(*intrinsics, w, h)))
        p["view_t"].write(_gl(view(cam_to_world)))
        p["view_t1"].write(_gl(view(cam_to_world_next)))
        sun = np.asarray(sun_dir, dtype=np.float64)
        p["sun_dir"].value = tuple(float(x) for x in sun / np.linalg.norm(sun))
        p["ambient"].value = float(ambient)
        last = None
        for d, vao in zip(self.drawables, self.vaos, strict=True):
            nxt = min(frame + 1, len(d.transforms) - 1)
            p["model_t"].write(_gl(d.transforms[frame]))
            p["model_t1"].write(_gl(d.transforms[nxt]))
            if last is None or (d.class_id, d.instance_id, d.colour) != last:
                p["class_id"].value = d.class_id
                p["instance_id"].value = d.instance_id
                p["base_colour"].value = d.colour
                last = (d.class_id, d.instance_id, d.colour)
            vao.render(moderngl.TRIANGLES)
        colour = self._read(0, 4, "f1", np.uint8)[..., :3]
        flow = self._read(4, 4, "f4", np.float32)
        return Frame(
            colour=colour,
            class_id=self._read(1, 1, "u2", np.uint16)[..., 0],
            instance=self._read(2, 1, "u2", np.uint16)[..., 0],
            depth_m=self._read(3, 1, "f4", np.float32)[..., 0],
            flow=np.ascontiguousarray(flow[..., :2]),
            flow_valid=flow[..., 2] > 0.5,
        )

    def _read(self, attachment: int, components: int, dtype: str, np_dtype) -> np.ndarray:
        w, h = self.size
        raw = self.fbo.read(components=components, attachment=attachment, dtype=dtype)
        # GL's row 0 is the bottom of the image.
        return np.ascontiguousarray(np.frombuffer(raw, dtype=np_dtype).reshape(h, w, components)[::-1])

    def release(self) -> None:
        """Free the GL objects (the context stays)."""
        for obj in [*self.vaos, *self._buffers, self.sky_vao, self._sky_buffer, self.fbo, self.depth, *self.targets]:
            obj.release()
        self.program.release()
        self.sky.release()


def _gl(m: np.ndarray) -> bytes:
    """A row-major numpy matrix as the column-major float32 bytes GLSL expects."""
    return np.ascontiguousarray(m.T, dtype=np.float32).tobytes()
