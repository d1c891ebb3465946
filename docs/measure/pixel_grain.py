"""How much each class varies from pixel to pixel, in real photographs and in our frames
(docs/realism-gap.md): the median, over a class's pixels at least 4 px inside it, of a pixel's
luminance less its 3 × 3 neighbourhood's mean, over that mean (linear light). A material
faded out under the pixel scores near 0, a photograph's road about 0.14; a street model
takes a smooth grey ground for a car's paint.

    .venv/bin/python docs/measure/pixel_grain.py --real opencv-doc/usr/share/doc/opencv-doc/examples/data \
        --dump judged [--group weather=clear]

The photographs are judged_real.py's (OpenCV's sample data, its hand-drawn boxes); the
dump is judged_frames.py --dump's frames (their pixels and truth; the outdoor frames).
"""

from __future__ import annotations

import argparse
from collections import defaultdict
from pathlib import Path

import numpy as np
from judged_frames import dump_files
from judged_real import MARGIN_PX, REGIONS, _targets, as_frame, interior
from judged_repaint import _LUMINANCE, linear

#: A frame's class counts when this many of its pixels are inside it.
MIN_PIXELS = 200


def contrast(rgb: np.ndarray) -> np.ndarray:
    """Each pixel's |luminance − its 3 × 3 mean| / that mean (edge pixels: their clipped window)."""
    y = linear(rgb) @ _LUMINANCE
    padded = np.pad(y, 1, mode="edge")
    mean = sum(padded[dy : dy + y.shape[0], dx : dx + y.shape[1]] for dy in range(3) for dx in range(3)) / 9.0
    return np.abs(y - mean) / np.maximum(mean, 1e-4)


def real(folder: Path) -> dict[str, list[float]]:
    """Per class, each hand-drawn box's median contrast."""
    out: dict[str, list[float]] = defaultdict(list)
    for name, boxes in REGIONS.items():
        if not (folder / name).is_file():
            raise SystemExit(f"{folder / name}: not found (judged_real.py says where the photographs come from)")
        c = contrast(as_frame(folder / name))
        for cls, (x0, y0, x1, y1) in boxes:
            out[cls].append(float(np.median(c[y0:y1, x0:x1])))
    return out


def ours(folder: Path, group: str) -> dict[str, tuple[float, int]]:
    """Per judge class, the median over ``group``'s outdoor frames of each frame's median
    contrast inside our pixels of it, and the number of frames."""
    targets, to_target = _targets()
    per: dict[str, list[float]] = defaultdict(list)
    for path in dump_files(folder):
        with np.load(path) as z:
            if "said" not in z or group not in [str(g) for g in z["where"]]:
                continue  # a room, which the street model does not judge, or another group
            target = to_target[z["ours"]]
            inside = interior(target, MARGIN_PX) & (target >= 0)
            c = contrast(z["rgb"])
        for t in np.unique(target[inside]):
            mask = inside & (target == t)
            if mask.sum() >= MIN_PIXELS:
                per[targets[t]].append(float(np.median(c[mask])))
    return {cls: (float(np.median(v)), len(v)) for cls, v in sorted(per.items())}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--real", type=Path, required=True, help="the folder of OpenCV's sample photographs")
    parser.add_argument("--dump", type=Path, action="append", required=True,
                        help="a judged_frames.py --dump folder (repeat to set several side by side)")  # fmt: skip
    parser.add_argument("--group", default="all", help="only the frames of this group, e.g. weather=clear")
    args = parser.parse_args()
    photos = real(args.real)
    columns = [ours(d, args.group) for d in args.dump]
    names = sorted(set(photos) | {c for col in columns for c in col})
    heads = " | ".join(f"{d} ({args.group}: frames)" for d in args.dump)
    print(f"| class | real photographs (each box) | {heads} |")
    print("| --- | --- |" + " ---: |" * len(columns))
    for cls in names:
        shot = ", ".join(f"{v:.3f}" for v in photos.get(cls, []))
        cells = " | ".join(f"{col[cls][0]:.3f} ({col[cls][1]})" if cls in col else "" for col in columns)
        print(f"| {cls} | {shot} | {cells} |")


if __name__ == "__main__":
    main()
