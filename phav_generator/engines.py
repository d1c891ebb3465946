"""Where the units of work run: in this process, a local pool of spawned processes, or Ray.

An engine is handed the stage function to run (``dataset.write.render_task`` bound to its
output folder, or a validator's shard scan) and the tasks; it knows nothing of what they do. Each
finished task's result goes to ``finished`` in this process, so the caller journals it; the
order in which tasks finish cannot change a byte of what they make.

Ray runs the tasks on a cluster (``address``) or on a Ray started here; its workers write
into the output directory themselves, so every node must see it at the same path (a shared
or cluster filesystem). Ray is an optional extra: ``pip install 'phav[ray]'``.
"""

from __future__ import annotations

import contextlib
import importlib.util
import logging
import multiprocessing
import os
import queue
import signal
import socket
import sys
import threading
import time
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool
from pathlib import Path
from typing import Any

from phav_generator.faults import fault_env
from phav_spec.errors import PhavUserError

#: Where tasks run: a local process pool, or a Ray cluster.
ENGINES = ("local", "ray")
#: Object store for a Ray started here (bytes): records are small, pixels go to disk.
LOCAL_OBJECT_STORE_BYTES = 128 * 1024**2
#: How often (s) a local pool worker checks that the process that started it still runs.
PARENT_POLL_S = 0.5

#: Called with (tasks finished, frames finished) increments as work completes.
Progress = Callable[[int, int], None]
#: ``stage(task, report)``: one unit of work, reporting frames as it goes; returns its record.
Stage = Callable[[Any, Progress | None], dict[str, Any]]


def check_engine(engine: str, address: str | None = None) -> None:
    """A one-line user error for an engine that is not one of ``ENGINES``, or a Ray cluster
    address given to another engine (it would be ignored: the work would run here)."""
    if engine not in ENGINES:
        raise PhavUserError(f"unknown engine {engine!r}; choose one of {', '.join(ENGINES)}", field="--engine")
    if address is not None and engine != "ray":
        raise PhavUserError(f"a Ray cluster address needs --engine ray (the engine is {engine})", field="--address")
    if engine == "ray" and importlib.util.find_spec("ray") is None:  # before any work, not once it has begun
        raise PhavUserError(_NO_RAY, field="--engine")


def run_tasks(stage: Stage, tasks: Sequence[Any], *, engine: str, workers: int, address: str | None,
              out: Path, progress: Progress | None, finished: Callable[[dict[str, Any]], None]) -> None:  # fmt: skip
    """Run ``stage`` on every task with ``engine``; ``finished`` gets each record, in this process.

    ``out`` names the directory the tasks write to (for the message when a worker dies).
    Each finished task also counts as one video for ``progress``.
    """
    check_engine(engine, address)
    if workers < 1:
        raise PhavUserError(f"must be at least 1, got {workers}", field="--workers")
    if not tasks:
        return
    if engine == "ray":
        _run_on_ray(stage, tasks, workers=workers, address=address, out=out, progress=progress, finished=finished)
    elif workers <= 1 or len(tasks) == 1:
        for task in tasks:
            record = stage(task, progress)
            if progress is not None:
                progress(1, 0)
            finished(record)
    else:
        _run_on_pool(stage, tasks, workers, out, progress, finished)


# --- a local pool of spawned processes -------------------------------------------------------

_worker_events: Any = None
#: Set by the driver when the run stops: a task a worker takes after it is skipped.
_worker_stopping: Any = None


class WorkerTerminated(BaseException):
    """SIGTERM or SIGINT in a pool's worker (a scheduler's time limit or a terminal's Ctrl-C
    signals the whole process group): raised so that the write under way removes its
    temporary before the worker exits."""

    def __init__(self, signum: int):
        super().__init__(signum)
        self.signum = signum


_in_task = False


