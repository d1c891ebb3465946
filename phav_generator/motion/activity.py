"""Where each catalogue motion moves: the spans ``phav_spec.motion_activity`` ships.

A take holds its action for a part of its length only: a dive is a second and a half of a
5-s take, the rest is standing and lying. A 1–2 s window drawn uniformly from the take
(``motion.start: uniform``) often shows the body holding a pose, and nothing in the
pixels says which action it was. θ's ``motion.start: active`` draws the window among
those that move (``phav_spec.motions.active_start``), from the spans computed here.

The spec cannot run the motions (sampling never reaches into the pixel stages), so the
spans are data in ``phav_spec/motion_activity.py``, written by this module's ``main``
and checked against a fresh computation by the test suite, like a MoCap take's
annotation of where its action happens.

    .venv/bin/python -m phav_generator.motion.activity > phav_spec/motion_activity.py
"""

from __future__ import annotations

import numpy as np

from phav_generator.motion.animation import MotionDef, MotionParams
from phav_generator.motion.library import BUILTIN_MOTIONS
from phav_generator.motion.reference import REF_BODY
from phav_generator.motion.skeleton import capsule_points, forward_kinematics

#: Samples per second of the take (the spans' resolution).
SAMPLE_HZ = 10
#: The body moves when its fastest capsule end point goes faster than this (m/s): a hand
#: combing hair goes 0.5–2, a standing body's breathing sway under 0.1.
MOVING_SPEED_M_S = 0.3
#: Pauses shorter than this (s) belong to the motion around them (a hand turning at the
#: end of a stroke, a foot at the top of a step).
MERGED_GAP_S = 0.5
#: A take approaches when its body goes at least this fast (m/s, over the ground) before
#: its first pause: a walk up to someone; a hand at work moves the body a few cm.
APPROACH_PACE_M_S = 0.3
#: The reference playback: no speed change, no mirror, the motion's neutral amplitude,
#: phase and style.
_PARAMS = MotionParams(speed=1.0, amplitude=1.0, phase=0.0, style=0.0, mirror=False)


def fastest_point_speed(motion: MotionDef, hz: int = SAMPLE_HZ) -> np.ndarray:
    """Per interval of 1/``hz`` s of the take, the speed (m/s) of the reference body's
    fastest capsule end point (the root's travel included: a walk moves)."""
    tau = np.arange(int(np.floor(motion.length_s * hz)) + 1) / hz
    pose = motion.fn(np.minimum(tau, motion.length_s), _PARAMS)
    pos, rot = forward_kinematics(REF_BODY, pose.root_pos, pose.root_quat, pose.q)
    a, b = capsule_points(REF_BODY, pos, rot)
    points = np.concatenate([a, b], axis=1)  # (T, 30, 3)
    return np.linalg.norm(np.diff(points, axis=0), axis=-1).max(axis=1) * hz


def moving_spans(motion: MotionDef, hz: int = SAMPLE_HZ) -> tuple[tuple[float, float], ...]:
    """The (start, end) seconds of the take where the body moves, in order; pauses under
    ``MERGED_GAP_S`` are part of the motion around them."""
    moving = fastest_point_speed(motion, hz) > MOVING_SPEED_M_S
    edges = np.flatnonzero(np.diff(np.concatenate([[0], moving.astype(np.int8), [0]])))
    spans: list[tuple[float, float]] = []
    for i, j in zip(edges[::2], edges[1::2], strict=True):
        start, end = round(float(i) / hz, 1), round(min(float(j) / hz, motion.length_s), 1)
        if spans and start - spans[-1][1] < MERGED_GAP_S:
            start = spans.pop()[0]
        spans.append((start, end))
    return tuple(spans)


def approach(motion: MotionDef, hz: int = SAMPLE_HZ) -> tuple[float, float] | None:
    """(end s, pace m/s) of a take that walks up to a stop: its first moving span, where
    another follows (a pause between), and the reference body's mean speed over the ground
    along it; None for a take that never pauses or stands nearly still before its pause."""
    spans = moving_spans(motion, hz)
    if len(spans) < 2:
        return None
    start, end = spans[0]
    pose = motion.fn(np.array([start, end]), _PARAMS)
    pace = float(np.linalg.norm(pose.root_pos[1, :2] - pose.root_pos[0, :2])) / (end - start)
    return (end, round(pace, 3)) if pace >= APPROACH_PACE_M_S else None


def table_source() -> str:
    """The Python source of ``phav_spec/motion_activity.py`` for the built-in motions."""
    lines = [
        '"""Where each catalogue motion moves: (start, end) seconds of the take, merged and in',
        "order (the body's fastest point above "
        f"{MOVING_SPEED_M_S} m/s, sampled at {SAMPLE_HZ} Hz at the reference playback).",
        "",
        "Written by ``python -m phav_generator.motion.activity``; the test suite checks it against",
        'the motions. Do not edit by hand."""',
        "",
        "from collections.abc import Mapping",
        "from types import MappingProxyType",
        "",
        "MOVING_SPANS: Mapping[str, tuple[tuple[float, float], ...]] = MappingProxyType({",
    ]
    for name, motion in BUILTIN_MOTIONS.items():
        spans = [f"({a!r}, {b!r})," for a, b in moving_spans(motion)]
        if len(spans) <= 4:
            lines.append(f'    "{name}": ({" ".join(spans)}),')
            continue
        lines.append(f'    "{name}": (')
        lines += ["        " + " ".join(spans[i : i + 8]) for i in range(0, len(spans), 8)]
        lines.append("    ),")
    lines.append("})  # fmt: skip")
    lines += [
        "",
        "#: The takes that walk up to a stop (a pause follows their first moving span): that",
        "#: span's end (s) and the body's mean speed over the ground along it (m/s, at least",
        f"#: {APPROACH_PACE_M_S}), at the reference playback.",
        "APPROACHES: Mapping[str, tuple[float, float]] = MappingProxyType({",
    ]
    for name, motion in BUILTIN_MOTIONS.items():
        found = approach(motion)
        if found is not None:
            lines.append(f'    "{name}": ({found[0]!r}, {found[1]!r}),')
    lines.append("})  # fmt: skip")
    return "\n".join(lines) + "\n"


def main() -> None:
    print(table_source(), end="")


if __name__ == "__main__":
    main()
