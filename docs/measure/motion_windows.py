"""How much of a short clip's window shows its action: per action, the share of windows of a
base motion in which the body barely moves (docs/experiments/learnability.md, "Why it
scores what it scores").

A clip plays ``duration`` seconds of its base motion from a start drawn as θ's
``motion.start`` says (``phav_generator.sampling``; two people walking into each other on a
take that stops them start where they meet, ``phav_spec.motions.meeting_start``, which this
does not count). For every motion θ_AB allows an
action, this measures the joint-angle speed (rad/s summed over the 30 degrees of freedom,
root excluded) along the whole motion, averages it over every window of the clip length,
and counts the windows whose mean is below a quarter of the motion's busiest window: clips
that mostly hold a pose. It does so for the starts ``uniform`` allows (every window) and
for those ``active`` keeps (``phav_spec.motions.active_start``, which decides from the
moving spans, a different measure: the fastest body point's speed).

    .venv/bin/python docs/measure/motion_windows.py --theta phav-v1-short --seconds 1.5
"""

from __future__ import annotations

import argparse
from importlib import resources

import numpy as np

from phav_generator.motion.animation import MotionParams
from phav_generator.motion.library import BUILTIN_MOTIONS
from phav_spec.motions import MOTIONS, active_start
from phav_spec.theta import load_theta
from phav_spec.vocab import ACTIONS

FPS = 30


def still_share(name: str, seconds: float, start: str = "uniform", quiet: float = 0.25) -> float:
    """Share of ``seconds``-long windows of motion ``name`` (those ``start`` draws from)
    whose mean joint speed is below ``quiet`` × the busiest window's."""
    motion = BUILTIN_MOTIONS[name]
    pose = motion.fn(np.arange(0.0, motion.length_s, 1.0 / FPS), MotionParams())
    speed = np.abs(np.diff(pose.q, axis=0)).sum(axis=1) * FPS
    window = round(seconds * FPS)
    if len(speed) <= window:
        return 0.0
    means = np.convolve(speed, np.ones(window) / window, mode="valid")
    still = means < quiet * means.max()
    if start == "active":  # the frame-grid starts active_start draws from, each equally likely
        u = (np.arange(len(means)) + 0.5) / len(means)
        starts = sorted({round(active_start(name, motion.length_s, seconds, x) * FPS) for x in u})
        still = still[np.minimum(starts, len(still) - 1)]
    return float(still.mean())


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--theta", default="phav-v1-short")
    parser.add_argument("--seconds", type=float, default=1.5)
    args = parser.parse_args()
    path = resources.files("phav_spec") / "presets" / f"{args.theta}.yaml"
    ab = load_theta(str(path)).arrays.ab
    print(f"| action | motions | windows of {args.seconds:g} s mostly holding a pose: uniform start | active start "
          "| per motion, uniform → active |")  # fmt: skip
    print("| --- | ---: | ---: | ---: | --- |")
    rows = []
    for a, action in enumerate(ACTIONS.names):
        names = [m for m, hit in zip(MOTIONS.names, ab[a], strict=True) if hit]
        uniform = [still_share(m, args.seconds) for m in names]
        active = [still_share(m, args.seconds, "active") for m in names]
        rows.append((float(np.mean(uniform)), float(np.mean(active)), action, names, uniform, active))
    for mean, mean_active, action, names, uniform, active in sorted(rows, reverse=True):
        per = ", ".join(f"{m} {u:.0%} → {v:.0%}" for m, u, v in zip(names, uniform, active, strict=True) if u > 0)
        print(f"| {action} | {len(names)} | {mean:.0%} | {mean_active:.0%} | {per or 'none'} |")
    print(f"\nall actions: {np.mean([r[0] for r in rows]):.0%} uniform, {np.mean([r[1] for r in rows]):.0%} active")


if __name__ == "__main__":
    main()
