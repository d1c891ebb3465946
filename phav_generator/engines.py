"""The Ray engine: the same video tasks as the local pool, run as Ray tasks on a cluster.

Workers render into the output directory themselves, so every node must see it at the same
path (a shared or cluster filesystem); the driver journals each video and joins the shards
exactly as with the local pool. Results are identical byte for byte, whatever the order
in which tasks finish. Ray is an optional extra: ``pip install 'phav[ray]'``.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
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
    ray = _require_ray()
    if not tasks:
        return
    started = False
    if not ray.is_initialized():
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
        started = True
    try:
        render = ray.remote(num_cpus=1, max_retries=0)(_render)
        pending = [render.remote(t, str(out)) for t in tasks]
        while pending:
            done, pending = ray.wait(pending, num_returns=1, timeout=1.0)
            for ref in done:
                record = _result(ray, ref, out)
                if progress is not None:
                    progress(1, record["n_frames"])
                finished(record)
    finally:
        if started:
            ray.shutdown()


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
