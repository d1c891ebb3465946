"""The asset library's gallery: every kind of object alone on a turntable, three variants
each from two sides, RGB above its semantic labels (docs/world.md).

    .venv/bin/python docs/measure/world_gallery.py docs/images/world [--pages buildings,trees]

writes one JPEG per page of kinds (all pages, or those named) into the folder and prints
each kind's triangles per level.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import cv2
import numpy as np

from phav_generator.render.assets import asset_drawable, turntable, vehicle_drawables
from phav_generator.render.context import gl_context
from phav_generator.world.library import CATALOGUE
from phav_generator.world.parts import LEVELS
from phav_generator.world.vehicles import Vehicle
from phav_spec.seeding import stream
from phav_spec.vocab import PIXEL_CLASSES

_STILL = np.broadcast_to(np.eye(4), (2, 4, 4))

#: The gallery's pages: kinds of the library's catalogue, each in three variants.
PAGES = {
    "cars": ("hatchback", "sedan", "suv", "van"),
    "trucks_buses": ("truck", "bus"),
    "street": ("lamp_post", "traffic_light", "traffic_sign", "floodlight_head", "bench_seat", "bench_back",
               "guard_rail"),
    "seating": ("chair", "chair_back", "sofa", "table", "bed"),
    "room": ("bookcase", "cabinet", "screen", "fridge", "fireplace", "table_lamp", "lamp_shade"),
    "fittings": ("door", "window", "curtain", "step"),
    "props": ("ball", "baseball_bat", "golf_club", "bow", "hair_brush", "cup", "bottle", "gun", "crate",
              "shopping_cart", "door_leaf", "pull_up_bar"),
    "buildings": ("urban_block", "suburban_house", "stadium_wall"),
    "facades": ("urban_block",),
    "trees": ("broadleaf_crown", "conifer_crown", "birch_crown", "trunk", "birch_trunk"),
    "plants": ("hedge", "bush", "planter", "reeds"),
    "ground": ("carriageway", "pavement", "grass_terrace", "lake_bank", "pitch"),
    "rooms_stands": ("room_wall", "ceiling", "stand_tier", "goal_bar"),
}  # fmt: skip
VARIANTS = 3
ANGLES = (35.0, 215.0)
#: Pages seen from higher up than the usual 15°: the flat slabs and grounds.
ELEVATION = {"ground": 55.0}
#: Pages seen closer than the whole object (zoom, frame height, angles): the urban blocks'
#: storeys, from the side the depth of their openings shows.
ZOOM = {"facades": (1.6, 300, (30.0, 210.0))}


def drawables_of(built):
    """A built object's drawables, standing still."""
    if isinstance(built, Vehicle):
        return vehicle_drawables(built, _STILL), built.body
    return [asset_drawable(built, _STILL, lamp_glow=(1.0, 0.8, 0.5))], built


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", type=Path)
    parser.add_argument("--pages", default=",".join(PAGES), help=f"comma-separated, of {', '.join(PAGES)}")
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    ctx = gl_context()
    palette = np.array([PIXEL_CLASSES[n].rgb for n in PIXEL_CLASSES.names], dtype=np.uint8)
    for page in args.pages.split(","):
        kinds = PAGES[page]
        rows = []
        for kind in kinds:
            build, _ = CATALOGUE[kind]
            rgb, labels = [], []
            for variant in range(VARIANTS):
                drawables, asset = drawables_of(build(stream(7, f"gallery/{kind}/{variant}"), 0))
                zoom, height, angles = ZOOM.get(page, (1.0, 120, ANGLES))
                frames = turntable(ctx, drawables, asset, angles, height=height, zoom=zoom,
                                   elevation_deg=ELEVATION.get(page, 15.0))  # fmt: skip
                rgb += [f.rgb for f in frames]
                labels += [palette[f.class_id] for f in frames]
            rows += [np.concatenate(rgb, axis=1), np.concatenate(labels, axis=1)]
            levels = [build(stream(7, f"gallery/{kind}/0"), level).n_triangles for level in range(LEVELS)]
            print(f"{kind}: triangles at levels 0-{LEVELS - 1}: {levels}")
        sheet = np.concatenate(rows, axis=0)[..., ::-1]
        cv2.imwrite(str(args.out / f"{page}.jpg"), sheet, [cv2.IMWRITE_JPEG_QUALITY, 85])


if __name__ == "__main__":
    main()
