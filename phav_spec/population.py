"""Calibration of people in physical units: ages in years, statures in metres, skin tones,
hair and garment colours, and how each maps onto anny's phenotype and the recipe's sRGB.

θ describes people the way a person would (a 34-year-old woman of 1.68 m, a light skin
tone); the body model (``phav_generator.body``, anny) takes a phenotype in [0, 1]. This
module is the one translation between the two, as data plus a few pure functions, so the
sampler, the 20 fixed human models of H and the validators agree on it:

- **Age.** anny's age runs 0 (baby) … 1/3 (child) … 2/3 (young adult) … 1 (old). Up to 16
  years phav uses anny's own WHO-calibrated "morphological age" anchors (anny 0.6.2,
  ``data/shape_calibration``: 1 y → 0.05, 4 y → 0.215, 11 y → 0.415, 16 y → 0.67); past
  16, where anny's calibration only fits heights, age runs linearly to MakeHuman's "old"
  target at 90 years (1.0).
- **Stature.** A person's target stature is the WHO reference median for their sex and
  age plus ``stature_z`` reference standard deviations (WHO 2007 growth reference, 5–19
  years; WHO child growth standards at 4; adults keep the 19-year values to 40 years and
  lose height after, about 6 cm by 90). anny's ``height`` parameter is then solved for that
  stature from ``ANNY_STATURE_M``, the standing heights of anny's bodies at its phenotype
  anchors: anny's vertices are multilinear in the anchor weights, so interpolating the
  table is within 2 mm of ``phav_generator.body.model.stature`` (tested there; regenerate
  the table with ``python -m tests.generator.test_population``).
- **Skin.** A tone in [0, 1] runs along the ten swatches of the Monk Skin Tone scale
  (Ellis Monk, 2019; Google, CC BY 4.0), lightest to darkest, interpolated in linear light;
  an undertone in [−1, 1] turns the hue by up to ±8° (−1 pinker, +1 more golden).
- **Hair and clothes.** Hair colours are named ranges (black, brown, blond, red, grey),
  a shade picks a point between their light and dark ends; garment colours are HSV.
"""

from __future__ import annotations

import colorsys
import math
from bisect import bisect_right
from collections.abc import Sequence

from phav_spec.people import RGB, Phenotype

#: Age in years ↔ anny's age: anny's calibrated anchors to 16 years, then linear to 90.
AGE_YEARS_ANCHORS: tuple[float, ...] = (0.0, 1.0, 4.0, 11.0, 16.0, 90.0)
ANNY_AGE_ANCHORS: tuple[float, ...] = (0.0, 0.05, 0.215, 0.415, 0.67, 1.0)
#: A person younger than this is a child (θ's ``child_age_years``), older an adult.
ADULT_AGE_YEARS = 16.0
#: The ages θ may draw (years): children from 4, adults to 90.
MIN_AGE_YEARS, MAX_AGE_YEARS = 4.0, 90.0

#: Bounds of θ's continuous ``people`` parameters: name → (unit, lower, upper). Ages stay
#: where anny's bodies are calibrated; a gender offset below one half keeps the sex; skin
#: tone spans the Monk scale; the pattern scale is Garment.scale's range.
PEOPLE_PARAMETER_BOUNDS: dict[str, tuple[str, float, float]] = {
    "adult_age_years": ("years", ADULT_AGE_YEARS, MAX_AGE_YEARS),
    "child_age_years": ("years", MIN_AGE_YEARS, ADULT_AGE_YEARS),
    "stature_z": ("reference sd", -3.0, 3.0),
    "gender_offset": ("anny gender", 0.0, 0.45),
    "weight": ("anny", 0.0, 1.0),
    "muscle": ("anny", 0.0, 1.0),
    "proportions": ("anny", 0.0, 1.0),
    "skin_tone": ("Monk scale, 0 lightest", 0.0, 1.0),
    "skin_undertone": ("−1 pink … +1 golden", -1.0, 1.0),
    "saturation": ("HSV", 0.0, 1.0),
    "value": ("HSV", 0.0, 1.0),
    "pattern_scale": ("×", 0.1, 10.0),
}

