"""Crash safety of `phav generate`: SIGKILL at any point, a full disk, a dead worker — then a
rerun gives exactly the dataset an uninterrupted run gives (issue: scale-out, crash safety).
The uninterrupted run is the shared `small_dataset`: these runs ask `phav generate` for it again."""

from __future__ import annotations

import contextlib
import errno
import os
import resource
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from phav_generator.dataset import write as write_module
from phav_generator.dataset.journal import JOURNAL_FILE, Journal
from phav_generator.dataset.write import WORK_DIR, chunk, write_dataset
from phav_generator.faults import DELAY_ENV, KILL_AT_ENV, SIGNAL_ENV, delay_for
from phav_spec.errors import PhavUserError
from tests.helpers import SMALL_SEED, SMALL_SHARD_SIZE, SMALL_VIDEOS, cli_env, file_bytes


@pytest.fixture(scope="module")
def reference(small_dataset) -> dict[str, bytes]:
    """Every file of an uninterrupted run (the shared dataset, made with two workers)."""
    return file_bytes(small_dataset)


@pytest.fixture(scope="module")
def generate(small_dataset):
    """``generate(out, *extra, kill_at=, fsize=)``: the shared dataset's `phav generate` into ``out``."""
    args = ("--theta", str(small_dataset / "theta.yaml"), "--videos", str(SMALL_VIDEOS), "--seed", str(SMALL_SEED),
            "--shard-size", str(SMALL_SHARD_SIZE))  # fmt: skip

    def run(out: Path, *extra: str, kill_at: str | None = None, fsize: int | None = None):
        env = cli_env()
        if kill_at is not None:
            env[KILL_AT_ENV] = kill_at

        def limit() -> None:  # runs in the child: a file size limit, as `ulimit -f` sets
            if fsize is not None:
                resource.setrlimit(resource.RLIMIT_FSIZE, (fsize, fsize))

        return subprocess.run(
            [sys.executable, "-m", "phav_app.cli", "generate", *args, "--out", str(out), *extra],
            capture_output=True, text=True, env=env, preexec_fn=limit,
        )  # fmt: skip

    return run


def test_sigkill_anywhere_then_resume_gives_the_uninterrupted_dataset(generate, reference, tmp_path):
    """One directory killed again and again: inside a video's tar part, between a part and
    its journal line, half-way through a journal line, inside a shard's tar — each rerun
    gets further, and the last gives the same bytes as a run never interrupted."""
    out = tmp_path / "data"
    points = ("part:v000000:3", "part-done:v000000", "journal:2", "shard:phav-000000.tar:0", "journal:3",
              "part:v000002:3")  # fmt: skip
    for point in points:
        result = generate(out, kill_at=point)
        assert result.returncode == -signal.SIGKILL, (point, result.returncode, result.stderr[-500:])
        assert not (out / "manifest.json").exists()
        journal = Journal(out / WORK_DIR / JOURNAL_FILE)  # a torn line is cut off here
        for shard in journal.shards:
            assert (out / shard).exists()
    finished = generate(out)
    assert finished.returncode == 0, finished.stderr
    assert file_bytes(out) == reference
    assert not (out / WORK_DIR).exists()


@pytest.mark.parametrize(("sent", "code", "said"), [
    ("INT", 130, "interrupted; finished files are intact (writes are atomic)"),
    ("TERM", 143, "terminated; finished files are intact (writes are atomic)"),
], ids=["ctrl-c", "sigterm"])  # fmt: skip
def test_ctrl_c_or_sigterm_says_what_it_left_and_exits(small_dataset, tmp_path, sent, code, said):
    """SIGINT or SIGTERM while the run is writing a video's part: exit code 130 or 143 and one
    line saying finished files are intact (Typer turned Ctrl-C into a bare exit code before
    ``run_app`` could say so; SIGTERM killed the run where it stood). The run signals itself at
    that point (``PHAV_FAULT_SIGNAL``), and starts with Ctrl-C's default handling, as a command
    typed at a terminal does: a test run started in the background of a non-interactive shell
    ignores SIGINT, and a run it starts would inherit that (and rightly ignore Ctrl-C)."""
    out = tmp_path / "data"
    args = ("--theta", str(small_dataset / "theta.yaml"), "--videos", str(SMALL_VIDEOS), "--seed", str(SMALL_SEED),
            "--shard-size", str(SMALL_SHARD_SIZE), "--out", str(out))  # fmt: skip
    env = cli_env() | {KILL_AT_ENV: "part:v000000:3", SIGNAL_ENV: sent}
    run = subprocess.run([sys.executable, "-m", "phav_app.cli", "generate", *args], stdout=subprocess.DEVNULL,
                         stderr=subprocess.PIPE, text=True, env=env, timeout=120,
                         preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))  # fmt: skip
    err = run.stderr
    assert run.returncode == code, err[-500:]
    assert [line for line in err.splitlines() if line.strip()] == [said]
    assert not [p for p in out.rglob(".*.tmp")], "a temporary was left behind"
    assert not (out / "manifest.json").exists()


