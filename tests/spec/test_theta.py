"""θ: loading, validation (every bad input is one clear line naming file and field), hash."""

from __future__ import annotations

import math

import pytest
import yaml

from phav_spec.errors import PhavUserError
from phav_spec.theta import Theta, load_preset, load_theta, parse_theta
from phav_spec.vocab import ACTIONS
from tests.helpers import PRESET_PATH, preset_dict, run_cli, theta_variant


def test_preset_loads_by_path_and_by_name():
    by_path = load_theta(PRESET_PATH)
    assert by_path == load_theta("phav-v1") == load_preset()
    assert by_path.name == "phav-v1"


def test_hash_is_canonical_and_survives_a_yaml_round_trip():
    theta = load_preset()
    again = parse_theta(yaml.safe_load(theta.to_yaml()))
    assert again.hash == theta.hash and len(theta.hash) == 64
    # "uniform" and the explicit equal weights are the same θ, hence the same hash.
    data = preset_dict()
    data["theta_w"] = {"clear": 1, "overcast": 1, "rain": 1, "fog": 1}
    assert parse_theta(data).hash == theta.hash
    data["theta_w"] = {"clear": 2, "overcast": 1, "rain": 1, "fog": 1}
    assert parse_theta(data).hash != theta.hash


def test_paper_values_in_the_preset():
    theta = load_preset()
    arr = theta.arrays
    assert theta.theta_d == {"dawn": 1.0, "day": 1.0, "dusk": 1.0, "night": 0.0}
    assert set(arr.w) == {1.0} and set(arr.a) == {1.0} and set(arr.h) == {1.0}
    assert theta.theta_c == {"kite": 1.0, "indoors": 1.0, "closeup": 1.0, "static": 0.0}
    assert (theta.durations.t_min, theta.durations.t_max) == (1.0, 10.0)
    night = theta.clock_hours["night"]
    assert (night.min, night.max, night.mode) == (20.0, 7.0, 0.0)
    assert theta.video.width == 340 and theta.video.height == 256 and theta.video.fps == 30
    # Indoors camera only in the house; close-up only for brush hair.
    assert all(row["indoors"] == 0 for env, row in theta.theta_ec.items() if env != "house_interior")
    assert [a for a, row in theta.theta_ac.items() if row["closeup"] > 0] == ["brush_hair"]


def _set(path: str, value):
    def edit(d):
        *parents, last = path.split(".")
        for p in parents:
            d = d[p]
        d[last] = value

    return edit


def _rename(old: str, new: str):
    def edit(d):
        d[new] = d.pop(old)

    return edit


BAD = {
    "negative weight": (_set("theta_a", {"walk": -1, "run": 1}), "theta_a", "non-negative"),
    "NaN weight": (_set("theta_w", {"clear": math.nan, "fog": 1}), "theta_w", "finite"),
    "infinite weight": (_set("theta_h", {"model_01": math.inf, "model_02": 1}), "theta_h", "finite"),
    "all-zero row": (_set("theta_ae.rows.walk", {}), "theta_ae.rows.walk", "all-zero row"),
    "all-zero vector": (_set("theta_v", {}), "theta_v", "all weights are zero"),
    "unknown action": (_set("theta_a", {"walkk": 1}), "theta_a", "did you mean 'walk'"),
    "unknown environment in a row": (_set("theta_ae.rows.walk", {"moon": 1}), "theta_ae", "unknown environment 'moon'"),
    "misspelt top-level key": (_rename("theta_a", "theta_aa"), "theta_aa", "unknown key"),
    "misspelt nested key": (_set("durations.t_mni", 1.0), "durations.t_mni", "unknown key"),
    "T_min > T_max": (_set("durations", {"t_min": 5, "t_max": 2, "t_mod": 3}), "durations", "t_min (5.0) must not exceed t_max (2.0)"),
    "T_mod outside": (_set("durations", {"t_min": 1, "t_max": 10, "t_mod": 12}), "durations", "t_mod"),
    "T_min longer than every motion": (_set("durations", {"t_min": 9.9, "t_max": 10, "t_mod": 10}), "durations.t_min", "longer than every motion"),
    "indoors camera outdoors": (_set("theta_ec.default.indoors", 1), "theta_ec.rows.simple.indoors", "needs an indoor environment"),
    "car hit without a road": (_set("theta_ae.rows.car_hit", {"green": 1}), "theta_ae.rows.car_hit.green", "no road"),
    "climbing stairs indoors": (
        _set("theta_ae.rows.climb_stairs", {"urban": 1, "house_interior": 1}),
        "theta_ae.rows.climb_stairs.house_interior",
        "needs open sky",
    ),
    "regex that does not compile": (_set("theta_ab.regex.walk", "(("), "theta_ab.regex.walk", "does not compile"),
    "regex that matches nothing": (_set("theta_ab.regex.walk", "^zzz$"), "theta_ab.regex.walk", "matches no motion"),
    "stiff spring": (_set("cameras.kite.springs.ct_spring_strength", {"kind": "uniform", "low": 1, "high": 1e7}), "cameras.kite.springs.ct_spring_strength", "allowed range"),
    "unknown distribution": (_set("motion.speed", {"kind": "normal", "mean": 1}), "motion.speed", "does not match any of the expected tags"),
    "mode outside the night interval": (_set("clock_hours.night", {"min": 20, "max": 7, "mode": 12}), "clock_hours.night", "mode"),
    "missing day phase": (lambda d: d["clock_hours"].pop("dusk"), "clock_hours.dusk", "missing"),
    "one human model for two-people actions": (_set("theta_h", {"model_01": 1}), "theta_h", "supporting character"),
    "objects for an action without props": (_set("theta_av.rows.clap", "uniform"), "theta_av.rows.clap.objects", "declares no objects"),
    "probability above one": (_set("weather_elements.fog.clouds.p_if_parent", 1.5), "weather_elements.fog.clouds.p_if_parent", "less than or equal to 1"),
    "variation on zero muscles": (_set("variations.random_perturbation.n_muscles", {"min": 0, "max": 0}), "variations.random_perturbation.n_muscles.min", "greater than or equal to 1"),
    "negative motion speed": (_set("motion.speed", {"kind": "uniform", "low": -1, "high": 1.1}), "motion.speed", "allowed range"),
    "zero perturbation period": (_set("variations.random_perturbation.period_s", {"kind": "uniform", "low": 0.0, "high": 0.0}), "variations.random_perturbation.period_s", "allowed range"),
    "a crowd of background actors": (_set("background_actors.count", {"min": 0, "max": 3_000_000_000}), "background_actors.count.max", "at most 50"),
    "future format": (_set("format_version", 99), "format_version", "newer than this phav"),
}  # fmt: skip


