"""The run journal: one JSON line per finished video or shard; a torn last line is cut off."""

from __future__ import annotations

import pytest

from phav_generator.dataset.journal import RUN_FILE, Journal, check_run
from phav_spec.errors import PhavUserError


def test_a_torn_journal_line_is_cut_off(tmp_path):
    path = tmp_path / "journal.jsonl"
    j = Journal(path)
    j.append("video", {"video_id": "v000000", "shard": "a.tar", "part_bytes": 1})
    with open(path, "ab") as fh:
        fh.write(b'{"kind": "video", "rec')
    again = Journal(path)
    assert list(again.videos) == ["v000000"]
    assert path.read_bytes().endswith(b"}\n")
    again.append("shard", {"name": "a.tar"})
    assert list(Journal(path).shards) == ["a.tar"]


def test_a_whole_line_without_what_a_record_needs_is_cut_off_with_the_rest(tmp_path):
    path = tmp_path / "journal.jsonl"
    j = Journal(path)
    j.append("video", {"video_id": "v000000", "shard": "a.tar", "part_bytes": 1})
    good = path.read_bytes()
    with open(path, "ab") as fh:
        fh.write(b'{"kind": "video", "record": {"shard": "a.tar"}}\n{"kind": "shard", "record": {"name": "a.tar"}}\n')
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
