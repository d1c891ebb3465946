"""The machine a process runs on, as far as results depend on it: its CPU's fields.

The renderer fingerprint records the CPU's SIMD class (llvmpipe's code path, which decides
pixels) and training picks its arithmetic by the flags; both read them here, alike."""

from __future__ import annotations

from pathlib import Path

CPUINFO = Path("/proc/cpuinfo")


def cpu_fields(path: Path = CPUINFO) -> dict[str, str]:
    """The first processor's fields of Linux's ``/proc/cpuinfo`` (``vendor_id``, ``model name``,
    ``flags`` on x86, ``Features`` on ARM), stripped; empty where the file cannot be read."""
    try:
        text = path.read_text(encoding="utf-8", errors="replace")
    except OSError:
        return {}
    fields: dict[str, str] = {}
    for line in text.splitlines():
        key, sep, value = line.partition(":")
        if sep:
            fields.setdefault(key.strip(), value.strip())  # later processors repeat the keys
    return fields


#: llvmpipe's code paths on x86-64, best first: the flags that open each, and the class name.
#: Measured (docs/reproducibility.md): forcing llvmpipe's capabilities down level by level
#: changes the bytes only where one of these lines is crossed — AVX2 with FMA, with or
#: without AVX-512, gives one set of bytes; SSSE3 and SSE4.1 another; SSE2 and SSE3 a third.
#: AVX without AVX2 and FMA (Sandy and Ivy Bridge), where Mesa compiles without fused
#: multiply-adds, was never measured: a class of its own, promised nothing against the rest.
X86_SIMD_CLASSES: tuple[tuple[tuple[str, ...], str], ...] = (
    (("avx2", "fma"), "x86-64-avx"),
    (("avx",), "x86-64-avx1"),
    (("ssse3",), "x86-64-ssse3"),
    (("sse2",), "x86-64-sse2"),
)


#: Mesa's override of the CPU capabilities llvmpipe uses (a measurement tool), and the flags
#: each of its values leaves: llvmpipe then takes the code path of that level. ``avx`` turns
#: off AVX-512 alone (Mesa's ``check_cpu_caps_override``): AVX2, F16C and FMA stay.
GALLIUM_CAPS_ENV = "GALLIUM_OVERRIDE_CPU_CAPS"
_GALLIUM_CAPS = {
    "nosse": (),
    "sse": ("sse",),
    "sse2": ("sse", "sse2"),
    "sse3": ("sse", "sse2", "sse3"),
    "ssse3": ("sse", "sse2", "sse3", "ssse3"),
    "sse4.1": ("sse", "sse2", "sse3", "ssse3", "sse4_1"),
    "avx": ("sse", "sse2", "sse3", "ssse3", "sse4_1", "sse4_2", "avx", "avx2", "f16c", "fma"),
}


def simd_class(flags: str, machine: str, model: str = "", override: str | None = None) -> str:
    """The class of CPU whose pixels are alike: on x86-64 llvmpipe's code path, from the
    ``/proc/cpuinfo`` flags, lowered to Mesa's ``override`` (``GALLIUM_OVERRIDE_CPU_CAPS``)
    where one is set; elsewhere (not measured) the architecture and the CPU's model."""
    if machine.lower() in ("x86_64", "amd64"):
        present = set(flags.split())
        if override is not None and override in _GALLIUM_CAPS:
            present &= set(_GALLIUM_CAPS[override])
        for needs, name in X86_SIMD_CLASSES:
            if present.issuperset(needs):
                return name
        return "x86-64"
    return f"{machine}: {model}" if model else machine
