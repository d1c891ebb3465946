"""The generator tests' GL context: Mesa's llvmpipe, the renderer of record, one per module."""

from __future__ import annotations

from collections.abc import Iterator

import moderngl
import pytest

from phav_generator.render.context import gl_context


@pytest.fixture(scope="module")
def ctx() -> Iterator[moderngl.Context]:
    c = gl_context()
    yield c
    c.release()
