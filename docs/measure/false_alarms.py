"""False alarms of every phav-validate check on small clean datasets, and the recall of the
failures check on physics failures injected into their poses and cameras.

Generates ``--datasets`` datasets of ``--videos`` phav-v1-short videos (seeds 100, 101, …;
kept in ``--work`` and reused when run again), validates each with every check (one video
regenerated) and counts, per check, the datasets it failed or warned on: on clean data
every fail is a false alarm. Then, per clean video, injects each failure case of the
issue's list into a copy of its metadata (``phav_validators.checks.inject`` says how) and asks
the failures check about it.

    .venv/bin/python docs/measure/false_alarms.py --work /tmp/phav-fa --datasets 20 --videos 4
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import time
from pathlib import Path

import pyarrow.parquet as pq

from phav_spec.recipe_table import read_recipe_table
from phav_validators.checks.failures import camera_series, people_series, video_failures
from phav_validators.checks.inject import INJECTIONS, inject
from phav_validators.options import CHECKS, Options
from phav_validators.source import resolve
from phav_validators.validate import validate_dataset

SEED0 = 100


def generate(work: Path, seed: int, videos: int) -> Path:
    out = work / f"seed{seed}"
    if not (out / "manifest.json").exists():
        cmd = [str(Path(sys.executable).parent / "phav"), "generate", "--theta", "phav-v1-short",
               "--videos", str(videos), "--seed", str(seed), "--workers", "2", "--out", str(out)]  # fmt: skip
        subprocess.run(cmd, check=True, capture_output=True)
    return out


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
                if injected is None or (kind == "sliding" and "planted_foot_speed_m_s" not in clean.measures):
                    continue  # not applicable (no box to walk into, no planted foot to slide, …)
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
