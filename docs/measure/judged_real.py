"""The Cityscapes judge on real photographs at our frames' size, beside our frames: the
closest real frames to be had offline, for the targets our frames miss (docs/realism-gap.md).
The photographs are OpenCV's sample data, from Debian's opencv-doc package, and Google
Coral's test data: a Cityscapes frame (a street in Germany) and three frames of a highway
video (its ``automl_video_ondevice/traffic_frames``). Neither is shipped:

    apt-get download opencv-doc && dpkg-deb -x opencv-doc_*.deb opencv-doc
    git clone --depth 1 https://github.com/google-coral/test_data coral
    .venv/bin/python docs/measure/judged_real.py opencv-doc/usr/share/doc/opencv-doc/examples/data coral --ours r52

Each photograph is scaled to cover 340 × 256 and centre-cropped, as a frame is; inside boxes
drawn by hand that hold one class only, it prints the share of pixels the judge names as
that class (its recall there), the share PASCAL VOC's judge names so where it judges the
class, and what the street model names most. Photographs in none of the folders given are
listed and left out. With --ours DATASET, the same share
over our frames' pixels of each class at least 4 px from any other class (the realism
check's sample of outdoor frames): all of them, and the clear or overcast daytime ones;
with --dump FOLDER (judged_frames.py --dump) and --group, the same share over its frames
of one condition group (e.g. weather=fog), from the answers stored there.

With --veil T,T,…, each photograph is also judged through fog: Koschmieder's law at one
distance, in linear light, its own light times the transmission T and the fog's airlight
(--airlight, an 8-bit grey: our foggy days' sky) times 1 − T. A real scene under our fog,
as far as one veil over the whole frame stands for it (near things are veiled less).
"""

from __future__ import annotations

import argparse
from collections import Counter, defaultdict
from pathlib import Path

import numpy as np
from judged_frames import dumped
from judged_repaint import display, linear
from PIL import Image

from phav_spec.clips import ClipReader
from phav_spec.judge_classes import CITYSCAPES, PASCAL_VOC
from phav_spec.recipe_table import read_recipe_table
from phav_spec.scene import ENVIRONMENT_SCENES
from phav_spec.vocab import PIXEL_CLASSES
from phav_validators.checks.scan import class_lut, rgb_code
from phav_validators.realism.check import sample_frames
from phav_validators.realism.judges import load_judges

W, H = 340, 256
#: Pixels of margin an interior pixel keeps from any other class, in our frames.
MARGIN_PX = 4
#: Hand-drawn boxes (x0, y0, x1, y1 in the 340 × 256 crop) that hold one class each.
REGIONS: dict[str, list[tuple[str, tuple[int, int, int, int]]]] = {
    "building.jpg": [("building", (120, 20, 330, 150)), ("sky", (5, 80, 45, 135)),
                     ("vegetation", (5, 160, 80, 198)), ("vegetation", (70, 210, 145, 225)),
                     ("terrain", (0, 234, 340, 256))],
    "leuvenA.jpg": [("sky", (100, 5, 220, 70)), ("building", (0, 100, 50, 190)),
                    ("building", (270, 75, 340, 165)), ("road", (0, 210, 240, 256))],
    "leuvenB.jpg": [("sky", (220, 20, 320, 90)), ("building", (0, 90, 170, 170)), ("road", (60, 225, 340, 256))],
    "messi5.jpg": [("person", (125, 100, 180, 165)), ("terrain", (0, 205, 120, 256))],
    "licenseplate_motion.jpg": [("car", (10, 40, 330, 250))],
    # A Cityscapes frame: a red hatchback whole (63 px), a grey estate behind a pole.
    "cityscapes_segmentation.bmp": [("car", (105, 30, 190, 70)), ("car", (262, 28, 320, 62)),
                                    ("road", (0, 110, 340, 256)), ("pole", (198, 0, 204, 60)),
                                    ("vegetation", (60, 3, 100, 18))],
    # A highway from above its verge: a saloon whole (60 px), a pick-up and a white car cut
    # by the frame's right edge.
    "automl_video_ondevice/traffic_frames/0001.bmp": [("car", (80, 170, 155, 205)), ("car", (290, 160, 338, 200)),
                                                      ("car", (320, 210, 340, 240)), ("road", (0, 225, 250, 256))],
    "automl_video_ondevice/traffic_frames/0003.bmp": [("car", (52, 168, 132, 205)), ("car", (275, 160, 338, 198)),
                                                      ("car", (300, 205, 338, 240)), ("road", (0, 225, 250, 256))],
}  # fmt: skip
#: Most-named classes shown per row.
SHOWN = 3


