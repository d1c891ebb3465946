"""Contact sheets that show what each environment, weather, day phase and action looks like.

One sheet per value: RGB at the first, middle and last frame above the middle frame's
semantic labels, depth and flow. Environments and actions are shown by the first recipe of
the dataset that has them; weathers and day phases by one base scene re-sampled with the
value forced (``RecipeSampler.sample(force=…)``), so those sheets differ only in what they
name. Everything is drawn from (θ, seed): the same command makes the same sheets.
"""

from __future__ import annotations

import shlex
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from PIL import Image, ImageDraw

from phav_app.preview import depth_image, flow_image
from phav_generator.physics.simulate import simulate
from phav_generator.render.context import gl_context
from phav_generator.render.modalities import encode_frame
from phav_generator.render.video import scene_renderer
from phav_generator.sampling import RecipeSampler
from phav_spec.errors import PhavUserError
from phav_spec.expectations import exact_expectations
from phav_spec.files import atomic_write, holds_dataset
from phav_spec.recipe import Recipe
from phav_spec.theta import Theta
from phav_spec.vocab import ACTIONS, DAY_PHASES, ENVIRONMENTS, WEATHERS

if TYPE_CHECKING:
    import moderngl

#: What a sheet can be made per, and the values of each.
SHEET_KINDS: dict[str, tuple[str, ...]] = {
    "environment": ENVIRONMENTS.names,
    "weather": WEATHERS.names,
    "day_phase": DAY_PHASES.names,
    "action": ACTIONS.names,
}
#: How far into the dataset to look for a recipe with a given environment or action.
SEARCH_LIMIT = 20000
#: The environment of the base scene that weather and day-phase sheets vary (roads, lamps).
BASE_ENVIRONMENT = "urban"


@dataclass(frozen=True)
class SheetSpec:
    """One sheet to make: what it shows (kind, value) and the recipe that shows it."""

    kind: str
    value: str
    recipe: Recipe

    @property
    def name(self) -> str:
        return f"{self.kind}-{self.value}"


def _first(sampler: RecipeSampler, seed: int, keep: Callable[[Recipe], bool], what: str) -> Recipe:
    for index in range(SEARCH_LIMIT):
        r = sampler.sample(seed, index)
        if keep(r):
            return r
    raise ValueError(f"no recipe with {what} among the first {SEARCH_LIMIT:,} of seed {seed}")


def sheet_specs(theta: Theta, seed: int, kinds: tuple[str, ...]) -> Iterator[SheetSpec]:
    """The sheets of ``kinds`` (each named once), in the vocabularies' order. Environments and
    actions are those θ gives a chance (a recipe with another is never drawn); weathers and
    day phases are all of them, forced on one base scene (what the renderer makes of each)."""
    unknown = sorted(set(kinds) - set(SHEET_KINDS))
    if unknown or not kinds:
        raise ValueError(f"unknown sheet kind(s) {unknown}; choose from {', '.join(SHEET_KINDS)}")
    tables = exact_expectations(theta)
    sampler = RecipeSampler(theta)
    base = None
    for kind in dict.fromkeys(kinds):
        chance = tables[kind].marginal_dict() if kind in ("environment", "action") else {}
        for value in (v for v in SHEET_KINDS[kind] if chance.get(v, 1.0) > 0):
            if kind == "environment":
                r = _first(sampler, seed, lambda r, v=value: r.environment.name == v, f"environment {value}")
            elif kind == "action":
                r = _first(sampler, seed, lambda r, v=value: r.action == v, f"action {value}")
            else:
                if base is None:
                    base = _first(sampler, seed, lambda r: r.environment.name == BASE_ENVIRONMENT,
                                  f"environment {BASE_ENVIRONMENT}")  # fmt: skip
                other = {"weather": {"day_phase": "day"}, "day_phase": {"weather": "clear"}}[kind]
                r = sampler.sample(seed, base.index, force={kind: value, **other})
            yield SheetSpec(kind, value, r)


def _caption(r: Recipe) -> str:
    w = r.world
    hour = int(w.clock_hour)
    minute = round((w.clock_hour - hour) * 60) % 60
    return (f"{r.video_id}: {r.action} in {r.environment.name}, {w.weather} {w.day_phase} "
            f"{hour:02d}:{minute:02d}, {r.camera.kind} camera, {r.n_frames} frames")  # fmt: skip


