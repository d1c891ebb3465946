"""A confused pair side by side: for each named video of a dataset, a row of RGB frames
with the flow of the same frames beneath (docs/experiments/learnability.md, "The check on a
fresh phav-v1-short set": per class and confused pairs).

    .venv/bin/python docs/measure/pair_sheet.py /tmp/g7 v000033 v000488 --out pair.jpg \\
        --label "limp, answered moonwalk" --label "moonwalk"
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
from PIL import Image, ImageDraw

from phav_app.preview import flow_image, frames_from_dataset


def video_rows(dataset: Path, video: str, label: str, frames: int, scale: int) -> np.ndarray:
    """One video's labelled strip: ``frames`` evenly spaced RGB frames over their flow."""
    vid, _, modalities = frames_from_dataset(dataset, video)
    picks = np.linspace(0, len(modalities) - 1, frames).round().astype(int)
    rgb = np.concatenate([modalities[i]["rgb"][::scale, ::scale] for i in picks], axis=1)
    flow = np.concatenate([flow_image(modalities[i]["flow"])[::scale, ::scale] for i in picks], axis=1)
    strip = Image.fromarray(np.concatenate([rgb, flow], axis=0))
    draw = ImageDraw.Draw(strip)
    draw.rectangle((0, 0, 8 + 7 * len(f"{vid}: {label}"), 14), fill=(0, 0, 0))
    draw.text((4, 2), f"{vid}: {label}", fill=(255, 255, 255))
    return np.asarray(strip)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("dataset", type=Path)
    parser.add_argument("videos", nargs="+")
    parser.add_argument("--label", action="append", default=[], help="one per video, in order")
    parser.add_argument("--frames", type=int, default=4)
    parser.add_argument("--scale", type=int, default=2, help="keep every n-th pixel")
    parser.add_argument("--out", type=Path, required=True)
    args = parser.parse_args()
    labels = args.label + [""] * (len(args.videos) - len(args.label))
    rows = [
        video_rows(args.dataset, v, lab, args.frames, args.scale) for v, lab in zip(args.videos, labels, strict=True)
    ]
    gap = np.full((4, rows[0].shape[1], 3), 255, np.uint8)
    sheet = np.concatenate([part for row in rows for part in (row, gap)][:-1], axis=0)
    Image.fromarray(sheet).save(args.out, quality=88)
    print(f"wrote {args.out} ({sheet.shape[1]}×{sheet.shape[0]})")


if __name__ == "__main__":
    main()
