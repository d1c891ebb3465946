"""The schema check on a dataset's recipes table: a recipe this phav cannot read is named."""

from __future__ import annotations

from phav_validators.findings import Reason
from tests.validators.checks.support import assert_fails, edit_recipes, validate


def test_future_schema_version_fails_schema(data):
    edit_recipes(data, "v000001", lambda d: d.update(schema_version=99))
    hits = assert_fails(validate(data, "schema"), "schema", Reason.RECIPE_INVALID, video="v000001")
    assert "newer" in hits[0].message and "schema_version" in hits[0].message