def _raise_worker_terminated(signum: int, frame: object) -> None:
    if not _in_task:  # between videos: nothing is half-written (and no traceback from the pool's queue)
        os._exit(128 + signum)
    raise WorkerTerminated(signum)


def _init_worker(events: Any, stopping: Any, parent: int) -> None:
    global _worker_events, _worker_stopping
    _worker_events, _worker_stopping = events, stopping
    signal.signal(signal.SIGTERM, _raise_worker_terminated)
    if signal.getsignal(signal.SIGINT) is not signal.SIG_IGN:  # a run started ignoring Ctrl-C keeps doing so
        signal.signal(signal.SIGINT, _raise_worker_terminated)
    exit_with_parent(parent)


def exit_with_parent(parent: int) -> None:
    """In a local pool's worker (``parent`` the pid that started it): end this process once
    ``parent`` is gone (killed, or stopped by a signal before it could shut its pool down),
    instead of working on for nobody. A watching daemon thread; what the worker left half
    written is a temporary the next run removes."""

    def watch() -> None:
        while os.getppid() == parent:
            time.sleep(PARENT_POLL_S)
        os._exit(1)

    threading.Thread(target=watch, name="phav-parent-watch", daemon=True).start()


def _report(videos: int, frames: int) -> None:
    if _worker_events is not None:
        _worker_events.put((videos, frames))


def _pool_call(stage: Stage, task: Any) -> dict[str, Any] | None:
    """``stage(task)`` in a worker; None, not run, once the driver has stopped (the pool has
    handed a few tasks to its workers' queue, which cancelling cannot take back)."""
    global _in_task
    if _worker_stopping is not None and _worker_stopping.is_set():
        return None
    _in_task = True
    try:
        return stage(task, _report)
    except WorkerTerminated as e:  # the write under way has removed its temporary; the pool's loop would go on
        os._exit(128 + e.signum)
    finally:
        _in_task = False


def _run_on_pool(stage: Stage, tasks: Sequence[Any], workers: int, out: Path, progress: Progress | None,
                 finished: Callable[[dict[str, Any]], None]) -> None:  # fmt: skip
    mp = multiprocessing.get_context("spawn")
    events, stopping = mp.Queue(), mp.Event()
    with ProcessPoolExecutor(
        max_workers=min(workers, len(tasks)), mp_context=mp, initializer=_init_worker,
        initargs=(events, stopping, os.getpid()),
    ) as pool:  # fmt: skip
        futures: dict[Future, int] = {pool.submit(_pool_call, stage, t): i for i, t in enumerate(tasks)}
        pending = set(futures)
        unhanded: set[Future] = set()  # finished, not yet handed on
        try:
            while pending:
                done, pending = wait(pending, timeout=0.2, return_when=FIRST_COMPLETED)
                unhanded = set(done)
                _drain(events, progress)
                # Handed on in task order within a batch: which finishes first cannot change a byte.
                for fut in sorted(done, key=lambda f: futures[f]):
                    unhanded.discard(fut)
                    record = fut.result()
                    if progress is not None:
                        progress(1, 0)
                    finished(record)
        except BrokenProcessPool:
            # The tasks that succeeded before the pool broke are handed on: a resume need not redo them.
            stopping.set()
            _finish_under_way(futures, pending | unhanded, finished)
            raise PhavUserError(
                "a worker process died (killed, or out of memory); finished videos are kept, rerun to resume",
                source=str(out),
            ) from None
        except BaseException:
            # Stopped here (Ctrl-C, SIGTERM, a failed task): the pool lets the tasks under way
            # finish before it shuts down, so hand on those that do; a resume need not redo them.
            # Those not begun are skipped, queued to a worker or not.
            stopping.set()
            _finish_under_way(futures, pending | unhanded, finished)
            raise
        finally:
            for fut in pending:
                fut.cancel()
        _drain(events, progress)


