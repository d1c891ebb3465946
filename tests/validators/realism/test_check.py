"""The realism check end to end on the shared dataset: figures with intervals, the same
figures for the same seed, minimums that fail, and one-line errors."""

from __future__ import annotations

import json
import shutil
import sys
from dataclasses import replace

import numpy as np
import pytest

from phav_spec.errors import PhavUserError
from phav_validators.findings import Reason, Status
from phav_validators.realism.check import (
    HEADLINES,
    RealismOptions,
    Tally,
    cityscapes_miou,
    conditions_of,
    judge_world,
    parse_minimums,
    realism_check,
    run_realism,
    view_of,
)
from phav_validators.realism.judges import JUDGE_MODELS, MODELS_DIR
from tests.helpers import invoke_cli

pytest.importorskip("ai_edge_litert")


@pytest.fixture(scope="module")
def judged(small_dataset):
    return run_realism(small_dataset, RealismOptions(frames=12, seed=5))


def test_the_check_judges_people_and_world_with_intervals(judged):
    assert judged.frames == 12 and judged.videos == 3 and judged.people > 0
    assert set(judged.models) == set(JUDGE_MODELS)
    for key in ("person_found|all", "person_pck_0.2|all", "iou|pascal_voc|person|all", "recall|pascal_voc|person|all"):
        fig = judged.figures[key]
        assert 0 <= fig.low <= fig.value <= fig.high <= 1 and fig.count > 0 and 1 <= fig.videos <= 3, key
    # The shared set's scenes: urban and stadium outdoors (judged by Cityscapes), "simple" too.
    assert any(k.startswith("iou|cityscapes|") for k in judged.figures)
    assert "cityscapes_miou" in judged.figures
    # ... and per weather and day phase, each condition's own mean over its classes present
    by_condition = [
        k for k in judged.figures if k.startswith(("cityscapes_miou|weather=", "cityscapes_miou|day_phase="))
    ]
    assert by_condition and all(0 <= judged.figures[k].value <= 1 for k in by_condition)
    assert {k.split("|")[1].split("=")[0] for k in by_condition} == {"weather", "day_phase"}
    # People are scored as one class, never as parts.
    assert not any("|head|" in k or "|chest|" in k for k in judged.figures)
    # Per action only where MIN_VIDEOS videos were judged (three videos of three actions: none).
    assert not any("|action=" in k for k in judged.figures)
    # The sample's frames add up: every judged frame is in one of the three videos' groups.
    assert sum(f.count for k, f in judged.figures.items() if k.startswith("person_found|view=")) <= judged.people


def test_clear_or_overcast_daytime_videos_form_the_fair_day_group():
    assert conditions_of("overcast", "day") == ("weather=overcast", "day_phase=day", "light=fair_day")
    assert conditions_of("clear", "day")[-1] == "light=fair_day"
    for weather, phase in (("fog", "day"), ("rain", "day"), ("clear", "dusk"), ("overcast", "night")):
        assert conditions_of(weather, phase) == (f"weather={weather}", f"day_phase={phase}")


def test_the_same_seed_gives_the_same_figures_and_another_seed_other_frames(small_dataset, judged):
    again = run_realism(small_dataset, RealismOptions(frames=12, seed=5))
    assert again.to_json() == judged.to_json()
    other = run_realism(small_dataset, RealismOptions(frames=4, seed=6))
    assert other.frames == 4


def test_a_figure_below_its_minimum_fails_and_none_fails_by_default(judged):
    assert realism_check(judged, judged.options).status == Status.PASS
    pck = judged.figures["person_pck_0.2|all"].value
    opts = replace(judged.options, minimums={"person_pck_0.2": pck + 0.01, "person_pck_0.1": 0.0})
    result = realism_check(judged, opts)
    assert result.status == Status.FAIL
    [finding] = result.report.findings
    assert finding.reason == Reason.REALISM_BELOW_MIN and "person_pck_0.2" in finding.message
    assert set(result.numbers["headline"]) <= set(HEADLINES)


