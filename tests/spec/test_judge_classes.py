"""The realism judges' class tables: every pixel class judged as a judge's class or named as
not judged, and the judges' label ids as their model files number them."""

from __future__ import annotations

import pytest

from phav_spec.judge_classes import CITYSCAPES, JUDGE_CLASSES, PASCAL_VOC
from phav_spec.vocab import PIXEL_CLASSES, PixelGroup


@pytest.mark.parametrize("judge", list(JUDGE_CLASSES.values()), ids=list(JUDGE_CLASSES))
def test_every_pixel_class_is_judged_or_named_as_not_judged(judge):
    ours = [name for name, _ in PIXEL_CLASSES.items()]
    assert sorted([*judge.judged_as, *judge.not_judged]) == sorted(ours)
    assert not set(judge.judged_as) & set(judge.not_judged)
    assert set(judge.judged_as.values()) <= set(judge.labels)
    assert all(reason for reason in judge.not_judged.values())


def test_people_are_persons_to_both_judges():
    people = [n for n, c in PIXEL_CLASSES.items() if c.group in (PixelGroup.HUMAN_PARTS, PixelGroup.HUMAN_JOINTS)]
    assert len(people) == 27
    for judge in (PASCAL_VOC, CITYSCAPES):
        assert {judge.judged_as[n] for n in people} == {"person"}


def test_label_ids_are_the_models_output_ids():
    # The ids of the models' label files (PASCAL VOC 2012; Cityscapes trainIds without the
    # "background" line the source repository puts first).
    assert [PASCAL_VOC.label_id(n) for n in ("background", "bus", "car", "chair", "person", "sofa", "tvmonitor")] == [
        0, 6, 7, 9, 15, 18, 20]  # fmt: skip
    assert len(PASCAL_VOC.labels) == 21 and len(CITYSCAPES.labels) == 19
    assert [CITYSCAPES.label_id(n) for n in ("road", "vegetation", "sky", "person", "car", "bicycle")] == [
        0, 8, 10, 11, 13, 18]  # fmt: skip


def test_trucks_and_benches_are_judged_only_where_the_judges_annotators_named_them():
    # VOC's annotation guidelines leave trucks out of car and benches out of chair.
    assert "truck" in PASCAL_VOC.not_judged and CITYSCAPES.judged_as["truck"] == "truck"
    assert "bench" in PASCAL_VOC.not_judged and "bench" in CITYSCAPES.not_judged
    assert PASCAL_VOC.judged_as["car"] == "car" and PASCAL_VOC.judged_as["chair"] == "chair"
    # Cityscapes labels guard rails apart and trains on none of them (trainId 255).
    assert "guard_rail" in CITYSCAPES.not_judged and "fence" not in CITYSCAPES.judged_as.values()
    assert CITYSCAPES.judged_as["tree"] == "vegetation" and "tree" in PASCAL_VOC.not_judged


@pytest.mark.parametrize("judge", list(JUDGE_CLASSES.values()), ids=list(JUDGE_CLASSES))
def test_a_merged_judge_class_counts_as_one_of_ours_and_is_nothing_else(judge):
    judged = set(judge.judged_as.values())
    for finer, coarser in judge.merged.items():
        assert finer in judge.labels and coarser in judged and finer not in judged
        assert judge.label_id(finer) in judge.answer_ids(coarser)
    assert all(judge.answer_ids(m)[0] == judge.label_id(m) for m in judged)


def test_cityscapes_sidewalk_is_the_papers_road():
    assert CITYSCAPES.answer_ids("road") == (CITYSCAPES.label_id("road"), CITYSCAPES.label_id("sidewalk"))
    assert CITYSCAPES.answer_ids("building") == (CITYSCAPES.label_id("building"),)
    assert PASCAL_VOC.merged == {}
