"""Clothes as texture images in anny's UV atlas: where each cut covers the body, the fabrics,
and the skirt's own tube.

An outfit is painted once (cached per process) on a texture of ``TEXTURE_SIZE``: anny's
atlas above, a strip for the skirt below. Every texel is a point of a canvas body (an
average adult); its region (skin, top, bottom, shoes) follows the cuts along the limbs
and its fabric the point's rest position divided by the garment's pattern scale. The
canvas is the same for every phenotype, so a garment's pattern stretches with the body
like a printed texture. Texels outside the atlas copy the nearest covered texel, so
filtering and mipmaps never bleed black across seams.
"""

from __future__ import annotations

import functools

import numpy as np

from phav_generator.body.data import BodyData, load_body_data
from phav_generator.body.model import RestBody, at_points, rest_body
from phav_generator.body.uv import atlas_texels
from phav_generator.motion.skeleton import BONE_INDEX, BONES, FIRST_CHILD
from phav_generator.render.gl import linear_colour
from phav_generator.render.meshes import ring_triangles
from phav_spec.people import Garment, Outfit, Phenotype
from phav_spec.vocab import PIXEL_CLASSES

#: How far (0 at the proximal joint, 1 at the distal one) each cut covers its limb.
#: A value ≥ 1 covers the whole body, past its distal joint.
SLEEVES = {"sleeveless": (0.0, 0.0), "short_sleeves": (0.45, 0.0), "long_sleeves": (2.0, 0.92)}
LEGS = {"shorts": (0.45, 0.0), "skirt": (0.55, 0.0), "trousers": (2.0, 0.93)}
#: Shoes reach this far up the shin (share of the shin from the ankle).
SHOE_TOP = 0.06
#: Appearance regions, the values ``regions`` returns.
REGIONS = ("skin", "top", "bottom", "shoes")
#: The body clothes are painted on: an average young adult.
CANVAS = Phenotype(gender=0.5, age=2.0 / 3.0, muscle=0.5, weight=0.5, height=0.5, proportions=0.5)
#: Texels of anny's atlas per side (~3 mm of skin each) and rows of the skirt's strip below
#: it: the texture is ``ATLAS`` wide and ``ATLAS + STRIP`` high.
ATLAS = 512
STRIP = 64
TEXTURE_SIZE = (ATLAS, ATLAS + STRIP)  # width, height
#: A skirt: rings from the waist to this share of the way down the thigh, flaring out by
#: this much at the hem; how much of the hem the thighs carry (the rest follows the pelvis).
SKIRT_LENGTH = 0.6
SKIRT_FLARE = 0.3
SKIRT_THIGH = 0.4
SKIRT_RINGS, SKIRT_AROUND = 6, 24
#: Strip rows below the hem that repeat it: the atlas lies right below the strip, and a mip
#: level's bilinear footprint (8 texels at level 3) would mix its shoes and skin into the hem.
STRIP_PAD = 16


def atlas_uv(uv: np.ndarray) -> np.ndarray:
    """anny's UVs (…, 2) as coordinates of the clothes texture (its atlas above the strip)."""
    return np.stack([uv[..., 0], (STRIP + uv[..., 1] * ATLAS) / (ATLAS + STRIP)], axis=-1)


def _limb_lengths(body: RestBody) -> np.ndarray:
    """Each body's length to its child's joint (1 where it has none)."""
    lengths = np.array([
        -body.dims.offsets[k if FIRST_CHILD[k] is None else FIRST_CHILD[k], 2] if k > 0 else 1.0
        for k in range(len(BONES))
    ])  # fmt: skip
    return np.where(lengths > 1e-6, lengths, 1.0)


def regions(body: RestBody, points: np.ndarray, owner: np.ndarray, outfit: Outfit) -> np.ndarray:
    """The region (index into ``REGIONS``) of points (n, 3) of ``body``'s rest mesh carried
    by the bodies ``owner`` (n,), for an outfit's cuts."""
    local = np.einsum("vij,vi->vj", body.bind.rotations[owner], points - body.bind.heads[owner])
    t = -local[:, 2] / _limb_lengths(body)[owner]  # 0 at the body's joint, 1 at its child's
    kind = np.array([b.name.split("_", 1)[1] if "_" in b.name and b.name[0] in "lr" else b.name for b in BONES])[owner]
    waist = body.bind.heads[0, 2] + 0.05 * body.dims.height_m
    upper_sleeve, lower_sleeve = SLEEVES[outfit.top.kind]
    upper_leg, lower_leg = LEGS[outfit.bottom.kind]

    def cut(limb: str, share: float) -> np.ndarray:
        # A share of 0 covers nothing, not even the limb's skin above its joint (t < 0).
        return (kind == limb) & (t < share) & (share > 0.0)

    top = (kind == "chest") | ((kind == "pelvis") & (points[:, 2] >= waist))
    top |= cut("upper_arm", upper_sleeve) | cut("lower_arm", lower_sleeve)
    bottom = ((kind == "pelvis") & (points[:, 2] < waist)) | cut("upper_leg", upper_leg) | cut("lower_leg", lower_leg)
    shoes = (kind == "foot") | ((kind == "lower_leg") & (t > 1.0 - SHOE_TOP))
    out = np.zeros(len(points), dtype=np.int64)
    out[top], out[bottom], out[shoes] = 1, 2, 3
    return out