def test_minimums_parse_and_refuse_unknown_figures():
    assert parse_minimums("person_pck_0.2=0.9, voc_person_iou=0.5") == {"person_pck_0.2": 0.9, "voc_person_iou": 0.5}
    assert parse_minimums(None) == {}
    with pytest.raises(PhavUserError, match="unknown figure 'pck'"):
        parse_minimums("pck=0.9")
    with pytest.raises(PhavUserError, match="not a number"):
        parse_minimums("person_found=high")
    with pytest.raises(PhavUserError, match="person_found: 'nan' is not a finite number"):
        parse_minimums("person_found=nan")  # no figure is below nan: the minimum would never fail


def test_a_ratio_is_of_sums_over_videos_with_a_seeded_interval():
    tally = Tally()
    for video, (num, den) in {"a": (9, 10), "b": (1, 10), "c": (5, 5)}.items():
        tally.add("x", video, num, den)
    fig = tally.figure("x", seed=0)
    assert fig.value == pytest.approx(15 / 25) and fig.videos == 3 and fig.count == 25
    assert fig.low < fig.value < fig.high
    assert tally.figure("x", seed=0) == fig and tally.figure("y", seed=0) is None


def test_one_ratio_under_two_names_has_one_interval_and_one_video_has_none():
    """The bootstrap draws once per set of videos: a judge class that is one of our classes
    (`class_iou` and `iou` of terrain) gets one interval under both names. A figure from one
    video has no interval: resampling one video gives it back every time."""
    tally = Tally()
    for video, (num, den) in {"a": (9, 10), "b": (1, 10), "c": (5, 5)}.items():
        tally.add("class_iou|cityscapes|terrain|all", video, num, den)
        tally.add("iou|cityscapes|terrain|all", video, num, den)
    tally.add("iou|cityscapes|terrain|weather=fog", "a", 9, 10)
    one, other = (tally.figure(f"{k}|cityscapes|terrain|all", seed=0) for k in ("class_iou", "iou"))
    assert one == other and one.low < one.value < one.high
    fog = tally.figure("iou|cityscapes|terrain|weather=fog", seed=0)
    assert (fog.value, fog.low, fog.high, fog.videos) == (0.9, None, None, 1)
    assert fog.to_json()["ci95"] is None and fog.said() == "0.90 (one video)"


def test_a_class_s_interval_leaves_out_resamples_that_do_not_show_it():
    """One video of ten shows the class (named right on 8 of 10 pixels); the nine others
    give it only false answers: a resample without that video has no figure, not 0."""
    tally = Tally()
    tally.add("iou", "v0", 8, 10)
    for k in range(1, 10):
        tally.add("iou", f"v{k}", 0, 1, present=False)
    fig = tally.figure("iou", seed=0)
    assert fig.value == pytest.approx(8 / 19) and fig.videos == 10
    # v0 drawn k ≥ 1 times of 10: 8k / (10k + 10 − k), at least 8 / 19 (it was 0)
    assert 8 / 19 - 1e-9 <= fig.low < fig.high <= 0.8


def test_a_judges_answer_merged_into_a_class_counts_as_it():
    from phav_spec.judge_classes import CITYSCAPES
    from phav_spec.vocab import PIXEL_CLASSES

    road, building = PIXEL_CLASSES["road"].class_id, PIXEL_CLASSES["building"].class_id
    classes = np.full((4, 4), road, np.uint8)
    classes[:, 3] = building
    answers = np.full((4, 4), CITYSCAPES.label_id("road"))
    answers[:2, :3] = CITYSCAPES.label_id("sidewalk")  # pavement, to the judge
    answers[:, 3] = CITYSCAPES.label_id("sidewalk")  # a building called sidewalk stays wrong
    tally = Tally()
    judge_world(answers, classes, CITYSCAPES, tally, "v", ("all",))
    assert tally.figure("recall|cityscapes|road|all", seed=0).value == 1.0
    assert tally.figure("iou|cityscapes|road|all", seed=0).value == pytest.approx(12 / 16)
    assert tally.figure("recall|cityscapes|building|all", seed=0).value == 0.0


