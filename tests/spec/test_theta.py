"""θ: loading, validation (every bad input is one clear line naming file and field), hash."""

from __future__ import annotations

import json
import math
import os
import threading
from pathlib import Path

import pytest
import yaml

from phav_spec.errors import PhavUserError
from phav_spec.files import parse_json_object
from phav_spec.theta import PRESETS_DIR, Theta, load_preset, load_theta, parse_theta
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
    "a camera kicked too fast": (_set("cameras.kite.springs.camera_mass", {"kind": "uniform", "low": 0.01, "high": 1.0}),
                                 "cameras.kite", "throws it at up to 500 m/s; at most 50"),
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
    # A wrapped interval draws from its whole period: a field of view of 0–200° otherwise.
    "field of view wrapped past its range": (_set("cameras.kite.fov_deg", {"kind": "triangular", "min": 100, "max": 20, "mode": 110, "period": 200}), "cameras.kite", "wrapped support [0, 200.0) leaves the allowed range [10.0, 120.0]"),
    "zero perturbation period": (_set("variations.random_perturbation.period_s", {"kind": "uniform", "low": 0.0, "high": 0.0}), "variations.random_perturbation.period_s", "allowed range"),
    "a crowd of background actors": (_set("background_actors.count", {"min": 0, "max": 3_000_000_000}), "background_actors.count.max", "at most 50"),
    "future format": (_set("format_version", 99), "format_version", "newer than this phav"),
    "format written as a float": (_set("format_version", 2.0), "format_version", "must be a whole number, got 2.0"),
    "format written as text": (_set("format_version", "7"), "format_version", "must be a whole number, got '7'"),
    "format below one": (_set("format_version", -3), "format_version", "Input should be 1"),
    "frame rate written yes": (_set("video.fps", True), "video.fps", "valid integer"),
    # A sum of two huge weights overflows (every draw the last value); tiny ones are subnormal.
    "weights that overflow": (_set("theta_w", {"clear": 1e308, "fog": 1e308}), "theta_w", "must be 0 or in [1e-100, 1e+100]"),
    "subnormal weights": (_set("theta_w", {"clear": 5e-324, "fog": 5e-324}), "theta_w", "must be 0 or in [1e-100, 1e+100]"),
    "unknown clip start": (_set("motion.start", "middle"), "motion.start", "'uniform' or 'active'"),
    "a table's stray keys, a number and a name": (_set("theta_ae", {"default": "uniform", 1: 2, "zz": 3}), "theta_ae", "unexpected key 1; a table has"),
}  # fmt: skip


@pytest.mark.parametrize("case", sorted(BAD))
def test_bad_theta_names_file_and_field(tmp_path, case):
    edit, field, words = BAD[case]
    _assert_one_line_error(theta_variant(tmp_path, edit), field, words)


def _assert_one_line_error(path, field: str, words: str) -> None:
    """Loading the θ at ``path`` fails with one line naming the file and ``field``."""
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


def test_the_pure_python_parser_reads_the_same_theta(tmp_path, monkeypatch):
    """Where PyYAML lacks libyaml, its own parser gives the same θ and the same refusals."""
    import yaml

    from phav_spec import theta as theta_module

    fast = load_theta(PRESET_PATH)
    monkeypatch.setattr(theta_module, "_LOADER", yaml.SafeLoader)
    assert load_theta(PRESET_PATH).hash == fast.hash
    path = tmp_path / "dup.yaml"
    path.write_text(PRESET_PATH.read_text(encoding="utf-8") + "\ntheta_w: {clear: 1}\n", encoding="utf-8")
    with pytest.raises(PhavUserError, match=r"dup\.yaml: line \d+: theta_w: key written twice"):
        load_theta(path)


def test_keys_that_read_as_the_same_number_are_refused(tmp_path):
    path = theta_variant(tmp_path, _set("cameras.kite.springs.min_distance_weights", {0: 1, 1: 1, 2: 1}))
    lines = path.read_text(encoding="utf-8").splitlines(keepends=True)
    at = next(i for i, line in enumerate(lines) if line.strip() == "2: 1")
    indent = lines[at][: len(lines[at]) - len(lines[at].lstrip())]
    lines.insert(at + 1, f"{indent}2.0: 0\n")  # the same key as 2, in another spelling
    path.write_text("".join(lines), encoding="utf-8")
    with pytest.raises(PhavUserError, match=r"line \d+: 2\.0: key written twice"):
        load_theta(path)


