"""The judges on a real object at the sizes our frames show ours: the closest real
photographs to be had offline of a class our frames miss. OpenCV's sample data (Debian's
opencv-doc, see judged_real.py) holds three photographs of an office with a real CRT
monitor in view (left06, right06, left13 of its stereo calibration set); the ultralytics
wheel on PyPI holds a photograph of a real city bus in a Madrid street (its
``assets/bus.jpg``, AGPL-3.0; read here, not shipped). Each is scaled to cover 340 × 256
and centre-cropped, as a frame is, then shrunk to a half and a quarter and tiled to fill
the frame again, so the judge sees the same real object at the heights
docs/measure/judged_alone.py shows ours at.

    pip download --no-deps ultralytics==8.4.190 -d wheels
    unzip -j wheels/ultralytics-8.4.190-py3-none-any.whl ultralytics/assets/bus.jpg
    .venv/bin/python docs/measure/judged_real_small.py opencv-doc/usr/share/doc/opencv-doc/examples/data \\
        [--bus bus.jpg]

prints, per photograph, judge and scale, the height of the hand-drawn box inside the object
and the share of its pixels the judge names as the object's class.
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
#: A box inside the bus's side, above the people before it and below its roof.
BUS = (165, 40, 320, 165)
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
    parser.add_argument("--bus", type=Path, help="ultralytics' assets/bus.jpg")
    args = parser.parse_args()
    segmenters = load_judges(threads=2).segmenters
    shown = [(args.photos / photo, "pascal_voc", "tvmonitor", box) for photo, box in MONITORS.items()]
    if args.bus:
        shown += [(args.bus, judge, "bus", BUS) for judge in ("pascal_voc", "cityscapes")]
    print("| photograph | judge | class | scale | box height (px) | named as the class |")
    print("| --- | --- | --- | --- | ---: | ---: |")
    for path, judge, name, box in shown:
        segmenter = segmenters[judge]
        frame = as_frame(path)
        for k in TILES:
            said = segmenter.labels(np.ascontiguousarray(tiled(frame, k)))
            share = float(np.isin(said[boxes(box, k)], segmenter.classes.answer_ids(name)).mean())
            print(f"| {path.name} | {judge} | {name} | 1/{k} | {(box[3] - box[1]) // k} | {share:.2f} |")


if __name__ == "__main__":
    main()