#: WHO reference stature by age: (years, male median, male sd, female median, female sd),
#: metres. WHO 2007 growth reference (5–19 y) and child growth standards (4 y); adults
#: keep the 19-year values to 40 and shrink with age after (about 1 cm per decade, faster
#: late in life).
REFERENCE_STATURE_M: tuple[tuple[float, float, float, float, float], ...] = (
    (4.0, 1.033, 0.042, 1.027, 0.043),
    (5.0, 1.100, 0.047, 1.094, 0.048),
    (6.0, 1.160, 0.049, 1.151, 0.051),
    (7.0, 1.217, 0.052, 1.208, 0.054),
    (8.0, 1.273, 0.055, 1.266, 0.058),
    (9.0, 1.326, 0.058, 1.325, 0.062),
    (10.0, 1.378, 0.061, 1.386, 0.066),
    (11.0, 1.431, 0.067, 1.450, 0.070),
    (12.0, 1.491, 0.075, 1.512, 0.071),
    (13.0, 1.560, 0.081, 1.564, 0.068),
    (14.0, 1.632, 0.082, 1.598, 0.065),
    (15.0, 1.690, 0.077, 1.617, 0.064),
    (16.0, 1.729, 0.074, 1.625, 0.064),
    (17.0, 1.752, 0.072, 1.629, 0.064),
    (18.0, 1.761, 0.072, 1.631, 0.064),
    (19.0, 1.765, 0.072, 1.632, 0.064),
    (40.0, 1.765, 0.072, 1.632, 0.064),
    (50.0, 1.760, 0.072, 1.627, 0.064),
    (60.0, 1.750, 0.072, 1.615, 0.064),
    (70.0, 1.735, 0.072, 1.600, 0.064),
    (80.0, 1.720, 0.072, 1.585, 0.064),
    (90.0, 1.705, 0.072, 1.570, 0.064),
)

