"""``phav-validate`` on a dataset: the seven checks, run once each, collected into one report.

integrity · schema · encoding · distribution · failures · consistency · reproducibility,
and when named, learnability (a small TSN trained on the pixels; docs/learnability.md) and
realism (models trained on real photographs judge a sample of frames; docs/realism.md)
(docs/validation.md says what each measures and where its thresholds come from). Shards are
scanned once, in a process pool when ``workers`` > 1; integrity, encoding and consistency
read their numbers off that one pass. Every check runs even when another fails, so one
report lists everything wrong; a check whose inputs are missing is skipped, and says why.
"""

from __future__ import annotations

from phav_validators.as_is import validate_as_is
from phav_validators.findings import ProgressFactory
from phav_validators.options import DEFAULT_OPTIONS, PIXEL_CHECKS, DatasetReport, Options
from phav_validators.regenerated import validate_release
from phav_validators.source import DatasetInput, is_recipe_release


def validate_dataset(
    inp: DatasetInput,
    *,
    theta: str | None = None,
    options: Options = DEFAULT_OPTIONS,
    progress: ProgressFactory | None = None,
) -> DatasetReport:
    """Run the chosen checks on one dataset; user errors (bad --theta) raise PhavUserError.
    A recipe-only release has the pixels its checks read regenerated first (``regenerated``)."""
    if is_recipe_release(inp) and set(options.checks) & set(PIXEL_CHECKS):
        return validate_release(inp, theta=theta, options=options, progress=progress)
    return validate_as_is(inp, theta=theta, options=options, progress=progress)