@pytest.mark.parametrize(
    ("weights", "said"),
    [
        ({0: 1e308, 1: 1e308, 2: 1e308}, "must be 0 or in"),  # their sum is inf: every draw the same
        ({0: 1e-320}, "must be 0 or in"),
        ({1: 1, "1": 0, 0: 1}, "1 m is given twice"),  # one distance in two spellings: one was lost
        ({0: True}, "must be a number"),
        ({5: 1}, "5 m is not one of"),
        ({0: -1}, "finite and non-negative"),
    ],
)
def test_dead_zone_weights_follow_the_rules_of_every_categorical(tmp_path, weights, said):
    """The kite's ``min_distance_weights`` took any finite non-negative number: sums
    overflowing to inf gave one distance for every draw, and ``1`` and ``"1"`` merged."""
    path = theta_variant(tmp_path, _set("cameras.kite.springs.min_distance_weights", weights))
    with pytest.raises(PhavUserError, match=rf"cameras\.kite\.springs\.min_distance_weights: .*{said}"):
        load_theta(path)


@pytest.mark.parametrize(
    ("path", "value"),
    [("durations.t_min", True), ("motion.p_mirror", True), ("video.width", "340"), ("video.width", True),
     ("background_actors.count.max", "3"), ("render.supersampling", True)],
)  # fmt: skip
def test_a_number_is_a_number_not_a_boolean_or_a_quoted_string(tmp_path, path, value):
    """YAML's ``yes`` or ``true`` read as 1 and ``"340"`` as 340 wherever θ wants a number,
    as the categoricals' weights and the frame rate already refused."""
    with pytest.raises(
        PhavUserError, match=rf"{path.replace('.', '[.]')}: (Input should be a valid|expected a number)"
    ):
        load_theta(theta_variant(tmp_path, _set(path, value)))


@pytest.mark.parametrize("value", [True, "0.5"])
def test_a_probability_is_a_number_not_a_boolean_or_a_quoted_string(tmp_path, value):
    text = (PRESETS_DIR / "phav-people.yaml").read_text(encoding="utf-8")
    path = tmp_path / "people.yaml"
    path.write_text(text.replace("  p_female: 0.5", f"  p_female: {json.dumps(value)}"), encoding="utf-8")
    with pytest.raises(PhavUserError, match=r"people\.p_female: Input should be a valid number"):
        load_theta(path)


def test_a_tables_default_row_is_checked_when_every_row_is_given(tmp_path):
    """A ``default`` every action overrides was not read at all: ``{bogus: -5}`` loaded."""
    from phav_spec.vocab import ACTIONS

    rows = {a: "uniform" for a in ACTIONS.names}
    path = theta_variant(tmp_path, _set("theta_ac", {"default": {"bogus": -5}, "rows": rows}))
    with pytest.raises(PhavUserError, match=r"theta_ac\.default: unknown camera 'bogus'"):
        load_theta(path)


def test_a_node_shared_by_aliases_is_checked_once(tmp_path, monkeypatch):
    """Aliases share their node: walked again at every use, 30 levels of them were 2^30 visits."""
    from phav_spec import theta as theta_module

    levels = ["a0: &a0 [x, y]"] + [f"a{i}: &a{i} [*a{i - 1}, *a{i - 1}]" for i in range(1, 31)]
    path = tmp_path / "aliases.yaml"
    path.write_text("\n".join(levels) + "\n", encoding="utf-8")
    visits = []
    walk = theta_module._refuse_duplicate_keys
    monkeypatch.setattr(theta_module, "_refuse_duplicate_keys", lambda node, **kw: visits.append(1) or walk(node, **kw))
    with pytest.raises(PhavUserError):  # no θ, but its keys were looked at first
        load_theta(path)
    assert len(visits) < 200


