"""phav_spec.population: ages, statures, skin tones and colours in physical units ↔ anny and sRGB."""

from __future__ import annotations

import colorsys

import numpy as np
import pytest

from phav_spec.people import Phenotype
from phav_spec.population import (
    AGE_YEARS_ANCHORS,
    SKIN_TONES_SRGB,
    age_years,
    anny_age,
    estimated_stature,
    hair_rgb,
    height_for_stature,
    hsv_rgb,
    p_grey,
    phenotype_for,
    reference_stature,
    skin_rgb,
)


def test_age_in_years_maps_onto_anny_and_back():
    ages = np.linspace(0.0, 90.0, 181)
    anny = [anny_age(a) for a in ages]
    assert anny[0] == 0.0 and anny[-1] == 1.0 and all(np.diff(anny) > 0)
    assert [age_years(x) for x in anny] == pytest.approx(ages.tolist(), abs=1e-9)
    assert anny_age(11.0) == pytest.approx(0.415) and anny_age(16.0) == pytest.approx(0.67)
    assert AGE_YEARS_ANCHORS[-1] == 90.0


def test_reference_statures_grow_then_shrink():
    for female in (False, True):
        medians = [reference_stature(female, a)[0] for a in range(4, 91)]
        peak = int(np.argmax(medians))
        assert all(np.diff(medians[: peak + 1]) >= 0) and all(np.diff(medians[peak:]) <= 0)
    assert reference_stature(False, 30)[0] == pytest.approx(1.765)
    assert reference_stature(True, 30)[0] == pytest.approx(1.632)
    assert reference_stature(False, 8)[0] == pytest.approx(1.273)


def test_height_is_solved_for_a_stature():
    for female, age, target in ((False, 30, 1.85), (True, 45, 1.55), (False, 9, 1.30), (True, 70, 1.60)):
        p = phenotype_for(
            female=female, age=age, stature_m=target, gender_offset=0.1, muscle=0.6, weight=0.4, proportions=0.5
        )
        assert 0.0 < p.height < 1.0
        assert estimated_stature(p) == pytest.approx(target, abs=1e-9)
        assert (p.gender > 0.5) == female
    # Out of reach: clamped to the nearest end, never outside [0, 1].
    kw = {"gender": 0.0, "age": 0.7, "muscle": 0.5, "weight": 0.5, "proportions": 0.5}
    assert height_for_stature(9.0, **kw) == 1.0 and height_for_stature(0.1, **kw) == 0.0


def test_stature_is_anny_all_defaults_and_grows_with_height():
    default = Phenotype(gender=0.5, age=0.5, muscle=0.5, weight=0.5, height=0.5, proportions=0.5)
    assert estimated_stature(default) == pytest.approx(1.626, abs=0.002)
    man = default.model_copy(update={"gender": 0.0, "age": 0.7})
    assert estimated_stature(man) == pytest.approx(1.906, abs=0.002)
    taller = man.model_copy(update={"height": 0.8})
    assert estimated_stature(taller) > estimated_stature(man)


def test_skin_tones_run_along_the_monk_scale():
    assert skin_rgb(0.0, 0.0) == SKIN_TONES_SRGB[0] and skin_rgb(1.0, 0.0) == SKIN_TONES_SRGB[-1]
    for k, swatch in enumerate(SKIN_TONES_SRGB):
        assert skin_rgb(k / 9, 0.0) == pytest.approx(swatch, abs=1)
    lightness = [sum(skin_rgb(t, 0.0)) for t in np.linspace(0, 1, 50)]
    assert lightness[0] > 3 * 220 and lightness[-1] < 3 * 45
    # The undertone turns the hue (pinker below zero, more golden above), keeping the tone.
    hue = [colorsys.rgb_to_hsv(*(c / 255 for c in skin_rgb(0.5, u)))[0] for u in (-1.0, 0.0, 1.0)]
    assert hue[0] < hue[1] < hue[2]
    assert skin_rgb(0.5, 5.0) == skin_rgb(0.5, 1.0)


def test_colours():
    assert hsv_rgb(0.0, 1.0, 1.0) == (255, 0, 0)
    assert hsv_rgb(120.0, 1.0, 0.5) == (0, 128, 0)
    assert hsv_rgb(360.0, 0.0, 1.0) == (255, 255, 255)
    light, dark = hair_rgb("blond", 0.0), hair_rgb("blond", 1.0)
    assert sum(light) > sum(hair_rgb("blond", 0.5)) > sum(dark)
    assert p_grey(30, start_years=35, full_years=75, p_full=0.9) == 0.0
    assert p_grey(55, start_years=35, full_years=75, p_full=0.9) == pytest.approx(0.45)
    assert p_grey(80, start_years=35, full_years=75, p_full=0.9) == 0.9
    assert p_grey(50, start_years=50, full_years=50, p_full=0.5) == 0.5
