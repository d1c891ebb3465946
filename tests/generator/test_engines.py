"""Engines: Ray (≥ 2 workers, random per-task delays) and the local pool give the same
dataset byte for byte (issue: scale-out, crash safety)."""

from __future__ import annotations

import contextlib
import os
import re
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import pytest

from phav_generator.dataset.write import chunk, write_dataset
from phav_generator.faults import delay_for
from phav_spec.errors import PhavUserError
from tests.helpers import RAY_DELAY_S, SMALL_SEED, SMALL_SHARD_SIZE, file_bytes, run_cli


def test_ray_and_the_local_pool_give_identical_datasets(ray_with_delays, small_dataset, small_recipes, small_theta,
                                                        tmp_path):  # fmt: skip
    """The shared dataset (`phav generate`, a local pool of two workers) made again on Ray."""
    shards = chunk(small_recipes, SMALL_SHARD_SIZE)
    # Up to 3 s per task, fixed by the video id: later videos finish first.
    delays = [delay_for(r.video_id, RAY_DELAY_S) for recipes in shards for r in recipes]
    assert delays != sorted(delays)
    ray = write_dataset(shards, tmp_path / "ray", name="phav", theta=small_theta, dataset_seed=SMALL_SEED, workers=2,
                        engine="ray")  # fmt: skip
    assert file_bytes(tmp_path / "ray") == file_bytes(small_dataset)
    assert ray.rendered_videos == len(small_recipes)


def test_an_unknown_engine_is_a_one_line_error(small_theta, tmp_path):
    with pytest.raises(PhavUserError, match="unknown engine 'spark'"):
        write_dataset([], tmp_path / "x", name="demo", theta=small_theta, dataset_seed=0, engine="spark")


def test_a_ray_address_without_the_ray_engine_is_refused_not_ignored(small_theta, tmp_path):
    with pytest.raises(PhavUserError, match=r"--address: a Ray cluster address needs --engine ray"):
        write_dataset([], tmp_path / "x", name="demo", theta=small_theta, dataset_seed=0, address="10.0.0.1:6379")


@pytest.mark.parametrize(
    ("address", "said"),
    [("notahost", "expected HOST:PORT"), ("127.0.0.1:1", "cannot reach the Ray cluster")],
)
def test_a_cluster_address_that_is_malformed_or_silent_is_one_line(address, said, monkeypatch):
    """Ray raised a ValueError traceback for a malformed address and retried a silent one
    for minutes; both are a one-line error naming --address, before Ray starts."""
    ray = pytest.importorskip("ray")
    from phav_generator.engines import ray_session

    def init(**options):
        raise AssertionError("ray.init was called")

    monkeypatch.setattr(ray, "is_initialized", lambda: False)  # another test's Ray may be up
    monkeypatch.setattr(ray, "init", init)
    with pytest.raises(PhavUserError, match=said) as caught, ray_session(2, address):
        pass
    assert caught.value.field == "--address" and caught.value.source == address


def test_ray_address_is_the_clusters_and_a_local_ray_is_asked_for_as_such(monkeypatch):
    """Ray follows RAY_ADDRESS (and a cluster a `ray start` left on the machine) and then
    refused the CPU count asked of a local Ray, blaming --address, which nobody gave: a set
    RAY_ADDRESS is now the cluster's address, checked and named as such, and without one a
    local Ray is asked for explicitly."""
    ray = pytest.importorskip("ray")
    from phav_generator.engines import ray_session

    asked: list[dict] = []
    monkeypatch.setattr(ray, "is_initialized", lambda: False)
    monkeypatch.setattr(ray, "init", lambda **options: asked.append(options))
    monkeypatch.setattr(ray, "shutdown", lambda: None)
    monkeypatch.delenv("RAY_ADDRESS", raising=False)
    with ray_session(3, None):
        pass
    assert asked[-1]["address"] == "local" and asked[-1]["num_cpus"] == 3
    with socket.create_server(("127.0.0.1", 0)) as server:
        live = f"127.0.0.1:{server.getsockname()[1]}"
        monkeypatch.setenv("RAY_ADDRESS", live)
        with ray_session(3, None):
            pass
    assert asked[-1]["address"] == live and "num_cpus" not in asked[-1]
    monkeypatch.setenv("RAY_ADDRESS", "127.0.0.1:1")
    with pytest.raises(PhavUserError, match="cannot reach the Ray cluster") as caught, ray_session(3, None):
        pass
    assert caught.value.field == "RAY_ADDRESS" and caught.value.source == "127.0.0.1:1"
    monkeypatch.setenv("RAY_ADDRESS", "local")  # Ray's word for a local Ray
    with ray_session(3, None):
        pass
    assert asked[-1]["address"] == "local" and asked[-1]["num_cpus"] == 3
    monkeypatch.delenv("RAY_ADDRESS")

    def fails(**options):
        raise ValueError("The requested object store memory size is greater than the total available memory.")

    monkeypatch.setattr(ray, "init", fails)  # a local Ray that cannot start names no address
    with pytest.raises(PhavUserError, match=r"^--engine: cannot start a local Ray: The requested object store"):
        with ray_session(3, None):
            pass


