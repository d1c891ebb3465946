"""Two datasets made from the same recipes at different RGB supersampling, compared: which
modalities' content hashes agree, and how far apart the RGB frames are at the stored size
and at the size the learnability check trains on (docs/experiments/learnability.md, "One
sample a pixel").

    .venv/bin/python docs/measure/theta_factors.py --out factors
    .venv/bin/phav generate --theta factors/phav-v1-short-supersampling-2.yaml --videos 64 --seed 7 --out ss2
    .venv/bin/phav generate --theta phav-v1-short --videos 64 --seed 7 --out ss1
    .venv/bin/python docs/measure/supersampling.py ss2 ss1
"""

from __future__ import annotations

import argparse
import json
from collections.abc import Iterator
from pathlib import Path

import numpy as np

from phav_spec.encoding import modality
from phav_spec.manifest import load_manifest
from phav_spec.webdataset import decode_png
from phav_validators.checks.tarsafe import TarScan, iter_members
from phav_validators.learn.data import DEFAULT_SIZE, resize_rgb


def rgb_frames(dataset: Path) -> Iterator[tuple[str, np.ndarray]]:
    """Every RGB frame of ``dataset``'s shards as (member name, (H, W, 3) uint8), in shard order."""
    rgb = modality("rgb")
    for shard in sorted(dataset.glob("*.tar")):
        for name, data in iter_members(shard, TarScan(), only=lambda n: n.endswith(f".{rgb.key}")):
            yield name, decode_png(data, rgb, source=f"{shard.name}:{name}")


def compare(reference: Path, other: Path) -> dict:
    """Videos whose hash agrees per modality, and the RGB frames' mean |difference| (levels)
    at the stored size and as the check stores them (``resize_rgb`` to ``DEFAULT_SIZE``): mean
    over frames and 99th percentile."""
    a = {v.video_id: v for v in load_manifest(reference / "manifest.json").videos}
    b = {v.video_id: v for v in load_manifest(other / "manifest.json").videos}
    if set(a) != set(b):
        raise SystemExit(f"{reference} and {other} hold different videos")
    modalities = sorted(next(iter(a.values())).modality_hashes)
    equal = {m: sum(a[v].modality_hashes[m] == b[v].modality_hashes[m] for v in a) for m in modalities}
    full, small = [], []
    theirs = dict(rgb_frames(other))
    for name, x in rgb_frames(reference):
        y = theirs[name]
        full.append(float(np.abs(x.astype(np.float32) - y.astype(np.float32)).mean()))
        xs, ys = (resize_rgb(f, DEFAULT_SIZE).astype(np.float32) for f in (x, y))
        small.append(float(np.abs(xs - ys).mean()))
    return {
        "videos": len(a), "frames": len(full), "equal_hashes": equal,
        "rgb_mean_abs": {"stored": float(np.mean(full)), "stored_p99": float(np.percentile(full, 99)),
                         "check_size": float(np.mean(small)), "check_size_p99": float(np.percentile(small, 99))},
    }  # fmt: skip


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("reference", type=Path)
    parser.add_argument("other", type=Path)
    args = parser.parse_args()
    print(json.dumps(compare(args.reference, args.other), indent=1))


if __name__ == "__main__":
    main()
