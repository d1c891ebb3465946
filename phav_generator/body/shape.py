"""Phenotype → rest body, in numpy: anny's phenotype interpolation and blend shapes.

The same arithmetic as anny's ``phenotype_blendshape_weights`` and
``apply_linear_blendshape`` (the tests hold it to anny's own output), in float64 with a
fixed summation order, so a phenotype gives the same rest mesh on every machine.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np

from phav_generator.body.data import PHENOTYPE_LABELS, VARIATIONS, BodyData

#: The interpolated phenotypes and their anchors (anny's ``make_phenotype_anchors``).
_INTERPOLATED = ("age", "gender", "muscle", "weight", "height", "proportions", "cupsize", "firmness")
#: anny → phav's person frame: anny faces −Y with +X on its left; phav faces +X, +Y left.
ANNY_TO_PERSON = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])


def _anchors(feature: str) -> np.ndarray:
    n = len(VARIATIONS[feature])
    return np.linspace(-1.0 / 3.0, 1.0, n) if feature == "age" else np.linspace(0.0, 1.0, n)


def _interpolation(value: float, anchors: np.ndarray) -> np.ndarray:
    """Weights of ``value`` on the anchors: linear between the two that enclose it, clamped."""
    v = min(max(float(value), float(anchors[0])), float(anchors[-1]))
    i = min(max(int(np.searchsorted(anchors, v, side="left")), 1), len(anchors) - 1)
    alpha = (v - anchors[i - 1]) / (anchors[i] - anchors[i - 1])
    out = np.zeros(len(anchors))
    out[i - 1], out[i] = 1.0 - alpha, alpha
    return out


def phenotype_coefficients(data: BodyData, phenotype: Mapping[str, float]) -> np.ndarray:
    """Coefficients (C,) of the compact blend shapes for a phenotype (values in [0, 1] for
    ``PHENOTYPE_LABELS``; missing ones are anny's default 0.5)."""
    unknown = sorted(set(phenotype) - set(PHENOTYPE_LABELS))
    if unknown:
        raise ValueError(f"unknown phenotype parameters {unknown}; expected {list(PHENOTYPE_LABELS)}")
    weights: dict[str, np.ndarray] = {"race": np.full(3, 1.0 / 3.0)}
    for feature in _INTERPOLATED:
        weights[feature] = _interpolation(phenotype.get(feature, 0.5), _anchors(feature))
    phens = np.concatenate([weights[f] for f in VARIATIONS])  # (26,) in the mask's column order
    mask = data.stacked_mask
    targets = np.prod(phens[None, :] * mask + (1.0 - mask), axis=1)  # (K,)
    # math.fsum: correctly rounded, so the same bits whatever BLAS the machine has.
    return np.array([math.fsum(targets * data.projection[:, c]) for c in range(data.projection.shape[1])])


def _blend(template: np.ndarray, shapes: np.ndarray, coefficients: np.ndarray) -> np.ndarray:
    """template + Σ c·shape, summed shape by shape in index order (the same bits anywhere)."""
    out = np.array(template, dtype=np.float64)
    for c, shape in zip(coefficients, shapes, strict=True):
        if c != 0.0:
            out += float(c) * shape.astype(np.float64)
    return out


def rest_vertices(data: BodyData, coefficients: np.ndarray) -> np.ndarray:
    """The rest mesh (V, 3) of a phenotype, in anny's frame (metres, feet near z = 0)."""
    return _blend(data.template_vertices, data.blendshapes, coefficients)


def rest_bone_heads(data: BodyData, coefficients: np.ndarray) -> np.ndarray:
    """The rig's bone heads (B, 3) at rest for a phenotype, in anny's frame."""
    return _blend(data.template_bone_heads, data.bone_heads_blendshapes, coefficients)
