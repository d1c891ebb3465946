"""The asset library's objects as drawables: an asset's parts with their classes, materials
and glow; a vehicle's wheels turning as it drives; and a turntable that shows one asset
alone (the gallery in docs/world.md, the tests' "nothing but its classes")."""

from __future__ import annotations

import math
from collections.abc import Sequence

import moderngl
import numpy as np

from phav_generator.motion.rotations import look_at
from phav_generator.render.gl import EMISSIVE, GROUND, MATTE, Drawable, Frame, FrameRenderer, PartLook
from phav_generator.render.meshes import Mesh
from phav_generator.world.parts import LAMP_GLOW, Asset
from phav_generator.world.vehicles import Vehicle
from phav_spec.vocab import PIXEL_CLASSES

#: Classes whose upward faces are ground: they get wet in the rain.
WET_CLASSES = frozenset({"terrain", "road", "floor", "stairs"})
_WET_IDS = np.array(sorted(PIXEL_CLASSES[c].class_id for c in WET_CLASSES))


def asset_mesh(asset: Asset) -> Mesh:
    """An asset's triangles as a renderer mesh."""
    return Mesh(asset.positions, asset.normals, asset.triangles)


def asset_look(asset: Asset, *, lamp_glow: tuple[float, float, float] = (0.0, 0.0, 0.0)) -> PartLook:
    """An asset's per-vertex look: parts that glow are emissive (lamps with ``lamp_glow``),
    ground classes get wet."""
    glowing = asset.glow != 0
    emission = np.zeros((len(asset.glow), 3), dtype=np.float32)
    emission[asset.glow == LAMP_GLOW] = lamp_glow
    lit = glowing & (emission.max(axis=1) > 0.0)
    surfaces = np.where(np.isin(asset.class_ids, _WET_IDS), GROUND, MATTE).astype(np.uint8)
    surfaces[lit] = EMISSIVE
    return PartLook(asset.class_ids, asset.materials, surfaces, asset.colours, emission)


def asset_drawable(
    asset: Asset, transforms: np.ndarray, *, casts_shadow: bool = True, **glow: tuple[float, float, float]
) -> Drawable:
    """A rigid asset with world transforms (F, 4, 4)."""
    return Drawable(asset_mesh(asset), transforms, int(asset.class_ids[0]), 0, casts_shadow=casts_shadow,
                    part_look=asset_look(asset, **glow))  # fmt: skip


def wheel_spin(transforms: np.ndarray, radius: float) -> np.ndarray:
    """How far (radians) a wheel of ``radius`` has turned at each frame, rolling without
    slipping along its vehicle's forward axis (+x of ``transforms`` (F, 4, 4))."""
    step = np.diff(transforms[:, :3, 3], axis=0)
    forward = transforms[:-1, :3, 0]
    travelled = np.concatenate([[0.0], np.cumsum(np.sum(step * forward, axis=1))])
    return travelled / radius


