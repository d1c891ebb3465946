"""The judges on a real object at the sizes our frames show ours: the closest real
photographs to be had offline of a class our frames miss. OpenCV's sample data (Debian's
opencv-doc, see judged_real.py) holds three photographs of an office with a real CRT
monitor in view (left06, right06, left13 of its stereo calibration set); the ultralytics
wheel on PyPI holds a photograph of a real city bus in a Madrid street (its
``assets/bus.jpg``, AGPL-3.0; read here, not shipped). Each is scaled to cover 340 × 256
and centre-cropped, as a frame is, then shrunk to a half and a quarter and tiled to fill
the frame again, so the judge sees the same real object at the heights
docs/measure/judged_alone.py shows ours at. The other way, the photograph of a real car's
back (licenseplate_motion.jpg) is cropped round parts of the car and scaled up to fill the
frame: the car seen closer than whole and cut by the frame's edges, as `car_hit`'s camera
often shows ours.

    pip download --no-deps ultralytics==8.4.190 -d wheels
    unzip -j wheels/ultralytics-8.4.190-py3-none-any.whl ultralytics/assets/bus.jpg
    .venv/bin/python docs/measure/judged_real_small.py opencv-doc/usr/share/doc/opencv-doc/examples/data \\
        [--bus bus.jpg]

prints, per photograph, judge and scale, the height of the hand-drawn box inside the object
and the share of its pixels the judge names as the object's class; then, per crop of the car,
how much of the frame the car fills and the share each judge names `car`.
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
#: A real car's back (OpenCV's sample data) and the box its car fills in the 340 × 256 crop.
CAR, CAR_BOX = "licenseplate_motion.jpg", (10, 40, 330, 250)
#: Crops (x0, y0, x1, y1 of the 340 × 256 frame, its aspect) scaled up to fill the frame.
CLOSER = {
    "whole": (0, 0, 340, 256), "2×, its right middle": (170, 64, 340, 192),
    "2×, its bottom right": (170, 128, 340, 256), "2×, its top left": (0, 0, 170, 128),
    "2×, its middle": (85, 64, 255, 192), "3×, its top right": (226, 0, 340, 85),
}  # fmt: skip


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


def closer(frame: np.ndarray, mask: np.ndarray, crop: tuple[int, int, int, int]) -> tuple[np.ndarray, np.ndarray]:
    """``frame`` cropped to ``crop`` and scaled up to the frame's size, with ``mask`` cut and
    scaled the same way (nearest)."""
    x0, y0, x1, y1 = crop
    image = np.asarray(Image.fromarray(frame[y0:y1, x0:x1]).resize((W, H), Image.Resampling.BILINEAR))
    cut = Image.fromarray(mask[y0:y1, x0:x1].astype(np.uint8)).resize((W, H), Image.Resampling.NEAREST)
    return image, np.asarray(cut).astype(bool)


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
    car, inside = as_frame(args.photos / CAR), boxes(CAR_BOX, 1)
    print(f"\n| {CAR}, seen | the car's share of the frame | PASCAL VOC: named car | Cityscapes: named car |")
    print("| --- | ---: | ---: | ---: |")
    for view, crop in CLOSER.items():
        image, mask = closer(car, inside, crop)
        shares = [float(np.isin(segmenters[j].labels(image)[mask], segmenters[j].classes.answer_ids("car")).mean())
                  for j in ("pascal_voc", "cityscapes")]  # fmt: skip
        print(f"| {view} | {mask.mean():.2f} | {shares[0]:.2f} | {shares[1]:.2f} |")


if __name__ == "__main__":
    main()
