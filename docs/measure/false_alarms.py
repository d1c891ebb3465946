"""False alarms of every phav-validate check on small clean datasets, and the recall of the
failures check on physics failures injected into their poses and cameras.

Generates ``--datasets`` datasets of ``--videos`` phav-v1-short videos (seeds 100, 101, …;
kept in ``--work`` and reused when run again), validates each with every check (one video
regenerated) and counts, per check, the datasets it failed or warned on: on clean data
every fail is a false alarm. Then, per clean video, injects each failure case of the
issue's list into a copy of its metadata and asks the failures check about it:

- wall: the protagonist's path bent so that the hips end at the centre of the nearest
  collision box at least 1 m tall (videos whose scene has none: not applicable);
- knee: both knees moved 15 cm backwards (behind the hip–ankle line) in every frame;
- nan: one joint of the middle frame set to NaN;
- explosion: every joint of the middle frame thrown 1.5 m (45 m/s at 30 fps);
- off-screen: the camera turned 180° about the vertical in every frame;
- camera-inside: the camera moved into the nearest box's centre (else 50 cm under the
  ground) for the middle third of the clip;
- perturbation: (random-perturbation videos) the necessary muscles' joints moved 40 cm;
- sliding: the whole body drifting sideways at 1.5 m/s, planted feet included.

    .venv/bin/python docs/measure/false_alarms.py --work /tmp/phav-fa --datasets 20 --videos 4
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pyarrow.parquet as pq

from phav_spec.metadata import JOINT_ORDER
from phav_spec.recipe_table import read_recipe_table
from phav_spec.scene import ENVIRONMENT_SCENES
from phav_validators.failures import (
    CameraSeries,
    PersonSeries,
    boxes,
    camera_series,
    necessary_joints,
    people_series,
    video_failures,
)
from phav_validators.findings import Reason
from phav_validators.source import resolve
from phav_validators.validate import CHECKS, Options, validate_dataset

SEED0 = 100
_J = {name: i for i, name in enumerate(JOINT_ORDER)}
INJECTIONS: dict[str, Reason] = {
    "wall": Reason.INTERPENETRATION,
    "knee": Reason.JOINT_LIMIT,
    "nan": Reason.NAN_POSE,
    "explosion": Reason.ENERGY_EXPLOSION,
    "off-screen": Reason.OFF_SCREEN,
    "camera-inside": Reason.CAMERA_IN_GEOMETRY,
    "perturbation": Reason.PERTURBATION_TOO_STRONG,
    "sliding": Reason.FOOT_SLIDING,
}


def generate(work: Path, seed: int, videos: int) -> Path:
    out = work / f"seed{seed}"
    if not (out / "manifest.json").exists():
        cmd = [str(Path(sys.executable).parent / "phav"), "generate", "--theta", "phav-v1-short",
               "--videos", str(videos), "--seed", str(seed), "--workers", "2", "--out", str(out)]  # fmt: skip
        subprocess.run(cmd, check=True, capture_output=True)
    return out


def _nearest_box(env: str, point: np.ndarray) -> np.ndarray | None:
    box = boxes(env)
    tall = [i for i, c in enumerate(box.colliders) if 2 * c.half_size[2] >= 1.0 and min(c.half_size[:2]) >= 0.3]
    if not tall:
        return None
    d = np.linalg.norm(box.center[tall, :2] - point[:2], axis=1)
    return box.center[tall[int(np.argmin(d))]]


def inject(kind: str, recipe, people: list[PersonSeries], cams: CameraSeries):
    """A copy of (people, cams) with one failure case injected, None where not applicable."""
    pid = recipe.protagonist.person_id
    people = [dataclasses.replace(p, joints=p.joints.copy()) for p in people]
    cams = dataclasses.replace(cams, poses=cams.poses.copy())
    me = next(p for p in people if p.person_id == pid)
    j = me.joints
    t = len(j)
    mid = t // 2
    hips = 0.5 * (j[:, _J["left_hip"]] + j[:, _J["right_hip"]])
    env = recipe.environment.name
    if kind == "wall":
        centre = _nearest_box(env, hips[0])
        if centre is None:
            return None
        ramp = np.linspace(0.0, 1.0, t)[:, None]
        j += (ramp * (centre - hips[-1]))[:, None, :]
    elif kind == "knee":
        up = j[:, _J["neck"]] - hips
        right = j[:, _J["right_hip"]] - j[:, _J["left_hip"]]
        forward = np.cross(up, right)
        forward /= np.linalg.norm(forward, axis=-1, keepdims=True)
        for side in ("left", "right"):
            j[:, _J[f"{side}_knee"]] -= 0.15 * forward
    elif kind == "nan":
        j[mid, _J["left_wrist"]] = np.nan
    elif kind == "explosion":
        j[mid] += np.array([1.5, 0.0, 0.0])
    elif kind == "off-screen":
        turn = np.diag([-1.0, -1.0, 1.0])  # 180° about world z, about the camera's own position
        cams.poses[:, :3, :3] = turn @ cams.poses[:, :3, :3]
    elif kind == "camera-inside":
        third = slice(len(cams.poses) // 3, 2 * len(cams.poses) // 3)
        centre = _nearest_box(env, cams.poses[len(cams.poses) // 2, :3, 3])
        if centre is None:
            centre = cams.poses[third, :3, 3].copy()
            centre[:, 2] = ENVIRONMENT_SCENES[env].ground_z - 0.5
        cams.poses[third, :3, 3] = centre
    elif kind == "perturbation":
        if recipe.variation.kind != "random_perturbation":
            return None
        moved = necessary_joints(recipe.action)
        if not moved:
            return None
        j[:, moved] += np.array([0.4, 0.0, 0.0])
    elif kind == "sliding":
        j += (np.arange(t) / recipe.video.fps * 1.5)[:, None, None] * np.array([1.0, 0.0, 0.0])
    return people, cams


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--work", type=Path, required=True)
    parser.add_argument("--datasets", type=int, default=20)
    parser.add_argument("--videos", type=int, default=4)
    args = parser.parse_args()
    args.work.mkdir(parents=True, exist_ok=True)
    start = time.time()
    status = {c: {"pass": 0, "warn": 0, "fail": 0, "skip": 0} for c in CHECKS}
    clean_flags: dict[str, int] = {}
    clean_videos = flagged_videos = 0
    recall = {k: [0, 0, 0] for k in INJECTIONS}  # applicable, right reason, any failure
    gen_s = val_s = 0.0
    for i in range(args.datasets):
        seed = SEED0 + i
        t0 = time.time()
        ds = generate(args.work, seed, args.videos)
        t1 = time.time()
        report = validate_dataset(resolve([ds])[0], options=Options(workers=2, regenerate=1, seed=seed))
        t2 = time.time()
        gen_s += t1 - t0
        val_s += t2 - t1
        for c in report.checks:
            status[c.name][c.status.value] += 1
        print(f"seed {seed}: {report.status.value} " + " ".join(f"{c.name}={c.status.value}" for c in report.checks),
              flush=True)  # fmt: skip
        for c in report.checks:
            for f in c.report.findings:
                print(f"    {c.name} {f.reason.value} {f.video_id}: {f.message}", flush=True)
        recipes = {r.video_id: r for r in read_recipe_table(ds / "recipes.parquet").recipes()}
        people = people_series(pq.read_table(ds / "people.parquet"))
        cams = camera_series(pq.read_table(ds / "cameras.parquet"))
        for vid, recipe in sorted(recipes.items()):
            clean = video_failures(recipe, people[vid], cams[vid])
            clean_videos += 1
            flagged_videos += clean.failed
            for reason in dict.fromkeys(r for r, _ in clean.failures):
                clean_flags[reason.value] = clean_flags.get(reason.value, 0) + 1
            for kind, reason in INJECTIONS.items():
                injected = inject(kind, recipe, people[vid], cams[vid])
                if injected is None:
                    continue
                result = video_failures(recipe, *injected)
                row = recall[kind]
                row[0] += 1
                row[1] += any(r == reason for r, _ in result.failures)
                row[2] += result.failed
    print(f"\n{args.datasets} datasets × {args.videos} videos in {time.time() - start:.0f} s "
          f"(generation {gen_s:.0f} s, validation {val_s:.0f} s)\n")  # fmt: skip
    print("| check | pass | warn | fail (false alarm) |")
    print("| --- | ---: | ---: | ---: |")
    for name in CHECKS:
        s = status[name]
        print(f"| {name} | {s['pass']} | {s['warn']} | {s['fail']}/{args.datasets} |")
    print(f"\nclean videos flagged by the failures check: {flagged_videos}/{clean_videos} {clean_flags}\n")
    print("| injected failure | expected reason | videos | caught (that reason) | caught (any reason) |")
    print("| --- | --- | ---: | ---: | ---: |")
    for kind, (n, right, any_) in recall.items():
        print(f"| {kind} | {INJECTIONS[kind].value} | {n} | {right}/{n} | {any_}/{n} |")
    summary = {"status": status, "clean_videos": clean_videos, "flagged": flagged_videos, "by_reason": clean_flags,
               "recall": recall}  # fmt: skip
    (args.work / "false_alarms.json").write_text(json.dumps(summary, indent=1), encoding="utf-8")


if __name__ == "__main__":
    main()