def test_false_answers_count_in_every_frame_as_the_benchmarks_pool_them():
    from phav_spec.judge_classes import CITYSCAPES
    from phav_spec.vocab import PIXEL_CLASSES

    # a bus named right in one video's frame; the judge's `bus` on grass in another video
    # counts against it, and `truck`, named on grass where no truck is anywhere, is no figure
    bus, grass = PIXEL_CLASSES["bus"].class_id, PIXEL_CLASSES["terrain"].class_id
    tally = Tally()
    shown = np.array([[bus, bus, grass, grass]], np.uint8)
    judge_world(np.array([[15, 15, 9, 9]]), shown, CITYSCAPES, tally, "a", ("all",))
    said = np.full((1, 4), CITYSCAPES.label_id("terrain"))
    said[0, :2] = CITYSCAPES.label_id("bus")
    said[0, 3] = CITYSCAPES.label_id("truck")
    judge_world(said, np.full((1, 4), grass, np.uint8), CITYSCAPES, tally, "b", ("all",))
    assert CITYSCAPES.label_id("bus") == 15 and CITYSCAPES.label_id("terrain") == 9
    assert tally.figure("class_iou|cityscapes|bus|all", seed=0).value == pytest.approx(2 / 4)
    assert tally.figure("iou|cityscapes|bus|all", seed=0).value == pytest.approx(2 / 4)
    assert tally.figure("recall|cityscapes|bus|all", seed=0).value == 1.0
    assert tally.figure("class_iou|cityscapes|truck|all", seed=0) is None
    assert "iou|cityscapes|truck|all" not in tally.figures(seed=0)
    # the mean is over the classes present: bus 2 of 4, grass 3 of its 6 pixels (no false answers)
    assert tally.figure("class_iou|cityscapes|terrain|all", seed=0).value == pytest.approx(3 / 6)
    assert cityscapes_miou(tally, 0).value == pytest.approx((2 / 4 + 3 / 6) / 2)


def test_the_miou_interval_is_of_the_figure_each_resample_would_give():
    """A resample of videos that show no road leaves road out of its mean, as the figure on
    those videos would, though the judge's `road` elsewhere gives road a denominator there."""
    from phav_spec.judge_classes import CITYSCAPES
    from phav_spec.vocab import PIXEL_CLASSES

    road, sky, grass = (PIXEL_CLASSES[c].class_id for c in ("road", "sky", "terrain"))
    label = {c: CITYSCAPES.label_id(c) for c in ("road", "sky", "terrain")}
    tally = Tally()
    a = np.array([[road, road, sky, sky]], np.uint8)  # named right
    judge_world(np.array([[label["road"]] * 2 + [label["sky"]] * 2]), a, CITYSCAPES, tally, "a", ("all",))
    b = np.array([[sky, sky, grass, grass, grass, grass, grass, grass, grass, grass]], np.uint8)
    said = np.array([[label["sky"]] * 2 + [label["terrain"]] * 7 + [label["road"]]])  # one lawn pixel `road`
    judge_world(said, b, CITYSCAPES, tally, "b", ("all",))
    whole = cityscapes_miou(tally, 0)
    only_b = (1.0 + 7 / 8) / 2  # sky, grass: the road's one false answer is no class of b's
    assert whole.value == pytest.approx((2 / 3 + 1.0 + 7 / 8) / 3)
    assert whole.low >= min(only_b, whole.value, 1.0) - 1e-9 and whole.high <= 1.0