#: anny's phenotype anchors, the axes of ANNY_STATURE_M (age from 0: no newborns here).
STATURE_AXES: dict[str, tuple[float, ...]] = {
    "gender": (0.0, 1.0),
    "age": (0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0),
    "muscle": (0.0, 0.5, 1.0),
    "weight": (0.0, 0.5, 1.0),
    "height": (0.0, 1.0),
    "proportions": (0.0, 1.0),
}
# fmt: off
#: Standing height (m, top of the head above the soles) of anny's body at each anchor of
#: STATURE_AXES, indexed [gender][age][muscle][weight][height][proportions]; race, cup size
#: and firmness at anny's defaults. Generated from phav_generator.body.model.stature (anny
#: 0.6.2). Stature hardly depends on muscle and weight, except that anny's old, heavy and
#: muscular anchor at minimum height stands 0.37 m taller than its neighbours.
ANNY_STATURE_M: tuple = (
    (  # gender 0 (male)
    (  # age 0
    (((0.4376, 0.4376), (0.8910, 0.8910)), ((0.4376, 0.4376), (0.8910, 0.8910)), ((0.4376, 0.4376), (0.8910, 0.8910))),
    (((0.4376, 0.4376), (0.8910, 0.8910)), ((0.4376, 0.4376), (0.8910, 0.8910)), ((0.4376, 0.4376), (0.8910, 0.8910))),
    (((0.4376, 0.4376), (0.8910, 0.8910)), ((0.4376, 0.4376), (0.8910, 0.8910)), ((0.4376, 0.4376), (0.8910, 0.8910))),
    ),
    (  # age 1/3
    (((0.9883, 0.9883), (1.9331, 1.9331)), ((0.9909, 0.9909), (1.9359, 1.9359)), ((0.9909, 0.9909), (1.9359, 1.9359))),
    (((0.9909, 0.9909), (1.9359, 1.9359)), ((0.9909, 0.9909), (1.9359, 1.9359)), ((0.9909, 0.9909), (1.9359, 1.9359))),
    (((0.9909, 0.9909), (1.9359, 1.9359)), ((0.9909, 0.9909), (1.9359, 1.9359)), ((0.9909, 0.9909), (1.9359, 1.9359))),
    ),
    (  # age 2/3
    (((1.3639, 1.3639), (2.4535, 2.4535)), ((1.3639, 1.3639), (2.4535, 2.4535)), ((1.3645, 1.3645), (2.4538, 2.4538))),
    (((1.3639, 1.3639), (2.4535, 2.4535)), ((1.3639, 1.3639), (2.4535, 2.4535)), ((1.3639, 1.3639), (2.4535, 2.4535))),
    (((1.3639, 1.3639), (2.4535, 2.4535)), ((1.3639, 1.3639), (2.4535, 2.4535)), ((1.3639, 1.3639), (2.4535, 2.4535))),
    ),
    (  # age 1
    (((1.3340, 1.3340), (2.4228, 2.4228)), ((1.3340, 1.3340), (2.4228, 2.4228)), ((1.3340, 1.3340), (2.4228, 2.4228))),
    (((1.3340, 1.3340), (2.4228, 2.4228)), ((1.3340, 1.3340), (2.4228, 2.4228)), ((1.3340, 1.3340), (2.4228, 2.4228))),
    (((1.3340, 1.3340), (2.4228, 2.4228)), ((1.3340, 1.3340), (2.4228, 2.4228)), ((1.7000, 1.7000), (2.4228, 2.4228))),
    ),
    ),
    (  # gender 1 (female)
    (  # age 0
    (((0.4377, 0.4377), (0.8911, 0.8911)), ((0.4377, 0.4377), (0.8911, 0.8911)), ((0.4377, 0.4377), (0.8911, 0.8911))),
    (((0.4377, 0.4377), (0.8911, 0.8911)), ((0.4377, 0.4377), (0.8911, 0.8911)), ((0.4377, 0.4377), (0.8911, 0.8911))),
    (((0.4377, 0.4377), (0.8911, 0.8911)), ((0.4377, 0.4377), (0.8911, 0.8911)), ((0.4377, 0.4377), (0.8911, 0.8911))),
    ),
    (  # age 1/3
    (((0.9035, 0.8876), (1.8484, 1.8325)), ((0.9050, 0.8891), (1.8499, 1.8340)), ((0.9019, 0.8860), (1.8468, 1.8309))),
    (((0.9035, 0.8876), (1.8484, 1.8325)), ((0.9035, 0.8876), (1.8484, 1.8325)), ((0.9035, 0.8876), (1.8484, 1.8325))),
    (((0.9035, 0.8876), (1.8484, 1.8325)), ((0.9035, 0.8876), (1.8484, 1.8325)), ((0.9035, 0.8876), (1.8484, 1.8325))),
    ),
    (  # age 2/3
    (((1.2353, 1.2194), (2.3250, 2.3091)), ((1.2320, 1.2160), (2.3213, 2.3054)), ((1.2320, 1.2160), (2.3213, 2.3054))),
    (((1.2320, 1.2160), (2.3213, 2.3054)), ((1.2320, 1.2160), (2.3213, 2.3054)), ((1.2320, 1.2160), (2.3213, 2.3054))),
    (((1.2320, 1.2160), (2.3213, 2.3054)), ((1.2320, 1.2160), (2.3213, 2.3054)), ((1.2320, 1.2160), (2.3213, 2.3054))),
    ),
    (  # age 1
    (((1.2188, 1.2028), (2.3080, 2.2921)), ((1.2187, 1.2027), (2.3080, 2.2921)), ((1.2187, 1.2027), (2.3080, 2.2921))),
    (((1.2187, 1.2027), (2.3080, 2.2921)), ((1.2187, 1.2027), (2.3087, 2.2928)), ((1.2187, 1.2027), (2.3080, 2.2921))),
    (((1.2187, 1.2027), (2.3080, 2.2921)), ((1.2187, 1.2027), (2.3080, 2.2921)), ((1.5856, 1.5696), (2.3080, 2.2921))),
    ),
    ),
)
# fmt: on

#: The Monk Skin Tone scale's ten swatches (sRGB), lightest (MST 1) to darkest (MST 10).
SKIN_TONES_SRGB: tuple[RGB, ...] = (
    (246, 237, 228),
    (243, 231, 219),
    (247, 234, 208),
    (234, 218, 186),
    (215, 189, 150),
    (160, 126, 86),
    (130, 92, 67),
    (96, 65, 52),
    (58, 49, 42),
    (41, 36, 32),
)
#: Largest hue turn (degrees) of a skin undertone of ±1.
UNDERTONE_HUE_DEG = 8.0

