"""Fault injection for the crash-safety tests: kill this process, or delay a task, on cue.

Both are driven by environment variables so they reach worker processes (spawned pool
workers and Ray workers alike) without any code path of their own:

- ``PHAV_FAULT_KILL_AT=NAME`` — ``crash_point(NAME)`` sends this process SIGKILL: no
  ``finally`` block, no flush, exactly what a power cut or the OOM killer does. Names are
  ``part:{video_id}:{frame}`` (inside a video's tar part, after that frame's members),
  ``part-done:{video_id}`` (part written, not yet journalled), ``shard:{name}:{k}`` (inside
  a shard's tar, after its k-th video part was copied) and ``journal:{n}`` (half-way
  through writing the n-th journal line).
- ``PHAV_FAULT_SIGNAL=INT`` (or ``TERM``) — the point sends that signal instead: Ctrl-C or
  SIGTERM arriving at a known moment, so that their handling is tested without a race.
- ``PHAV_FAULT_DELAY_S=MAX`` — ``task_delay(key)`` sleeps a pseudo-random time in
  [0, MAX) s derived from ``key``, to scramble the order in which parallel tasks finish.

Unset (the normal case), both cost one dictionary lookup.
"""

from __future__ import annotations

import hashlib
import os
import signal
import time

KILL_AT_ENV = "PHAV_FAULT_KILL_AT"
SIGNAL_ENV = "PHAV_FAULT_SIGNAL"
DELAY_ENV = "PHAV_FAULT_DELAY_S"


def armed(name: str) -> bool:
    """Whether ``PHAV_FAULT_KILL_AT`` names this point (a writer may tear its write first)."""
    return os.environ.get(KILL_AT_ENV) == name


def crash_point(name: str) -> None:
    """SIGKILL this process (or send it ``PHAV_FAULT_SIGNAL``) if ``PHAV_FAULT_KILL_AT`` names
    this point."""
    if armed(name):
        os.kill(os.getpid(), signal.Signals[f"SIG{os.environ.get(SIGNAL_ENV) or 'KILL'}"])


def delay_for(key: str, limit: float) -> float:
    """The delay ``task_delay`` sleeps for ``key``: a fraction of ``limit`` fixed by its sha256."""
    return limit * int.from_bytes(hashlib.sha256(key.encode()).digest()[:8], "big") / 2.0**64


def task_delay(key: str) -> float:
    """Sleep a time in [0, ``PHAV_FAULT_DELAY_S``) fixed by ``key``; returns the seconds slept."""
    limit = float(os.environ.get(DELAY_ENV) or 0.0)
    if limit <= 0.0:
        return 0.0
    seconds = delay_for(key, limit)
    time.sleep(seconds)
    return seconds


def fault_env() -> dict[str, str]:
    """The fault variables set in this process (to hand on to Ray workers)."""
    return {k: os.environ[k] for k in (KILL_AT_ENV, SIGNAL_ENV, DELAY_ENV) if os.environ.get(k)}
