"""How far our pixels can still move the Cityscapes mIoU (docs/realism-gap.md): per judge class,
its IoU split into our pixels it names otherwise (misses) and its answers on pixels of our
other classes (false answers), and the mIoU were every one of our pixels of that class named
right, the rest unchanged. A false answer on a lawn is a miss of the lawn, so the table says
which of our classes each class's false answers lie on.

Reads the frames ``judged_frames.py --dump DIR`` wrote (pixels, truth and answers): the
figures are the realism check's own on those frames, and no judge runs here.

    .venv/bin/python docs/measure/judged_frames.py --dump judged
    .venv/bin/python docs/measure/judged_ceiling.py judged [--group weather=rain]
"""

from __future__ import annotations

import argparse
from collections import Counter
from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from judged_frames import dumped

from phav_spec.judge_classes import JUDGE_CLASSES
from phav_spec.vocab import PIXEL_CLASSES
from phav_validators.realism.check import Tally, cityscapes_miou, judge_world, judged_groups

JUDGE = "cityscapes"


@dataclass(frozen=True)
class Frame:
    """One judged frame: its video, our class ids, the judge's answer ids, its groups."""

    video: str
    ours: np.ndarray
    said: np.ndarray
    groups: tuple[str, ...]


@dataclass(frozen=True)
class Ceiling:
    """A judge class's figures as judged and with our pixels of it all named right."""

    name: str
    iou: float
    pixels: int  # ours judged as it
    missed: int  # of those, named something else
    false_on: Counter  # its answers on our other (judged) classes, by our class
    iou_right: float
    miou_right: float
    elsewhere: int  # of its false answers, those in frames that show none of ours judged as it


def ceilings(frames: Iterable[Frame], group: str = "all") -> tuple[float, list[Ceiling]]:
    """The mIoU of ``group`` as judged, and each present judge class's ceiling."""
    judge = JUDGE_CLASSES[JUDGE]
    ids = {m: [i for ids in ours.values() for i in ids] for m, ours in judged_groups(JUDGE).items()}
    scored_ids = [i for v in ids.values() for i in v]  # Cityscapes voids what it does not judge
    names = {PIXEL_CLASSES[n].class_id: n for n in PIXEL_CLASSES.names}
    tallies: dict[str | None, Tally] = {None: Tally(), **{m: Tally() for m in ids}}
    counts = {m: Counter() for m in ids}  # hit, miss; false answers by our class they lie on
    elsewhere = Counter()  # false answers in frames that show none of the class
    for frame in frames:
        if group not in frame.groups:
            continue
        judge_world(frame.said, frame.ours, judge, tallies[None], frame.video, frame.groups)
        scored = np.isin(frame.ours, scored_ids)
        for m in ids:
            truth = np.isin(frame.ours, ids[m])
            answered = np.isin(frame.said, judge.answer_ids(m))
            counts[m]["hit"] += int((answered & truth).sum())
            counts[m]["miss"] += int((~answered & truth).sum())
            on, n = np.unique(frame.ours[answered & ~truth & scored], return_counts=True)
            counts[m].update({f"false:{names[int(c)]}": int(k) for c, k in zip(on, n, strict=True)})
            if not truth.any():
                elsewhere[m] += int(n.sum())
            right = np.where(truth, judge.label_id(m), frame.said)
            judge_world(right, frame.ours, judge, tallies[m], frame.video, frame.groups)
    base = cityscapes_miou(tallies[None], 0, group)
    if base is None:
        return float("nan"), []
    rows = []
    for m, c in counts.items():
        if c["hit"] + c["miss"] == 0:
            continue
        key = f"class_iou|{JUDGE}|{m}|{group}"
        false_on = Counter({k[6:]: v for k, v in c.items() if k.startswith("false:")})
        right = tallies[m]
        rows.append(Ceiling(m, tallies[None].figure(key, 0).value, c["hit"] + c["miss"], c["miss"], false_on,
                            right.figure(key, 0).value, cityscapes_miou(right, 0, group).value,
                            elsewhere[m]))  # fmt: skip
    return base.value, rows


def read_dump(folder: Path) -> list[Frame]:
    """The frames ``judged_frames.py --dump`` wrote that the Cityscapes judge saw (outdoors)."""
    return [Frame(video, ours, answers[JUDGE], groups) for video, groups, ours, answers in dumped(folder)
            if JUDGE in answers]  # fmt: skip


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("dump", type=Path, help="folder of judged_frames.py --dump")
    parser.add_argument("--group", default="all", help="condition group, e.g. weather=fog")
    args = parser.parse_args()
    frames = read_dump(args.dump)
    miou, rows = ceilings(frames, args.group)
    print(f"{sum(args.group in f.groups for f in frames)} frames, {args.group}: mIoU {miou:.3f} as judged\n")
    print("| class | IoU | our pixels | named otherwise | its answers on our other classes (in frames without it) | "
          "IoU, ours all named right | mIoU then |")  # fmt: skip
    print("| --- | ---: | ---: | ---: | --- | ---: | ---: |")
    for r in rows:
        false = sum(r.false_on.values())
        on = ", ".join(f"{k} {v / false:.0%}" for k, v in r.false_on.most_common(3))
        print(f"| {r.name} | {r.iou:.2f} | {r.pixels:,} | {r.missed / r.pixels:.0%} | {false:,} ({r.elsewhere:,})"
              f"{f': {on}' if on else ''} | {r.iou_right:.2f} | {r.miou_right:.3f} |")  # fmt: skip


if __name__ == "__main__":
    main()