#: Hair colours θ weighs; grey is not among them: it comes with age (θ's ``hair.grey``).
HAIR_COLOURS: tuple[str, ...] = ("black", "brown", "blond", "red")
#: Each hair colour's range, (lightest, darkest) sRGB; a shade in [0, 1] picks a point.
HAIR_COLOUR_RANGES: dict[str, tuple[RGB, RGB]] = {
    "black": ((48, 40, 36), (14, 12, 12)),
    "brown": ((128, 88, 56), (52, 34, 22)),
    "blond": ((230, 200, 140), (160, 118, 68)),
    "red": ((190, 96, 46), (110, 42, 20)),
    "grey": ((214, 212, 208), (128, 126, 124)),
}


def _interp(x: float, xs: Sequence[float], ys: Sequence[float]) -> float:
    """Piecewise-linear interpolation, clamped at both ends."""
    if x <= xs[0]:
        return float(ys[0])
    if x >= xs[-1]:
        return float(ys[-1])
    i = bisect_right(xs, x) - 1
    t = (x - xs[i]) / (xs[i + 1] - xs[i])
    return float(ys[i] + t * (ys[i + 1] - ys[i]))


def anny_age(age_years: float) -> float:
    """anny's age parameter of a person ``age_years`` old (0 … 90 years → 0 … 1)."""
    return _interp(age_years, AGE_YEARS_ANCHORS, ANNY_AGE_ANCHORS)


def age_years(anny_age_value: float) -> float:
    """The age in years of anny's age parameter (the inverse of ``anny_age``)."""
    return _interp(anny_age_value, ANNY_AGE_ANCHORS, AGE_YEARS_ANCHORS)


def reference_stature(female: bool, age: float) -> tuple[float, float]:
    """(median, standard deviation) in metres of the reference stature at ``age`` years."""
    ages = [row[0] for row in REFERENCE_STATURE_M]
    col = 3 if female else 1
    median = _interp(age, ages, [row[col] for row in REFERENCE_STATURE_M])
    sd = _interp(age, ages, [row[col + 1] for row in REFERENCE_STATURE_M])
    return median, sd


def _weights(value: float, anchors: Sequence[float]) -> list[tuple[int, float]]:
    """(anchor index, weight) of ``value`` between the two anchors enclosing it (clamped)."""
    v = min(max(float(value), anchors[0]), anchors[-1])
    i = min(max(bisect_right(anchors, v) - 1, 0), len(anchors) - 2)
    t = (v - anchors[i]) / (anchors[i + 1] - anchors[i])
    return [(i, 1.0 - t), (i + 1, t)]


def _stature_at_height(phenotype: dict[str, float], height_index: int) -> float:
    """Interpolated stature with ``height`` at one of its two anchors (0 or 1)."""
    total = 0.0
    for gi, gw in _weights(phenotype["gender"], STATURE_AXES["gender"]):
        for ai, aw in _weights(phenotype["age"], STATURE_AXES["age"]):
            for mi, mw in _weights(phenotype["muscle"], STATURE_AXES["muscle"]):
                for wi, ww in _weights(phenotype["weight"], STATURE_AXES["weight"]):
                    for pi, pw in _weights(phenotype["proportions"], STATURE_AXES["proportions"]):
                        w = gw * aw * mw * ww * pw
                        if w != 0.0:
                            total += w * ANNY_STATURE_M[gi][ai][mi][wi][height_index][pi]
    return total


def estimated_stature(phenotype: Phenotype) -> float:
    """Standing height (m) of anny's body of ``phenotype``, interpolated from ANNY_STATURE_M."""
    p = phenotype.as_dict()
    h = p["height"]
    return (1.0 - h) * _stature_at_height(p, 0) + h * _stature_at_height(p, 1)


def height_for_stature(
    stature_m: float, *, gender: float, age: float, muscle: float, weight: float, proportions: float
) -> float:
    """anny's ``height`` in [0, 1] that gives a body of ``stature_m`` (clamped where the other
    phenotype parameters cannot reach it): stature is linear in ``height`` between its anchors."""
    p = {"gender": gender, "age": age, "muscle": muscle, "weight": weight, "proportions": proportions}
    low, high = _stature_at_height(p, 0), _stature_at_height(p, 1)
    if high <= low:  # never for anny's bodies; a flat table would make every height equal
        return 0.5
    return min(max((stature_m - low) / (high - low), 0.0), 1.0)


def _to_linear(c: float) -> float:
    c /= 255.0
    return c / 12.92 if c <= 0.04045 else ((c + 0.055) / 1.055) ** 2.4