def _finish_under_way(futures: dict[Future, int], pending: set[Future],
                      finished: Callable[[dict[str, Any]], None]) -> None:  # fmt: skip
    """Cancel the tasks not begun, wait for those under way and hand on each that succeeds,
    in task order. Best effort while the run stops: a task that fails, or a record that
    cannot be handed on, is left for the resume to redo."""
    for fut in pending:
        fut.cancel()
    done, _ = wait(pending)
    for fut in sorted(done, key=lambda f: futures[f]):
        if fut.cancelled() or fut.exception() is not None or fut.result() is None:  # None: skipped
            continue
        try:
            finished(fut.result())
        except Exception:  # the stop's own exception is the one to raise
            continue


def _drain(events: Any, progress: Progress | None) -> None:
    while True:
        try:
            videos, frames = events.get_nowait()
        except (queue.Empty, OSError, ValueError):
            return
        if progress is not None:
            progress(videos, frames)


# --- Ray -------------------------------------------------------------------------------------


_NO_RAY = "Ray is not installed; pip install 'phav[ray]'"


def _require_ray() -> Any:
    try:
        import ray  # optional extra: only --engine ray needs it
    except ImportError:
        raise PhavUserError(_NO_RAY, field="--engine") from None
    return ray


@contextlib.contextmanager
def ray_session(workers: int, address: str | None) -> Iterator[Any]:
    """Ray, connected: to the cluster at ``address``, else to a local Ray with ``workers``
    CPUs started here and stopped on exit (an already initialised Ray is used as it is)."""
    ray = _require_ray()
    # Ray itself would follow RAY_ADDRESS (or a cluster `ray start` left on this machine) and
    # then refuse the CPU count asked of a local Ray: a set RAY_ADDRESS is the cluster's
    # address, and a local Ray is asked for as such.
    field = "--address" if address else "RAY_ADDRESS" if os.environ.get("RAY_ADDRESS") else "--engine"
    address = address or os.environ.get("RAY_ADDRESS") or None
    if address == "local":  # Ray's own word for a local Ray: started here with ``workers`` CPUs
        address = None
    if address:  # first: a malformed or silent address is the user's error, Ray started or not
        _check_reachable(address, field)
    if ray.is_initialized():
        yield ray
        return
    env = fault_env()
    options: dict[str, Any] = {"include_dashboard": False, "log_to_driver": False, "logging_level": logging.ERROR,
                               "runtime_env": {"env_vars": env} if env else None}  # fmt: skip
    if address:
        options["address"] = address
    else:
        options.update(address="local", num_cpus=workers, object_store_memory=LOCAL_OBJECT_STORE_BYTES)
    # ray.init puts in its own SIGTERM handler (it exits 15 with a stack dump); ours stays,
    # so that SIGTERM still cleans up and exits 143.
    handler = signal.getsignal(signal.SIGTERM)
    try:
        ray.init(**options)
    except (ConnectionError, ValueError) as e:
        what = "cannot reach the Ray cluster" if address else "cannot start a local Ray"
        raise PhavUserError(f"{what}: {str(e).splitlines()[0]}", source=address, field=field) from None
    finally:
        if handler is not None and threading.current_thread() is threading.main_thread():
            signal.signal(signal.SIGTERM, handler)
    try:
        yield ray
    finally:
        ray.shutdown()


#: How long (s) a cluster's address has to answer before ``ray.init`` is tried (it retries
#: an address that never answers for minutes).
REACH_TIMEOUT_S = 10.0


def _check_reachable(address: str, field: str = "--address") -> None:
    """A ``HOST:PORT`` cluster address that accepts a connection, else a one-line error
    naming ``field``, where it was given (``auto`` and ``ray://`` addresses are left to Ray)."""
    if address == "auto" or "://" in address:
        return
    host, sep, port = address.rpartition(":")
    host = host[1:-1] if host.startswith("[") and host.endswith("]") else host  # [IPv6]:PORT
    if not sep or not host or not port.isdigit():
        raise PhavUserError("expected HOST:PORT (the head node's GCS address), auto or ray://HOST:PORT",
                            source=address, field=field)  # fmt: skip
    try:
        socket.create_connection((host, int(port)), timeout=REACH_TIMEOUT_S).close()
    except (OSError, ValueError) as e:
        raise PhavUserError(f"cannot reach the Ray cluster ({e})", source=address, field=field) from None