def as_frame(path: Path) -> np.ndarray:
    """A photograph scaled to cover 340 × 256 and centre-cropped: (256, 340, 3) uint8."""
    with Image.open(path) as im:
        im = im.convert("RGB")
        scale = max(W / im.width, H / im.height)
        im = im.resize((round(im.width * scale), round(im.height * scale)), Image.Resampling.LANCZOS)
        left, top = (im.width - W) // 2, (im.height - H) // 2
        return np.asarray(im.crop((left, top, left + W, top + H)))


def found(folders: list[Path], photo: str) -> Path | None:
    """The first of ``folders`` that holds ``photo`` (a path relative to it), joined; None if none does."""
    return next((folder / photo for folder in folders if (folder / photo).is_file()), None)


def veiled(rgb: np.ndarray, transmission: float, airlight: float) -> np.ndarray:
    """``rgb`` seen through fog that lets ``transmission`` of its light through and adds
    the 8-bit grey ``airlight`` for the rest (Koschmieder's law at one distance), in linear light."""
    return display(transmission * linear(rgb) + (1.0 - transmission) * linear(np.float64(airlight)))


def transmissions(text: str) -> list[float]:
    """``--veil``'s comma-separated transmissions, each in (0, 1]."""
    try:
        values = [float(t) for t in text.split(",") if t.strip()]
    except ValueError:
        raise SystemExit(f"--veil {text!r}: comma-separated numbers, as in 0.8,0.6") from None
    if not values or not all(0.0 < t <= 1.0 for t in values):
        raise SystemExit(f"--veil {text!r}: each transmission is in (0, 1]")
    return values


def named(counts: Counter, names: tuple[str, ...]) -> str:
    total = sum(counts.values())
    top = sorted(counts.items(), key=lambda kv: (-kv[1], kv[0]))[:SHOWN]
    return ", ".join(f"{names[k]} {n / total:.2f}" for k, n in top)


def interior(labels: np.ndarray, margin: int) -> np.ndarray:
    """Pixels whose (2·margin + 1)² window holds their label only."""
    padded = np.pad(labels, margin, mode="edge")
    out = np.ones(labels.shape, dtype=bool)
    for dy in range(2 * margin + 1):
        for dx in range(2 * margin + 1):
            out &= padded[dy : dy + labels.shape[0], dx : dx + labels.shape[1]] == labels
    return out


def _targets() -> tuple[list[str], np.ndarray]:
    """The judge classes our classes are judged as, and our class id → index among them (−1: none)."""
    targets = sorted(set(CITYSCAPES.judged_as.values()))
    to_target = np.full(65536, -1, dtype=np.int32)
    for ours, m in CITYSCAPES.judged_as.items():
        to_target[PIXEL_CLASSES[ours].class_id] = targets.index(m)
    return targets, to_target


def _tally(answers: dict[str, Counter], target: np.ndarray, said: np.ndarray, targets: list[str]) -> None:
    """Add the judge's answers ``said`` on the interior pixels of each class of ``target``."""
    inside = interior(target, MARGIN_PX) & (target >= 0)
    for t in np.unique(target[inside]):
        values, counts = np.unique(said[inside & (target == t)], return_counts=True)
        answers[targets[t]].update(dict(zip(values.tolist(), counts.tolist(), strict=True)))


def judge_dump(folder: Path, group: str) -> dict[str, dict[str, Counter]]:
    """As ``judge_ours``, from the frames and Cityscapes answers a ``judged_frames.py --dump``
    stored, over those of condition ``group``."""
    targets, to_target = _targets()
    answers: dict[str, Counter] = defaultdict(Counter)
    for _, where, ours, said in dumped(folder):
        if "cityscapes" in said and group in where:
            _tally(answers, to_target[ours], said["cityscapes"], targets)
    if not answers:
        raise SystemExit(f"{folder}: no judged outdoor frame of {group} (judged_frames.py --dump {folder})")
    return {m: {group: a} for m, a in answers.items()}


