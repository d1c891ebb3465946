"""How the judges see one of our object classes by the view a frame gives of it
(docs/realism-gap.md): each object (a connected region of the class's pixels, 30 or more) in the
realism check's frames is whole or cut by the frame's edge, and small, middling or large on
screen; per view, its share of the class's pixels and the share each judge names as its
class. A real object's figures by view are judged_real_small.py's: whole, then shrunk or
cropped round its parts.

Reads the frames ``judged_frames.py --dump DIR`` wrote: the figures are the check's own
frames and answers, and no judge runs here.

    .venv/bin/python docs/measure/judged_frames.py --voc --dump judged
    .venv/bin/python docs/measure/judged_views.py judged [--class car]
"""

from __future__ import annotations

import argparse
from collections import Counter
from collections.abc import Iterable
from pathlib import Path

import cv2
import numpy as np
from judged_frames import dump_files

from phav_spec.judge_classes import JUDGE_CLASSES
from phav_spec.vocab import PIXEL_CLASSES

#: A dump's array of each judge's answers (judged_frames.py's names).
_ANSWERS = {"said": "cityscapes", "voc": "pascal_voc"}
#: Heights on screen (px) that part small, middling and large objects: below 24 px our cars
#: and a real one alone are named by neither judge, from 64 px by both (judged_alone.py).
_BANDS = ((24, "under 24 px"), (64, "24–63 px"), (10**9, "64 px and up"))
#: Smaller regions are the slivers an occluder leaves, not a view of an object.
_MIN_PIXELS = 30


def view_of(x: int, y: int, w: int, h: int, shape: tuple[int, int]) -> str:
    """A region's view from its bounding box: cut or whole, and its height band."""
    cut = x == 0 or y == 0 or x + w == shape[1] or y + h == shape[0]
    band = next(name for top, name in _BANDS if h < top)
    return f"{'cut by the edge' if cut else 'whole'}, {band}"


def tally(files: Iterable[Path], ours_name: str) -> dict[str, Counter]:
    """Per view: objects, pixels, and per judge the pixels it saw and those it named right."""
    class_id = PIXEL_CLASSES[ours_name].class_id
    out: dict[str, Counter] = {}
    for f in files:
        with np.load(f) as z:
            mask = (z["ours"] == class_id).astype(np.uint8)
            if not mask.any():
                continue
            answers = {judge: z[name] for name, judge in _ANSWERS.items() if name in z}
            n, regions, boxes, _ = cv2.connectedComponentsWithStats(mask, connectivity=8)
            for i in range(1, n):
                x, y, w, h, area = (int(v) for v in boxes[i])
                if area < _MIN_PIXELS:
                    continue
                c = out.setdefault(view_of(x, y, w, h, mask.shape), Counter())
                c["objects"] += 1
                c["pixels"] += area
                inside = regions == i
                for judge, said in answers.items():
                    named = JUDGE_CLASSES[judge].judged_as.get(ours_name)
                    if named is None:
                        continue
                    c[f"seen:{judge}"] += area
                    c[f"named:{judge}"] += int(np.isin(said[inside], JUDGE_CLASSES[judge].answer_ids(named)).sum())
    return out


def table(views: dict[str, Counter]) -> str:
    """Markdown: a row per view, the pixels' share and each judge's recall, then all views."""
    judges = [j for j in _ANSWERS.values() if any(c[f"seen:{j}"] for c in views.values())]
    total = Counter()
    for c in views.values():
        total.update(c)
    head = "| " + " | ".join(["view", "objects", "pixels (share)", *(f"{j} recall" for j in judges)]) + " |"
    lines = [head, "| --- | ---: | ---: |" + " ---: |" * len(judges)]
    order = [f"{cut}, {band}" for cut in ("whole", "cut by the edge") for _, band in _BANDS]
    for name, c in [*sorted(views.items(), key=lambda kv: order.index(kv[0])), ("all", total)]:
        recalls = [f"{c[f'named:{j}'] / c[f'seen:{j}']:.2f}" if c[f"seen:{j}"] else "—" for j in judges]
        share = c["pixels"] / max(total["pixels"], 1)
        lines.append("| " + " | ".join([name, str(c["objects"]), f"{c['pixels']:,} ({share:.2f})", *recalls]) + " |")
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("dump", type=Path, help="a judged_frames.py --dump folder")
    parser.add_argument("--class", dest="cls", default="car", choices=PIXEL_CLASSES.names, help="our class")
    args = parser.parse_args()
    print(table(tally(dump_files(args.dump), args.cls)))


if __name__ == "__main__":
    main()