def test_answers_on_a_class_the_judge_does_not_judge_are_void_where_its_benchmark_voids_them():
    from phav_spec.judge_classes import CITYSCAPES, PASCAL_VOC
    from phav_spec.vocab import PIXEL_CLASSES

    # Cityscapes leaves guard rails out of its evaluation: a `building` answer on one is not
    # a false building. VOC calls a truck background: a `car` answer on one is a false car.
    building, rail, grass = (PIXEL_CLASSES[n].class_id for n in ("building", "guard_rail", "terrain"))
    classes = np.full((2, 4), building, np.uint8)
    classes[1, :2], classes[1, 2:] = rail, grass
    tally = Tally()
    judge_world(np.full((2, 4), CITYSCAPES.label_id("building")), classes, CITYSCAPES, tally, "v", ("all",))
    assert tally.figure("iou|cityscapes|building|all", seed=0).value == pytest.approx(4 / 6)
    car, truck = PIXEL_CLASSES["car"].class_id, PIXEL_CLASSES["truck"].class_id
    classes = np.array([[car, car, truck, truck]], np.uint8)
    tally = Tally()
    judge_world(np.full((1, 4), PASCAL_VOC.label_id("car")), classes, PASCAL_VOC, tally, "v", ("all",))
    assert tally.figure("iou|pascal_voc|car|all", seed=0).value == pytest.approx(2 / 4)


def _person(facing_deg: float) -> dict:
    """A person at the origin facing ``facing_deg`` (0: +x) with hips 0.2 m apart, z up."""
    a = np.radians(facing_deg)
    left = np.array([-np.sin(a), np.cos(a), 0.0]) * 0.1  # the person's left of its facing
    joints = np.zeros((13, 3))
    joints[7], joints[8] = left + [0, 0, 1], -left + [0, 0, 1]
    return {"joints3d": joints.ravel().tolist()}


@pytest.mark.parametrize(("facing", "view"), [(0, "front"), (180, "back"), (90, "side"), (-60, "side"), (30, "front")])
def test_the_view_is_where_the_camera_stands_around_the_person(facing, view):
    camera = {"cam_to_world": np.array([[1, 0, 0, 5], [0, 1, 0, 0], [0, 0, 1, 1.5], [0, 0, 0, 1]]).ravel().tolist()}
    assert view_of(_person(facing), camera) == view


def test_the_check_in_phav_validate_reports_and_passes(small_dataset, tmp_path):
    out = tmp_path / "report.json"
    result = invoke_cli("validate!", str(small_dataset), "--checks", "realism", "--realism-frames", "6",
                        "--json", str(out))  # fmt: skip
    assert result.returncode == 0, result.stdout + result.stderr
    assert "realism" in result.stdout and "person_pck_0.2" in result.stdout
    [check] = json.loads(out.read_text())["datasets"][0]["checks"]
    assert check["name"] == "realism" and check["status"] == "pass"
    assert check["numbers"]["frames"] == 6 and check["numbers"]["models"]["pascal_voc"]["sha256"]
    failing = invoke_cli("validate!", str(small_dataset), "--checks", "realism", "--realism-frames", "6",
                         "--realism-min", "person_pck_0.1=1.01")  # fmt: skip
    assert failing.returncode == 1 and "REALISM_BELOW_MIN" in failing.stdout


def _one_line_exit_2(result, *words: str) -> None:
    assert result.returncode == 2, result.stdout + result.stderr
    said = result.stderr.strip()
    assert "Traceback" not in said and len(said.splitlines()) == 1, said
    for w in words:
        assert w in said, said


