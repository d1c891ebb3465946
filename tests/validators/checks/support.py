"""Damaging a dataset the way the issue's list does, and asking one check about it.

Each test copies the run's shared small dataset (``data``, tests/validators/checks/conftest.py),
changes one thing, and runs only the checks that thing concerns."""

from __future__ import annotations

import io
import json
import tarfile
from collections.abc import Callable, Sequence
from pathlib import Path

import cv2
import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq

from phav_spec.manifest import dump_manifest, load_manifest
from phav_validators.checks.scan import ShardJob, VideoExpect, scan_shard
from phav_validators.findings import CheckResult, Finding, Reason, Status
from phav_validators.options import CHECKS, DatasetReport, Options
from phav_validators.source import resolve
from phav_validators.validate import validate_dataset


def validate(
    path: Path, *checks: str, theta: str | None = None, regenerate: int = 0, workers: int = 1
) -> DatasetReport:
    """``phav-validate PATH --checks …`` in this process (every check when none is named)."""
    options = Options(checks=checks or CHECKS, regenerate=regenerate, workers=workers)
    return validate_dataset(resolve([path])[0], theta=theta, options=options)


def check(report: DatasetReport, name: str) -> CheckResult:
    return next(c for c in report.checks if c.name == name)


def assert_fails(
    report: DatasetReport, name: str, reason: Reason, *, video: str | None = None, file: str | None = None
) -> list[Finding]:
    """The check failed with ``reason`` (about ``video`` / ``file`` when given); its findings."""
    result = check(report, name)
    assert result.status == Status.FAIL, (name, result.summary, [f.message for f in result.report.findings])
    hits = [f for f in result.report.findings if f.reason == reason]
    assert hits, (reason, [(f.reason, f.message) for f in result.report.findings])
    if video is not None:
        assert any(f.video_id == video for f in hits), [(f.video_id, f.message) for f in hits]
    if file is not None:
        assert any(f.file is not None and file in f.file for f in hits), [(f.file, f.message) for f in hits]
    return hits


def shard_of(ds: Path, video: str) -> Path:
    m = load_manifest(ds / "manifest.json")
    return ds / next(v.shard for v in m.videos if v.video_id == video)


def rewrite_tar(
    path: Path, edit: Callable[[str, bytes], bytes | None], extra: Sequence[tuple[str, bytes]] = ()
) -> None:
    """Rewrite a shard member by member: ``edit(name, data)`` returns new bytes or None to drop."""
    with tarfile.open(path) as tar:
        members = [(info, tar.extractfile(info).read()) for info in tar.getmembers()]
    buf = io.BytesIO()
    with tarfile.open(fileobj=buf, mode="w", format=tarfile.USTAR_FORMAT) as tar:
        for info, data in members:
            new = edit(info.name, data)
            if new is None:
                continue
            info.size = len(new)
            tar.addfile(info, io.BytesIO(new))
        for name, data in extra:
            info = tarfile.TarInfo(name)
            info.size = len(data)
            tar.addfile(info, io.BytesIO(data))
    path.write_bytes(buf.getvalue())


def png_edit(member: str, change: Callable[[np.ndarray], np.ndarray]) -> Callable[[str, bytes], bytes | None]:
    """An edit that decodes one PNG member (OpenCV's channel order), changes it, re-encodes it."""

    def edit(name: str, data: bytes) -> bytes:
        if name != member:
            return data
        image = cv2.imdecode(np.frombuffer(data, np.uint8), cv2.IMREAD_UNCHANGED)
        ok, png = cv2.imencode(".png", change(image.copy()))
        assert ok
        return png.tobytes()

    return edit


def refresh_manifest(ds: Path) -> None:
    """Recompute every video's content hashes and every shard's digest from the files, as a
    forger who edits frames and manifest together would."""
    m = load_manifest(ds / "manifest.json")
    data = m.model_dump(mode="json")
    by_video = {v["video_id"]: v for v in data["videos"]}
    for shard in data["shards"]:
        job = ShardJob(str(ds / shard["name"]), tuple(
            VideoExpect(vid, by_video[vid]["n_frames"], 340, 256, None) for vid in shard["video_ids"]
        ))  # fmt: skip
        scan = scan_shard(job)
        shard["sha256"], shard["bytes"] = scan.tar.sha256, scan.tar.bytes
        for vid in shard["video_ids"]:
            by_video[vid]["modality_hashes"] = scan.videos[vid].modality_hashes
            by_video[vid]["content_hash"] = scan.videos[vid].content_hash
    dump_manifest(type(m).model_validate(data), ds / "manifest.json")


def edit_people(ds: Path, edit: Callable[[dict[str, list]], None]) -> None:
    """Rewrite ``people.parquet`` with ``edit`` applied to its columns (as lists)."""
    table = pq.read_table(ds / "people.parquet")
    columns = {name: table.column(name).to_pylist() for name in table.column_names}
    edit(columns)
    pq.write_table(pa.Table.from_pydict(columns, schema=table.schema), ds / "people.parquet")


def edit_recipes(ds: Path, video: str, edit: Callable[[dict], None], **column_values) -> None:
    """Rewrite one video's recipe JSON with ``edit``, and its stable columns with ``column_values``."""
    table = pq.read_table(ds / "recipes.parquet")
    row = table.column("video_id").to_pylist().index(video)
    texts = table.column("recipe").to_pylist()
    data = json.loads(texts[row])
    edit(data)
    texts[row] = json.dumps(data)
    table = table.set_column(table.column_names.index("recipe"), "recipe", pa.array(texts, pa.string()))
    for name, value in column_values.items():
        values = table.column(name).to_pylist()
        values[row] = value
        i = table.column_names.index(name)
        table = table.set_column(i, table.schema.field(name), pa.array(values, table.schema.field(name).type))
    pq.write_table(table, ds / "recipes.parquet")