def test_a_number_past_pythons_digit_limit_is_a_one_line_error(tmp_path):
    path = tmp_path / "huge.yaml"
    path.write_text(f"format_version: 1{'0' * 5000}\n", encoding="utf-8")
    with pytest.raises(PhavUserError, match=r"huge\.yaml: invalid YAML: Exceeds the limit"):
        load_theta(path)
    with pytest.raises(PhavUserError, match=r"r\.json: invalid JSON: Exceeds the limit"):
        parse_json_object('{"dataset_seed": 1' + "0" * 5000 + "}", source="r.json")


def test_a_negative_zero_weight_is_the_theta_of_zero():
    base = preset_dict()
    zero = dict(base, theta_d={**base["theta_d"], "night": 0.0}) if isinstance(base.get("theta_d"), dict) else None
    if zero is None:
        pytest.skip("the preset writes theta_d as a word")
    negative = dict(base, theta_d={**base["theta_d"], "night": -0.0})
    assert parse_theta(negative, source="x").hash == parse_theta(zero, source="x").hash


def test_deep_nesting_a_device_and_an_unreadable_place_are_one_line_errors(tmp_path, monkeypatch):
    """Nothing a user can point ``--theta`` at ends in a traceback or all memory; a pipe
    (``<(…)``, ``/dev/stdin``) is read."""
    deep = tmp_path / "deep.yaml"
    deep.write_text("a: " + "[" * 5000 + "]" * 5000 + "\n", encoding="utf-8")
    # libyaml's limit, or Python's recursion limit without it
    with pytest.raises(
        PhavUserError, match=r"deep\.yaml(: line 1)?: invalid YAML: (nested too deeply|exceeded maximum nesting depth)"
    ):
        load_theta(deep)
    with pytest.raises(PhavUserError, match=r"/dev/zero: not a file or a pipe \(a device or a socket\)"):
        load_theta("/dev/zero")
    with pytest.raises(PhavUserError, match=r"r\.json: invalid JSON: nested too deeply"):
        parse_json_object("[" * 100_000 + "]" * 100_000, source="r.json")
    pipe = tmp_path / "pipe.yaml"
    os.mkfifo(pipe)
    writer = threading.Thread(target=lambda: pipe.write_text(PRESET_PATH.read_text(encoding="utf-8")))
    writer.start()
    assert load_theta(pipe).hash == load_preset().hash
    writer.join()

    def locked(self):  # a folder on the way that a user may not enter
        raise PermissionError(13, "Permission denied", str(self))

    monkeypatch.setattr(Path, "exists", locked)
    with pytest.raises(PhavUserError, match=r"locked/t\.yaml: cannot read: Permission denied"):
        load_theta(tmp_path / "locked" / "t.yaml")


def test_only_bare_names_fall_back_to_presets(tmp_path, monkeypatch):
    assert load_theta("phav-v1").name == "phav-v1"
    with pytest.raises(PhavUserError, match="no such file"):
        load_theta(tmp_path / "phav-v1")
    monkeypatch.chdir(tmp_path)
    (tmp_path / "phav-v1-short").mkdir()  # a dataset named after its preset: resuming it reads the preset
    assert load_theta("phav-v1-short").name == "phav-v1-short"


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


# --------------------------------------------------------------------------- people

PEOPLE_PATH = PRESETS_DIR / "phav-people.yaml"


def _people_variant(tmp_path, edit):
    data = yaml.safe_load(PEOPLE_PATH.read_text(encoding="utf-8"))
    edit(data)
    path = tmp_path / "people.yaml"
    path.write_text(yaml.safe_dump(data, sort_keys=False), encoding="utf-8")
    return path


_UNIFORM = lambda lo, hi: {"kind": "uniform", "low": lo, "high": hi}  # noqa: E731

