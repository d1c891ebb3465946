"""The PASCAL VOC judge on a real object at the sizes our frames show ours: the closest real
photographs to be had offline of a class our frames miss. OpenCV's sample data (Debian's
opencv-doc, see judged_real.py) holds three photographs of an office with a real CRT
monitor in view (left06, right06, left13 of its stereo calibration set). Each is scaled to
cover 340 × 256 and centre-cropped, as a frame is, then shrunk to a half and a quarter and
tiled to fill the frame again, so the judge sees the same real monitor at the heights
docs/measure/judged_alone.py shows ours at.

    .venv/bin/python docs/measure/judged_real_small.py opencv-doc/usr/share/doc/opencv-doc/examples/data

prints, per photograph and scale, the height of the hand-drawn box inside the monitor and
the share of its pixels the judge names `tvmonitor`.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
from judged_real import H, W, as_frame
from PIL import Image

from phav_validators.realism.judges import load_judges

#: Boxes (x0, y0, x1, y1 in the 340 × 256 crop) inside the monitor of each photograph.
MONITORS = {"left06.jpg": (3, 90, 70, 185), "right06.jpg": (2, 95, 45, 200), "left13.jpg": (2, 100, 55, 200)}
#: Each photograph at full size, at a half and at a quarter, tiled k × k.
TILES = (1, 2, 4)


def tiled(frame: np.ndarray, k: int) -> np.ndarray:
    """``frame`` shrunk k times (area-averaged) and repeated k × k times: the same frame size."""
    small = np.asarray(Image.fromarray(frame).resize((W // k, H // k), Image.Resampling.BOX))
    out = np.zeros_like(frame)
    out[: k * (H // k), : k * (W // k)] = np.tile(small, (k, k, 1))
    return out


def boxes(box: tuple[int, int, int, int], k: int) -> np.ndarray:
    """The mask of ``box`` in every tile of a k × k tiling."""
    x0, y0, x1, y1 = box
    mask = np.zeros((H, W), dtype=bool)
    for i in range(k):
        for j in range(k):
            top, left = i * (H // k), j * (W // k)
            mask[top + y0 // k : top + y1 // k, left + x0 // k : left + x1 // k] = True
    return mask


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("photos", type=Path, help="the directory of OpenCV's sample data")
    args = parser.parse_args()
    segmenter = load_judges(threads=2).segmenters["pascal_voc"]
    monitor = segmenter.classes.label_id("tvmonitor")
    print("| photograph | scale | box height (px) | named `tvmonitor` |")
    print("| --- | --- | ---: | ---: |")
    for photo, box in MONITORS.items():
        frame = as_frame(args.photos / photo)
        for k in TILES:
            said = segmenter.labels(np.ascontiguousarray(tiled(frame, k)))
            share = float((said[boxes(box, k)] == monitor).mean())
            print(f"| {photo} | 1/{k} | {(box[3] - box[1]) // k} | {share:.2f} |")


if __name__ == "__main__":
    main()