def test_a_bracketed_ipv6_cluster_address_is_reached():
    from phav_generator.engines import _check_reachable

    try:
        server = socket.create_server(("::1", 0), family=socket.AF_INET6)
    except OSError:
        pytest.skip("no IPv6 loopback here")
    with server:
        _check_reachable(f"[::1]:{server.getsockname()[1]}")


@pytest.mark.parametrize("workers", [0, -1])
def test_fewer_than_one_worker_is_refused(workers, tmp_path):
    """A Ray asked for no CPUs never ran a task (it hung); the local pool ran in-process."""
    from phav_generator.engines import run_tasks

    with pytest.raises(PhavUserError, match="--workers: must be at least 1"):
        run_tasks(_sleep_for, [(0, 0.0)], engine="ray", workers=workers, address=None, out=tmp_path,
                  progress=None, finished=lambda record: None)  # fmt: skip


def test_starting_ray_keeps_the_sigterm_handler(monkeypatch):
    """ray.init puts in a SIGTERM handler of its own (exit 15 and a stack dump): ours is put back."""
    import signal

    ray = pytest.importorskip("ray")
    from phav_generator.engines import ray_session

    def ours(signum, frame):
        raise KeyboardInterrupt

    def init(**options):
        signal.signal(signal.SIGTERM, signal.SIG_DFL)  # as Ray's own handler replaces ours

    monkeypatch.setattr(ray, "is_initialized", lambda: False)
    monkeypatch.setattr(ray, "init", init)
    monkeypatch.setattr(ray, "shutdown", lambda: None)
    before = signal.signal(signal.SIGTERM, ours)
    try:
        with ray_session(2, None):
            assert signal.getsignal(signal.SIGTERM) is ours
    finally:
        signal.signal(signal.SIGTERM, before)


def _sleep_for(task, report):
    """A pool stage: ``task`` is (index, seconds); sleeps, then returns the index."""
    import time

    time.sleep(task[1])
    return {"task": task[0]}


def test_a_stopped_pool_hands_on_the_tasks_under_way_that_finish():
    """Ctrl-C or SIGTERM in the driver stops the loop, and the pool lets the tasks under way
    finish before it shuts down: their records are handed on (journalled), not thrown away
    to be made again on resume. The tasks not begun are not run, not even those the pool
    had queued to its workers (which cancelling cannot take back)."""
    from phav_generator.engines import run_tasks

    records: list[int] = []

    def finished(record):
        records.append(record["task"])
        if len(records) == 1:
            raise KeyboardInterrupt  # Ctrl-C while the first record is journalled

    tasks = [(0, 0.0), *((i, 2.0) for i in range(1, 10))]
    with pytest.raises(KeyboardInterrupt):
        run_tasks(_sleep_for, tasks, engine="local", workers=2, address=None, out=Path("."), progress=None,
                  finished=finished)  # fmt: skip
    # At most tasks 1 and 2 were under way when the first record was handed on (the two
    # workers'), and 3 was queued: before, it and the next were run too.
    assert records[0] == 0 and records == sorted(records) and set(records) <= {0, 1, 2}, records


_IGNORING_CTRL_C = """
import signal, sys
from pathlib import Path
signal.signal(signal.SIGINT, signal.SIG_IGN)  # as a job a script starts in the background
from phav_generator.engines import run_tasks
from tests.generator.test_engines import _sleep_for
done = []
run_tasks(_sleep_for, [(i, 1.5) for i in range(4)], engine="local", workers=2, address=None, out=Path("."),
          progress=None, finished=lambda r: done.append(r["task"]))
print(sorted(done))
"""


