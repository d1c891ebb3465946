"""The generator's pipeline: one video, from its recipe to its part of a shard, stage by stage.

::

    Recipe ──plan_scene──▶ ScenePlan ──simulate_plan──▶ Trajectory ──render_video──▶ RenderedFrame…
    (phav_spec)            (physics/plan)               (physics/simulate)           (render/video)
        ──write_part──▶ a video's part: tar members + metadata rows ──assemble_shard──▶ shard
                        (io/shards, here)                                 (io/shards, by dataset/)

Every stage is a pure function of what flows into it: the recipe carries every seed, and each
stage draws only from its own named streams of those seeds (``phav_spec.seeding``). Side
effects sit at the edges: the GL context (``render/context``) and files (``io/``). A video is
the unit of work: ``run_task`` is the function the engines (``engines``: a local process
pool or Ray) run for each ``VideoTask``; the dataset driver (``dataset/``) journals what
comes back and joins parts into shards.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import moderngl
import pyarrow as pa
import pyarrow.parquet as pq

from phav_generator.engines import Progress
from phav_generator.faults import crash_point, task_delay
from phav_generator.io.shards import open_part
from phav_generator.physics.plan.scene import plan_scene
from phav_generator.physics.simulate import simulate_plan
from phav_generator.render.context import gl_context, gl_strings
from phav_generator.render.video import RenderedFrame, render_video
from phav_spec.encoding import VideoHashes
from phav_spec.files import atomic_write
from phav_spec.metadata import CAMERA_COLUMNS, PEOPLE_COLUMNS, arrow_schema, finite_row, frame_json
from phav_spec.recipe import Recipe, parse_recipe

#: The metadata tables a video's part carries beside its tar members, with their columns.
PART_TABLES = (("cameras", CAMERA_COLUMNS), ("people", PEOPLE_COLUMNS))


@dataclass(frozen=True)
class VideoTask:
    """One video to render: the shard it belongs to and its recipe's JSON."""

    shard: str
    video_id: str
    recipe: str
    #: The renderer (``render.gl.GL_KINDS``): llvmpipe, the renderer of record, or egl-gpu.
    gl: str = "llvmpipe"


def video_frames(recipe: Recipe, ctx: moderngl.Context) -> Iterator[RenderedFrame]:
    """Recipe → plan → trajectory → frames: the stages that decide a video's content."""
    scene = plan_scene(recipe)
    trajectory = simulate_plan(scene, keep_state=False)
    return render_video(recipe, trajectory, ctx=ctx)


def part_path(parts: Path, video_id: str, what: str) -> Path:
    """Where a video's part file ``what`` (``tar.part``, ``cameras.parquet``…) lives."""
    return parts / f"{video_id}.{what}"


def write_part(task: VideoTask, recipe: Recipe, frames: Iterator[RenderedFrame], parts: Path,
               report: Progress | None = None) -> dict[str, Any]:  # fmt: skip
    """Frames → a video's part of its shard: its tar members and metadata rows, each written
    atomically under ``parts``; returns the video's record (hashes, size) for the journal."""
    hashes = VideoHashes(recipe.n_frames)
    rows: dict[str, list[dict[str, Any]]] = {"cameras": [], "people": []}
    with open_part(part_path(parts, recipe.video_id, "tar.part")) as part:
        for rf in frames:
            hashes.add(rf.index, rf.modalities)
            camera, people = finite_row(rf.camera), [finite_row(row) for row in rf.people]
            part.add_frame(recipe.video_id, rf.index, rf.modalities, frame_json(camera, people),
                           recipe.render.png_compression)  # fmt: skip
            rows["cameras"].append(camera)
            rows["people"] += people
            crash_point(f"part:{recipe.video_id}:{rf.index}")
            if report is not None:
                report(0, 1)
    for table, columns in PART_TABLES:
        with atomic_write(part_path(parts, recipe.video_id, f"{table}.parquet")) as tmp:
            pq.write_table(pa.Table.from_pylist(rows[table], schema=arrow_schema(columns)), tmp, compression="zstd")
    crash_point(f"part-done:{recipe.video_id}")
    return {
        "video_id": recipe.video_id, "shard": task.shard, "n_frames": recipe.n_frames,
        "content_hash": hashes.video_hash(), "modality_hashes": hashes.hexdigests(), "part_bytes": part.size,
    }  # fmt: skip


#: This process's GL contexts by kind, made on first use (one per worker process).
_contexts: dict[str, moderngl.Context] = {}


def _context(kind: str) -> moderngl.Context:
    if kind not in _contexts:
        _contexts[kind] = gl_context(kind)
    return _contexts[kind]


def run_task(task: VideoTask, report: Progress | None = None, *, parts: Path) -> dict[str, Any]:
    """The unit of work: render one video into its part under ``parts``, in this process's GL
    context; returns its record, with the GL strings of the renderer that made it."""
    task_delay(task.video_id)
    ctx = _context(task.gl)
    recipe = parse_recipe(task.recipe, source=f"{task.shard} recipe {task.video_id}")
    record = write_part(task, recipe, video_frames(recipe, ctx), parts, report)
    return {**record, "gl": gl_strings(ctx)}
