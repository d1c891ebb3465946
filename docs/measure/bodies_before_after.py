"""The same recipe before and after the people became anny bodies (README.md): the capsule
renderer's row, as the picture made before the bodies shows it, above this code's render of
the same frame: the whole frame, then the people and their labels zoomed.

    git show f56a250:docs/images/bodies-before-after.png > before.png   # the capsule renderer's row
    .venv/bin/python docs/measure/bodies_before_after.py tests/spec/data/recipe-v1-walk_holding_hands.json \\
        before.png docs/images/bodies-before-after.png

The recipe is the phav-v1 recipe of seed 0, video 0 as released before the bodies (recipe
schema 1; it loads upgraded). The "before" row is the upper half of a picture of this layout
made at f56a250, whose renderer is gone; the "after" row is rendered now.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
from PIL import Image, ImageDraw

from phav_generator.physics.simulate import simulate
from phav_generator.render.context import gl_context
from phav_generator.render.modalities import encode_frame
from phav_generator.render.video import scene_renderer
from phav_spec.recipe import load_recipe

W, H = 340, 256
#: Height of a row's caption strip (px), as in the picture made before.
CAPTION_PX = 16
#: Zoom of the middle and right panels: the people's box, grown by this margin, scaled to a frame.
MARGIN = 0.35


def zoom_box(mask: np.ndarray) -> tuple[int, int, int, int]:
    """A box of the frame's aspect around ``mask``'s pixels, grown by MARGIN, inside the frame."""
    ys, xs = np.nonzero(mask)
    if len(xs) == 0:
        return 0, 0, W, H
    cx, cy = (xs.min() + xs.max()) / 2, (ys.min() + ys.max()) / 2
    h = max((ys.max() - ys.min() + 1), (xs.max() - xs.min() + 1) * H / W) * (1 + 2 * MARGIN)
    h = min(h, H)
    w = h * W / H
    x0 = round(float(min(max(cx - w / 2, 0), W - w)))
    y0 = round(float(min(max(cy - h / 2, 0), H - h)))
    return x0, y0, x0 + round(float(w)), y0 + round(float(h))


def after_row(recipe_path: Path, frame: int) -> Image.Image:
    """The recipe's frame rendered now: RGB, then RGB and semantic labels zoomed on the people."""
    recipe = load_recipe(recipe_path)
    if not 0 <= frame < recipe.n_frames - 1:
        raise SystemExit(f"{recipe_path}: frame {frame} is not in 0 … {recipe.n_frames - 2}")
    trajectory = simulate(recipe, keep_state=False)
    renderer = scene_renderer(recipe, trajectory, gl_context())
    try:
        rendered = renderer.render(frame, trajectory.cam_to_world[frame], trajectory.cam_to_world[frame + 1],
                                   trajectory.intrinsics)  # fmt: skip
    finally:
        renderer.release()
    modalities = encode_frame(rendered)
    rgb, semantic = Image.fromarray(modalities["rgb"]), Image.fromarray(modalities["semantic"])
    box = zoom_box(rendered.instance > 0)
    panels = [rgb, rgb.crop(box).resize((W, H), Image.LANCZOS), semantic.crop(box).resize((W, H), Image.NEAREST)]
    row = Image.new("RGB", (3 * W, H))
    for i, panel in enumerate(panels):
        row.paste(panel, (i * W, 0))
    ImageDraw.Draw(row).text((4, 4), f"frame {frame}", fill=(255, 255, 255))
    return row


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("recipe", type=Path, help="the recipe both rows show")
    parser.add_argument("before", type=Path, help="a picture made before the bodies: its upper row is kept")
    parser.add_argument("out", type=Path)
    parser.add_argument("--frame", type=int, default=30)
    args = parser.parse_args()
    before = Image.open(args.before).convert("RGB")
    if before.size != (3 * W, 2 * (CAPTION_PX + H)):
        raise SystemExit(f"{args.before}: {before.size[0]} × {before.size[1]} px, not a picture of this layout")
    picture = Image.new("RGB", before.size, (255, 255, 255))
    picture.paste(before.crop((0, 0, 3 * W, CAPTION_PX + H)), (0, 0))
    picture.paste(after_row(args.recipe, args.frame), (0, 2 * CAPTION_PX + H))
    ImageDraw.Draw(picture).text(
        (4, CAPTION_PX + H + 2), f"after: anny bodies, dressed, in today's world (same recipe, frame {args.frame}; "
        "middle and right: the people zoomed)", fill=(0, 0, 0))  # fmt: skip
    picture.save(args.out)


if __name__ == "__main__":
    main()