def _ray_stage(stage: Stage, task: Any) -> dict[str, Any]:
    return stage(task, None)


def _run_on_ray(stage: Stage, tasks: Sequence[Any], *, workers: int, address: str | None, out: Path,
                progress: Progress | None, finished: Callable[[dict[str, Any]], None]) -> None:  # fmt: skip
    """Run ``stage`` on ``tasks`` as Ray tasks of one CPU; ``finished`` gets each record."""
    with ray_session(workers, address) as ray:
        remote = ray.remote(num_cpus=1, max_retries=0)(_ray_stage)
        pending = [remote.remote(stage, t) for t in tasks]
        while pending:
            done, pending = ray.wait(pending, num_returns=1, timeout=1.0)
            for ref in done:
                record = _result(ray, ref, out)
                if progress is not None:
                    progress(1, record["n_frames"])
                finished(record)


_initialised: set[str] = set()


def _call(fn: Callable[..., Any], initializer: Callable[[], None] | None, *args: Any) -> Any:
    """``fn(*args)`` in a Ray worker, after ``initializer`` has run once in that process."""
    if initializer is not None:
        key = f"{initializer.__module__}.{initializer.__qualname__}"
        if key not in _initialised:
            initializer()
            _initialised.add(key)
    return fn(*args)


class RayPool:
    """What the validator uses of ``ProcessPoolExecutor`` (``submit`` → a Future, and
    ``shutdown``), with Ray tasks of one CPU as the workers. ``initializer`` runs once in
    each worker process before its first task, as the executor's would."""

    def __init__(self, workers: int, address: str | None, initializer: Callable[[], None] | None = None):
        self._session = ray_session(workers, address)
        ray = self._session.__enter__()
        try:
            self._remote = ray.remote(num_cpus=1, max_retries=0)(_call)
        except BaseException:
            self._session.__exit__(None, None, None)
            raise
        self._initializer = initializer

    def submit(self, fn: Callable[..., Any], *args: Any) -> Future[Any]:
        return self._remote.remote(fn, self._initializer, *args).future()

    def shutdown(self, wait: bool = True, cancel_futures: bool = False) -> None:
        self._session.__exit__(None, None, None)


def worker_died(error: BaseException) -> bool:
    """Whether ``error`` says a worker process died under its task (killed, out of memory, its
    node lost), in a local pool or on Ray: not the task's own failure."""
    if isinstance(error, BrokenProcessPool):
        return True
    if "ray" not in sys.modules:  # no Ray task ran in this process
        return False
    from ray.exceptions import LocalRayletDiedError, NodeDiedError, OutOfMemoryError, WorkerCrashedError

    return isinstance(error, WorkerCrashedError | OutOfMemoryError | NodeDiedError | LocalRayletDiedError)


def _result(ray: Any, ref: Any, out: Path) -> dict[str, Any]:
    """A task's record; a user error or OSError raised in a task is raised here as itself."""
    from ray.exceptions import RayTaskError  # optional extra, as above

    try:
        return ray.get(ref)
    except RayTaskError as e:
        # As the local pool raises them: a user error its one line, an OSError (a full disk)
        # with its errno for the writer's message, not Ray's traceback of the task.
        if isinstance(e.cause, PhavUserError | OSError):
            raise e.cause from None
        raise
    except Exception as e:
        if worker_died(e):
            raise PhavUserError(
                "a Ray worker died (killed, or out of memory); finished videos are kept, rerun to resume",
                source=str(out),
            ) from None
        raise