def judge_ours(root: Path, segmenter, frames: int) -> dict[str, dict[str, Counter]]:
    """Per judge class and sample ("all", "clear day"): the judge's answers on our interior pixels."""
    targets, to_target = _targets()
    table = read_recipe_table(root / "recipes.parquet")
    looks = {v: (e, w in ("clear", "overcast") and d == "day") for v, e, w, d in zip(
        table.column("video_id"), table.column("environment"), table.column("weather"), table.column("day_phase"),
        strict=True)}  # fmt: skip
    answers: dict[str, dict[str, Counter]] = defaultdict(dict)
    lut = class_lut()[0]
    reader = ClipReader(root)
    try:
        for video, chosen in sample_frames(reader, frames, 0).items():
            environment, clear_day = looks[video]
            if ENVIRONMENT_SCENES[environment].indoor:
                continue
            clip = reader.read(video, chosen, ("rgb", "semantic"))
            for rgb, semantic in zip(clip["rgb"], clip["semantic"], strict=True):
                target = to_target[lut[rgb_code(semantic)]]
                per_class: dict[str, Counter] = defaultdict(Counter)
                _tally(per_class, target, segmenter.labels(rgb), targets)
                for m, counts in per_class.items():
                    for sample in ("all", "clear day") if clear_day else ("all",):
                        answers[m].setdefault(sample, Counter()).update(counts)
    finally:
        reader.close()
    return answers


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("photos", type=Path, nargs="+", help="the photographs' folders (OpenCV's, Coral's)")
    parser.add_argument("--ours", type=Path, help="a dataset: the same figure on its frames")
    parser.add_argument("--frames", type=int, default=400)
    parser.add_argument("--dump", type=Path, help="judged_frames.py --dump's folder: the same figure on its frames")
    parser.add_argument("--group", default="all", help="with --dump: the condition group, e.g. weather=fog")
    parser.add_argument("--veil", default="", help="fog transmissions T,T,… to judge each photograph through")
    parser.add_argument("--airlight", type=float, default=215.0, help="the fog's 8-bit grey (our foggy days' sky)")
    args = parser.parse_args()
    veils = transmissions(args.veil) if args.veil else []
    if not 0.0 <= args.airlight <= 255.0:
        raise SystemExit(f"--airlight {args.airlight}: an 8-bit grey, 0 to 255")
    judges = load_judges(threads=2).segmenters
    segmenter, voc = judges["cityscapes"], judges["pascal_voc"]
    names = segmenter.classes.labels
    through = "".join(f" through fog, T = {t:g} |" for t in veils)
    print(f"| photograph | class | box (x0, y0, x1, y1) | named as the class |{through} VOC | named most |")
    print("| --- | --- | --- | ---: |" + " ---: |" * len(veils) + " ---: | --- |")
    missing = []
    for photo, regions in REGIONS.items():
        path = found(args.photos, photo)
        if path is None:
            missing.append(photo)
            continue
        frame = as_frame(path)
        said, *fogged = (segmenter.labels(f) for f in [frame] + [veiled(frame, t, args.airlight) for t in veils])
        voc_said = voc.labels(frame)
        for m, (x0, y0, x1, y1) in regions:
            inside = said[y0:y1, x0:x1]
            shares = [float(np.isin(s[y0:y1, x0:x1], CITYSCAPES.answer_ids(m)).mean()) for s in (said, *fogged)]
            answers = Counter(dict(zip(*(a.tolist() for a in np.unique(inside, return_counts=True)), strict=True)))
            cells = " | ".join(f"{v:.2f}" for v in shares)
            by_voc = (
                f"{float(np.isin(voc_said[y0:y1, x0:x1], PASCAL_VOC.answer_ids(m)).mean()):.2f}"
                if (m in PASCAL_VOC.labels)
                else ""
            )
            print(f"| {photo} | {m} | {x0}, {y0}, {x1}, {y1} | {cells} | {by_voc} | {named(answers, names)} |")
    if missing:
        print(f"\nNot in {', '.join(str(f) for f in args.photos)}, left out: {', '.join(missing)}")
    if args.ours is None and args.dump is None:
        return
    ours = judge_dump(args.dump, args.group) if args.dump else judge_ours(args.ours, segmenter, args.frames)
    print(f"\n| our class (≥ {MARGIN_PX} px inside) | frames | pixels | named as the class | named most |")
    print("| --- | --- | ---: | ---: | --- |")
    for m, samples in sorted(ours.items()):
        for sample, answers in sorted(samples.items()):
            total = sum(answers.values())
            hit = sum(answers[i] for i in CITYSCAPES.answer_ids(m))
            print(f"| {m} | {sample} | {total:,} | {hit / total:.2f} | {named(answers, names)} |")


if __name__ == "__main__":
    main()
