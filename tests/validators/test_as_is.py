"""Validating a dataset as it is: shards split into parts scanned by a pool of workers (or Ray
tasks), the checks that need no pixels running meanwhile, give the report one process gives."""

from __future__ import annotations

import subprocess
import sys

import pytest

from phav_generator.faults import KILL_AT_ENV
from phav_spec.errors import PhavUserError
from phav_validators.findings import Reason
from phav_validators.options import CHECKS, Options
from phav_validators.source import resolve
from phav_validators.validate import validate_dataset
from tests.helpers import cli_env
from tests.validators.checks.support import assert_fails, png_edit, rewrite_tar, shard_of, validate


def test_worker_count_does_not_change_the_report(small_dataset_copy):
    """Shards split into parts scanned by a pool, with failures overlapping the scan, give the
    report one process gives, findings in the same order (here in a secondary part's video)."""
    data = small_dataset_copy

    def paint(image):
        image[10:12, 20:22] = (1, 2, 3)
        return image

    rewrite_tar(shard_of(data, "v000001"), png_edit("v000001/00004.seg.png", paint))
    checks = tuple(c for c in CHECKS if c != "reproducibility")
    one, two = (validate(data, *checks, workers=w) for w in (1, 2))
    assert_fails(two, "encoding", Reason.FOREIGN_COLOUR, video="v000001")
    one_json, two_json = one.to_json(), two.to_json()
    for report in (one_json, two_json):
        for c in report["checks"]:
            c.pop("seconds")
    assert one_json == two_json


def test_a_scanning_worker_killed_is_a_one_line_error(small_dataset):
    """A scan worker killed (the OOM killer, a kill -9) broke the pool: a traceback and exit
    code 1. It is the one-line error the generator gives for its own workers, exit code 2."""
    shard = sorted(small_dataset.glob("*.tar"))[0]
    env = cli_env() | {KILL_AT_ENV: f"scan:{shard.name}"}
    args = (str(small_dataset), "--workers", "2", "--checks", "integrity,encoding")
    run = subprocess.run([sys.executable, "-m", "phav_app.validate_cli", *args], capture_output=True, text=True,
                         env=env, timeout=180)  # fmt: skip
    lines = [line for line in run.stderr.splitlines() if line.strip()]
    assert run.returncode == 2 and "Traceback" not in run.stderr, run.stderr[-800:]
    assert lines == [f"error: {shard}: a scanning worker process died (killed, or out of memory); nothing was "
                     "written, rerun to validate"], lines  # fmt: skip


def test_ray_scans_give_the_report_one_process_gives(ray_with_delays, small_dataset):
    """`--engine ray`: the shard parts scanned as Ray tasks (``RayPool``), same report."""
    checks = ("integrity", "encoding", "consistency")
    here = validate_dataset(resolve([small_dataset])[0], options=Options(checks=checks))
    ray = validate_dataset(resolve([small_dataset])[0], options=Options(checks=checks, workers=2, engine="ray"))
    reports = [here.to_json(), ray.to_json()]
    for report in reports:
        for c in report["checks"]:
            c.pop("seconds")
    assert reports[0] == reports[1]
    assert reports[1]["checks"][0]["numbers"]["hashed"] == 3


def test_distribution_runs_only_when_asked(small_dataset):
    """The distribution tests (and their import of scipy) run only when that check is asked
    for: the report of other checks carries no distribution details, and asking adds them."""
    inp = resolve([small_dataset])[0]
    without = validate_dataset(inp, options=Options(checks=("schema", "integrity")))
    assert without.distribution is None
    assert [c.name for c in without.checks] == ["integrity", "schema"]
    asked = validate_dataset(inp, options=Options(checks=("schema", "distribution")))
    assert asked.distribution is not None and asked.distribution.tests
    assert [c.name for c in asked.checks] == ["schema", "distribution"]


def test_a_named_shard_is_what_every_check_covers_and_the_sample_is_drawn_from(small_dataset, small_recipes):
    """phav-000000.tar holds v000000 and v000001, phav-000001.tar v000002: named alone, a
    shard's videos are what the failures check, the sample and the header count; the
    report knows the dataset's folder (the HTML read example frames below the shard's path)."""
    first = resolve([small_dataset / "phav-000000.tar"])[0]
    report = validate_dataset(first, options=Options(checks=("failures",)))
    failures = next(c for c in report.checks if c.name == "failures")
    assert failures.numbers["videos"] == 2 and report.n_videos == 2
    assert report.n_frames == small_recipes[0].n_frames + small_recipes[1].n_frames
    # The HTML report reads the learnability check's example frames from the folder, not the shard.
    assert report.source.endswith("phav-000000.tar") and report.root == str(small_dataset.resolve())
    second = resolve([small_dataset / "phav-000001.tar"])[0]
    report = validate_dataset(second, options=Options(checks=("integrity",), sample=0.1))
    integrity = next(c for c in report.checks if c.name == "integrity")
    assert (integrity.numbers["videos"], integrity.numbers["hashed"]) == (1, 1) and report.n_videos == 1


def test_only_a_dataset_s_own_json_files_name_it(tmp_path):
    """manifest.json and release.json name their directory's dataset; another .json (a
    report, a recipe) is refused in one line, where it used to validate the directory beside it."""
    for name in ("manifest.json", "release.json"):
        (tmp_path / name).write_text("{}", encoding="utf-8")
        (inp,) = resolve([tmp_path / name])
        assert inp.root == tmp_path.resolve() and inp.shards is None
    report = tmp_path / "report.json"
    report.write_text("{}", encoding="utf-8")
    with pytest.raises(PhavUserError, match="expected a dataset directory") as caught:
        resolve([report])
    assert caught.value.source == str(report)
