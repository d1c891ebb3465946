"""Golden content hashes of two short fixed recipes, per modality.

Pixels are promised identical only for the same renderer fingerprint (DESIGN.md), so the
stored hashes carry the fingerprint digest they were made with; on another machine or
stack the comparison is skipped and says why. Regenerate after an intended change with
PHAV_UPDATE_GOLDEN=1 pytest tests/generator/render/test_golden_render.py.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest

from phav_generator.dataset.fingerprint import renderer_fingerprint
from phav_generator.render.context import gl_context, gl_strings
from phav_spec.encoding import VideoHashes
from tests.generator.physics.support import recipe_for
from tests.generator.render.support import render_recipe

GOLDEN = Path(__file__).parents[2] / "golden" / "render-hashes.json"
CASES = {"walk-urban": ("walk", "urban"), "wave-lake": ("wave", "lake")}


def _hashes(ctx) -> dict[str, dict[str, str]]:
    out = {}
    for name, (action, env) in CASES.items():
        recipe = recipe_for(action, env, seconds=0.2, variation="none")
        h = VideoHashes(recipe.n_frames)
        for rf in render_recipe(recipe, ctx):
            h.add(rf.index, rf.modalities)
        out[name] = h.hexdigests()
    return out


def test_golden_render_hashes():
    ctx = gl_context()
    try:
        fingerprint = renderer_fingerprint(gl_strings(ctx)).digest()
        current = {"fingerprint": fingerprint, "videos": _hashes(ctx)}
    finally:
        ctx.release()
    if os.environ.get("PHAV_UPDATE_GOLDEN") == "1":
        GOLDEN.write_text(json.dumps(current, indent=1, sort_keys=True) + "\n", encoding="utf-8")
    stored = json.loads(GOLDEN.read_text(encoding="utf-8"))
    if stored["fingerprint"] != fingerprint:
        pytest.skip("renderer fingerprint differs from the golden one: bit-exact pixels are not promised")
    assert current["videos"] == stored["videos"]
