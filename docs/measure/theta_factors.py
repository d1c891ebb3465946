"""θ presets that change one data factor of phav-v1-short each, for the learnability
experiments (docs/experiments/learnability.md, "The data" and "One sample a pixel"): clip
length, camera, the kite's framing, weather, motions per action, and the RGB modality's
supersampling (phav-v1's 2 samples a pixel against phav-v1-short's 1).

Each variant is phav-v1-short's YAML with one key replaced, written as
``<out>/phav-v1-short-<factor>.yaml``; generate from it with ``phav generate --theta FILE``.

    .venv/bin/python docs/measure/theta_factors.py --out /tmp/factors
    .venv/bin/phav generate --theta /tmp/factors/phav-v1-short-kite.yaml --videos 700 --seed 9 --out /tmp/f-kite
"""

from __future__ import annotations

import argparse
import re
from pathlib import Path
from typing import Any

import yaml

from phav_spec.motions import MOTIONS
from phav_spec.theta import PRESETS_DIR, load_theta

#: The kite camera's distance and field of view of the ``kite-far`` variant.
FAR_KITE = {
    "fov_deg": {"kind": "uniform", "low": 40.0, "high": 70.0},
    "distance_m": {"kind": "uniform", "low": 2.5, "high": 8.0},
}


def one_motion_per_action(regex: dict[str, str], t_min: float) -> dict[str, str]:
    """Each action's pattern narrowed to the first catalogue motion it matches that is long
    enough for the shortest clip: the same actions, one take each."""
    out = {}
    for action, pattern in sorted(regex.items()):
        first = next(m for m in (MOTIONS[n] for n in MOTIONS.names)
                     if re.search(pattern, m.description) and m.length_s >= t_min)  # fmt: skip
        out[action] = f"^{re.escape(first.description)}$"
    return out


def base_preset() -> dict[str, Any]:
    """phav-v1-short's θ as the YAML mapping the variants change."""
    return yaml.safe_load((PRESETS_DIR / "phav-v1-short.yaml").read_text(encoding="utf-8"))


def variants(base: dict[str, Any]) -> dict[str, dict[str, Any]]:
    """Factor name → (key, new value) applied to ``base``: one θ key changed per variant."""
    cameras = {name: 0 for name in base["theta_c"]}
    weathers = {name: 0 for name in ("clear", "overcast", "rain", "fog")}
    regex = base["theta_ab"]["regex"]
    changes = {
        "clips-0.5-1s": ("durations", {"t_min": 0.5, "t_max": 1.0, "t_mod": 0.75}),
        "clips-2-4s": ("durations", {"t_min": 2.0, "t_max": 4.0, "t_mod": 3.0}),
        "kite": ("theta_c", {**cameras, "kite": 1}),
        # The kite's framing: its earlier, wider ranges (2.5–8 m, 40–70°), under which the
        # protagonist's median height was 26 % of the frame against 48 % (docs/framing.md).
        "kite-far": ("cameras", {**base["cameras"], "kite": {**base["cameras"]["kite"], **FAR_KITE}}),
        "clear": ("theta_w", {**weathers, "clear": 1}),
        "one-motion": ("theta_ab", {"regex": one_motion_per_action(regex, base["durations"]["t_min"])}),
        "supersampling-2": ("render", {**base["render"], "supersampling": 2}),
    }
    out = {}
    for factor, (key, value) in changes.items():
        theta = {**base, key: value, "name": f"{base['name']}-{factor}"}
        theta["description"] = f"{base['name']} with {key} changed ({factor}); learnability factor study."
        out[factor] = theta
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, required=True)
    args = parser.parse_args()
    base = base_preset()
    args.out.mkdir(parents=True, exist_ok=True)
    for factor, theta in variants(base).items():
        path = args.out / f"phav-v1-short-{factor}.yaml"
        path.write_text(yaml.safe_dump(theta, sort_keys=False, allow_unicode=True), encoding="utf-8")
        load_theta(path)  # a variant θ must be valid
        print(f"wrote {path}")


if __name__ == "__main__":
    main()
