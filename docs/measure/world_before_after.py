"""Before and after, the same recipes: the middle RGB frame of contact sheets made by two
versions of phav, side by side (docs/world.md, README.md).

    git worktree add ../before be2cb92            # the commit before the asset library
    (cd ../before && python -m phav_app.cli sheets --by environment,action --seed 0 --out ../sheets-before)
    phav sheets --by environment,action --seed 0 --out sheets-after
    python docs/measure/world_before_after.py sheets-before sheets-after OUT.jpg --sheets environment-urban,...

The pictures in the docs, "before" being be2cb92's sheets or (the places) 25e2d83's:

    world-environments-before-after.jpg  be2cb92  environment-simple,environment-urban,environment-middle,
                                                   environment-green,environment-lake,environment-stadium,
                                                   environment-house_interior
    world-actions-before-after.jpg       be2cb92  action-car_hit,action-sit,action-push,action-golf,
                                                   action-pour,action-shoot_bow,action-climb_stairs
    world-before-after.jpg               be2cb92  action-car_hit
    world-places-before-after.jpg        25e2d83  environment-urban,environment-middle,environment-stadium,
                                                   environment-simple
    world-parks-before-after.jpg         25e2d83  action-clap,action-crawl,action-hop,action-catch

Each row: one sheet's recipe, before on the left, after on the right, with its name.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
from PIL import Image, ImageDraw

#: The sheets' layout (phav_app.sheets.render_sheet): a caption, then frames of this size.
HEADER_PX = 18
WIDTH, HEIGHT = 340, 256


def middle_frame(sheet: Path) -> np.ndarray:
    """The middle RGB frame of a contact sheet."""
    image = np.asarray(Image.open(sheet).convert("RGB"))
    return image[HEADER_PX : HEADER_PX + HEIGHT, WIDTH : 2 * WIDTH]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("before", type=Path)
    parser.add_argument("after", type=Path)
    parser.add_argument("out", type=Path)
    parser.add_argument("--sheets", required=True, help="comma-separated sheet names, e.g. environment-urban")
    args = parser.parse_args()
    rows = []
    for name in args.sheets.split(","):
        pair = np.concatenate([middle_frame(args.before / f"{name}.jpg"), middle_frame(args.after / f"{name}.jpg")],
                              axis=1)  # fmt: skip
        rows.append(pair)
    image = Image.fromarray(np.concatenate(rows, axis=0))
    draw = ImageDraw.Draw(image)
    for k, name in enumerate(args.sheets.split(",")):
        for x, when in ((4, "before"), (WIDTH + 4, "after")):
            text = f"{name}, {when}"
            draw.rectangle(draw.textbbox((x, k * HEIGHT + 3), text), fill=(0, 0, 0))
            draw.text((x, k * HEIGHT + 3), text, fill=(255, 255, 255))
    image.save(args.out, quality=85)


if __name__ == "__main__":
    main()