def test_a_corrupt_model_or_a_missing_extra_is_one_line_and_exit_2(small_dataset, tmp_path, monkeypatch):
    models = tmp_path / "models"
    models.mkdir()
    for m in JUDGE_MODELS.values():
        shutil.copy(MODELS_DIR / m.file, models)
    bad = models / JUDGE_MODELS["pascal_voc"].file
    bad.write_bytes(bad.read_bytes()[:1000])
    args = ("validate!", str(small_dataset), "--checks", "realism", "--realism-frames", "2")
    _one_line_exit_2(invoke_cli(*args, "--realism-models", str(models)), "not a TensorFlow Lite model", bad.name)
    _one_line_exit_2(invoke_cli(*args, "--realism-models", str(tmp_path / "none")), "missing model file")
    # A TFLite model of another kind under a judge's name is refused on loading, not judged with.
    shutil.copy(MODELS_DIR / JUDGE_MODELS["pascal_voc"].file, bad)
    detector = models / JUDGE_MODELS["pose_detector"].file
    shutil.copy(MODELS_DIR / JUDGE_MODELS["pascal_voc"].file, detector)
    _one_line_exit_2(invoke_cli(*args, "--realism-models", str(models)), "not the PoseDetector model", detector.name)
    shutil.copy(MODELS_DIR / JUDGE_MODELS["pose_detector"].file, detector)
    bad.write_bytes(bad.read_bytes()[:1000])
    _one_line_exit_2(invoke_cli(*args, "--realism-min", "pck=1"), "--realism-min", "unknown figure")
    twice = "person_pck_0.2=0.5,person_pck_0.2=0.9"  # the last one won, unsaid
    _one_line_exit_2(invoke_cli(*args, "--realism-min", twice), "--realism-min", "person_pck_0.2 is given twice")
    monkeypatch.setitem(sys.modules, "ai_edge_litert.interpreter", None)  # as if the extra were not installed
    shutil.copy(MODELS_DIR / JUDGE_MODELS["pascal_voc"].file, bad)
    _one_line_exit_2(invoke_cli(*args, "--realism-models", str(models)), "pip install 'phav[realism]'")


def test_the_html_report_shows_the_tables_and_judged_frames(small_dataset, tmp_path):
    page = tmp_path / "report.html"
    result = invoke_cli("validate!", str(small_dataset), "--checks", "realism", "--realism-frames", "4",
                        "--html", str(page))  # fmt: skip
    assert result.returncode == 0, result.stdout + result.stderr
    text = page.read_text()
    assert "Realism: models trained on real photographs" in text and "World: pascal_voc" in text
    assert "<td>person</td>" in text and text.count("<figure><img src='data:image/png") >= 2


def test_an_example_sheet_puts_what_a_judge_should_answer_beside_its_answer(judged):
    from phav_spec.judge_classes import JUDGE_CLASSES
    from phav_validators.realism.figures import NOT_JUDGED, example_sheet, expected_labels, palette

    ex = judged.examples[0]
    sheet = example_sheet(ex, JUDGE_CLASSES)
    tiles = 1 + 2 * sum(ex[n] is not None for n in JUDGE_CLASSES)
    assert sheet.shape == (256, tiles * 340 + (tiles - 1) * 4, 3)
    voc = JUDGE_CLASSES["pascal_voc"]
    expected = palette(voc)[expected_labels(ex["classes"], voc)]
    assert np.array_equal(sheet[:, 344:684], expected)
    assert np.array_equal(sheet[:, 688:1028], palette(voc)[ex["pascal_voc"]])
    # VOC counts its answers on what it has no class for (the ground, the walls) against it:
    # it should answer background there, where Cityscapes' benchmark voids such pixels.
    from phav_spec.vocab import PIXEL_CLASSES

    unjudged = ~np.isin(ex["classes"], [PIXEL_CLASSES[c].class_id for c in voc.judged_as])
    assert unjudged.any() and not (expected == NOT_JUDGED).all(axis=-1).any()
    assert (expected[unjudged] == palette(voc)[voc.label_id("background")]).all()
    city = JUDGE_CLASSES["cityscapes"]
    assert (palette(city)[expected_labels(np.array([PIXEL_CLASSES["chair"].class_id]), city)] == NOT_JUDGED).all()
