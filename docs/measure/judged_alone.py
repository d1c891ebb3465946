"""How the judges answer on each object kind alone, at the sizes a frame shows it: every kind
a judge has a class for (PASCAL VOC: cars, buses and furniture, and a table amid chairs;
Cityscapes: the vehicles), three variants from two sides, on a plain floor (the indoor
kinds in front of a wall), seen from 15° up at four distances (docs/realism.md). It tells
an object a judge cannot recognise from one it does not recognise at the size our frames
show it.

    .venv/bin/python docs/measure/judged_alone.py [--kinds sofa,table] [--judges cityscapes] [--threads 2]
    .venv/bin/python docs/measure/judged_alone.py --kinds hatchback,sedan,suv --variants 8 --sides 4

prints, per kind, judge and distance, the object's height on screen, the judge's IoU and
recall on the object's pixels and what it names most of them.
"""

from __future__ import annotations

import argparse
import math
from collections import Counter

import numpy as np
from rich.console import Console
from rich.table import Table
from world_gallery import drawables_of

from phav_generator.render.assets import asset_drawable, turntable_camera
from phav_generator.render.context import gl_context
from phav_generator.render.gl import SPECKLE, Drawable, FrameRenderer
from phav_generator.render.meshes import box, ground
from phav_generator.world import interiors
from phav_generator.world.library import CATALOGUE
from phav_generator.world.parts import Asset
from phav_spec.seeding import stream
from phav_spec.vocab import PIXEL_CLASSES
from phav_validators.realism.judges import load_judges

#: Each kind, the judges that have a class for it and that class (the realism check's mapping).
KINDS = {
    **{body: {"pascal_voc": "car", "cityscapes": "car"} for body in ("hatchback", "sedan", "suv", "van")},
    "truck": {"cityscapes": "truck"}, "bus": {"pascal_voc": "bus", "cityscapes": "bus"},
    "chair": {"pascal_voc": "chair"}, "sofa": {"pascal_voc": "sofa"}, "table": {"pascal_voc": "diningtable"},
    "dining_set": {"pascal_voc": "diningtable"}, "screen": {"pascal_voc": "tvmonitor"},
}  # fmt: skip
#: The dining set's chairs round its table: (x, y) of each in the table's frame, facing it.
CHAIRS_AT = ((-0.45, -0.65), (0.45, -0.65), (-0.45, 0.65), (0.45, 0.65))
#: The judge's classes for things indoors: they stand in front of a wall, the rest under the sky.
INDOORS = ("chair", "sofa", "diningtable", "tvmonitor")
WALL_BEHIND_M = 1.5
#: How much farther than the distance at which the object fills the frame.
FARTHER = (1.0, 2.0, 4.0, 8.0)
WIDTH, HEIGHT = 340, 256
VARIANTS, SIDES = 3, 2
#: The first side seen, in degrees round the object; more sides are spread evenly from it.
FIRST_SIDE_DEG = 35.0


def _behind(asset, cam_to_world: np.ndarray, *, indoors: bool) -> list[Drawable]:
    """A room's wall ``WALL_BEHIND_M`` behind the object, across the camera's view, indoors."""
    if not indoors:
        return []
    lo, hi = asset.bounds()
    away = (lo + hi) / 2 - cam_to_world[:3, 3]
    away[2] = 0.0
    away /= np.linalg.norm(away)
    pose = np.eye(4)
    pose[:3, :3] = np.array([[-away[1], away[0], 0.0], away, [0.0, 0.0, 1.0]]).T
    reach = float(np.linalg.norm(hi[:2] - lo[:2])) / 2
    pose[:3, 3] = (lo + hi) / 2 + away * (reach + WALL_BEHIND_M)
    pose[2, 3] = lo[2] + 1.5
    return [Drawable(box((8.0, 0.05, 1.5)), np.stack([pose, pose]), PIXEL_CLASSES["building"].class_id,
                     colour=(0.78, 0.72, 0.62))]  # fmt: skip


