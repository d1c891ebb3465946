"""phav-validate and phav stats on good and damaged recipe tables."""

from __future__ import annotations

import json
import re

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq
import pytest

from phav_generator.sampling import RecipeSampler
from phav_spec.errors import PhavUserError
from phav_spec.recipe_table import RecipeRows, read_recipe_table, write_recipe_table
from phav_spec.theta import load_preset
from phav_validators.findings import Reason
from phav_validators.options import Options, sample_videos
from tests.helpers import PRESET_PATH, invoke_cli, run_cli, theta_variant
from tests.validators.checks.support import check as check_of
from tests.validators.checks.support import validate

#: Recipes in the good table: enough for every distribution test to run, and for the wrong θ
#: below to be rejected by far.
N = 500


@pytest.fixture(scope="module")
def good(tmp_path_factory):
    folder = tmp_path_factory.mktemp("dataset")
    result = invoke_cli(
        "sample", "--theta", "phav-v1", "--n", str(N), "--seed", "4", "--out", str(folder / "recipes.parquet")
    )
    assert result.returncode == 0, result.stderr
    return folder / "recipes.parquet"


def _rewrite(src, dst, edit):
    table = pq.read_table(src)
    table = edit(table)
    pq.write_table(table, dst)
    return dst


def _replace_column(table: pa.Table, name: str, values) -> pa.Table:
    i = table.column_names.index(name)
    return table.set_column(i, name, pa.array(values, type=table.schema.field(name).type))


def test_good_table_passes(good):
    result = run_cli("validate!", str(good))  # the installed entry point, in a fresh process
    assert result.returncode == 0, result.stdout + result.stderr
    assert f"{N} recipes" in result.stdout and f"{N}/{N} recipes valid" in result.stdout
    assert "all checks passed" in result.stdout
    stats = invoke_cli("stats", str(good))
    assert stats.returncode == 0 and "goodness of fit" in stats.stdout and "camera" in stats.stdout
    for alpha in ("nan", "-1", "5"):  # not significance levels: NaN passed every test
        stats = invoke_cli("stats", str(good), "--alpha", alpha)
        assert stats.returncode == 2 and "--alpha: must be in (0, 1)" in stats.stderr, stats.stderr


def test_an_empty_table_has_nothing_to_test(tmp_path):
    """0 recipes: `phav stats` refuses (it printed a NaN mean and "all checks passed"), and
    phav-validate skips the distribution check rather than passing it: nothing checked."""
    empty = tmp_path / "empty.parquet"
    assert invoke_cli("sample", "--n", "0", "--out", str(empty)).returncode == 0
    stats = invoke_cli("stats", str(empty))
    assert stats.returncode == 2 and "empty.parquet: the table has no recipes" in stats.stderr, stats.stderr
    assert "nan" not in stats.stdout + stats.stderr and "Traceback" not in stats.stderr
    result = invoke_cli("validate!", str(empty), "--checks", "distribution")
    assert result.returncode == 1 and "SKIP" in result.stdout and "has no rows" in result.stdout, result.stdout
    assert "nothing checked" in result.stdout


def test_dataset_directory_with_theta_yaml(good):
    (good.parent / "theta.yaml").write_text(PRESET_PATH.read_text(encoding="utf-8"), encoding="utf-8")
    result = invoke_cli("validate!", str(good.parent), "--details")
    assert result.returncode == 0 and "environment" in result.stdout


def test_column_disagreeing_with_recipe_is_found(good, tmp_path):
    def edit(t):
        cams = t.column("camera").to_pylist()
        cams[7] = "indoors" if cams[7] != "indoors" else "kite"
        return _replace_column(t, "camera", cams)

    bad = _rewrite(good, tmp_path / "r.parquet", edit)
    result = invoke_cli("validate!", str(bad), "--theta", "phav-v1")
    assert result.returncode == 1
    assert "COLUMN_MISMATCH" in result.stdout and "v000007" in result.stdout


def test_invalid_recipe_json_is_found_and_the_rest_still_checked(good, tmp_path):
    def edit(t):
        texts = t.column("recipe").to_pylist()
        data = json.loads(texts[3])
        data["world"]["weather"] = "snow"
        texts[3] = json.dumps(data)
        texts[5] = texts[5][:40]
        return _replace_column(t, "recipe", texts)

    bad = _rewrite(good, tmp_path / "r.parquet", edit)
    result = invoke_cli("validate!", str(bad), "--theta", "phav-v1")
    assert result.returncode == 1
    assert result.stdout.count("schema RECIPE_INVALID") == 2
    assert "world.weather" in result.stdout and f"{N - 2}/{N} recipes valid" in result.stdout