@pytest.mark.parametrize("case", sorted(BAD))
def test_bad_theta_names_file_and_field(tmp_path, case):
    edit, field, words = BAD[case]
    path = theta_variant(tmp_path, edit)
    with pytest.raises(PhavUserError) as info:
        load_theta(path)
    message = str(info.value)
    assert message.startswith(f"{path}: {field}"), message
    assert words in message
    assert "\n" not in message


@pytest.mark.parametrize(
    "case",
    [
        "negative weight",
        "NaN weight",
        "all-zero row",
        "unknown action",
        "misspelt nested key",
        "T_min > T_max",
    ],
)
def test_bad_theta_on_the_command_line_is_one_line_and_exit_2(tmp_path, case):
    edit, field, _ = BAD[case]
    path = theta_variant(tmp_path, edit)
    result = run_cli("theta", "check", str(path))
    assert result.returncode == 2
    assert "Traceback" not in result.stderr
    lines = [line for line in result.stderr.splitlines() if line.strip()]
    assert len(lines) == 1 and f"{path}: {field}" in lines[0], result.stderr


def test_unreadable_inputs(tmp_path):
    broken = tmp_path / "broken.yaml"
    broken.write_text("theta_a: [\n", encoding="utf-8")
    with pytest.raises(PhavUserError, match=r"broken.yaml: line \d+: invalid YAML"):
        load_theta(broken)
    with pytest.raises(PhavUserError, match="no such file"):
        load_theta(tmp_path / "missing.yaml")
    scalar = tmp_path / "scalar.yaml"
    scalar.write_text("42\n", encoding="utf-8")
    with pytest.raises(PhavUserError, match="mapping at the top level"):
        load_theta(scalar)


def test_duplicate_keys_are_refused(tmp_path):
    text = PRESET_PATH.read_text(encoding="utf-8") + "\ntheta_w: {clear: 1}\n"
    path = tmp_path / "dup.yaml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(PhavUserError, match=r"dup\.yaml: line \d+: theta_w: key written twice"):
        load_theta(path)


def test_only_bare_names_fall_back_to_presets(tmp_path):
    assert load_theta("phav-v1").name == "phav-v1"
    with pytest.raises(PhavUserError, match="no such file"):
        load_theta(tmp_path / "phav-v1")


def test_name_and_description_do_not_change_the_hash():
    data = preset_dict()
    data["name"], data["description"] = "renamed", "edited"
    assert parse_theta(data).hash == load_preset().hash


def test_yaml_is_loaded_safely(tmp_path):
    evil = tmp_path / "evil.yaml"
    evil.write_text("name: !!python/object/apply:os.system ['echo pwned']\n", encoding="utf-8")
    with pytest.raises(PhavUserError, match="invalid YAML"):
        load_theta(evil)


def test_unreachable_rows_may_be_zero():
    data = preset_dict()
    data["theta_a"] = {"walk": 1, "run": 1}
    data["theta_ae"]["rows"]["clap"] = {}  # clap is never sampled: a zero row is fine
    theta = parse_theta(data)
    assert isinstance(theta, Theta)
    assert theta.arrays.ae[ACTIONS.index("clap")].sum() == 0
