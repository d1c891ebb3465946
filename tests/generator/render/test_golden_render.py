"""The reference renders (``phav_generator/dataset/reference.json``) against this machine.

Pixels are promised identical for the same renderer fingerprint key (GL strings, the CPU's
SIMD class, the versions, the body data), not the same CPU model, and every stage where
numpy's SIMD targets and OpenBLAS's kernels agree too: the test runs on every machine of the
recording machine's class and, where it skips, names the fields that differ. The reference
records the machine only (``without_code``): a change to phav's code, shaders or asset
library that moves a byte fails here rather than skipping.
Record again after an intended change with
PHAV_UPDATE_GOLDEN=1 pytest tests/generator/render/test_golden_render.py.
"""

from __future__ import annotations

import os

import pytest

from phav_generator.dataset.fingerprint import renderer_fingerprint
from phav_generator.dataset.reference import (
    REFERENCE_FILE,
    broken_promise,
    compare,
    load_reference,
    promised_stages,
    record,
    trace_all,
    without_code,
)
from phav_generator.render.context import gl_context, gl_strings


def test_the_reference_renders_are_bit_exact_on_the_renderer_of_record():
    reference = load_reference()
    ctx = gl_context()
    try:
        here = renderer_fingerprint(gl_strings(ctx))
        if os.environ.get("PHAV_UPDATE_GOLDEN") == "1":
            reference = record(reference.recipes, without_code(here), ctx, REFERENCE_FILE)
        promised = promised_stages(reference.fingerprint, here)
        if not promised:
            differs = reference.fingerprint.differences(here)
            pytest.skip(f"this renderer differs from the reference's in {', '.join(differs)}: bit-exact not promised")
        differing = compare(reference.stages, trace_all(reference.recipes, ctx))
    finally:
        ctx.release()
    assert broken_promise(differing, promised) == [], f"stages that differ per video: {differing}"
