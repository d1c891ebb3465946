"""Structured validator results: findings with a reason, collected into reports and checks."""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Callable
from dataclasses import dataclass, field
from enum import StrEnum
from typing import Any

#: ``progress(description, total)`` starts a bar and returns its ``advance(n)``; every long
#: check reports through one.
ProgressFactory = Callable[[str, int], Callable[[int], None]]


class Reason(StrEnum):
    """Why a check complained; stable names a consumer can filter on (docs/validation.md)."""

    # distribution / recipes
    IMPOSSIBLE_VALUE = "IMPOSSIBLE_VALUE"  # a value with probability zero under θ was observed
    DISTRIBUTION_MISMATCH = "DISTRIBUTION_MISMATCH"  # a goodness-of-fit test rejected θ
    RECIPE_INVALID = "RECIPE_INVALID"  # a recipe does not validate against its schema
    COLUMN_MISMATCH = "COLUMN_MISMATCH"  # a stable column disagrees with the recipe JSON
    THETA_MISMATCH = "THETA_MISMATCH"  # the θ given differs from the one the data records
    DUPLICATE_VIDEO = "DUPLICATE_VIDEO"  # a video id or index appears twice
    # integrity
    MANIFEST_INVALID = "MANIFEST_INVALID"  # manifest.json missing, unparsable or inconsistent
    MISSING_FILE = "MISSING_FILE"  # a file the layout or manifest lists is absent
    UNLISTED_FILE = "UNLISTED_FILE"  # a shard in the directory the manifest does not list
    MISSING_MEMBER = "MISSING_MEMBER"  # a frame's modality or metadata member is absent
    UNLISTED_MEMBER = "UNLISTED_MEMBER"  # a tar member no listed video/frame/modality explains
    UNSAFE_MEMBER = "UNSAFE_MEMBER"  # absolute path, '..', link, device: refused unread
    OVERSIZED_MEMBER = "OVERSIZED_MEMBER"  # a member or image too large to be a frame (bomb)
    TRUNCATED_SHARD = "TRUNCATED_SHARD"  # the tar ends mid-member or cannot be read
    HASH_MISMATCH = "HASH_MISMATCH"  # decoded pixels differ from the manifest's content hash
    SHARD_BYTES_CHANGED = "SHARD_BYTES_CHANGED"  # tar bytes differ, pixels identical (re-encoded)
    RELEASE_FILE_CHANGED = "RELEASE_FILE_CHANGED"  # a file's size or sha256 differs from release.json's
    # schema
    VIDEO_RECIPE_MISMATCH = "VIDEO_RECIPE_MISMATCH"  # videos and recipes do not pair one to one
    VERSION_UNKNOWN = "VERSION_UNKNOWN"  # a spec / metadata version this phav does not know
    METADATA_INVALID = "METADATA_INVALID"  # metadata tables or frame json break the contract
    # encoding
    PNG_FORMAT = "PNG_FORMAT"  # bit depth, colour type, size or readability of a PNG
    FRAME_COUNT = "FRAME_COUNT"  # a video has another number of frames than its recipe
    DEPTH_CODE = "DEPTH_CODE"  # depth code 0 (never written)
    FLOW_CODE = "FLOW_CODE"  # flow B not in {0, 1}, or an invalid pixel not (0, 0, 0)
    FOREIGN_COLOUR = "FOREIGN_COLOUR"  # a semantic colour outside the palette
    INSTANCE_MISMATCH = "INSTANCE_MISMATCH"  # instance colours or pixel counts ≠ metadata ids
    # failures
    NAN_POSE = "NAN_POSE"  # a non-finite joint position
    ENERGY_EXPLOSION = "ENERGY_EXPLOSION"  # joints moving impossibly fast or limbs stretching
    INTERPENETRATION = "INTERPENETRATION"  # a body inside or through static geometry
    JOINT_LIMIT = "JOINT_LIMIT"  # a joint bent past what a body allows
    OFF_SCREEN = "OFF_SCREEN"  # the protagonist out of view or hidden most of the clip
    CAMERA_IN_GEOMETRY = "CAMERA_IN_GEOMETRY"  # the camera inside a wall or under the ground
    PERTURBATION_TOO_STRONG = "PERTURBATION_TOO_STRONG"  # the action's muscles far from its motion
    FOOT_SLIDING = "FOOT_SLIDING"  # feet moving while planted on the ground
    FAILURE_BUDGET = "FAILURE_BUDGET"  # more failed videos than the budget allows
    # consistency
    FLOW_DEPTH_MISMATCH = "FLOW_DEPTH_MISMATCH"  # flow ≠ depth + camera motion on static pixels
    JOINT_PROJECTION = "JOINT_PROJECTION"  # 3D joints do not project to the 2D joints or depth
    MASK_MISMATCH = "MASK_MISMATCH"  # instance masks ≠ semantic person classes
    # reproducibility
    REGENERATION_MISMATCH = "REGENERATION_MISMATCH"  # a regenerated video differs
    RENDERER_UNRECORDED = "RENDERER_UNRECORDED"  # no renderer of record: compared within tolerances (warn)
    # learnability
    NOT_LEARNABLE = "NOT_LEARNABLE"  # a small TSN does not beat chance on held-out actors
    LEARNING_INCONCLUSIVE = "LEARNING_INCONCLUSIVE"  # the time budget stopped training first (warn)
    # realism
    REALISM_BELOW_MIN = "REALISM_BELOW_MIN"  # a figure asked for with --realism-min is below it