def _subject(kind: str, variant: int) -> tuple[list[Drawable], Asset]:
    """The drawables of ``kind``'s variant and the asset judged: a dining set is a table (the
    one judged) with four chairs drawn round it."""
    rng = stream(7, f"judged/{kind}/{variant}")
    if kind != "dining_set":
        return drawables_of(CATALOGUE[kind][0](rng, 0))
    drawables, table = drawables_of(CATALOGUE["table"][0](rng, 0))
    floor = table.bounds()[0][2]
    for k, (x, y) in enumerate(CHAIRS_AT):
        chair = interiors.chair((0.225, 0.225, 0.45), stream(7, f"judged/{kind}/{variant}/{k}"), 0,
                                front=(0.0, -math.copysign(1.0, y)))  # fmt: skip
        pose = np.eye(4)
        pose[:3, 3] = (x, y, floor + 0.45)
        drawables.append(asset_drawable(chair, np.stack([pose, pose])))
    return drawables, table


def _judged(ctx, judge, kind: str, answer: str, variants: int = VARIANTS, sides: int = SIDES):
    """(farther, object height px, IoU, recall, names) over the variants and sides."""
    classes = judge.classes
    said_id = classes.label_id(answer)
    floor_id = PIXEL_CLASSES["floor"].class_id
    subjects = []  # each variant built once, with the floor it stands on
    for variant in range(variants):
        drawables, asset = _subject(kind, variant)
        under = np.eye(4)
        under[2, 3] = asset.bounds()[0][2]
        floor = Drawable(ground(60.0), np.stack([under, under]), floor_id, colour=(0.52, 0.47, 0.42),
                         pattern=SPECKLE)  # fmt: skip
        subjects.append(([*drawables, floor], asset))
    rows = []
    for farther in FARTHER:
        inter = union = size = 0.0
        heights, names = [], Counter()
        for drawn, asset in subjects:
            lo, hi = asset.bounds()
            for angle in (FIRST_SIDE_DEG + 360.0 * k / sides for k in range(sides)):
                c2w, intrinsics = turntable_camera(asset, angle, fy=1.2 * HEIGHT, height=HEIGHT)
                centre = (lo + hi) / 2
                c2w[:3, 3] = centre + farther * (c2w[:3, 3] - centre)
                intrinsics = (intrinsics[0], intrinsics[1], WIDTH / 2, HEIGHT / 2)
                scene = [*drawn, *_behind(asset, c2w, indoors=answer in INDOORS)]
                with FrameRenderer(ctx, WIDTH, HEIGHT, scene, sky_class=PIXEL_CLASSES["sky"].class_id,
                                   focus=np.zeros(3)) as renderer:  # fmt: skip
                    frame = renderer.render(0, c2w, c2w, intrinsics)
                    labels = judge.labels(frame.rgb)
                    mask = np.isin(frame.class_id, asset.class_ids)
                    said = labels == said_id
                    inter += float((said & mask).sum())
                    union += float((said | mask).sum())
                    size += float(mask.sum())
                    rows_on = np.flatnonzero(mask.any(axis=1))
                    heights.append(int(rows_on[-1] - rows_on[0] + 1) if rows_on.size else 0)
                    names.update(classes.labels[i] for i in labels[mask])
        top = ", ".join(f"{n} {c / max(sum(names.values()), 1):.2f}" for n, c in names.most_common(2))
        rows.append((farther, int(np.median(heights)), inter / max(union, 1.0), inter / max(size, 1.0), top))
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--kinds", default=",".join(KINDS), help="comma-separated")
    parser.add_argument("--judges", default="pascal_voc,cityscapes", help="comma-separated")
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--variants", type=int, default=VARIANTS, help="variants of each kind")
    parser.add_argument("--sides", type=int, default=SIDES, help="sides each is seen from, evenly round it")
    args = parser.parse_args()
    ctx = gl_context()
    segmenters = load_judges(None, args.threads).segmenters
    judges = args.judges.split(",")
    table = Table("kind", "judge", "judged as", "distance", "height (px)", "IoU", "recall", "named most")
    for kind in args.kinds.split(","):
        for name, answer in KINDS[kind].items():
            if name not in judges:
                continue
            for farther, height, iou, recall, top in _judged(
                ctx, segmenters[name], kind, answer, args.variants, args.sides
            ):
                table.add_row(kind, name, answer, f"{farther:g}×", str(height), f"{iou:.2f}", f"{recall:.2f}", top)
    Console(width=140).print(table)


if __name__ == "__main__":
    main()
