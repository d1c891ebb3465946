"""One recipe per environment in three looks: the environment's fixed look and two videos'
own (θ ``world_variety: video``), the middle frame each, side by side (docs/world.md).

    .venv/bin/python docs/measure/world_looks.py OUT.jpg [--environments urban,middle]

The recipes are the contact sheets' (``phav sheets --by environment --seed 0``); only
``environment.look_seed`` is changed.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import cv2
import numpy as np

from phav_app.sheets import sheet_specs
from phav_generator.physics.simulate import simulate
from phav_generator.render.context import gl_context
from phav_generator.render.modalities import encode_frame
from phav_generator.render.video import scene_renderer
from phav_spec.theta import load_preset

#: The looks shown: the fixed one, then two videos' seeds.
LOOKS = (None, 1, 2)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", type=Path)
    parser.add_argument("--environments", default="urban,middle")
    args = parser.parse_args()
    wanted = args.environments.split(",")
    specs = {s.value: s for s in sheet_specs(load_preset(), 0, ("environment",)) if s.value in wanted}
    ctx = gl_context()
    rows = []
    for env in wanted:
        recipe = specs[env].recipe
        trajectory = simulate(recipe, keep_state=False)
        middle = (recipe.n_frames - 1) // 2
        row = []
        for seed in LOOKS:
            environment = recipe.environment.model_copy(update={"look_seed": seed})
            looked = recipe.model_copy(update={"environment": environment})
            renderer = scene_renderer(looked, trajectory, ctx)
            try:
                frame = renderer.render(middle, trajectory.cam_to_world[middle], trajectory.cam_to_world[middle + 1],
                                        trajectory.intrinsics)  # fmt: skip
            finally:
                renderer.release()
            rgb = np.ascontiguousarray(encode_frame(frame)["rgb"])
            label = f"{env}, " + ("fixed look" if seed is None else f"look_seed {seed}")
            cv2.putText(rgb, label, (4, 14), cv2.FONT_HERSHEY_SIMPLEX, 0.4, (255, 255, 255), 1, cv2.LINE_AA)
            row.append(rgb)
        rows.append(np.concatenate(row, axis=1))
    cv2.imwrite(str(args.out), np.concatenate(rows, axis=0)[..., ::-1], [cv2.IMWRITE_JPEG_QUALITY, 85])


if __name__ == "__main__":
    main()