class Status(StrEnum):
    """A check's verdict: ``fail`` makes ``phav-validate`` exit 1, ``warn`` does not."""

    PASS = "pass"
    WARN = "warn"
    FAIL = "fail"
    SKIP = "skip"


@dataclass(frozen=True)
class Finding:
    """One problem: the reason, where it is, and the numbers behind it.

    ``severity`` ``warn`` is worth reading but does not fail the check (a shard whose bytes
    changed while its pixels did not)."""

    reason: Reason
    message: str
    file: str | None = None
    video_id: str | None = None
    numbers: dict[str, Any] = field(default_factory=dict)
    severity: str = "fail"

    def to_json(self) -> dict[str, Any]:
        return {
            "reason": self.reason.value, "severity": self.severity, "message": self.message,
            "file": self.file, "video_id": self.video_id, "numbers": self.numbers,
        }  # fmt: skip


def figure_text(x: float | None, spec: str) -> str:
    """``x`` formatted by ``spec``, or a dash where there is no finite number (a camera that
    never sees the protagonist has no height quartiles; the JSON writes them null)."""
    return format(x, spec) if x is not None and math.isfinite(x) else "—"


#: Findings kept per reason in one check; the rest are counted, not listed.
MAX_PER_REASON = 50


@dataclass
class Report:
    """Findings collected lazily across checks, rather than stopping at the first."""

    findings: list[Finding] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    counts: Counter[Reason] = field(default_factory=Counter)

    def add(self, finding: Finding) -> None:
        """Record a finding; checks go on. Past ``MAX_PER_REASON`` per reason only counted."""
        self.counts[finding.reason] += 1
        if self.counts[finding.reason] <= MAX_PER_REASON:
            self.findings.append(finding)

    @property
    def failures(self) -> list[Finding]:
        return [f for f in self.findings if f.severity == "fail"]

    @property
    def ok(self) -> bool:
        """True when nothing failed (warnings allowed)."""
        return not self.failures

    def overflow_notes(self) -> list[str]:
        """One line per reason with findings beyond the listed ones."""
        return [
            f"{r.value}: {k} findings, first {MAX_PER_REASON} listed" for r, k in self.counts.items()
            if k > MAX_PER_REASON
        ]  # fmt: skip

    def all_notes(self) -> list[str]:
        """The notes, then the overflow lines: what every rendering of a report shows."""
        return self.notes + self.overflow_notes()


@dataclass
class CheckResult:
    """One named check of ``phav-validate``: verdict, summary line, numbers and findings."""

    name: str
    status: Status
    summary: str
    numbers: dict[str, Any] = field(default_factory=dict)
    report: Report = field(default_factory=Report)
    seconds: float = 0.0

    @classmethod
    def from_report(cls, name: str, report: Report, summary: str, numbers: dict[str, Any]) -> CheckResult:
        """Status from the findings: fail if any fails, warn if any warns, else pass."""
        if not report.ok:
            status = Status.FAIL
        elif report.findings:
            status = Status.WARN
        else:
            status = Status.PASS
        return cls(name, status, summary, numbers, report)

    @classmethod
    def skipped(cls, name: str, why: str) -> CheckResult:
        return cls(name, Status.SKIP, why)

    def to_json(self) -> dict[str, Any]:
        return {
            "name": self.name,
            "status": self.status.value,
            "summary": self.summary,
            "seconds": round(self.seconds, 3),
            "numbers": self.numbers,
            "finding_counts": {r.value: k for r, k in sorted(self.report.counts.items())},
            "findings": [f.to_json() for f in self.report.findings],
            "notes": self.report.all_notes(),
        }
