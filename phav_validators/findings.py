"""Structured validator results: findings with a reason, collected into one report."""

from __future__ import annotations

from dataclasses import dataclass, field
from enum import StrEnum
from typing import Any


class Reason(StrEnum):
    """Why a check failed; stable names a consumer can filter on."""

    IMPOSSIBLE_VALUE = "IMPOSSIBLE_VALUE"  # a value with probability zero under θ was observed
    DISTRIBUTION_MISMATCH = "DISTRIBUTION_MISMATCH"  # a goodness-of-fit test rejected θ
    RECIPE_INVALID = "RECIPE_INVALID"  # a recipe does not validate against its schema
    COLUMN_MISMATCH = "COLUMN_MISMATCH"  # a stable column disagrees with the recipe JSON
    THETA_MISMATCH = "THETA_MISMATCH"  # the θ given differs from the one the data records
    DUPLICATE_VIDEO = "DUPLICATE_VIDEO"  # a video id or index appears twice


@dataclass(frozen=True)
class Finding:
    """One problem: the reason, where it is, and the numbers behind it."""

    reason: Reason
    message: str
    file: str | None = None
    video_id: str | None = None
    numbers: dict[str, Any] = field(default_factory=dict)


@dataclass
class Report:
    """Findings collected lazily across checks, rather than stopping at the first."""

    findings: list[Finding] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)

    def add(self, finding: Finding) -> None:
        """Record a finding; checks go on."""
        self.findings.append(finding)

    @property
    def ok(self) -> bool:
        """True when nothing was found."""
        return not self.findings
