"""The run journal: one JSON line per finished video or shard; a torn last line is cut off."""

from __future__ import annotations

import json

import pytest

from phav_generator.dataset.journal import RUN_FILE, Journal, check_run
from phav_spec.errors import PhavUserError


def _video(vid: str, **change) -> dict:
    """A video's record as the driver journals it."""
    return {"video_id": vid, "shard": "a.tar", "n_frames": 6, "part_bytes": 1, "content_hash": "0" * 64,
            "modality_hashes": {}, "gl": {}, "renderer": {}, **change}  # fmt: skip


def _shard(name: str) -> dict:
    """A shard's record as the driver journals it."""
    return {"name": name, "shard": {"name": name, "sha256": "0" * 64, "bytes": 1, "video_ids": ["v000000"]},
            "videos": [{}], "gl": {}, "renderer": {}}  # fmt: skip


def test_a_torn_journal_line_is_cut_off(tmp_path):
    path = tmp_path / "journal.jsonl"
    j = Journal(path)
    j.append("video", _video("v000000"))
    with open(path, "ab") as fh:
        fh.write(b'{"kind": "video", "rec')
    again = Journal(path)
    assert list(again.videos) == ["v000000"]
    assert path.read_bytes().endswith(b"}\n")
    again.append("shard", _shard("a.tar"))
    assert list(Journal(path).shards) == ["a.tar"]


@pytest.mark.parametrize(
    "line",
    [
        {"kind": "video", "record": {"shard": "a.tar"}},
        {"kind": "video", "record": {"video_id": "v000002"}},
        {"kind": "video", "record": _video("v000001", shard=["a"])},
        {"kind": "video", "record": _video("v000001", part_bytes=True)},
        {"kind": "video", "record": _video("v000001", renderer="x")},
        {"kind": "shard", "record": {"name": "a.tar"}},
        {"kind": "shard", "record": {**_shard("a.tar"), "shard": {"name": "a.tar"}}},
        {"kind": "other", "record": _video("v000001")},
        {"kind": "video", "record": [1]},
    ],
)
def test_a_whole_line_without_what_a_record_needs_is_cut_off_with_the_rest(tmp_path, line):
    """Valid JSON, not a record the driver writes (a field missing or of another type): the
    journal is cut off there, as at a torn line, and what follows is redone."""
    path = tmp_path / "journal.jsonl"
    j = Journal(path)
    j.append("video", _video("v000000"))
    good = path.read_bytes()
    with open(path, "ab") as fh:
        fh.write(json.dumps(line).encode() + b"\n" + json.dumps({"kind": "shard", "record": _shard("a.tar")}).encode()
                 + b"\n")  # fmt: skip
    again = Journal(path)
    assert (list(again.videos), list(again.shards)) == (["v000000"], [])
    assert path.read_bytes() == good


def test_a_damaged_run_file_is_refused_not_overwritten(tmp_path):
    work = tmp_path / ".phav-work"
    work.mkdir()
    (work / RUN_FILE).write_text('{"name": "dem')
    with pytest.raises(PhavUserError, match=r"run\.json: run\.json of the unfinished run is damaged; delete .*"):
        check_run(work, {"name": "demo"})
    assert (work / RUN_FILE).read_text() == '{"name": "dem'
