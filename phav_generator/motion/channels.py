"""Channels: the named curves a procedural motion is written in.

A motion is a set of named curves over motion time, each a *channel*:

* joint angles: DOF names of ``skeleton.DOFS``, degrees; ``shoulder_flex`` without a side
  sets both sides;
* root offsets: ``x y z`` metres in the heading frame, ``yaw pitch roll`` degrees;
* foot targets ``lf_* rf_*``: sole position and pitch/yaw in the heading frame;
* hand targets ``lh_* rh_*``: wrist position in the chest or heading frame, and elbow poles
  ``le_* re_*`` (the direction each elbow points);
* blend weights: ``l_leg r_leg`` (leg IK, default on), ``l_arm r_arm`` (arm IK, default
  off), ``snap`` (put the lowest body point on the ground).

A posture is a mapping channel → value written with shorthands (``expand``); ``Channels``
holds the curves of one evaluation, and a channel nobody wrote reads as its default.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np

from phav_generator.motion.reference import HIP_Y
from phav_generator.motion.skeleton import DOF_INDEX

#: Radians per degree: channel angles are written in degrees.
DEG = math.pi / 180.0

#: A posture: channel (or shorthand) → value, degrees and metres.
Posture = Mapping[str, float]

_BILATERAL = {d.split("_", 1)[1] for d in DOF_INDEX if d.startswith("left_")}
_DEFAULTS: dict[str, float] = {
    "l_leg": 1.0, "r_leg": 1.0, "l_arm": 0.0, "r_arm": 0.0, "snap": 0.0,
    "lf_y": HIP_Y, "rf_y": -HIP_Y, "lf_yaw": 6.0, "rf_yaw": -6.0,
    "lh_x": 0.05, "rh_x": 0.05, "lh_y": 0.18, "rh_y": -0.18, "lh_z": -0.24, "rh_z": -0.24,
    "le_x": -0.2, "re_x": -0.2, "le_y": 0.4, "re_y": -0.4, "le_z": -1.0, "re_z": -1.0,
}  # fmt: skip


def expand(posture: Posture) -> dict[str, float]:
    """Channel values of a posture written with shorthands.

    ``shoulder_flex`` (no side) sets both sides; ``leg``/``arm`` both IK weights; ``f_x``,
    ``f_z``, ``f_pitch`` both feet; ``f_w`` the feet's half-width (left +, right −); ``f_out``
    the toe-out angle; ``h_x``, ``h_z`` both hands, ``h_w`` the hands' half-width.
    """
    out: dict[str, float] = {}
    for key, value in posture.items():
        v = float(value)
        if key in _BILATERAL:
            out[f"left_{key}"] = out[f"right_{key}"] = v
        elif key in ("leg", "arm"):
            out[f"l_{key}"] = out[f"r_{key}"] = v
        elif key in ("f_x", "f_z", "f_pitch", "h_x", "h_z", "e_x", "e_z"):
            out[f"l{key}"] = out[f"r{key}"] = v
        elif key == "f_w":
            out["lf_y"], out["rf_y"] = v, -v
        elif key == "f_out":
            out["lf_yaw"], out["rf_yaw"] = v, -v
        elif key in ("h_w", "e_w"):
            out[f"l{key[0]}_y"], out[f"r{key[0]}_y"] = v, -v
        else:
            out[key] = v
    return out


def default(name: str) -> float:
    """The value of channel ``name`` where no layer wrote it."""
    return _DEFAULTS.get(name, 0.0)


class Channels:
    """Channel curves over the sample times; missing channels read as their default."""

    def __init__(self, n: int) -> None:
        self.n = n
        self.data: dict[str, np.ndarray] = {}

    def __getitem__(self, name: str) -> np.ndarray:
        if name in self.data:
            return self.data[name]
        return np.full(self.n, default(name))

    def __contains__(self, name: str) -> bool:
        return name in self.data

    def set(self, name: str, value: np.ndarray | float) -> None:
        """Write channel ``name`` (a value or one per sample), replacing what was there."""
        self.data[name] = np.broadcast_to(np.asarray(value, dtype=np.float64), (self.n,)).copy()

    def add(self, name: str, value: np.ndarray | float) -> None:
        """Add to channel ``name`` (to its default where it was not written)."""
        self.set(name, self[name] + value)
