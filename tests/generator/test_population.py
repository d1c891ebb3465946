"""phav_spec.population against the body model: the stature table is anny's, the age anchors
are anny's calibration, and the 20 fixed human models are people (statures measured on
their bodies).

Regenerate the stature table after a change of the body model with
``python -m tests.generator.test_population`` (prints ``ANNY_STATURE_M``).
"""

from __future__ import annotations

import importlib.util
import itertools
from pathlib import Path

import numpy as np
import pytest

from phav_generator.body.model import stature
from phav_spec.people import BOTTOMS, FABRICS, HAIR_STYLES, TOPS, Phenotype
from phav_spec.population import (
    AGE_YEARS_ANCHORS,
    ANNY_AGE_ANCHORS,
    ANNY_STATURE_M,
    STATURE_AXES,
    age_years,
    estimated_stature,
)
from phav_spec.scene import HUMAN_MODELS

_AXES = ("gender", "age", "muscle", "weight", "height", "proportions")


def stature_grid() -> np.ndarray:
    """anny's stature at every anchor of STATURE_AXES, measured on the bodies (~4 s)."""
    shape = tuple(len(STATURE_AXES[a]) for a in _AXES)
    grid = np.zeros(shape)
    for index in itertools.product(*(range(n) for n in shape)):
        values = {a: STATURE_AXES[a][i] for a, i in zip(_AXES, index, strict=True)}
        grid[index] = stature(Phenotype(**values))
    return grid


def test_stature_table_is_the_body_models():
    np.testing.assert_allclose(stature_grid(), np.array(ANNY_STATURE_M), atol=1e-4)


def test_interpolated_statures_are_within_two_millimetres_of_the_bodies():
    rng = np.random.default_rng(0)
    errors = []
    for _ in range(60):
        v = rng.random(6)
        v[1] = 0.2 + 0.8 * v[1]  # from about 3 years up
        p = Phenotype(**dict(zip(_AXES, v.tolist(), strict=True)))
        errors.append(abs(stature(p) - estimated_stature(p)))
    assert max(errors) < 0.002, max(errors)


def test_age_anchors_up_to_16_years_are_annys_calibration():
    torch = pytest.importorskip("torch")
    spec = importlib.util.find_spec("anny")
    if spec is None or not spec.submodule_search_locations:
        pytest.skip("anny is not installed")
    path = Path(next(iter(spec.submodule_search_locations))) / "data" / "shape_calibration" / "boys.pth"
    mapping = torch.load(path, weights_only=True, map_location="cpu")["morphological_age_mapping"]
    years = mapping["morphological_age_anchors"].tolist()
    anny = mapping["anny_age_anchors"].tolist()
    n = AGE_YEARS_ANCHORS.index(16.0) + 1
    np.testing.assert_allclose(years[:n], AGE_YEARS_ANCHORS[:n], atol=1e-6)
    np.testing.assert_allclose(anny[:n], ANNY_AGE_ANCHORS[:n], atol=1e-6)


def test_the_20_human_models_are_a_varied_set_of_people():
    rows = []
    for name, model in HUMAN_MODELS.items():
        p = model.phenotype
        height = stature(p)
        assert abs(height - estimated_stature(p)) < 0.002, name
        rows.append((name, p.gender > 0.5, age_years(p.age), height, p.weight, p.muscle))
    adults = [r for r in rows if r[2] >= 18]
    assert min(r[3] for r in adults) >= 1.49 and max(r[3] for r in adults) <= 1.96
    men = [r[3] for r in adults if not r[1]]
    women = [r[3] for r in adults if r[1]]
    assert 1.72 <= np.mean(men) <= 1.80 and 1.59 <= np.mean(women) <= 1.67
    assert sum(r[1] for r in rows) == 10  # ten women, ten men
    ages = [r[2] for r in rows]
    assert min(ages) < 16 and max(ages) > 70  # teenagers to elderly
    assert all(13 <= a <= 80 for a in ages) and all(r[3] >= 1.45 for r in rows)
    weights = [r[4] for r in rows]
    assert min(weights) <= 0.3 and max(weights) >= 0.85  # light to heavy builds
    models = [m for _, m in HUMAN_MODELS.items()]
    assert {m.outfit.top.kind for m in models} == set(TOPS)
    assert {m.outfit.bottom.kind for m in models} == set(BOTTOMS)
    assert {m.outfit.top.fabric for m in models} | {m.outfit.bottom.fabric for m in models} == set(FABRICS)
    assert {m.hair.style for m in models} == set(HAIR_STYLES)
    lightness = sorted(sum(m.skin_rgb) / 3 for m in models)
    assert lightness[0] < 60 and lightness[-1] > 225  # skin tones across the whole range


if __name__ == "__main__":
    grid = stature_grid()
    print("ANNY_STATURE_M: tuple = (")
    for g, gender in enumerate(("male", "female")):
        print(f"    (  # gender {g} ({gender})")
        for a, label in enumerate(("0", "1/3", "2/3", "1")):
            print(f"    (  # age {label}")
            for m in range(grid.shape[2]):
                cells = ", ".join(
                    "(" + ", ".join("(" + ", ".join(f"{grid[g, a, m, w, h, p]:.4f}" for p in range(2)) + ")"
                                    for h in range(2)) + ")"
                    for w in range(grid.shape[3])
                )  # fmt: skip
                print(f"    ({cells}),")
            print("    ),")
        print("    ),")
    print(")")
