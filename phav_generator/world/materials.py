"""Materials of the asset library and the colour palettes they are drawn from.

A material is computed in the scene shader from the surface's position in its object's own
frame (``render/shaders/materials.glsl``): grain, weave, speckle and gloss from integer
hashes, so it sticks to the surface as it moves (exact flow), costs no texture memory and
gives the same bytes on every CPU. The values are the shader's pattern codes (0 plain;
3 and 4 are the ground's speckle and the people's texture images).
"""

from __future__ import annotations

from enum import IntEnum

import numpy as np

RGB = tuple[float, float, float]


class Material(IntEnum):
    """A surface's material: its pattern code in the scene shader."""

    PLAIN = 0  # flat matte paint
    PAINT = 5  # glossy painted metal (car bodies, lamp posts, fridges)
    GLASS = 6  # dark, reflects the sky
    CHROME = 7  # bright, reflects the sky
    RUBBER = 8  # tyres, seals: dark, fine grain
    WOOD = 9  # grain along the object's long axis
    FABRIC = 10  # weave
    LEATHER = 11  # mottled, a little gloss
    PLASTIC = 12  # a little gloss
    CONCRETE = 13  # speckle at two scales
    METAL = 14  # galvanised or brushed metal: streaks, a little gloss
    LEAVES = 15  # foliage: clumps of light and shadow at two scales, hue from yellow to blue green
    GRASS = 16  # blades and patches, greener and drier
    ASPHALT = 17  # dark aggregate, worn patches
    PAVING = 18  # square slabs with joints, a tone per slab
    BRICK = 19  # running bond: bricks with a tone each, mortar joints
    PLASTER = 20  # rendered wall: fine grain, broad stains
    BARK = 21  # furrows along the trunk
    TILES = 22  # roof tiles: courses along the slope
    PITCH = 23  # mown grass: stripes across the pitch
    WALLPAPER = 24  # printed paper: stripes of two tones and a fine print, seams between its lengths
    SEATS = 25  # a stand's row of seats seen from the pitch: moulded shells 0.5 m apart, dark gaps
    FLOOR_TILES = 26  # ceramic floor tiles: 30 cm squares, a tone each, grout joints
    SHORE = 27  # a lake's shore: sand and pebbles, a tone per pebble


#: Car paints, display colours weighted towards what parks on real streets (white, grey,
#: black, silver first).
CAR_PAINTS: tuple[tuple[RGB, float], ...] = (
    ((0.92, 0.92, 0.90), 0.24), ((0.55, 0.56, 0.58), 0.18), ((0.06, 0.06, 0.07), 0.20),
    ((0.75, 0.76, 0.78), 0.12), ((0.55, 0.07, 0.06), 0.08), ((0.10, 0.18, 0.42), 0.08),
    ((0.20, 0.28, 0.22), 0.03), ((0.48, 0.36, 0.22), 0.03), ((0.85, 0.60, 0.10), 0.02),
    ((0.95, 0.95, 0.97), 0.02),
)  # fmt: skip
#: Wood tones: oak, walnut, pine, beech, painted white.
WOODS: tuple[RGB, ...] = ((0.62, 0.45, 0.28), (0.36, 0.23, 0.14), (0.78, 0.62, 0.42), (0.70, 0.52, 0.36),
                          (0.88, 0.86, 0.82))  # fmt: skip
#: Upholstery fabrics.
FABRICS: tuple[RGB, ...] = ((0.45, 0.47, 0.50), (0.30, 0.34, 0.45), (0.58, 0.52, 0.44), (0.35, 0.40, 0.30),
                            (0.55, 0.30, 0.28), (0.70, 0.68, 0.62))  # fmt: skip
#: Leathers: black, brown, tan.
LEATHERS: tuple[RGB, ...] = ((0.08, 0.07, 0.07), (0.30, 0.17, 0.10), (0.55, 0.36, 0.20))
#: Street metal: dark green-grey, black, galvanised grey.
STREET_METALS: tuple[RGB, ...] = ((0.20, 0.24, 0.22), (0.10, 0.10, 0.11), (0.55, 0.57, 0.58))

#: Facades: render and paint (cream, white, grey, ochre, pale blue), brick (red, brown, yellow).
PLASTERS: tuple[RGB, ...] = ((0.86, 0.80, 0.68), (0.90, 0.89, 0.85), (0.66, 0.65, 0.62), (0.80, 0.64, 0.42),
                             (0.70, 0.76, 0.80), (0.78, 0.70, 0.64))  # fmt: skip