def render_sheet(spec: SheetSpec, ctx: moderngl.Context | None = None) -> Image.Image:
    """The sheet of ``spec``: RGB at three frames above the middle frame's labels, depth, flow."""

    r = spec.recipe
    tr = simulate(r, keep_state=False)
    own = ctx is None
    if own:
        ctx = gl_context()
    renderer = scene_renderer(r, tr, ctx)
    try:
        middle = (r.n_frames - 1) // 2
        frames = {}
        for f in sorted({0, middle, r.n_frames - 1}):
            frames[f] = encode_frame(renderer.render(f, tr.cam_to_world[f], tr.cam_to_world[f + 1], tr.intrinsics))
    finally:
        renderer.release()
        if own:
            ctx.release()
    top = [frames[f]["rgb"] for f in (0, middle, r.n_frames - 1)]
    m = frames[middle]
    bottom = [m["semantic"], depth_image(m["depth"]), flow_image(m["flow"])]
    grid = np.concatenate([np.concatenate(top, axis=1), np.concatenate(bottom, axis=1)], axis=0)
    header = 18
    sheet = Image.new("RGB", (grid.shape[1], grid.shape[0] + header), (255, 255, 255))
    draw = ImageDraw.Draw(sheet)
    draw.text((4, 3), f"{spec.kind} = {spec.value}    {_caption(r)}", fill=(0, 0, 0))
    sheet.paste(Image.fromarray(grid), (0, header))
    w, h = r.video.width, r.video.height
    labels = ("rgb, frame 0", f"rgb, frame {middle}", f"rgb, frame {r.n_frames - 1}",
              f"semantic, frame {middle}", f"depth, frame {middle}", f"flow, frame {middle}")  # fmt: skip
    for k, text in enumerate(labels):
        x, y = (k % 3) * w + 4, header + (k // 3) * h + 3
        draw.text((x + 1, y + 1), text, fill=(0, 0, 0))
        draw.text((x, y), text, fill=(255, 255, 255))
    return sheet


#: The index page's first line: a README.md that begins otherwise is not ours to replace.
INDEX_TITLE = "# Contact sheets"


def check_sheets_dir(directory: Path) -> None:
    """Refuse, before any work, a folder whose README.md the index would replace though the
    sheets did not write it (a project's notes, a release's dataset card), or a dataset's."""
    if holds_dataset(directory):
        raise PhavUserError("holds a dataset; write the sheets elsewhere", source=str(directory), field="--out")
    readme = directory / "README.md"
    try:
        first = readme.read_text(encoding="utf-8", errors="replace").split("\n", 1)[0] if readme.is_file() else None
    except OSError:
        return  # the first write reports it
    if first is not None and first.strip() != INDEX_TITLE:
        raise PhavUserError("holds a README.md that phav sheets did not write; write the sheets elsewhere",
                            source=str(directory), field="--out")  # fmt: skip


def sheets_command(theta: str, seed: int, kinds: tuple[str, ...], directory: Path) -> str:
    """The ``phav sheets`` command line that makes these sheets again (``--by`` where not every kind)."""
    words = ["phav", "sheets", "--theta", theta, "--seed", str(seed)]
    if tuple(dict.fromkeys(kinds)) != tuple(SHEET_KINDS):
        words += ["--by", ",".join(dict.fromkeys(kinds))]
    return shlex.join([*words, "--out", str(directory)])


def write_index(specs: list[SheetSpec], directory: Path, theta: Theta, command: str) -> Path:
    """A Markdown page listing the sheets by kind, with the recipe each shows and the command
    (``sheets_command``) that made them."""

    lines = [INDEX_TITLE, "",
             f"Made by `{command}` (θ {theta.name}, {theta.hash[:12]}…): one sheet per value. Top row: RGB at",
             "the first, middle and last frame; bottom row: the middle frame's semantic labels, depth",
             "(inverse depth, turbo; sky black) and flow (hue = direction, brightness = speed).",
             "Weather and day-phase sheets are one base scene with only that value changed.", ""]  # fmt: skip
    for kind in SHEET_KINDS:
        group = [s for s in specs if s.kind == kind]
        if not group:
            continue
        lines += [f"## {kind.replace('_', ' ')}", ""]
        for s in group:
            lines += [f"### {s.value}", "", f"{_caption(s.recipe)}", "", f"![{s.name}]({s.name}.jpg)", ""]
    target = directory / "README.md"
    with atomic_write(target) as tmp:
        tmp.write_text("\n".join(lines), encoding="utf-8")
    return target


__all__ = [
    "INDEX_TITLE",
    "SHEET_KINDS",
    "SheetSpec",
    "check_sheets_dir",
    "render_sheet",
    "sheet_specs",
    "sheets_command",
    "write_index",
]