def test_a_killed_worker_is_a_one_line_error_and_the_rerun_resumes(generate, reference, tmp_path):
    out = tmp_path / "data"
    result = generate(out, "--workers", "2", kill_at="part:v000002:2")
    assert result.returncode == 2
    assert "worker process died" in result.stderr and "Traceback" not in result.stderr
    assert generate(out, "--workers", "2").returncode == 0
    assert file_bytes(out) == reference


def test_ctrl_c_at_a_terminal_stops_a_pool_in_one_line(small_dataset, tmp_path):
    """Ctrl-C at a terminal signals the whole process group: the pool's workers stop the
    video under way (removing its temporaries) or, idle, exit without the traceback their
    pool's queue printed, and the run says one line. One worker is idle here: v000000 is
    finished and v000001 still waits out its injected delay."""
    out = tmp_path / "data"
    args = ("--theta", str(small_dataset / "theta.yaml"), "--videos", "2", "--seed", str(SMALL_SEED),
            "--shard-size", str(SMALL_SHARD_SIZE), "--out", str(out), "--workers", "2")  # fmt: skip
    assert delay_for("v000000", 60.0) < 1.0 < 20.0 < delay_for("v000001", 60.0)
    run = subprocess.Popen([sys.executable, "-m", "phav_app.cli", "generate", *args], stdout=subprocess.DEVNULL,
                           stderr=subprocess.PIPE, text=True, env=cli_env() | {DELAY_ENV: "60"}, start_new_session=True,
                           preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))  # fmt: skip
    journal = out / WORK_DIR / JOURNAL_FILE
    try:
        deadline = time.monotonic() + 120.0
        while not (journal.exists() and journal.read_text(encoding="utf-8").count("\n") >= 1):  # v000000 finished
            assert run.poll() is None and time.monotonic() < deadline, "v000000 was never finished"
            time.sleep(0.05)
        time.sleep(0.5)  # the finished worker back at the pool's queue
        os.killpg(run.pid, signal.SIGINT)
        _, err = run.communicate(timeout=120)
    finally:
        with contextlib.suppress(ProcessLookupError):
            os.killpg(run.pid, signal.SIGKILL)
    assert run.returncode == 130, err[-800:]
    assert [line for line in err.splitlines() if line.strip()] == [
        "interrupted; finished files are intact (writes are atomic)"
    ], err[-1500:]
    assert not [p for p in out.rglob(".*.tmp")], "a temporary was left behind"
    assert not (out / "manifest.json").exists()


def test_a_worker_sent_sigterm_removes_the_part_it_was_writing(small_dataset, tmp_path):
    """A scheduler's time limit signals the whole process group: a pool's worker stopped while
    it writes a video's part removes its temporary, as the driver's writes do (it died where
    it stood and left it)."""
    out = tmp_path / "data"
    args = ("--theta", str(small_dataset / "theta.yaml"), "--videos", str(SMALL_VIDEOS), "--seed", str(SMALL_SEED),
            "--shard-size", str(SMALL_SHARD_SIZE), "--out", str(out), "--workers", "2")  # fmt: skip
    env = cli_env() | {KILL_AT_ENV: "part:v000002:2", SIGNAL_ENV: "TERM"}  # the worker signals itself
    run = subprocess.run([sys.executable, "-m", "phav_app.cli", "generate", *args], capture_output=True, text=True,
                         env=env, timeout=180)  # fmt: skip
    assert run.returncode == 2 and "worker process died" in run.stderr and "Traceback" not in run.stderr, run.stderr
    assert not [p for p in out.rglob(".*.tmp")], "a temporary was left behind"


def test_a_full_journal_is_said_of_the_journal(monkeypatch, tmp_path):
    """A full disk while a record is appended names the journal file (it named the folder)."""
    from phav_generator.dataset import journal as journal_module

    def full(fd: int) -> None:
        raise OSError(errno.ENOSPC, "No space left on device")

    journal = Journal(tmp_path / JOURNAL_FILE)
    monkeypatch.setattr(journal_module.os, "fsync", full)
    with pytest.raises(PhavUserError, match="the disk is full") as caught:
        journal.append("video", {"video_id": "v000000"})
    assert caught.value.source == str(tmp_path / JOURNAL_FILE)


