"""The machine a process runs on, as far as results depend on it: its CPU's fields.

The renderer fingerprint records the CPU (pixels may differ across CPUs) and training picks
its arithmetic by it; both read them here, so that they read them alike."""

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