def wheels_drawable(vehicle: Vehicle, transforms: np.ndarray) -> Drawable:
    """A vehicle's wheels as one mesh skinned to one bone per wheel, each turning about its
    axle as the vehicle moves: rigid per wheel, so their flow is exact.

    Bone 0 carries the vehicle's pose without a turn and holds no vertex: the renderer's
    culling follows a skinned mesh's first bone, and the wheels, baked at their axles,
    keep that bone's bounding sphere round all of them (one wheel's, following the front
    wheel, dropped every wheel where the front one left the view)."""
    k, n = len(vehicle.axles), len(vehicle.wheel.positions)
    spin = wheel_spin(transforms, vehicle.wheel_radius)
    # Scalar libm, not numpy's CPU-dispatched cos and sin: the same turn on every CPU.
    angles = spin.tolist()
    c = np.array([math.cos(a) for a in angles])
    s = np.array([math.sin(a) for a in angles])
    turn = np.zeros((len(spin), 4, 4))
    turn[:, 0, 0], turn[:, 0, 2], turn[:, 2, 0], turn[:, 2, 2] = c, s, -s, c  # about +y: forward rolls on
    turn[:, 1, 1] = turn[:, 3, 3] = 1.0
    bones = np.zeros((len(spin), k + 1, 4, 4))
    bones[:, 0] = transforms
    for i, axle in enumerate(vehicle.axles):
        at, back = np.eye(4), np.eye(4)
        at[:3, 3], back[:3, 3] = axle, -np.asarray(axle)
        bones[:, i + 1] = transforms @ at @ turn @ back
    w = vehicle.wheel
    mesh = Mesh(
        np.concatenate([w.positions + np.asarray(axle, dtype=w.positions.dtype) for axle in vehicle.axles]),
        np.tile(w.normals, (k, 1)),
        np.concatenate([w.triangles + i * n for i in range(k)]).astype(np.uint32),
        bones=np.repeat(np.arange(1, k + 1, dtype=np.uint32), n)[:, None] * np.array([1, 0, 0, 0], dtype=np.uint32),
        weights=np.tile(np.array([[1.0, 0.0, 0.0, 0.0]], dtype=np.float32), (k * n, 1)),
    )  # fmt: skip
    tiled = Asset(mesh.positions, mesh.normals, mesh.triangles, np.tile(w.class_ids, k), np.tile(w.materials, k),
                  np.tile(w.colours, (k, 1)), np.tile(w.glow, k), w.parts)  # fmt: skip
    return Drawable(mesh, bones, int(w.class_ids[0]), 0, part_look=asset_look(tiled))


def vehicle_drawables(vehicle: Vehicle, transforms: np.ndarray, **glow: tuple[float, float, float]) -> list[Drawable]:
    """A vehicle's body and its turning wheels."""
    return [asset_drawable(vehicle.body, transforms, **glow), wheels_drawable(vehicle, transforms)]


def turntable_camera(
    asset: Asset,
    angle_deg: float,
    *,
    elevation_deg: float = 15.0,
    fy: float = 300.0,
    height: int = 256,
    zoom: float = 1.0,
) -> tuple[np.ndarray, tuple[float, float, float, float]]:
    """A camera looking at ``asset``'s middle from ``angle_deg`` round it, far enough that its
    bounding sphere fills most of the frame (``zoom`` times closer for a detail):
    (cam_to_world, intrinsics) for a 4:3 frame."""
    lo, hi = asset.bounds()
    centre = (lo + hi) / 2
    radius = float(np.linalg.norm(hi - lo)) / 2
    distance = radius / math.tan(math.atan(height / 2 / fy) * 0.85) / zoom
    a, e = math.radians(angle_deg), math.radians(elevation_deg)
    eye = centre + distance * np.array([math.cos(a) * math.cos(e), math.sin(a) * math.cos(e), math.sin(e)])
    c2w = np.eye(4)
    c2w[:3, :3] = look_at(eye, centre)
    c2w[:3, 3] = eye
    width = height * 4 // 3
    return c2w, (fy, fy, width / 2, height / 2)


def turntable(ctx: moderngl.Context, drawables: list[Drawable], asset: Asset,
              angles: Sequence[float] = (30.0, 120.0, 210.0, 300.0), *, height: int = 192,
              elevation_deg: float = 15.0, zoom: float = 1.0) -> list[Frame]:  # fmt: skip
    """Frames of ``drawables`` (one asset, alone) from ``angles`` round it, seen from
    ``elevation_deg`` above its middle, ``zoom`` times closer than the whole of it needs: a
    list of ``gl.Frame``s with their RGB."""
    width = height * 4 // 3
    frames = []
    with FrameRenderer(ctx, width, height, drawables, sky_class=PIXEL_CLASSES["sky"].class_id,
                       focus=np.zeros(3)) as renderer:  # fmt: skip
        for angle in angles:
            c2w, intrinsics = turntable_camera(asset, angle, elevation_deg=elevation_deg, fy=1.2 * height,
                                               height=height, zoom=zoom)  # fmt: skip
            frames.append(renderer.render(0, c2w, c2w, intrinsics))
    return frames
