"""Skeleton previews: a contact sheet of stick figures seen through the recipe's camera.

No renderer needed: the trajectory's body origins are projected with the trajectory's own
camera (DESIGN.md's pinhole convention), so a sheet shows what the video will frame, where
the camera flies and whether the physics did what the action says.
"""

from __future__ import annotations

import itertools

import numpy as np
from PIL import Image, ImageDraw

from phav_generator.physics.trajectory import Trajectory
from phav_generator.skeleton import BONES, PARENTS

_ROLE_COLOURS = {"protagonist": (220, 40, 40), "supporting": (40, 90, 220), "background": (120, 120, 120)}


def project(points: np.ndarray, cam_to_world: np.ndarray, intrinsics: tuple[float, float, float, float]) -> np.ndarray:
    """Pixel coordinates (…, 2) of world points (…, 3); NaN for points behind the camera.

    The camera looks down −Z with +Y up; pixel (u, v) covers [u, u + 1) × [v, v + 1).
    """
    fx, fy, cx, cy = intrinsics
    r = cam_to_world[:3, :3]
    t = cam_to_world[:3, 3]
    local = (np.asarray(points) - t) @ r
    depth = -local[..., 2]
    with np.errstate(divide="ignore", invalid="ignore"):
        u = fx * local[..., 0] / depth + cx
        v = -fy * local[..., 1] / depth + cy
    out = np.stack([u, v], axis=-1)
    out[depth <= 1e-3] = np.nan
    return out


def _ground_grid(draw: ImageDraw.ImageDraw, cam: np.ndarray, intr, centre: np.ndarray, z: float) -> None:
    for k in range(-5, 6):
        for a, b in (((k, -5), (k, 5)), ((-5, k), (5, k))):
            pa = np.array([centre[0] + a[0], centre[1] + a[1], z])
            pb = np.array([centre[0] + b[0], centre[1] + b[1], z])
            seg = np.linspace(pa, pb, 20)
            px = project(seg, cam, intr)
            for p, q in itertools.pairwise(px):
                if np.all(np.isfinite(p)) and np.all(np.isfinite(q)):
                    draw.line([tuple(p), tuple(q)], fill=(200, 200, 200), width=1)


def frame_image(tr: Trajectory, frame: int, width: int, height: int, ground_z: float = 0.0) -> Image.Image:
    """One frame: ground grid, props as dots, people as stick figures, frame number."""
    img = Image.new("RGB", (width, height), (250, 250, 245))
    draw = ImageDraw.Draw(img)
    cam = tr.cam_to_world[frame]
    centre = tr.people[0].body_pos[frame, 0] if tr.people else np.zeros(3)
    _ground_grid(draw, cam, tr.intrinsics, centre, ground_z)
    for prop in tr.props:
        p = project(prop.pos[frame], cam, tr.intrinsics)
        if np.all(np.isfinite(p)):
            draw.ellipse([p[0] - 3, p[1] - 3, p[0] + 3, p[1] + 3], fill=(20, 150, 60))
    for person in tr.people:
        px = project(person.body_pos[frame], cam, tr.intrinsics)
        colour = _ROLE_COLOURS.get(person.role, (0, 0, 0))
        for b in range(1, len(BONES)):
            a, c = px[PARENTS[b]], px[b]
            if np.all(np.isfinite(a)) and np.all(np.isfinite(c)):
                draw.line([tuple(a), tuple(c)], fill=colour, width=2)
        for p in px:
            if np.all(np.isfinite(p)):
                draw.ellipse([p[0] - 2, p[1] - 2, p[0] + 2, p[1] + 2], fill=colour)
    draw.text((4, 4), f"{tr.video_id} frame {frame}", fill=(0, 0, 0))
    return img


def contact_sheet(
    tr: Trajectory, *, frames: int = 6, width: int = 340, height: int = 256, ground_z: float = 0.0
) -> Image.Image:
    """``frames`` evenly spaced frames of the clip in a grid of three columns."""
    picks = np.unique(np.linspace(0, tr.n_frames - 1, max(1, frames)).round().astype(int))
    cols = min(3, len(picks))
    rows = -(-len(picks) // cols)
    sheet = Image.new("RGB", (cols * width, rows * height), (255, 255, 255))
    for k, f in enumerate(picks):
        sheet.paste(frame_image(tr, int(f), width, height, ground_z), ((k % cols) * width, (k // cols) * height))
    return sheet
