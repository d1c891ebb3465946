"""The phav command as a user meets it: help, θ, sample, recipes, errors as one line."""

from __future__ import annotations

import json
import os
import signal
import stat
import subprocess
import sys
import time
from pathlib import Path

import pytest

from phav_spec.recipe_table import read_recipe_table
from phav_spec.theta import load_preset
from tests.helpers import cli_env, file_bytes, invoke_cli, run_cli


def test_help_lists_the_commands():
    result = run_cli("--help")  # the installed entry point, in a fresh process
    assert result.returncode == 0
    for command in ("sample", "stats", "theta", "spec", "bench"):
        assert command in result.stdout


def test_theta_check_prints_the_hash():
    result = invoke_cli("theta", "check", "phav-v1")
    assert result.returncode == 0 and load_preset().hash in result.stdout


def test_sample_is_deterministic_and_prefix_stable(tmp_path):
    """The same table from a fresh process and from this one; a shorter run is its prefix."""
    a, b, c = tmp_path / "a.parquet", tmp_path / "b.parquet", tmp_path / "c.parquet"
    assert run_cli("sample", "--n", "30", "--seed", "9", "--out", str(a)).returncode == 0
    assert invoke_cli("sample", "--n", "30", "--seed", "9", "--out", str(b)).returncode == 0
    assert invoke_cli("sample", "--n", "12", "--seed", "9", "--out", str(c)).returncode == 0
    ra, rb, rc = (read_recipe_table(p).column("recipe") for p in (a, b, c))
    assert ra == rb and ra[:12] == rc
    cols = read_recipe_table(a).table.column_names
    for required in ("video_id", "action", "human_model", "environment", "weather", "day_phase", "variation",
                     "camera", "base_motion", "duration_s", "n_frames", "clock_hour", "recipe"):  # fmt: skip
        assert required in cols


def test_usage_errors_exit_2_without_traceback(tmp_path):
    for args in (
        ("sample", "--n", "-3"),
        ("sample", "--theta", "nope-v9", "--n", "2", "--out", str(tmp_path / "x.parquet")),
        ("frobnicate",),
    ):
        result = invoke_cli(*args)
        assert result.returncode == 2, args
        assert "Traceback" not in result.stderr + result.stdout
    assert not (tmp_path / "x.parquet").exists()


def test_output_paths_that_cannot_be_written(tmp_path):
    result = invoke_cli("sample", "--n", "2", "--out", str(tmp_path))
    assert result.returncode == 2 and "Is a directory" in result.stderr and "Traceback" not in result.stderr
    odd = tmp_path / "a[bold]b.yaml"
    result = invoke_cli("theta", "check", str(odd))
    assert result.returncode == 2 and "a[bold]b.yaml" in result.stderr
    (tmp_path / "afile.txt").write_text("kept\n")
    below = tmp_path / "afile.txt" / "x.parquet"
    result = invoke_cli("sample", "--n", "2", "--out", str(below))
    assert result.returncode == 2 and "Traceback" not in result.stderr
    assert f"{below}: --out: cannot be written here: Not a directory: {tmp_path / 'afile.txt'}" in result.stderr
    assert (tmp_path / "afile.txt").read_text() == "kept\n"
    pipe = tmp_path / "pipe.parquet"
    os.mkfifo(pipe)
    result = invoke_cli("sample", "--n", "2", "--out", str(pipe))
    assert result.returncode == 2 and "Not a regular file" in result.stderr and "Traceback" not in result.stderr
    assert stat.S_ISFIFO(pipe.stat().st_mode)  # the pipe is still a pipe
    assert sorted(p.name for p in tmp_path.iterdir()) == ["afile.txt", "pipe.parquet"]  # no temporary left
    for args in (("sheets", "--out", str(below)), ("bench", "--sections", "sampling", "--out-dir", str(below))):
        result = invoke_cli(*args)  # refused before any sheet or bench is made
        option = args[-2]
        assert result.returncode == 2 and f"{below}: {option}: {tmp_path / 'afile.txt'} is not a directory" in (
            result.stderr
        ), result.stderr