BAD_PEOPLE = {
    "adults younger than 16": (_set("people.adult_age_years", _UNIFORM(10, 40)), "people.adult_age_years", "allowed range [16.0, 90.0] years"),
    "children older than 16": (_set("people.child_age_years", _UNIFORM(5, 18)), "people.child_age_years", "allowed range"),
    "statures beyond 3 sd": (_set("people.stature_z", _UNIFORM(-4, 4)), "people.stature_z", "allowed range"),
    "gender offset crossing the sexes": (_set("people.gender_offset", _UNIFORM(0, 0.6)), "people.gender_offset", "allowed range"),
    "anny weight above one": (_set("people.weight", _UNIFORM(0.5, 1.2)), "people.weight", "allowed range"),
    "misspelt people key": (_set("people.skin_tones", _UNIFORM(0, 1)), "people.skin_tones", "unknown key"),
    "unknown hair style": (_set("people.hair.styles", {"curly": 1}), "people.hair.styles", "unknown hair style 'curly'"),
    "all-zero tops": (_set("people.outfit.tops", {}), "people.outfit.tops", "all weights are zero"),
    "no bottoms for men": (_set("people.outfit.bottoms.male", {"skirt": 0}), "people.outfit.bottoms.male", "all weights are zero"),
    "bottoms for one sex only": (lambda d: d["people"]["outfit"]["bottoms"].pop("male"), "people.outfit.bottoms.male", "missing"),
    "greying backwards": (_set("people.hair.grey", {"start_years": 70, "full_years": 40, "p_full": 0.5}), "people.hair.grey", "start_years (70.0) must not exceed"),
    "p_child above one": (_set("people.p_child", 1.5), "people.p_child", "less than or equal to 1"),
    "unknown mode": (_set("people.mode", "crowd"), "people.mode", "Input should be 'models' or 'sampled'"),
    "models mode with distributions": (_set("people.mode", "models"), "people.p_female", "mode 'models' takes no distributions"),
    "missing distribution": (lambda d: d["people"].pop("skin_tone"), "people.skin_tone", "missing"),
}  # fmt: skip


@pytest.mark.parametrize("case", sorted(BAD_PEOPLE))
def test_bad_people_section_names_file_and_field(tmp_path, case):
    edit, field, words = BAD_PEOPLE[case]
    _assert_one_line_error(_people_variant(tmp_path, edit), field, words)


def test_people_of_h_are_the_same_theta_with_or_without_the_section():
    data = preset_dict()
    data["people"] = {"mode": "models"}
    theta = parse_theta(data)
    assert theta.people is None and theta.hash == load_preset().hash
    assert "people" not in yaml.safe_load(theta.to_yaml())


def test_the_people_preset_draws_people_and_round_trips():
    theta = load_theta("phav-people")
    assert theta.people is not None and theta.people_sampled
    again = parse_theta(yaml.safe_load(theta.to_yaml()))
    assert again == theta and again.people == theta.people
    # Per-sex weights may be one shared set: the same θ as writing it out for both sexes.
    data = yaml.safe_load(PEOPLE_PATH.read_text(encoding="utf-8"))
    data["people"]["outfit"]["tops"] = {"sleeveless": 1, "short_sleeves": 3, "long_sleeves": 3}
    data["people"]["hair"]["colours"] = {"black": 5, "brown": 4, "blond": 1.5, "red": 0.5}
    styles = data["people"]["hair"]["styles"]["male"]
    data["people"]["hair"]["styles"] = styles
    shared = parse_theta(data)
    expected = {k: float(v) for k, v in styles.items()}
    assert shared.people.hair.styles["female"] == shared.people.hair.styles["male"] == expected
    # θ_H is unused when people are sampled: it may be left out, or weigh nothing.
    data["theta_h"] = {}
    assert parse_theta(data).people is not None
    result = run_cli("theta", "show", "phav-people")
    assert result.returncode == 0 and "mode: sampled" in result.stdout


def test_the_uniform_clip_start_is_the_theta_from_before_the_choice_existed():
    data = preset_dict()
    data["motion"]["start"] = "uniform"
    theta = parse_theta(data)
    assert theta.hash == load_preset().hash and "start" not in yaml.safe_load(theta.to_yaml())["motion"]
    short = load_theta("phav-v1-short")
    assert short.motion.start == "active" and load_preset().motion.start == "uniform"
    again = parse_theta(yaml.safe_load(short.to_yaml()))
    assert again == short and again.motion.start == "active"
    data["motion"]["start"] = "active"
    assert parse_theta(data).hash != load_preset().hash