def test_wrong_theta_is_reported(good, tmp_path):
    other = theta_variant(tmp_path, lambda d: d.update(theta_w={"clear": 3, "overcast": 1, "rain": 1, "fog": 1}))
    result = invoke_cli("validate!", str(good), "--theta", str(other))
    assert result.returncode == 1
    assert "THETA_MISMATCH" in result.stdout and "DISTRIBUTION_MISMATCH" in result.stdout
    assert "weather" in result.stdout


def test_truncated_and_foreign_files_are_user_errors(good, tmp_path):
    truncated = tmp_path / "truncated.parquet"
    truncated.write_bytes(good.read_bytes()[: good.stat().st_size // 2])
    for args in (("validate!", str(truncated)), ("stats", str(truncated))):
        result = invoke_cli(*args)
        assert result.returncode == 2 and "Traceback" not in result.stderr
        assert "truncated.parquet: not a readable Parquet file" in result.stderr
    foreign = tmp_path / "foreign.parquet"
    pq.write_table(pa.table({"x": [1, 2]}), foreign)
    with pytest.raises(PhavUserError, match=r"foreign\.parquet: video_id: missing column"):
        read_recipe_table(foreign)
    missing = invoke_cli("validate!", str(tmp_path / "nope.parquet"))
    assert missing.returncode == 2 and "no such file" in missing.stderr


@pytest.mark.parametrize(
    ("column", "values", "message"),
    [
        ("duration_s", lambda n: ["abc"] * n, "duration_s: column is string, a recipes table's is double"),
        ("weather", lambda n: [["fog"]] * n, "weather: column is list<element: string>, a recipes table's is string"),
        ("video_id", lambda n: [[f"v{i:06d}"] for i in range(n)],
         "video_id: column is list<element: string>, a recipes table's is string"),
    ],
)  # fmt: skip
def test_a_recipes_column_of_another_type_is_a_user_error(good, tmp_path, column, values, message):
    table = pq.read_table(good)
    at = table.column_names.index(column)
    bad = tmp_path / "typed.parquet"
    pq.write_table(table.set_column(at, column, pa.array(values(table.num_rows))), bad)
    with pytest.raises(PhavUserError) as e:
        read_recipe_table(bad)
    assert str(e.value) == f"{bad}: {message}"
    for args in (("validate!", str(bad)), ("validate!", str(bad), "--checks", "schema")):
        result = invoke_cli(*args)
        assert result.returncode == 2 and "Traceback" not in result.stderr, result.stderr


def test_corrupt_table_metadata_is_a_user_error(good, tmp_path):
    table = pq.read_table(good)
    meta = dict(table.schema.metadata)
    cases = {
        "phav.recipe_schema_version": (b"abc", "not an integer"),
        "phav.dataset_seed": (b"-4", "must be non-negative"),
        "phav.theta": (b"{oops", "invalid JSON"),
    }
    for key, (value, words) in cases.items():
        path = tmp_path / f"{key}.parquet"
        pq.write_table(table.replace_schema_metadata({**meta, key.encode(): value}), path)
        result = invoke_cli("stats", str(path))
        assert result.returncode == 2 and "Traceback" not in result.stderr, result.stderr
        assert words in result.stderr


def test_empty_dataset(tmp_path):
    theta = load_preset()
    path = tmp_path / "empty.parquet"
    write_recipe_table(RecipeRows().to_arrow(theta=theta, dataset_seed=0), path)
    rt = read_recipe_table(path)
    assert rt.table.num_rows == 0 and rt.theta == theta
    result = invoke_cli("validate!", str(path))
    assert result.returncode == 0 and "0 recipes" in result.stdout


def test_writes_are_atomic(tmp_path):
    """A failed write leaves the previous file intact and no temp files behind."""
    theta = load_preset()
    path = tmp_path / "recipes.parquet"
    rows = RecipeRows().extend(RecipeSampler(theta).sample(0, i) for i in range(3))
    write_recipe_table(rows.to_arrow(theta=theta, dataset_seed=0), path)
    before = path.read_bytes()

    class Boom(RuntimeError):
        pass

    class BadTable:
        def __getattr__(self, name):
            raise Boom

    with pytest.raises(Exception):  # noqa: B017 - whatever pyarrow raises on a non-table
        write_recipe_table(BadTable(), path)
    assert path.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["recipes.parquet"]


@pytest.mark.parametrize(
    ("option", "message"),
    [
        ({"alpha": float("nan")}, "--alpha: must be in (0, 1), got nan"),
        ({"alpha": 5.0}, "--alpha: must be in (0, 1), got 5.0"),
        ({"budget": -0.1}, "--failure-budget: must be in [0, 1], got -0.1"),
        ({"sample": 0.0}, "--sample: must be in (0, 1], got 0.0"),
        ({"seed": -1}, "--seed: must be at least 0, got -1"),
    ],
)
def test_options_out_of_their_range_are_one_line_naming_the_option(option, message):
    with pytest.raises(PhavUserError) as e:
        Options(**option)
    assert str(e.value) == message


@pytest.mark.parametrize("fraction", [0.07, 0.14, 0.28, 0.55, 0.56, 0.5, 0.001])
def test_a_sample_is_the_ceiling_of_its_share_exactly(fraction):
    ids = [f"v{i:06d}" for i in range(100)]  # 0.07 · 100 is 7.000000000000001 in floats
    expected = max(1, -(-round(fraction * 1000) * 100 // 1000))
    assert len(sample_videos(ids, fraction, seed=0)) == expected


def test_the_json_report_writes_non_finite_numbers_as_null_and_leaves_text_alone(tmp_path, monkeypatch):
    from phav_validators import report as report_module

    data = {"member": "v000000/NaN.rgb.png", "error_px": float("inf"), "p": np.float64("nan"),
            "low": -np.inf, "rows": [np.int64(3), (1.5, float("nan"))]}  # fmt: skip
    monkeypatch.setattr(report_module, "report_json", lambda reports: data)
    report_module.write_json([], tmp_path / "r.json")

    def strict(name: str) -> None:
        raise ValueError(f"{name} is not JSON")

    back = json.loads((tmp_path / "r.json").read_text(), parse_constant=strict)
    assert back == {"member": "v000000/NaN.rgb.png", "error_px": None, "p": None, "low": None, "rows": [3, [1.5, None]]}


def test_a_shard_named_twice_is_validated_once(small_dataset):
    from phav_validators.source import resolve

    shard = small_dataset / "phav-000000.tar"
    [inp] = resolve([shard, shard, small_dataset / "." / "phav-000000.tar"])
    assert inp.shards == [shard.resolve()]


def test_report_files_that_cannot_be_written_are_refused_before_any_check(good, tmp_path):
    for option in ("--json", "--html"):
        result = invoke_cli("validate!", str(good), option, str(tmp_path))  # a folder
        assert result.returncode == 2 and "Traceback" not in result.stderr
        assert f"{option}: cannot be written here: Is a directory" in result.stderr
        assert "distribution" not in result.stdout  # no check ran
    result = invoke_cli("validate!", str(good), "--engine", "local", "--address", "10.0.0.1:6379")
    assert result.returncode == 2 and "--address: a Ray cluster address needs --engine ray" in result.stderr


def test_a_recipe_only_release_regenerates_every_shard_for_the_checks_that_read_them_all():
    """Learnability and realism sample the whole dataset themselves: with --sample below 1,
    the shards rebuilt from a recipe-only release are all of them, not only those holding the
    sampled videos (realism was then skipped, asking for the directory the user had named)."""
    from types import SimpleNamespace

    from phav_validators.options import Options
    from phav_validators.regenerated import _shards_to_build

    shards = [[SimpleNamespace(video_id=f"v{i:06d}")] for i in range(8)]
    plan = SimpleNamespace(shards=shards, expected=SimpleNamespace(videos=[s[0] for s in shards]))
    some = _shards_to_build(plan, Options(checks=("integrity",), sample=0.25))
    assert 0 < len(some) < len(shards)
    for check in ("learnability", "realism"):
        assert _shards_to_build(plan, Options(checks=("integrity", check), sample=0.25)) == list(range(len(shards)))


def test_an_invalid_theta_yaml_is_a_finding_naming_its_field(small_dataset_copy):
    """A dataset's theta.yaml that is not a valid θ: the finding names the field (it gave
    pydantic's words alone), and the summary says the file is there and wrong."""
    data = small_dataset_copy
    text = (data / "theta.yaml").read_text(encoding="utf-8")
    (data / "theta.yaml").write_text(re.sub(r"t_min: [0-9.]+", "t_min: -1.0", text, count=1), encoding="utf-8")
    report = validate(data, "distribution")
    (finding,) = check_of(report, "distribution").report.findings
    assert finding.reason == Reason.THETA_MISMATCH and finding.message.startswith("durations.t_min: "), finding.message
    assert "theta.yaml is not a valid θ" in check_of(report, "distribution").summary
