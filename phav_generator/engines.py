"""The Ray engine: the same video tasks as the local pool, run as Ray tasks on a cluster,
and a process-pool stand-in on Ray for the validator's shard scans.

Workers render into the output directory themselves, so every node must see it at the same
path (a shared or cluster filesystem); the driver journals each video and joins the shards
exactly as with the local pool. Results are identical byte for byte, whatever the order
in which tasks finish. Ray is an optional extra: ``pip install 'phav[ray]'``.
"""

from __future__ import annotations

import contextlib
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import Future
from pathlib import Path
from typing import Any

from phav_generator.faults import fault_env
from phav_spec.errors import PhavUserError

#: Object store for a Ray started here (bytes): records are small, pixels go to disk.
LOCAL_OBJECT_STORE_BYTES = 128 * 1024**2


def _require_ray() -> Any:
    try:
        import ray
    except ImportError:
        raise PhavUserError("Ray is not installed; pip install 'phav[ray]'", field="--engine") from None
    return ray


def _render(task: Any, out: str) -> dict[str, Any]:
    from phav_generator.dataset import render_part

    return render_part(task, Path(out))


@contextlib.contextmanager
def ray_session(workers: int, address: str | None) -> Iterator[Any]:
    """Ray, connected: to the cluster at ``address``, else to a local Ray with ``workers``
    CPUs started here and stopped on exit (an already initialised Ray is used as it is)."""
    ray = _require_ray()
    if ray.is_initialized():
        yield ray
        return
    env = fault_env()
    options: dict[str, Any] = {"include_dashboard": False, "log_to_driver": False,
                               "runtime_env": {"env_vars": env} if env else None}  # fmt: skip
    if address:
        options["address"] = address
    else:
        options.update(num_cpus=workers, object_store_memory=LOCAL_OBJECT_STORE_BYTES)
    try:
        ray.init(**options)
    except ConnectionError as e:
        raise PhavUserError(f"cannot reach the Ray cluster: {e}", source=address, field="--address") from None
    try:
        yield ray
    finally:
        ray.shutdown()


def run_on_ray(
    tasks: Sequence[Any],
    out: Path,
    *,
    workers: int,
    address: str | None,
    progress: Callable[[int, int], None] | None,
    finished: Callable[[dict[str, Any]], None],
) -> None:
    """Render ``tasks`` (``dataset.VideoTask``) as Ray tasks; ``finished`` gets each record.

    With ``address`` the tasks go to that cluster; otherwise a local Ray with ``workers``
    CPUs is started for the run and stopped after it.
    """
    if not tasks:
        return
    with ray_session(workers, address) as ray:
        render = ray.remote(num_cpus=1, max_retries=0)(_render)
        pending = [render.remote(t, str(out)) for t in tasks]
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


def _result(ray: Any, ref: Any, out: Path) -> dict[str, Any]:
    """A task's record; a user error raised in a task is raised here as itself."""
    from ray.exceptions import RayTaskError, WorkerCrashedError

    try:
        return ray.get(ref)
    except RayTaskError as e:
        if isinstance(e.cause, PhavUserError):
            raise e.cause from None
        raise
    except WorkerCrashedError:
        raise PhavUserError(
            "a Ray worker died (killed, or out of memory); finished videos are kept, rerun to resume",
            source=str(out),
        ) from None
