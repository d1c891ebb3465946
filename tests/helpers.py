"""Small shared test helpers: θ variants written to files, running the CLIs, the settings of
the shared small dataset (tests/conftest.py ``small_dataset``) and an image's luminance."""

from __future__ import annotations

import contextlib
import copy
import io
import os
import subprocess
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any
from unittest import mock

import numpy as np
import yaml

from phav_spec.theta import PRESETS_DIR, Theta, parse_theta

PRESET_PATH = PRESETS_DIR / "phav-v1.yaml"


def luma(rgb: np.ndarray) -> np.ndarray:
    """Rec. 709 luminance of the last axis's RGB (any scale), in float64."""
    return np.asarray(rgb, dtype=np.float64) @ np.array([0.2126, 0.7152, 0.0722])


#: The shared small dataset: SMALL_VIDEOS phav-v1-tiny recipes of SMALL_SEED (shoot_bow in
#: urban, shoot_ball in the stadium, golf in simple: the same scenes as phav-v1-short's seed 3),
#: SMALL_SHARD_SIZE videos per shard (two shards: 2 + 1 videos), the default name ``phav``.
SMALL_SEED = 3
SMALL_VIDEOS = 3
SMALL_SHARD_SIZE = 2
#: Clip length of phav-v1-tiny: 6 frames, enough for every per-frame test here.
TINY_SECONDS = 0.2
#: Most seconds a rendering task sleeps on the tests' Ray (``ray_with_delays``), fixed per video.
RAY_DELAY_S = 3.0


def preset_dict() -> dict[str, Any]:
    """The phav-v1 preset as its YAML file spells it (not normalised)."""
    return yaml.safe_load(PRESET_PATH.read_text(encoding="utf-8"))


def theta_variant(tmp_path: Path, edit: Callable[[dict[str, Any]], None], name: str = "theta.yaml") -> Path:
    """Write phav-v1 with ``edit`` applied to a copy of its mapping; return the file."""
    data = copy.deepcopy(preset_dict())
    edit(data)
    path = tmp_path / name
    path.write_text(yaml.safe_dump(data, sort_keys=False), encoding="utf-8")
    return path


def tiny(data: dict[str, Any]) -> None:
    """Edit phav-v1 into phav-v1-tiny, clips of TINY_SECONDS: what the dataset tests check
    (layout, encodings, hashes, resumption, validation) does not need longer ones."""
    data["name"] = "phav-v1-tiny"
    data["durations"] = {"t_min": TINY_SECONDS, "t_max": TINY_SECONDS, "t_mod": TINY_SECONDS}


def tiny_theta() -> Theta:
    """phav-v1-tiny as a θ (the one ``theta_variant(path, tiny)`` writes)."""
    data = copy.deepcopy(preset_dict())
    tiny(data)
    return parse_theta(data, source="<phav-v1-tiny>")


def cli_env() -> dict[str, str]:
    """A bare environment for a CLI run, keeping where phav's per-machine cache is (the body
    data: HOME or PHAV_CACHE_DIR), so no subprocess builds it again."""
    env = {"COLUMNS": "200", "PATH": ""}
    for name in ("HOME", "PHAV_CACHE_DIR"):
        if name in os.environ:
            env[name] = os.environ[name]
    return env


def run_measure(name: str, *args: str) -> str:
    """The output of ``docs/measure/NAME`` run with ``args`` in a bare environment (``cli_env``);
    a failed run fails the test."""
    script = Path(__file__).parents[1] / "docs" / "measure" / name
    return subprocess.run(
        [sys.executable, str(script), *args], capture_output=True, text=True, check=True, env=cli_env()
    ).stdout


def run_cli(*args: str, cwd: Path | None = None, env: dict[str, str] | None = None) -> subprocess.CompletedProcess[str]:
    """Run ``phav`` (or ``phav-validate`` when the first arg is 'validate!') as a user would,
    with ``env`` added to the bare environment."""
    if args and args[0] == "validate!":
        module, rest = "phav_app.validate_cli", args[1:]
    else:
        module, rest = "phav_app.cli", args
    return subprocess.run(
        [sys.executable, "-m", module, *rest],
        capture_output=True,
        text=True,
        cwd=cwd,
        env=cli_env() | (env or {}),
    )


def file_bytes(folder: Path) -> dict[str, bytes]:
    """Every file directly in ``folder``, by name: two datasets compare byte for byte."""
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir()) if p.is_file()}


def tree_bytes(root: Path) -> dict[str, bytes]:
    """Every file under ``root``, by relative path."""
    return {str(p.relative_to(root)): p.read_bytes() for p in sorted(root.rglob("*")) if p.is_file()}


def invoke_cli(*args: str) -> subprocess.CompletedProcess[str]:
    """``run_cli`` in this process: the same Typer app, ``run_app`` wrapper, exit code and
    output, without a fresh interpreter importing every floor again (~2 s of CPU each).
    For what a command answers; tests of the process itself (entry point, signals, a clean
    environment, determinism across processes) use ``run_cli``."""
    # The application floor, imported on first use: phav_spec tests need none of it.
    from phav_app.cli import app as phav_app
    from phav_app.console import run_app
    from phav_app.validate_cli import app as validate_app

    app, rest = (validate_app, args[1:]) if args and args[0] == "validate!" else (phav_app, args)
    out, err = io.StringIO(), io.StringIO()
    code: int | str | None = 0
    width = mock.patch.dict("os.environ", {"COLUMNS": "200"})  # as run_cli's environment: Typer's error boxes
    with width, contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            name = "phav-validate" if app is validate_app else "phav"
            run_app(lambda **kw: app(args=list(rest), prog_name=name, **kw))
        except SystemExit as e:
            code = e.code
    if isinstance(code, str):  # sys.exit("message"): printed to stderr, status 1
        err.write(code)
        code = 1
    return subprocess.CompletedProcess(list(args), code or 0, out.getvalue(), err.getvalue())


def written_frames(dataset: Path) -> dict[str, dict]:
    """Every frame of a dataset's shards as the writer's decoder reads it, by sample key."""
    import webdataset as wds

    from phav_spec.webdataset import phav_decoder

    urls = sorted(str(p) for p in dataset.glob("*.tar"))
    return {s["__key__"]: s for s in wds.WebDataset(urls, shardshuffle=False).decode(phav_decoder)}


def part_corners(asset, *prefixes: str) -> list[tuple[str, np.ndarray]]:
    """Each part of an asset whose name starts with one of ``prefixes``: (name, the corners
    of its triangles, (m, 3, 3) float64)."""
    return [(name, asset.positions[asset.triangles[first:end]].astype(np.float64))
            for name, first, end, _ in asset.parts if name.startswith(prefixes)]  # fmt: skip


def outside_hulls(points: np.ndarray, hulls) -> np.ndarray:
    """How far each point (n, 3) lies outside the nearest of the convex ``hulls`` (each its
    corners): its farthest face plane, negative inside."""
    from scipy.spatial import ConvexHull

    planes = [ConvexHull(np.asarray(h)).equations for h in hulls]
    return np.min([np.max(points @ e[:, :3].T + e[:, 3], axis=1) for e in planes], axis=0)
