"""The GL context: llvmpipe by default (the renderer of record), and ``--gl egl-gpu`` never
silently on the CPU."""

from __future__ import annotations

import pytest

from phav_generator.render.context import is_software_renderer, require_gl
from phav_spec.errors import PhavUserError
from tests.helpers import run_cli


def test_the_default_renderer_is_llvmpipe_the_renderer_of_record(ctx):
    assert is_software_renderer(str(ctx.info["GL_RENDERER"]))
    assert "llvmpipe" in str(ctx.info["GL_RENDERER"])


def test_egl_gpu_never_falls_back_to_the_cpu(tmp_path):
    """`--gl egl-gpu` on a machine whose EGL offers only llvmpipe is a one-line user error,
    said before anything is written (a GPU machine renders instead: not testable here)."""
    try:
        strings = require_gl("egl-gpu")
    except PhavUserError as e:
        assert e.field == "--gl" and "no EGL device is a GPU (EGL offers: llvmpipe" in str(e)
    else:
        assert not is_software_renderer(strings["GL_RENDERER"])
        pytest.skip(f"this machine has a GPU EGL device ({strings['GL_RENDERER']})")
    out = tmp_path / "data"
    result = run_cli("generate", "--theta", "phav-v1-short", "--videos", "1", "--gl", "egl-gpu", "--out", str(out))
    assert result.returncode == 2 and "Traceback" not in result.stderr
    assert "--gl: no EGL device is a GPU" in result.stderr and not out.exists()
    result = run_cli("generate", "--videos", "1", "--gl", "vulkan", "--out", str(out))
    assert result.returncode == 2 and "unknown renderer 'vulkan'" in result.stderr
    result = run_cli("bench", "--sections", "generation", "--gl", "egl-gpu")
    assert result.returncode == 2 and "no EGL device is a GPU" in result.stderr
