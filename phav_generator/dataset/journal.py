"""The run's memory: ``run.json`` (the settings of the run a directory holds) and
``journal.jsonl`` (one line per finished video and shard), so that a rerun resumes exactly
where a killed run stopped and never mixes two runs in one directory."""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any

from phav_generator.faults import armed, crash_point
from phav_spec.canonical import canonical_json
from phav_spec.errors import PhavUserError
from phav_spec.files import WriteError, atomic_write

RUN_FILE = "run.json"
JOURNAL_FILE = "journal.jsonl"


class Journal:
    """The run's journal: one JSON line per finished video and per finished shard.

    Appended (and fsynced) by the driver only, after the file it records is in place, so a
    line never claims work that is not on disk. A line torn by a crash is cut off when the
    journal is opened again; everything before it stands.
    """

    def __init__(self, path: Path):
        self.path = path
        self.videos: dict[str, dict[str, Any]] = {}
        self.shards: dict[str, dict[str, Any]] = {}
        self._lines = 0
        good = 0
        try:
            data = path.read_bytes()
        except FileNotFoundError:
            data = b""
        for line in data.splitlines(keepends=True):
            if not line.endswith(b"\n"):
                break
            try:
                entry = json.loads(line)
                kind, record = entry["kind"], entry["record"]
            except (ValueError, KeyError, TypeError):  # damaged from here on: cut off, redone
                break
            if not _well_formed(kind, record):  # the driver wrote no such line: damaged, as above
                break
            self._remember(kind, record)
            good += len(line)
            self._lines += 1
        if good != len(data):
            with open(path, "r+b") as fh:
                fh.truncate(good)
                os.fsync(fh.fileno())

    def append(self, kind: str, record: dict[str, Any]) -> None:
        line = (canonical_json({"kind": kind, "record": record}) + "\n").encode("utf-8")
        self._lines += 1
        try:
            with open(self.path, "ab") as fh:
                if armed(f"journal:{self._lines}"):
                    fh.write(line[: len(line) // 2])
                    fh.flush()
                    crash_point(f"journal:{self._lines}")
                fh.write(line)
                fh.flush()
                os.fsync(fh.fileno())
        except OSError as e:  # a full disk: said of the journal (a half line is cut off on resuming)
            raise WriteError(e, str(self.path)) from None
        self._remember(kind, record)

    def _remember(self, kind: str, record: dict[str, Any]) -> None:
        if kind == "video":
            self.videos[record["video_id"]] = record
        else:
            self.shards[record["name"]] = record


_VIDEO_FIELDS = {"video_id": str, "shard": str, "n_frames": int, "part_bytes": int, "content_hash": str,
                 "modality_hashes": dict, "gl": dict}  # fmt: skip
_SHARD_FIELDS = {"name": str, "shard": dict, "videos": list, "gl": dict, "renderer": dict}


def _well_formed(kind: Any, record: Any) -> bool:
    """Whether a journal line holds what the driver writes: a video's or a shard's record with
    its fields of their types (a video's ``renderer`` may be absent: an older phav's, refused
    by name on resuming)."""
    fields = {"video": _VIDEO_FIELDS, "shard": _SHARD_FIELDS}.get(kind) if isinstance(kind, str) else None
    if fields is None or not isinstance(record, dict):
        return False
    if not all(isinstance(record.get(k), t) and not isinstance(record.get(k), bool) for k, t in fields.items()):
        return False
    if kind == "video":
        return isinstance(record.get("renderer", {}), dict)
    shard = record["shard"]
    return (isinstance(shard.get("bytes"), int) and isinstance(shard.get("sha256"), str)
            and isinstance(shard.get("video_ids"), list) and all(isinstance(v, str) for v in shard["video_ids"])
            and all(isinstance(v, dict) for v in record["videos"]))  # fmt: skip


def check_run(work: Path, run: dict[str, Any]) -> None:
    """Refuse to mix two different runs in one directory; remember this run otherwise."""
    path = work / RUN_FILE
    if path.exists():
        try:
            before = json.loads(path.read_text(encoding="utf-8"))
        except (OSError, ValueError):
            before = None
        if not isinstance(before, dict):  # written atomically: damaged from outside, trust nothing
            raise PhavUserError(
                f"{RUN_FILE} of the unfinished run is damaged; delete {work} to start over",
                source=str(work.parent),
                field=RUN_FILE,
            )
        if before != run:
            differs = sorted(k for k in set(before) | set(run) if before.get(k) != run.get(k))
            raise PhavUserError(
                f"the directory holds an unfinished run with other settings ({', '.join(differs)} differ); "
                "use another --out, or delete the directory to start over",
                source=str(work.parent),
                field=differs[0] if differs else None,
            )
    with atomic_write(path) as tmp:
        tmp.write_text(canonical_json(run), encoding="utf-8")