def test_recipe_show_and_check_round_trip(tmp_path):
    table = tmp_path / "r.parquet"
    assert invoke_cli("sample", "--n", "5", "--seed", "2", "--out", str(table)).returncode == 0
    shown = invoke_cli("recipe", "show", str(table), "--video", "v000003")
    assert shown.returncode == 0
    path = tmp_path / "v000003.json"
    path.write_text(shown.stdout, encoding="utf-8")
    checked = invoke_cli("recipe", "check", str(path))
    assert checked.returncode == 0 and "valid recipe v000003" in checked.stdout
    assert "what θ phav-v1 at seed 2, video 3 gives" in checked.stdout
    missing = invoke_cli("recipe", "show", str(table), "--video", "v000099")
    assert missing.returncode == 2 and "no video 'v000099'" in missing.stderr


def test_recipe_check_and_vary_find_a_datasets_theta_beside_the_recipe(small_theta, small_recipes, tmp_path):
    """A θ that is no shipped preset (the tests' tiny one): the recipe check and vary take it
    from the theta.yaml beside the recipe when its hash is the recipe's, as a dataset's
    directory holds it; without it they ask for --theta."""
    path = tmp_path / "v000000.json"
    path.write_text(small_recipes[0].model_dump_json(), encoding="utf-8")
    alone = invoke_cli("recipe", "check", str(path))
    assert alone.returncode == 0 and "pass it with --theta" in alone.stdout
    refused = invoke_cli("vary", str(path), "--set", "weather=fog", "--out", str(tmp_path / "o.json"))
    assert refused.returncode == 2 and "nor a theta.yaml beside the recipe" in refused.stderr
    (tmp_path / "theta.yaml").write_text(small_theta.to_yaml(), encoding="utf-8")
    checked = invoke_cli("recipe", "check", str(path))
    assert checked.returncode == 0 and f"what θ {small_theta.name} at seed" in checked.stdout, checked.stdout
    varied = invoke_cli("vary", str(path), "--set", "weather=fog", "--out", str(tmp_path / "o.json"))
    assert varied.returncode == 0 and (tmp_path / "o.json").is_file()
    (tmp_path / "theta.yaml").write_text(load_preset("phav-v1-short").to_yaml(), encoding="utf-8")  # another θ
    assert "pass it with --theta" in invoke_cli("recipe", "check", str(path)).stdout


def test_bad_recipes_on_the_command_line(tmp_path):
    table = tmp_path / "r.parquet"
    assert invoke_cli("sample", "--n", "1", "--out", str(table)).returncode == 0
    data = json.loads(invoke_cli("recipe", "show", str(table), "--video", "v000000").stdout)
    cases = {
        "missing.json": (lambda d: d["camera"].pop("fov_deg"), "camera.fov_deg: missing required field"),
        "future.json": (lambda d: d.update(schema_version=7), "schema_version: version 7 is newer"),
    }
    for name, (edit, words) in cases.items():
        broken = json.loads(json.dumps(data))
        edit(broken)
        path = tmp_path / name
        path.write_text(json.dumps(broken), encoding="utf-8")
        result = invoke_cli("recipe", "check", str(path))
        assert result.returncode == 2 and "Traceback" not in result.stderr
        lines = [line for line in result.stderr.splitlines() if line.strip()]
        assert len(lines) == 1 and f"{path}: {words}" in lines[0], result.stderr
    edited = json.loads(json.dumps(data))
    edited["camera"]["fov_deg"] = 33.0  # valid, but not what θ and the seed give
    path = tmp_path / "edited.json"
    path.write_text(json.dumps(edited), encoding="utf-8")
    checked = invoke_cli("recipe", "check", str(path))
    assert checked.returncode == 0 and "not what θ phav-v1 at seed 0, video 0 gives: camera.fov_deg differs" in (
        checked.stdout
    ), checked.stdout
    custom = invoke_cli("recipe", "check", str(path), "--theta", "phav-v1-short")
    assert custom.returncode == 2 and f"{path}: theta_hash: the recipe was sampled from θ" in custom.stderr
    result = invoke_cli("vary", str(path), "--set", "weather=fog", "--out", str(tmp_path / "o.json"))
    assert result.returncode == 2 and f"{path}: v000000: this recipe is not what θ" in result.stderr
    assert not (tmp_path / "o.json").exists()
    sampled = tmp_path / "sampled.json"
    sampled.write_text(json.dumps(data), encoding="utf-8")
    result = invoke_cli("vary", str(sampled), "--set", "sun_brightness=5", "--out", str(tmp_path / "o.json"))
    assert result.returncode == 2 and "error: --set: the varied recipe is invalid: world.sun_brightness: " in (
        result.stderr
    ), result.stderr