BRICKS: tuple[RGB, ...] = ((0.55, 0.25, 0.17), (0.45, 0.30, 0.22), (0.78, 0.66, 0.45))
ROOFS: tuple[RGB, ...] = ((0.22, 0.22, 0.24), (0.52, 0.22, 0.14), (0.36, 0.26, 0.20))
#: A room's walls: paints (white, warm white, grey, sage, pale blue, ochre) and wallpapers.
WALL_PAINTS: tuple[RGB, ...] = ((0.90, 0.89, 0.86), (0.88, 0.84, 0.76), (0.72, 0.72, 0.70), (0.66, 0.72, 0.62),
                                (0.68, 0.76, 0.82), (0.84, 0.72, 0.50))  # fmt: skip
WALLPAPERS: tuple[RGB, ...] = ((0.80, 0.74, 0.62), (0.62, 0.70, 0.66), (0.74, 0.62, 0.60), (0.64, 0.66, 0.76),
                               (0.86, 0.84, 0.78))  # fmt: skip
#: A stadium's seats: blue, red, green, yellow, grey.
SEAT_COLOURS: tuple[RGB, ...] = ((0.08, 0.20, 0.55), (0.62, 0.08, 0.08), (0.10, 0.40, 0.18), (0.85, 0.70, 0.10),
                                 (0.55, 0.56, 0.58))  # fmt: skip
#: Foliage: broadleaf, conifer, birch greens.
LEAF_GREENS: tuple[RGB, ...] = ((0.20, 0.36, 0.10), (0.12, 0.26, 0.10), (0.22, 0.38, 0.13))
#: Hedges and shrubs (privet, box, yew, laurel): darker and bluer than a lawn, as in a photograph.
HEDGE_GREENS: tuple[RGB, ...] = ((0.10, 0.22, 0.09), (0.12, 0.24, 0.12), (0.16, 0.27, 0.10))
#: Bark: grey-olive and dark grey-olive (a street or park tree's bark under its film of algae,
#: as in a photograph, not a picture book's warm brown), birch white.
BARKS: tuple[RGB, ...] = ((0.26, 0.29, 0.19), (0.20, 0.22, 0.14), (0.82, 0.80, 0.76))
GRASS_GREEN: RGB = (0.22, 0.36, 0.12)
#: Asphalt: a worn road's light grey (linear albedo about 0.16), a little warm (its stones'
#: own colours), as in photographs; a darker one read as a car's paint under an overcast sky.
ASPHALT_GREY: RGB = (0.44, 0.43, 0.40)
PAVING_GREY: RGB = (0.50, 0.49, 0.47)
MARKING_WHITE: RGB = (0.85, 0.85, 0.82)
FLOOR_TILE: RGB = (0.78, 0.76, 0.72)
SAND: RGB = (0.50, 0.45, 0.36)
MUD: RGB = (0.28, 0.24, 0.19)
#: What a window shows behind its glass: a dark room, blinds, curtains.
WINDOW_TINTS: tuple[RGB, ...] = ((0.05, 0.06, 0.07), (0.10, 0.11, 0.12), (0.35, 0.33, 0.30), (0.45, 0.40, 0.32))
#: What a shop window shows: a lit interior of goods and shelves, warm or cool.
SHOP_TINTS: tuple[RGB, ...] = ((0.55, 0.50, 0.42), (0.48, 0.48, 0.46), (0.62, 0.55, 0.44), (0.50, 0.46, 0.40))
FRAMES: tuple[RGB, ...] = ((0.92, 0.92, 0.90), (0.15, 0.15, 0.16), (0.40, 0.28, 0.18))

TYRE: RGB = (0.06, 0.06, 0.06)
RIM: RGB = (0.70, 0.71, 0.73)
GLASS_TINT: RGB = (0.10, 0.12, 0.14)
CHROME_TINT: RGB = (0.80, 0.80, 0.82)
HEADLIGHT: RGB = (0.92, 0.92, 0.88)
TAIL_LIGHT: RGB = (0.70, 0.05, 0.04)
PLATE: RGB = (0.93, 0.93, 0.90)
TRIM: RGB = (0.08, 0.08, 0.09)


def pick(options: tuple[RGB, ...], rng: np.random.Generator) -> RGB:
    """One of ``options``, equally likely, from ``rng.integers``."""
    return options[int(rng.integers(0, len(options)))]


def pick_weighted(options: tuple[tuple[RGB, float], ...], rng: np.random.Generator) -> RGB:
    """One of ``options`` ((colour, weight) pairs) by weight, from one uniform double (no numpy
    distribution method, so the draw survives numpy releases)."""
    u = float(rng.random()) * sum(w for _, w in options)
    for colour, weight in options:
        u -= weight
        if u < 0.0:
            return colour
    return options[-1][0]