def _to_srgb(x: float) -> float:
    """Linear light in [0, 1] → sRGB in [0, 1]."""
    x = min(max(x, 0.0), 1.0)
    return 12.92 * x if x <= 0.0031308 else 1.055 * x ** (1.0 / 2.4) - 0.055


def _byte(x: float) -> int:
    """[0, 1] → 0 … 255, rounded half up."""
    return min(max(int(x * 255.0 + 0.5), 0), 255)


def _mix(a: RGB, b: RGB, t: float) -> tuple[float, float, float]:
    """sRGB (0 … 1) of the point ``t`` of the way from ``a`` to ``b``, mixed in linear light."""
    return tuple(_to_srgb((1.0 - t) * _to_linear(x) + t * _to_linear(y)) for x, y in zip(a, b, strict=True))  # type: ignore[return-value]


def skin_rgb(tone: float, undertone: float) -> RGB:
    """sRGB of a skin ``tone`` in [0, 1] (lightest … darkest) with an ``undertone`` in
    [−1, 1] (pinker … more golden)."""
    position = min(max(tone, 0.0), 1.0) * (len(SKIN_TONES_SRGB) - 1)
    i = min(int(position), len(SKIN_TONES_SRGB) - 2)
    r, g, b = _mix(SKIN_TONES_SRGB[i], SKIN_TONES_SRGB[i + 1], position - i)
    h, s, v = colorsys.rgb_to_hsv(r, g, b)
    h = math.fmod(h + UNDERTONE_HUE_DEG * min(max(undertone, -1.0), 1.0) / 360.0 + 1.0, 1.0)
    return tuple(_byte(x) for x in colorsys.hsv_to_rgb(h, s, v))  # type: ignore[return-value]


def hair_rgb(colour: str, shade: float) -> RGB:
    """sRGB of a hair ``colour`` (HAIR_COLOUR_RANGES) at ``shade`` in [0, 1] (light … dark)."""
    light, dark = HAIR_COLOUR_RANGES[colour]
    return tuple(_byte(x) for x in _mix(light, dark, min(max(shade, 0.0), 1.0)))  # type: ignore[return-value]


def p_grey(age: float, *, start_years: float, full_years: float, p_full: float) -> float:
    """Probability that hair has turned grey at ``age`` years: 0 before ``start_years``,
    rising linearly to ``p_full`` at ``full_years`` and staying there."""
    if age < start_years:
        return 0.0
    if age >= full_years:
        return p_full
    return p_full * (age - start_years) / (full_years - start_years)


def hsv_rgb(hue_deg: float, saturation: float, value: float) -> RGB:
    """sRGB of a colour given as hue (degrees), saturation and value in [0, 1]."""
    h = math.fmod(math.fmod(hue_deg, 360.0) + 360.0, 360.0) / 360.0
    s, v = min(max(saturation, 0.0), 1.0), min(max(value, 0.0), 1.0)
    return tuple(_byte(x) for x in colorsys.hsv_to_rgb(h, s, v))  # type: ignore[return-value]


def phenotype_for(
    *,
    female: bool,
    age: float,
    stature_m: float,
    gender_offset: float,
    muscle: float,
    weight: float,
    proportions: float,
) -> Phenotype:
    """anny's phenotype of a person of sex, ``age`` (years) and ``stature_m``: gender is
    ``gender_offset`` from its sex's end (0 male, 1 female), height solved for the stature."""
    gender = 1.0 - gender_offset if female else gender_offset
    a = anny_age(age)
    height = height_for_stature(stature_m, gender=gender, age=a, muscle=muscle, weight=weight, proportions=proportions)
    return Phenotype(gender=gender, age=a, muscle=muscle, weight=weight, height=height, proportions=proportions)


__all__ = [
    "ADULT_AGE_YEARS",
    "ANNY_STATURE_M",
    "HAIR_COLOURS",
    "HAIR_COLOUR_RANGES",
    "MAX_AGE_YEARS",
    "MIN_AGE_YEARS",
    "PEOPLE_PARAMETER_BOUNDS",
    "REFERENCE_STATURE_M",
    "SKIN_TONES_SRGB",
    "age_years",
    "anny_age",
    "estimated_stature",
    "hair_rgb",
    "height_for_stature",
    "hsv_rgb",
    "p_grey",
    "phenotype_for",
    "reference_stature",
    "skin_rgb",
]