def test_usage_errors_are_one_line_naming_the_option():
    """What Typer refuses on a command line is one line naming the option and the help to
    read, exit code 2 (it drew a box of five lines)."""
    cases = {
        ("generate", "--videos", "abc"): "error: Invalid value for '--videos'",
        ("generate", "--nope"): "error: No such option: --nope",
        ("recipe", "check"): "error: Missing argument 'file'.",
        ("validate!", "--nope"): "error: No such option: --nope",
    }
    for args, start in cases.items():
        result = invoke_cli(*args)
        lines = [line for line in result.stderr.splitlines() if line.strip()]
        assert result.returncode == 2 and len(lines) == 1 and lines[0].startswith(start), (args, result.stderr)
        assert lines[0].endswith("--help)")
    bare = invoke_cli("theta")  # a bare group shows its help
    assert bare.returncode == 2 and "check" in bare.stdout and not bare.stderr.strip()


def test_spec_vocab_lists_the_registries():
    result = invoke_cli("spec", "vocab", "pixel_class")
    assert result.returncode == 0 and "guard_rail" in result.stdout and "(64)" in result.stdout
    assert invoke_cli("spec", "vocab", "colours").returncode == 2


def test_generate_errors_are_one_line(tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("x")
    result = invoke_cli("generate", "--videos", "1", "--out", str(blocker))
    assert result.returncode == 2 and "Traceback" not in result.stderr and "not a directory" in result.stderr
    result = invoke_cli("generate", "--videos", "1", "--out", str(tmp_path / "d"), "--name", "a.b")
    assert result.returncode == 2 and "--name" in result.stderr
    result = invoke_cli("regenerate", str(tmp_path / "missing"), "--out", str(tmp_path / "o"))
    assert result.returncode == 2 and "missing" in result.stderr


def test_sample_refuses_a_place_it_cannot_write_before_drawing(monkeypatch):
    """The table's file is opened before the first recipe is drawn: --n 10^8 into a place
    nobody may write fails at once, not after sampling."""
    place = Path("/sys/phav-sample-test.parquet")  # sysfs: no new files, even for root
    try:
        (place.parent / ".phav-probe").touch()
    except OSError:
        pass
    else:
        pytest.skip("/sys takes new files here")

    def never(*args, **kwargs):
        raise AssertionError("a recipe was drawn")
        yield

    monkeypatch.setattr("phav_app.cli.sample_recipes", never)
    result = invoke_cli("sample", "--n", "100000000", "--out", str(place))
    assert result.returncode == 2 and f"{place}: --out: cannot be written here: the place is not writable" in (
        result.stderr
    ), result.stderr
    assert "Traceback" not in result.stderr


def test_sigterm_stops_sample_and_leaves_the_previous_table(tmp_path):
    """SIGTERM while `phav sample` writes: exit 143, one line, the previous table intact and
    no temporary left (the table's temporary lives as long as the sampling)."""
    out = tmp_path / "recipes.parquet"
    assert invoke_cli("sample", "--n", "2", "--out", str(out)).returncode == 0
    previous = out.read_bytes()
    run = subprocess.Popen([sys.executable, "-m", "phav_app.cli", "sample", "--n", "100000000", "--out", str(out)],
                           stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, env=cli_env())  # fmt: skip
    try:
        deadline = time.monotonic() + 60.0
        while not [p for p in tmp_path.iterdir() if p.suffix == ".tmp"]:
            assert run.poll() is None and time.monotonic() < deadline, "the run never started writing"
            time.sleep(0.05)
        run.send_signal(signal.SIGTERM)
        _, err = run.communicate(timeout=60)
    finally:
        run.kill()
    assert run.returncode == 143, err[-500:]
    assert [line for line in err.splitlines() if line.strip()] == [
        "terminated; finished files are intact (writes are atomic)"
    ]
    assert out.read_bytes() == previous
    assert [p.name for p in tmp_path.iterdir()] == ["recipes.parquet"]


def test_sample_after_a_sigkill_removes_the_killed_runs_temporary(tmp_path):
    """A SIGKILLed `phav sample` cannot remove its temporary; the next `phav sample` to the
    same file does, and leaves a live writer's temporary (another file's) alone."""
    out = tmp_path / "recipes.parquet"
    run = subprocess.Popen([sys.executable, "-m", "phav_app.cli", "sample", "--n", "100000000", "--out", str(out)],
                           stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=cli_env())  # fmt: skip
    try:
        deadline = time.monotonic() + 60.0
        # The table's temporary, not the writable-place probe made and removed before it.
        while not (left := [p for p in tmp_path.iterdir() if p.name.startswith(".recipes.parquet.")]):
            assert run.poll() is None and time.monotonic() < deadline, "the run never started writing"
            time.sleep(0.05)
    finally:
        run.kill()
        run.wait(timeout=60)
    assert left[0].exists() and not out.exists()
    other = tmp_path / f".other.parquet.{'0' * 16}.tmp"  # another file's, left as it is
    other.write_bytes(b"x")
    assert invoke_cli("sample", "--n", "3", "--out", str(out)).returncode == 0
    assert sorted(p.name for p in tmp_path.iterdir()) == [other.name, "recipes.parquet"]


def test_outputs_never_replace_what_is_read_or_a_datasets_files(small_dataset_copy, small_recipes, tmp_path):
    """A report, a sheet, a counterfactual recipe or a sampled table named as a dataset's own
    file (its manifest, a table), or as the file being read, is refused before any work; so is
    an output in a place this process cannot write, before the work it would keep."""
    data = small_dataset_copy
    before = file_bytes(data)
    recipe = tmp_path / "v000000.json"
    recipe.write_text(small_recipes[0].model_dump_json(), encoding="utf-8")
    table = tmp_path / "r.parquet"
    assert invoke_cli("sample", "--n", "3", "--out", str(table)).returncode == 0
    refusals = {
        ("validate!", str(data), "--checks", "schema", "--json", str(data / "manifest.json")): "--json",
        ("validate!", str(data), "--checks", "schema", "--html", str(data / "recipes.parquet")): "--html",
        ("validate!", str(table), "--json", str(table)): "--json",
        ("preview", str(data), "--out", str(data / "manifest.json")): "--out",
        ("vary", str(recipe), "--set", "weather=fog", "--out", str(data / "recipes.parquet")): "--out",
        ("vary", str(recipe), "--set", "weather=fog", "--out", str(recipe)): "--out",
        ("sample", "--n", "2", "--out", str(data / "recipes.parquet")): "--out",
        ("validate!", str(data), "--checks", "schema", "--json", "/proc/phav-report.json"): "--json",
    }
    for args, field in refusals.items():
        result = invoke_cli(*args)
        lines = [line for line in result.stderr.splitlines() if line.strip()]
        assert result.returncode == 2 and len(lines) == 1 and f"{field}:" in lines[0], (args, result.stderr)
    assert file_bytes(data) == before and json.loads(recipe.read_text())["video_id"] == "v000000"


def test_generate_writes_only_into_an_empty_directory_or_its_own_run(small_theta, tmp_path):
    """A directory holding other files (a θ file, a sampled table, a dataset that lost its
    manifest) or a release is refused before anything is sampled or written; a directory
    holding a run (its manifest, or its work folder) is the run's to resume or find finished."""
    from phav_generator.dataset.write import WORK_DIR, check_dataset_dir
    from phav_spec.errors import PhavUserError

    project = tmp_path / "project"
    project.mkdir()
    (project / "theta.yaml").write_text(small_theta.to_yaml(), encoding="utf-8")
    result = invoke_cli("generate", "--theta", str(project / "theta.yaml"), "--videos", "1", "--out", str(project))
    assert result.returncode == 2 and "holds other files and no run of phav generate" in result.stderr
    assert sorted(p.name for p in project.iterdir()) == ["theta.yaml"]
    release = tmp_path / "release"
    release.mkdir()
    (release / "release.json").write_text("{}", encoding="utf-8")
    with pytest.raises(PhavUserError, match="--out: holds a release"):
        check_dataset_dir(release)
    (project / WORK_DIR).mkdir()  # a run stopped before its manifest: resumed
    check_dataset_dir(project)
    check_dataset_dir(tmp_path / "new")


def test_stats_reads_the_rows_as_the_schema_check_does(tmp_path):
    """A table with a video twice (counted twice by the tests) or a row whose recipe does not
    parse is not "all checks passed": its rows' findings, exit 1."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    table = tmp_path / "r.parquet"
    assert invoke_cli("sample", "--n", "40", "--out", str(table)).returncode == 0
    clean = invoke_cli("stats", str(table))
    assert clean.returncode == 0 and "all checks passed" in clean.stdout
    rows = pq.read_table(table)
    pq.write_table(pa.concat_tables([rows, rows.slice(0, 1)]), tmp_path / "twice.parquet")
    twice = invoke_cli("stats", str(tmp_path / "twice.parquet"))
    assert twice.returncode == 1 and "DUPLICATE_VIDEO" in twice.stdout, twice.stdout
    shown = invoke_cli("recipe", "show", str(tmp_path / "twice.parquet"), "--video", "v000000")
    assert shown.returncode == 2 and "video_id: video v000000 has 2 recipes in this table" in shown.stderr
    # An empty recipe cell: a TypeError traceback and exit 1 in `recipe show`.
    recipe = rows.column("recipe").to_pylist()
    blank = rows.set_column(rows.schema.get_field_index("recipe"), "recipe", pa.array([None, *recipe[1:]], pa.string()))
    pq.write_table(blank, tmp_path / "blank.parquet")
    shown = invoke_cli("recipe", "show", str(tmp_path / "blank.parquet"), "--video", "v000000")
    assert shown.returncode == 2 and "Traceback" not in shown.stderr, shown.stderr
    assert "blank.parquet[v000000]: expected a JSON object, got nothing" in shown.stderr


def test_schema_and_fingerprint_never_write_over_a_dataset_s_files(tmp_path):
    """`spec schema --out` and `fingerprint --json` replaced a dataset's manifest.json, as the
    other commands writing one file refuse to."""
    (tmp_path / "manifest.json").write_text("{}", encoding="utf-8")
    for args, field in ((("spec", "schema", "--out"), "--out"), (("fingerprint", "--no-check", "--json"), "--json")):
        result = invoke_cli(*args, str(tmp_path / "manifest.json"))
        assert result.returncode == 2 and f"{field}: is a file of the dataset" in result.stderr, result.stderr
        assert (tmp_path / "manifest.json").read_text(encoding="utf-8") == "{}"


def test_an_output_never_replaces_a_file_of_another_kind(tmp_path, monkeypatch):
    """`sample --out notes.txt` replaced the notes with Parquet, `vary` and `preview` wrote
    over whatever had their default names, and the reports over any file. An output now
    replaces only an earlier file of its own kind (or an empty one), and says so otherwise."""
    monkeypatch.chdir(tmp_path)  # where vary writes its default name
    notes = tmp_path / "notes.txt"
    notes.write_text("my notes\n", encoding="utf-8")
    table, recipe = tmp_path / "r.parquet", tmp_path / "r.json"
    for _ in range(2):  # an earlier table of its own kind is replaced
        assert invoke_cli("sample", "--n", "2", "--out", str(table)).returncode == 0
    recipe.write_text(invoke_cli("recipe", "show", str(table), "--video", "v000000").stdout, encoding="utf-8")
    (tmp_path / "v000000-varied.json").write_text("my notes\n", encoding="utf-8")
    for args, field, kind in (
        (("sample", "--n", "2", "--out", str(notes)), "--out", "Parquet"),
        (("spec", "schema", "--out", str(notes)), "--out", "JSON"),
        (("vary", str(recipe), "--set", "weather=fog"), "--out", "JSON"),  # its default name
        (("preview", str(recipe), "--skeleton", "--out", str(notes.with_suffix(".png"))), "--out", "PNG"),
        (("fingerprint", "--no-check", "--json", str(notes)), "--json", "JSON"),
        (("validate!", str(tmp_path), "--html", str(notes)), "--html", "HTML"),
    ):
        notes.with_suffix(".png").write_text("my notes\n", encoding="utf-8")
        result = invoke_cli(*args)
        assert result.returncode == 2 and "Traceback" not in result.stderr, (args, result.stderr)
        assert f"{field}: exists and is not {'an' if kind == 'HTML' else 'a'} {kind} file" in result.stderr, (
            args, result.stderr)  # fmt: skip
    assert notes.read_text(encoding="utf-8") == (tmp_path / "v000000-varied.json").read_text(encoding="utf-8")

    # Before any work: the default names and the GIF beside the sheet are checked before a frame is made.
    def no_work(*args, **kwargs):
        raise AssertionError("the video was simulated or rendered before its outputs were checked")

    monkeypatch.setattr("phav_app.cli.simulate", no_work)
    monkeypatch.setattr("phav_app.cli.video_frames", no_work)
    (tmp_path / "v000000-skeleton.png").write_text("my notes\n", encoding="utf-8")
    (tmp_path / "sheet.gif").write_text("my notes\n", encoding="utf-8")
    for args, name, kind in (
        (("preview", str(recipe), "--skeleton"), "v000000-skeleton.png", "PNG"),
        (("preview", str(recipe), "--out", str(tmp_path / "sheet.png")), "sheet.gif", "GIF"),
    ):
        result = invoke_cli(*args)
        assert result.returncode == 2 and f"{name}: --out: exists and is not a {kind} file" in result.stderr, (
            args, result.stderr)  # fmt: skip


def test_a_file_of_another_kind_says_what_it_is(tmp_path):
    """A Parquet table, a shard or a PNG given where a recipe or θ's text is read: the error
    says what the file is, not only that it is not UTF-8; --regenerate-into a file names
    the option."""
    table = tmp_path / "r.parquet"
    assert invoke_cli("sample", "--n", "2", "--out", str(table)).returncode == 0
    for args in (("recipe", "check", str(table)), ("theta", "check", str(table))):
        result = invoke_cli(*args)
        assert result.returncode == 2 and f"{table}: not UTF-8 text: it is a Parquet table" in result.stderr, args
    (tmp_path / "afile").write_text("x")
    result = invoke_cli("validate!", str(table), "--regenerate-into", str(tmp_path / "afile"))
    assert result.returncode == 2 and "--regenerate-into: exists and is not a directory" in result.stderr


def test_a_theta_file_beside_a_recipe_that_is_no_theta_is_not_its_theta(small_recipes, tmp_path):
    """A broken or foreign theta.yaml beside the recipe is passed over (the hint to give
    --theta), not an error that fails a valid recipe."""
    path = tmp_path / "v000000.json"
    path.write_text(small_recipes[0].model_dump_json(), encoding="utf-8")
    (tmp_path / "theta.yaml").write_text("foo: [\n", encoding="utf-8")
    checked = invoke_cli("recipe", "check", str(path))
    assert checked.returncode == 0 and "pass it with --theta" in checked.stdout, checked.stderr
