"""What each level of detail of a person costs and changes: one walking person rendered at
several heights on screen with every level, against the full mesh.

For each on-screen height (the person's standing height in pixels) and level: the labelled
pass's time per frame (median of the frames), the share of the full mesh's person pixels
the level covers the same (mask IoU), and the mean absolute raw-RGB difference over the
union of both masks. Run from the repository root:

    .venv/bin/python docs/measure/lod.py [--heights 200,150,100,50,25,12]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from phav_generator.body.model import rest_body
from phav_generator.motion.animation import animate, motion_params
from phav_generator.motion.library import get_motion
from phav_generator.motion.rotations import look_at
from phav_generator.motion.skeleton import forward_kinematics
from phav_generator.render.context import gl_context
from phav_generator.render.gl import Drawable, FrameRenderer
from phav_generator.render.meshes import box
from phav_generator.render.people import LOD_MIN_HEIGHT_PX, person_drawables, person_mesh
from phav_spec.people import Bottom, Hair, Outfit, Phenotype, Top

W, H, F = 340, 256, 260.0
FRAMES = 12
PHENOTYPE = Phenotype(gender=0.3, age=0.75, muscle=0.5, weight=0.5, height=0.3, proportions=0.5)
OUTFIT = Outfit(
    top=Top(kind="short_sleeves", fabric="stripes", rgb=(30, 60, 140), pattern_rgb=(220, 220, 220)),
    bottom=Bottom(kind="trousers", fabric="denim", rgb=(40, 50, 80), pattern_rgb=(60, 70, 110)),
    shoes_rgb=(20, 20, 20),
)
HAIR = Hair(style="short", rgb=(60, 40, 20))


def _walk() -> tuple[np.ndarray, np.ndarray]:
    dims = rest_body(PHENOTYPE).dims
    times = np.arange(FRAMES) / 30.0
    pose = animate(get_motion("walk_forward_01"), times, 0.0, motion_params(1.0, False, 0), dims, (0.0, 0.0, 0.0), 90.0)
    pos, rot = forward_kinematics(dims, pose.root_pos, pose.root_quat, pose.q)
    return pos, rot


def main(heights: list[int]) -> None:
    ctx = gl_context()
    pos, rot = _walk()
    height = rest_body(PHENOTYPE).dims.height_m
    ground = np.eye(4)
    print("| height on screen (px) | level | triangles | labelled pass (ms/frame) | mask IoU vs full "
          "| mean abs raw-RGB diff |")  # fmt: skip
    print("| ---: | ---: | ---: | ---: | ---: | ---: |")
    for px in heights:
        distance = F * height / px
        target = pos[:, 0].mean(axis=0)
        eye = target + np.array([distance, 0.3 * distance, 0.0])
        cam = np.eye(4)
        cam[:3, :3], cam[:3, 3] = look_at(eye, target), eye
        full = None
        for level in range(4):
            person = person_drawables(PHENOTYPE, (224, 172, 105), OUTFIT, HAIR.style, HAIR.rgb, pos, rot, 1, level)
            scene = [Drawable(box((50, 50, 0.01)), np.stack([ground, ground]), 2), *person]
            frames, times = [], []
            with FrameRenderer(ctx, W, H, scene, sky_class=8, supersample=1) as r:
                for f in range(FRAMES):
                    t = time.perf_counter()
                    frames.append(r.render_labels(f, cam, cam, (F, F, W / 2, H / 2)))
                    times.append(time.perf_counter() - t)
            mask = np.stack([fr.instance == 1 for fr in frames])
            rgb = np.stack([fr.colour for fr in frames]).astype(float)
            if full is None:
                full = (mask, rgb)
            union = mask | full[0]
            iou = (mask & full[0]).sum() / max(union.sum(), 1)
            diff = np.abs(rgb - full[1])[union].mean() if union.any() else 0.0
            tris = person_mesh(PHENOTYPE, OUTFIT, level).mesh.n_triangles
            print(f"| {px} | {level} | {tris:,} | {1000 * np.median(times):.2f} | {iou:.3f} | {diff:.1f} |")
    print(f"\nlevels chosen from the tallest height on screen: >= {LOD_MIN_HEIGHT_PX} px -> 0, 1, 2, else 3")


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--heights",
        default="200,150,100,50,25,12",
        help="the person's standing heights on screen (px), comma-separated",
    )
    main([int(h) for h in parser.parse_args().heights.split(",")])
