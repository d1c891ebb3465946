"""The OpenGL context: a headless EGL device chosen by kind, and the strings that name it.

``llvmpipe`` (Mesa on the CPU) is the renderer of record: the same pixels on any machine
with the same fingerprint, of which ``gl_strings`` is the GL part. ``egl-gpu`` renders on
the first EGL device that is a real GPU, never silently on the CPU.
"""

from __future__ import annotations

import moderngl

from phav_spec.errors import PhavUserError

#: ``--gl`` choices: Mesa's llvmpipe (the renderer of record: the same pixels on any CPU
#: machine with the same fingerprint) or the first EGL device that is a real GPU.
GL_KINDS = ("llvmpipe", "egl-gpu")
#: EGL devices tried at most (a machine has its GPUs plus Mesa's software device).
MAX_EGL_DEVICES = 16
_SOFTWARE = ("llvmpipe", "softpipe", "swrast", "software")


def is_software_renderer(gl_renderer: str) -> bool:
    """True for Mesa's CPU rasterisers (llvmpipe, softpipe, swrast)."""
    return any(word in gl_renderer.lower() for word in _SOFTWARE)


def check_gl_kind(kind: str) -> None:
    """Refuse a ``--gl`` value that names no renderer."""
    if kind not in GL_KINDS:
        raise PhavUserError(f"unknown renderer {kind!r}; choose one of {', '.join(GL_KINDS)}", field="--gl")


def gl_context(kind: str = "llvmpipe") -> moderngl.Context:
    """A headless OpenGL 3.3+ context through EGL on the first EGL device of ``kind``.

    EGL lists its devices (GPUs, then Mesa's software device); each is tried in order, so
    ``llvmpipe`` renders on the CPU even on a GPU machine, and ``egl-gpu`` never silently
    falls back to the CPU: without a GPU device it is a user error naming what EGL offers.
    """
    check_gl_kind(kind)
    seen: list[str] = []
    for index in range(MAX_EGL_DEVICES):
        try:
            ctx = moderngl.create_standalone_context(backend="egl", device_index=index)
        except Exception as e:
            if "but found" in str(e):
                break  # past the last device
            seen.append(f"device {index} fails ({e})")  # a broken driver: try the next device
            continue
        renderer = str(ctx.info["GL_RENDERER"])
        if is_software_renderer(renderer) == (kind == "llvmpipe"):
            return ctx
        seen.append(renderer)
        ctx.release()
    offered = "; ".join(seen) or "no device"
    want = "a GPU" if kind == "egl-gpu" else "Mesa's llvmpipe"
    raise PhavUserError(f"no EGL device is {want} (EGL offers: {offered})", field="--gl")


def require_gl(kind: str) -> dict[str, str]:
    """The GL strings of the renderer ``kind`` here, or the user error ``gl_context`` gives:
    asked before long work starts, so that a missing GPU is said at once."""
    ctx = gl_context(kind)
    try:
        return gl_strings(ctx)
    finally:
        ctx.release()


def gl_strings(ctx: moderngl.Context) -> dict[str, str]:
    """The GL vendor, renderer and version: part of the pixels' fingerprint."""
    return {k: str(ctx.info[k]) for k in ("GL_VENDOR", "GL_RENDERER", "GL_VERSION")}


__all__ = [
    "GL_KINDS",
    "MAX_EGL_DEVICES",
    "check_gl_kind",
    "gl_context",
    "gl_strings",
    "is_software_renderer",
    "require_gl",
]