def test_a_run_started_ignoring_ctrl_c_keeps_ignoring_it_in_its_workers():
    """A run started with SIGINT ignored (a background job) finishes when Ctrl-C reaches its
    process group: its workers, which inherit the ignoring, do not stop on it either."""
    run = subprocess.Popen([sys.executable, "-c", _IGNORING_CTRL_C], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                           text=True, start_new_session=True, cwd=Path(__file__).resolve().parents[2])  # fmt: skip
    try:
        time.sleep(4.0)  # the workers started and busy
        os.killpg(run.pid, signal.SIGINT)
        out, err = run.communicate(timeout=120)
    finally:
        with contextlib.suppress(ProcessLookupError):
            os.killpg(run.pid, signal.SIGKILL)
    assert run.returncode == 0 and out.strip() == "[0, 1, 2, 3]", err[-800:]


def _fail_first(task, report):
    """A pool stage: task 0 fails, the others return their index."""
    if task == 0:
        raise ValueError("task 0 fails")
    return {"task": task}


def test_a_failed_task_does_not_lose_the_records_finished_beside_it(monkeypatch):
    """Tasks finished in one batch with a failed one are handed on (journalled) before the
    failure is raised: a resume does not make them again."""
    from phav_generator import engines

    real_wait = engines.wait
    monkeypatch.setattr(engines, "wait", lambda fs, timeout=None, return_when=None: real_wait(fs))  # one batch
    records: list[int] = []
    with pytest.raises(ValueError, match="task 0 fails"):
        engines.run_tasks(_fail_first, [0, 1, 2], engine="local", workers=2, address=None, out=Path("."),
                          progress=None, finished=lambda r: records.append(r["task"]))  # fmt: skip
    assert records == [1, 2]


def test_a_missing_ray_is_refused_before_any_work(small_theta, tmp_path, monkeypatch):
    """Without Ray installed, `--engine ray` wrote recipes.parquet, theta.yaml and the work
    folder, then said so; it is refused with the other engine checks, the folder untouched."""
    import importlib.util

    found = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec", lambda name, *a: None if name == "ray" else found(name, *a))
    out = tmp_path / "x"
    with pytest.raises(PhavUserError, match=r"Ray is not installed; pip install 'phav\[ray\]'") as caught:
        write_dataset([], out, name="demo", theta=small_theta, dataset_seed=0, engine="ray")
    assert caught.value.field == "--engine" and not out.exists()


def test_a_tasks_os_error_reaches_the_writer_as_itself_on_ray(tmp_path):
    """Ray raised a task's OSError (a full disk) as its own seven-line traceback, itself an
    OSError without the errno, which the writer's one-line message needs."""
    pytest.importorskip("ray")
    import errno

    from ray.exceptions import RayTaskError

    from phav_generator.engines import _result

    cause = OSError(errno.ENOSPC, "No space left on device", str(tmp_path / "v000000.tar.part"))

    class Ray:  # ray.get of a task that raised ``cause``, as Ray raises it
        @staticmethod
        def get(ref):
            raise RayTaskError("_ray_stage", "Traceback (most recent call last):\n  ...", cause).as_instanceof_cause()

    with pytest.raises(OSError) as caught:
        _result(Ray, None, tmp_path)
    assert caught.value is cause and caught.value.errno == errno.ENOSPC


def test_a_local_ray_run_prints_only_phavs_own_lines(tmp_path):
    """Every `--engine ray` run printed Ray's "WARNING … Token authentication is enabled" and
    "INFO … Started a local Ray instance" around phav's output (and a worker's death, Ray's
    paragraph before phav's one line); Ray now logs errors only."""
    pytest.importorskip("ray")
    result = run_cli("generate", "--theta", "phav-v1-short", "--videos", "1", "--seed", "3", "--workers", "1",
                     "--engine", "ray", "--out", str(tmp_path / "d"))  # fmt: skip
    assert result.returncode == 0, result.stderr
    assert not re.search(r"\b(INFO|WARNING)\b", result.stderr), result.stderr
