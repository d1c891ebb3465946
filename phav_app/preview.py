"""Skeleton previews: a contact sheet of stick figures seen through the recipe's camera.

No renderer needed: the trajectory's body origins are projected with the trajectory's own
camera (DESIGN.md's pinhole convention), so a sheet shows what the video will frame, where
the camera flies and whether the physics did what the action says.
"""

from __future__ import annotations

import itertools
import tarfile
from pathlib import Path

import cv2
import numpy as np
from PIL import Image, ImageDraw

from phav_generator.motion.skeleton import BONES, PARENTS
from phav_generator.physics.trajectory import Trajectory
from phav_generator.render.camera import project as project_points
from phav_spec.encoding import DEPTH_MAX_CODE, MODALITIES, decode_flow
from phav_spec.errors import PhavUserError
from phav_spec.files import atomic_write
from phav_spec.manifest import VideoEntry, load_manifest
from phav_spec.recipe import parse_recipe
from phav_spec.recipe_table import read_recipe_table
from phav_spec.release import RELEASE_FILE
from phav_spec.webdataset import decode_png

_ROLE_COLOURS = {"protagonist": (220, 40, 40), "supporting": (40, 90, 220), "background": (120, 120, 120)}


def project(points: np.ndarray, cam_to_world: np.ndarray, intrinsics: tuple[float, float, float, float]) -> np.ndarray:
    """Pixel coordinates (…, 2) of world points (…, 3) for drawing; NaN for points less than
    1 mm in front of the camera (``render.camera.project``'s convention)."""
    return project_points(points, cam_to_world, intrinsics, min_depth=1e-3)


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


# --- modality previews ------------------------------------------------------------------

#: Columns of a modality sheet, left to right.
SHEET_COLUMNS = ("rgb", "raw_rgb", "semantic", "instance", "depth", "flow")


def depth_image(code: np.ndarray) -> np.ndarray:
    """A 16-bit depth code (cm) as a colour image: inverse depth on the turbo map, sky black."""

    metres = code.astype(np.float64) / 100.0
    sky = code == DEPTH_MAX_CODE
    inverse = np.where(sky, 0.0, 1.0 / np.maximum(metres, 0.01))
    top = np.percentile(inverse[~sky], 99) if np.any(~sky) else 1.0
    scaled = np.clip(inverse / max(top, 1e-9) * 255.0, 0, 255).astype(np.uint8)
    out = cv2.applyColorMap(scaled, cv2.COLORMAP_TURBO)[..., ::-1]
    out[sky] = 0
    return np.ascontiguousarray(out)


def flow_image(code: np.ndarray, max_px: float | None = None) -> np.ndarray:
    """A KITTI flow code as a colour image: hue = direction, brightness = speed, invalid black."""

    flow, valid = decode_flow(code)
    u, v = np.nan_to_num(flow[..., 0]), np.nan_to_num(flow[..., 1])
    speed = np.hypot(u, v)
    top = max_px if max_px is not None else (np.percentile(speed[valid], 99) if valid.any() else 1.0)
    hsv = np.zeros((*speed.shape, 3), dtype=np.uint8)
    hsv[..., 0] = ((np.arctan2(v, u) + np.pi) / (2 * np.pi) * 179).astype(np.uint8)
    hsv[..., 1] = 255
    hsv[..., 2] = np.clip(speed / max(top, 1e-6) * 255, 0, 255).astype(np.uint8)
    out = cv2.cvtColor(hsv, cv2.COLOR_HSV2RGB)
    out[~valid] = 0
    return out


def modality_row(modalities: dict[str, np.ndarray]) -> np.ndarray:
    """One frame's six modalities side by side (labels kept pixel for pixel)."""
    tiles = []
    for name in SHEET_COLUMNS:
        m = modalities[name]
        tiles.append(depth_image(m) if name == "depth" else flow_image(m) if name == "flow" else m)
    return np.concatenate(tiles, axis=1)


