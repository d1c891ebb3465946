"""What the Cityscapes judge makes of our judged frames repainted (docs/realism-gap.md): each
repaint changes the pixels of a ``judged_frames.py --dump`` (the whole frame, or only where
our truth says sky), the judge looks again, and the realism check scores it as it scores a
dataset. It answers "what would the judge need to see?" in seconds a repaint, before any
renderer change is worth making; a repaint is not a render (the sky's light does not reach
the ground here), so a change it favours is measured again by rendering it.

    .venv/bin/python docs/measure/judged_frames.py --dump judged
    .venv/bin/python docs/measure/judged_repaint.py judged none sky-tint:0.12 tint:0.12 [--group weather=overcast]

Repaints, in linear light (the renderer's 2.2 display curve undone, then applied again):

- ``none``: the frames as rendered;
- ``tint:T``: the whole frame's red × (1 − T), blue × (1 + T): a cooler light;
- ``sky-tint:T``: the same, on our sky only;
- ``sky-gain:G``: our sky G times brighter (clipped at white);
- ``sky-grey:V``: our sky one flat grey of 8-bit value V;
- ``gain:G``: the whole frame G times brighter (clipped at white);
- ``grass-chroma:S``: our grass's colour S times as far from its grey (its luminance kept);
- ``dehaze:A``: the share A of the frame's airlight taken out (the median colour of our sky,
  or the frame's brightest without one) and the rest stretched back, as a dehazer does.
"""

from __future__ import annotations

import argparse
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from judged_frames import dump_files

from phav_spec.judge_classes import JUDGE_CLASSES
from phav_spec.vocab import PIXEL_CLASSES
from phav_validators.realism.check import Tally, cityscapes_miou, judge_world

JUDGE = "cityscapes"
_SKY = PIXEL_CLASSES["sky"].class_id
_GRASS = PIXEL_CLASSES["terrain"].class_id
_GAMMA = 2.2
_LUMINANCE = np.array([0.2126, 0.7152, 0.0722])
#: Sky pixels a frame needs for its airlight to be its sky's median colour.
_SKY_FOR_AIRLIGHT = 500

Repaint = Callable[[np.ndarray, np.ndarray], np.ndarray]


@dataclass(frozen=True)
class Painted:
    """One dumped frame's pixels, our class ids and groups."""

    video: str
    rgb: np.ndarray
    ours: np.ndarray
    groups: tuple[str, ...]


def linear(rgb: np.ndarray) -> np.ndarray:
    """8-bit display values in linear light (the renderer's 2.2 curve undone)."""
    return (rgb.astype(np.float64) / 255.0) ** _GAMMA


def display(x: np.ndarray) -> np.ndarray:
    """Linear light back to 8-bit display values, clipped to [0, 1] first."""
    return np.floor(255.0 * np.clip(x, 0.0, 1.0) ** (1.0 / _GAMMA) + 0.5).astype(np.uint8)


def _where(sky_only: bool, change: Callable[[np.ndarray], np.ndarray]) -> Repaint:
    def paint(rgb: np.ndarray, ours: np.ndarray) -> np.ndarray:
        out = display(change(linear(rgb)))
        if sky_only:
            out = np.where((ours == _SKY)[..., None], out, rgb)
        return out

    return paint


def _grass_chroma(scale: float) -> Repaint:
    def paint(rgb: np.ndarray, ours: np.ndarray) -> np.ndarray:
        x = linear(rgb)
        grey = (x @ _LUMINANCE)[..., None]
        return np.where((ours == _GRASS)[..., None], display(grey + scale * (x - grey)), rgb)

    return paint


def _dehaze(share: float) -> Repaint:
    def paint(rgb: np.ndarray, ours: np.ndarray) -> np.ndarray:
        x = linear(rgb)
        sky = ours == _SKY
        if sky.sum() >= _SKY_FOR_AIRLIGHT:
            airlight = np.median(x[sky], axis=0)
        else:
            pixels = x.reshape(-1, 3)
            airlight = pixels[np.argmax(pixels @ _LUMINANCE)]
        return display((x - share * airlight) / (1.0 - share))

    return paint