def skirt(body: RestBody, owner: np.ndarray):
    """A skirt's tube around the hips and thighs: each ring the body's cross-section there,
    widened; skinned to the pelvis and, towards the hem, to the thigh on its side. Returns
    positions, normals, triangles, bones, weights and pixel classes of its
    ``SKIRT_RINGS`` × (``SKIRT_AROUND`` + 1) vertices (the last column closes the ring at
    the texture's seam)."""
    heads, h = body.bind.heads, body.dims.height_m
    left, right = BONE_INDEX["left_upper_leg"], BONE_INDEX["right_upper_leg"]
    waist = heads[0, 2] + 0.05 * h
    hem = heads[left, 2] - SKIRT_LENGTH * (heads[left, 2] - heads[BONE_INDEX["left_lower_leg"], 2])
    trunk = body.vertices[np.isin(owner, (BONE_INDEX["pelvis"], BONE_INDEX["chest"], left, right))]
    angles = 2.0 * np.pi * np.arange(SKIRT_AROUND + 1) / SKIRT_AROUND
    positions, normals, weights, sides = [], [], [], []
    for t in np.linspace(0.0, 1.0, SKIRT_RINGS):
        z = waist + t * (hem - waist)
        # The trunk's vertices nearest this height (a band; enough of them on a coarse mesh).
        band = trunk[np.argsort(np.abs(trunk[:, 2] - z), kind="stable")[: max(12, len(trunk) // 60)]]
        lo, hi = band[:, :2].min(axis=0), band[:, :2].max(axis=0)
        centre, axes = (lo + hi) / 2.0, (hi - lo) / 2.0 * (1.04 + SKIRT_FLARE * t)
        for a in angles:
            c, s = np.cos(a), np.sin(a)
            positions.append((centre[0] + axes[0] * c, centre[1] + axes[1] * s, z))
            n = np.array([c / axes[0], s / axes[1], 0.0])
            normals.append(n / np.linalg.norm(n))
            thigh = SKIRT_THIGH * t
            weights.append((1.0 - thigh, thigh * (1.0 + s) / 2.0, thigh * (1.0 - s) / 2.0, 0.0))
            sides.append((s >= 0.0, t))
    # Per vertex: a triangle across the left/right or hip/thigh line takes its last corner's
    # class (the shader's flat value), colour and label alike.
    names = [("left" if is_left else "right") + ("_hip" if t < 0.5 else "_upper_leg") for is_left, t in sides]
    classes = np.array([PIXEL_CLASSES[n].class_id for n in names], dtype=np.uint16)
    n = len(positions)
    bones = np.tile(np.array([BONE_INDEX["pelvis"], left, right, BONE_INDEX["pelvis"]], dtype=np.uint32), (n, 1))
    tris = ring_triangles(SKIRT_RINGS, SKIRT_AROUND + 1, closed=False)
    return np.array(positions), np.array(normals), tris, bones, np.array(weights), classes


def skirt_uv() -> np.ndarray:
    """Texture coordinates (n, 2) of the skirt's vertices in the strip below the atlas."""
    u = np.arange(SKIRT_AROUND + 1) / SKIRT_AROUND
    v = (0.5 + np.linspace(0.0, 1.0, SKIRT_RINGS) * (STRIP - 1.0 - STRIP_PAD)) / (ATLAS + STRIP)
    return np.stack(np.meshgrid(u, v), axis=-1).reshape(-1, 2)


@functools.lru_cache(maxsize=1)
def _canvas_texels(data: BodyData) -> tuple[RestBody, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The canvas body, its covered atlas texels' points and bodies, the skirt strip's
    points (row-major, ``STRIP`` × ``ATLAS``) and every atlas texel's source texel, of the
    body ``data``."""
    body = rest_body(CANVAS)
    faces, bary, source = atlas_texels(ATLAS, ATLAS)
    corners = body.faces[faces]

    def at(values: np.ndarray) -> np.ndarray:
        return at_points(values, corners, bary)

    owner = np.argmax(at(body.weights), axis=1)
    # The skirt strip: the tube's rest positions, bilinear between its rings and columns.
    tube = skirt(body, np.argmax(body.weights, axis=1))[0].reshape(SKIRT_RINGS, SKIRT_AROUND + 1, 3)
    # Texel row r: ring r / (STRIP − 1 − STRIP_PAD), as skirt_uv; the rows below repeat the hem.
    y = np.minimum(np.arange(STRIP) / (STRIP - 1.0 - STRIP_PAD), 1.0) * (SKIRT_RINGS - 1)
    x = (np.arange(ATLAS) + 0.5) / ATLAS * SKIRT_AROUND  # texel centres: columns round the ring
    y0 = np.clip(np.floor(y).astype(int), 0, SKIRT_RINGS - 2)
    x0 = np.clip(np.floor(x).astype(int), 0, SKIRT_AROUND - 1)
    fy, fx = np.clip(y - y0, 0.0, 1.0)[:, None, None], (x - x0)[None, :, None]
    strip = ((1 - fy) * ((1 - fx) * tube[y0][:, x0] + fx * tube[y0][:, x0 + 1])
             + fy * ((1 - fx) * tube[y0 + 1][:, x0] + fx * tube[y0 + 1][:, x0 + 1]))  # fmt: skip
    return body, at(body.vertices), owner, strip.reshape(-1, 3), source


def _hash(cells: np.ndarray) -> np.ndarray:
    """A value in [0, 1) per integer cell (n, 3): an integer hash, the same on every CPU."""
    c = cells.astype(np.int64).astype(np.uint64)
    h = c[:, 0] * np.uint64(73856093) ^ c[:, 1] * np.uint64(19349663) ^ c[:, 2] * np.uint64(83492791)
    h = (h ^ (h >> np.uint64(13))) * np.uint64(0x5BD1E995) & np.uint64(0xFFFFFFFF)
    h ^= h >> np.uint64(15)
    return h.astype(np.float64) / 2.0**32


def fabric(garment: Garment, points: np.ndarray) -> np.ndarray:
    """How much of the pattern colour (0–1) shows at rest points (n, 3) of a garment."""
    p = points / garment.scale
    if garment.fabric == "stripes":  # horizontal stripes round the body, 7 cm
        return (np.mod(p[:, 2] * 14.0, 1.0) >= 0.5).astype(np.float64)
    if garment.fabric == "checks":  # woven 8 cm checks: bands across and along, darkest where they cross
        q = np.floor(p * 12.0).astype(np.int64)
        across = np.mod(q[:, 2], 2)
        along = np.mod(q[:, 0] + q[:, 1], 2)
        return 0.5 * (across + along).astype(np.float64)
    if garment.fabric == "denim":  # a mottled fade in 2.5 cm cells and a fine grain
        return 0.175 + 0.3 * _hash(np.floor(p * 40.0)) + 0.1 * _hash(np.floor(p * 250.0))
    if garment.fabric == "print":  # dots on a 6 cm lattice
        q = np.mod(p * 16.0, 1.0) - 0.5
        return (np.sqrt((q * q).sum(axis=1)) < 0.28).astype(np.float64)
    return np.zeros(len(points))


def _linear(rgb) -> np.ndarray:
    """Display colours 0–255 as the shader's linear colours."""
    return linear_colour(np.asarray(rgb, dtype=np.float64) / 255.0)


def outfit_texture(outfit: Outfit, skin_rgb: tuple[int, int, int]) -> np.ndarray:
    """The clothes texture of an outfit over a skin colour: (height, width, 3) float16 linear
    colours, row 0 at v = 0 (cached per process and body data: a few tens of ms)."""
    return _outfit_texture(outfit, skin_rgb, load_body_data())


@functools.lru_cache(maxsize=64)
def _outfit_texture(outfit: Outfit, skin_rgb: tuple[int, int, int], data: BodyData) -> np.ndarray:
    body, points, owner, strip, source = _canvas_texels(data)
    region = regions(body, points, owner, outfit)
    colours = np.zeros((len(points), 3))
    colours[region == 0] = _linear(skin_rgb)
    colours[region == 3] = _linear(outfit.shoes_rgb)
    for index, garment in ((1, outfit.top), (2, outfit.bottom)):
        on = region == index
        mix = fabric(garment, points[on])[:, None]
        colours[on] = (1.0 - mix) * _linear(garment.rgb) + mix * _linear(garment.pattern_rgb)
    mix = fabric(outfit.bottom, strip)[:, None]
    skirt_colours = (1.0 - mix) * _linear(outfit.bottom.rgb) + mix * _linear(outfit.bottom.pattern_rgb)
    image = np.concatenate([skirt_colours, colours[source]]).reshape(ATLAS + STRIP, ATLAS, 3)
    image = np.ascontiguousarray(image, dtype=np.float16)
    image.flags.writeable = False  # shared by the cache
    return image


__all__ = [
    "ATLAS",
    "CANVAS",
    "REGIONS",
    "TEXTURE_SIZE",
    "atlas_uv",
    "fabric",
    "outfit_texture",
    "regions",
    "skirt",
    "skirt_uv",
]