def modality_sheet(frames: list[tuple[int, dict[str, np.ndarray]]], title: str) -> Image.Image:
    """Rows of frames, columns of modalities, with a header naming them and each row's frame."""
    rows = [modality_row(m) for _, m in frames]
    width = rows[0].shape[1]
    tile_w = width // len(SHEET_COLUMNS)
    header = 18
    sheet = Image.new("RGB", (width, header + sum(r.shape[0] for r in rows)), (255, 255, 255))
    draw = ImageDraw.Draw(sheet)
    draw.text((4, 3), title, fill=(0, 0, 0))
    for k, name in enumerate(SHEET_COLUMNS[1:], start=1):
        draw.text((k * tile_w + 4, 3), name, fill=(0, 0, 0))
    y = header
    for (index, _), row in zip(frames, rows, strict=True):
        sheet.paste(Image.fromarray(row), (0, y))
        draw.text((4, y + 3), f"frame {index}", fill=(255, 255, 255))
        y += row.shape[0]
    return sheet


def write_gif(images: list[np.ndarray], path, fps: int) -> None:
    """An animated GIF of RGB frames (written atomically)."""

    pictures = [Image.fromarray(im).convert("P", palette=Image.Palette.ADAPTIVE, colors=255) for im in images]
    with atomic_write(path) as tmp:
        pictures[0].save(tmp, format="GIF", save_all=True, append_images=pictures[1:],
                         duration=round(1000 / fps), loop=0)  # fmt: skip


def dataset_video(directory, video_id: str | None) -> tuple[Path, VideoEntry]:
    """The manifest of a dataset (its directory or manifest.json) and the entry of ``video_id``
    (None: its first video), or a one-line error naming what is missing."""
    directory = Path(directory)
    manifest_path = directory if directory.suffix == ".json" else directory / "manifest.json"
    manifest = load_manifest(manifest_path)
    videos = {v.video_id: v for v in manifest.videos}
    if not videos:
        raise PhavUserError("the dataset holds no videos", source=str(manifest_path))
    vid = video_id or manifest.videos[0].video_id
    if vid not in videos:
        raise PhavUserError(f"no video {vid!r} in the manifest ({len(videos)} videos)", source=str(manifest_path),
                            field="--video")  # fmt: skip
    return manifest_path, videos[vid]


def frames_from_dataset(directory, video_id: str | None) -> tuple[str, int, list[dict[str, np.ndarray]]]:
    """(video id, fps, every frame's modalities) of one video of a dataset, read from its shard."""

    manifest_path, entry = dataset_video(directory, video_id)
    vid = entry.video_id
    shard = manifest_path.parent / entry.shard
    if not shard.exists() and (manifest_path.parent / RELEASE_FILE).exists():
        raise PhavUserError("a recipe-only release carries no shards: preview a recipe (phav recipe show), or "
                            "its regenerated pixels (phav regenerate)", source=str(manifest_path.parent))  # fmt: skip
    frames = []
    size: tuple[int, ...] | None = None  # every image the size of the first
    try:
        with tarfile.open(shard) as tar:
            for f in range(entry.n_frames):
                modalities = {}
                for m in MODALITIES:
                    name = f"{vid}/{f:05d}.{m.key}"
                    member = tar.extractfile(name)
                    if member is None:
                        raise KeyError(name)
                    image = decode_png(member.read(), m, source=f"{shard}:{name}")
                    size = size or image.shape[:2]
                    if image.shape[:2] != size:
                        raise ValueError(f"{name} is {image.shape[1]}×{image.shape[0]}, the video's frames "
                                         f"{size[1]}×{size[0]}")  # fmt: skip
                    modalities[m.name] = image
                frames.append(modalities)
    except (OSError, tarfile.TarError, KeyError, ValueError) as e:
        raise PhavUserError(f"cannot read the video's frames ({str(e).splitlines()[0]})", source=str(shard)) from None
    fps = 30  # DESIGN.md's rate; the recipe's own when the recipes table is there
    table_path = manifest_path.parent / "recipes.parquet"
    if table_path.exists():
        table = read_recipe_table(table_path)
        ids = table.column("video_id")
        if vid in ids:
            fps = parse_recipe_fps(table.column("recipe")[ids.index(vid)])
    return vid, fps, frames


def parse_recipe_fps(text: str) -> int:
    """The frame rate of a recipe given as JSON text."""

    return parse_recipe(text).video.fps