def repaint(spec: str) -> Repaint:
    """The repaint ``spec`` names (``none``, ``tint:T``, ``sky-tint:T``, ``sky-gain:G``,
    ``sky-grey:V``, ``gain:G``, ``grass-chroma:S``, ``dehaze:A``; the module doc says what
    each does)."""
    name, _, arg = spec.partition(":")
    if name == "none" and not arg:
        return lambda rgb, ours: rgb
    try:
        value = float(arg)
    except ValueError:
        raise SystemExit(f"repaint {spec!r}: {name} takes a number, as in {name}:0.1") from None
    if name in ("tint", "sky-tint"):
        if not 0.0 <= value < 1.0:
            raise SystemExit(f"repaint {spec!r}: a tint is in [0, 1)")
        gains = np.array([1.0 - value, 1.0, 1.0 + value])
        return _where(name == "sky-tint", lambda x: x * gains)
    if name == "sky-gain":
        if value <= 0.0:
            raise SystemExit(f"repaint {spec!r}: a gain is above 0")
        return _where(True, lambda x: x * value)
    if name == "sky-grey":
        if not 0.0 <= value <= 255.0:
            raise SystemExit(f"repaint {spec!r}: a grey is an 8-bit value, 0 to 255")
        return _where(True, lambda x: np.full_like(x, (value / 255.0) ** _GAMMA))
    if name == "gain":
        if value <= 0.0:
            raise SystemExit(f"repaint {spec!r}: a gain is above 0")
        return _where(False, lambda x: x * value)
    if name == "grass-chroma":
        if value < 0.0:
            raise SystemExit(f"repaint {spec!r}: a chroma scale is 0 (grey) or above")
        return _grass_chroma(value)
    if name == "dehaze":
        if not 0.0 <= value < 1.0:
            raise SystemExit(f"repaint {spec!r}: a dehaze's share is in [0, 1)")
        return _dehaze(value)
    raise SystemExit(f"repaint {spec!r}: not one of none, tint:T, sky-tint:T, sky-gain:G, sky-grey:V, gain:G, "
                     "grass-chroma:S, dehaze:A")  # fmt: skip


def scores(frames: Iterable[Painted], paint: Repaint, labels: Callable[[np.ndarray], np.ndarray],
           group: str) -> tuple[float, dict[str, float]]:  # fmt: skip
    """The Cityscapes mIoU and each judge class's IoU over ``group``'s frames, each repainted
    and labelled by ``labels`` (the judge's answer ids); nan where the group has no frame."""
    judge = JUDGE_CLASSES[JUDGE]
    tally = Tally()
    for f in frames:
        if group in f.groups:
            rgb = np.ascontiguousarray(paint(f.rgb, f.ours))
            judge_world(labels(rgb), f.ours, judge, tally, f.video, f.groups)
    miou = cityscapes_miou(tally, 0, group)
    prefix, suffix = f"class_iou|{JUDGE}|", f"|{group}"
    classes = {}
    for key in sorted(tally.parts):
        if key.startswith(prefix) and key.endswith(suffix) and (figure := tally.figure(key, 0)) is not None:
            classes[key[len(prefix) : -len(suffix)]] = figure.value
    return (miou.value if miou is not None else float("nan")), classes


def read(folder: Path) -> list[Painted]:
    """The frames ``judged_frames.py --dump`` wrote that the Cityscapes judge saw (outdoors:
    the check does not judge a room by a street model), with their pixels."""
    frames = []
    for path in dump_files(folder):
        with np.load(path) as z:
            if "said" in z:
                frames.append(Painted(path.stem.split("-")[0], z["rgb"], z["ours"], tuple(str(g) for g in z["where"])))
    return frames


def table(rows: Sequence[tuple[str, float, dict[str, float]]]) -> str:
    """Markdown: one row per repaint, the mIoU and each class's IoU."""
    names = sorted({c for _, _, classes in rows for c in classes})
    out = ["| repaint | mIoU | " + " | ".join(names) + " |", "| --- | ---: |" + " ---: |" * len(names)]
    for spec, miou, classes in rows:
        cells = " | ".join(f"{classes[c]:.2f}" if c in classes else "" for c in names)
        out.append(f"| {spec} | {miou:.3f} | {cells} |")
    return "\n".join(out)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("dump", type=Path, help="the folder judged_frames.py --dump wrote")
    parser.add_argument("repaints", nargs="+", help="none, tint:T, sky-tint:T, sky-gain:G, sky-grey:V, gain:G, "
                        "grass-chroma:S, dehaze:A (the module doc says what each does)")  # fmt: skip
    parser.add_argument("--group", default="all", help="only the frames of this group, e.g. weather=rain")
    args = parser.parse_args()
    paints = [(spec, repaint(spec)) for spec in args.repaints]  # every spec checked before judging
    frames = read(args.dump)
    from phav_validators.realism.judges import load_judges  # the judges load only once the input is good

    segmenter = load_judges().segmenters[JUDGE]
    n = sum(args.group in f.groups for f in frames)
    print(f"{n} frames of {args.group}")
    print(table([(spec, *scores(frames, paint, segmenter.labels, args.group)) for spec, paint in paints]))


if __name__ == "__main__":
    main()