def test_a_file_size_limit_is_a_clear_error_that_keeps_finished_videos(generate, reference, tmp_path):
    """RLIMIT_FSIZE below a shard's size: the videos' parts fit, joining them does not."""
    out = tmp_path / "data"
    shard = len(reference["phav-000000.tar"])
    result = generate(out, fsize=shard - 20_000)
    assert result.returncode == 2, result.stderr
    assert "file size limit" in result.stderr and "Traceback" not in result.stderr
    kept = Journal(out / WORK_DIR / JOURNAL_FILE)
    assert set(kept.videos) >= {"v000000", "v000001"} and not kept.shards
    assert generate(out).returncode == 0
    assert file_bytes(out) == reference


def test_a_full_disk_is_a_clear_error_that_keeps_finished_videos(monkeypatch, small_recipes, small_theta, tmp_path):
    shards = chunk(small_recipes[:2], 1)
    render = write_module.run_task

    def full_after_one(task, report=None, *, parts):
        if task.video_id == "v000001":
            raise OSError(errno.ENOSPC, "No space left on device", str(parts / "x"))
        return render(task, report, parts=parts)

    monkeypatch.setattr(write_module, "run_task", full_after_one)
    out = tmp_path / "data"
    with pytest.raises(PhavUserError, match="disk is full"):
        write_dataset(shards, out, name="demo", theta=small_theta, dataset_seed=SMALL_SEED)
    assert (out / "demo-000000.tar").exists()
    monkeypatch.setattr(write_module, "run_task", render)
    resumed = write_dataset(shards, out, name="demo", theta=small_theta, dataset_seed=SMALL_SEED)
    assert (resumed.resumed_videos, resumed.rendered_videos) == (1, 1)
    clean = write_dataset(shards, tmp_path / "clean", name="demo", theta=small_theta, dataset_seed=SMALL_SEED)
    assert resumed.manifest == clean.manifest


@pytest.mark.skipif(os.geteuid() == 0, reason="root writes into read-only directories")
def test_an_unwritable_output_directory_is_a_clear_error(generate, tmp_path):
    out = tmp_path / "ro"
    out.mkdir()
    out.chmod(0o555)
    try:
        result = generate(out)
    finally:
        out.chmod(0o755)
    assert result.returncode == 2 and "not writable" in result.stderr and "Traceback" not in result.stderr


def _workers_of(pid: int) -> list[int]:
    """The pool workers a process spawned (children running multiprocessing's spawn_main)."""
    out = []
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                ppid = int(next(li for li in (entry / "status").read_text().splitlines() if li.startswith("PPid:"))[5:])
                cmd = (entry / "cmdline").read_bytes()
            except (OSError, StopIteration, ValueError):
                continue
            if ppid == pid and b"spawn_main" in cmd:
                out.append(int(entry.name))
    return out


def _running(pid: int) -> bool:
    try:
        state = next(li for li in Path(f"/proc/{pid}/status").read_text().splitlines() if li.startswith("State:"))
    except (OSError, StopIteration):
        return False
    return "Z" not in state.split()[1]  # a zombie has ended


@pytest.mark.skipif(not Path("/proc/self/status").exists(), reason="reads processes from /proc")
def test_the_workers_end_with_a_killed_run(small_dataset, tmp_path):
    """A run SIGKILLed while its two workers render: the workers end within seconds instead
    of rendering on for nobody (they watch the process that started them)."""
    args = ("--theta", str(small_dataset / "theta.yaml"), "--videos", str(SMALL_VIDEOS), "--seed", str(SMALL_SEED),
            "--shard-size", str(SMALL_SHARD_SIZE), "--workers", "2", "--out", str(tmp_path / "data"))  # fmt: skip
    run = subprocess.Popen([sys.executable, "-m", "phav_app.cli", "generate", *args], stdout=subprocess.DEVNULL,
                           stderr=subprocess.DEVNULL, env=cli_env())  # fmt: skip
    workers: list[int] = []
    try:
        deadline = time.monotonic() + 120.0
        while len(workers := _workers_of(run.pid)) < 2:
            assert run.poll() is None and time.monotonic() < deadline, "the run never started two workers"
            time.sleep(0.1)
        run.kill()
        run.wait()
        deadline = time.monotonic() + 10.0
        while any(_running(w) for w in workers) and time.monotonic() < deadline:
            time.sleep(0.1)
        assert not any(_running(w) for w in workers), "a worker outlived its run"
    finally:  # nothing outlives the test, whatever it found
        run.kill()
        for w in workers:
            with contextlib.suppress(ProcessLookupError):
                os.kill(w, signal.SIGKILL)
