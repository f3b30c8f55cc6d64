"""Programs as tasks on a Dask cluster (``--scheduler``): the fleet-scale path of ``cnc check``
and ``cnc run``.

The task function is the one the local ``--jobs`` pool runs, so a program gives the same
result either way. A Dask task is a *batch* of programs (:func:`run_batch`), sized so that
Dask's cost per task is small beside the work (:class:`Sizer`). Inputs are *paths*: each
worker opens the program itself, so every worker must see the files at the same path as the
client (a shared filesystem: NFS, SMB, a cluster file system); programs the client holds as
bytes (:class:`cli.inline.InlineProgram`) travel inside the task. Results stream back as
batches finish; at most a bounded window of tasks is in flight, so the client's memory does
not grow with the size of the library. A worker that dies loses nothing: the scheduler hands
its batches to another worker (Dask's ``allowed-failures`` retries), and each program's
result is taken once, from the one run of its batch that finished.

Dask is imported by this module only; ``cli/check.py`` and ``cli/run.py`` import it when
``--scheduler`` is given, so a plain ``cnc check`` does not pay for it at start-up.
"""

from __future__ import annotations

import pickle
import time
import uuid
from collections.abc import Callable, Iterable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from itertools import islice
from typing import Any, TypeVar

import dask
from distributed import Client, LocalCluster, as_completed

from kernel.diagnostics import Diagnostic, Location

R = TypeVar("R")
T = TypeVar("T")

LOCAL_PREFIX = "local:"


def parse_local(address: str) -> int | None:
    """``local:N`` -> N (workers of a LocalCluster), any other address -> None."""
    if not address.startswith(LOCAL_PREFIX):
        return None
    text = address[len(LOCAL_PREFIX) :]
    if not text.isdigit() or int(text) < 1:
        raise Diagnostic(
            "CLUSTER-ADDRESS",
            f"'{address}': a local cluster is local:N with N >= 1 workers",
            Location(),
        )
    return int(text)


#: Dask settings of a ``local:N`` cluster (its worker processes inherit them). Programs are
#: independent tasks, so the scheduler hands each worker a queue of them instead of one per
#: thread (root-task queuing off), and no worker waits a round trip between two programs.
#: Dask's diagnostics cost CPU that the checks need on a small machine: the statistical
#: profiler samples every worker's task thread every 10 ms, the memory and system monitors
#: poll psutil many times a second, and the event-loop tick runs every 20 ms. They are off
#: or slowed; docs/cluster.md gives the same settings for the workers of a real cluster.
LOCAL_CONFIG: dict[str, object] = {
    "distributed.scheduler.worker-saturation": "inf",
    "distributed.worker.profile.enabled": False,
    "distributed.worker.memory.monitor-interval": "2s",
    "distributed.admin.system-monitor.interval": "5s",
    "distributed.admin.tick.interval": "500ms",
    "distributed.scheduler.work-stealing-interval": "1s",
}


@contextmanager
def connect(address: str) -> Iterator[Client]:
    """A client of the scheduler at ``address``, or of a fresh ``LocalCluster`` for
    ``local:N`` (N worker processes of one thread each, no dashboard), closed on exit."""
    n = parse_local(address)
    if n is not None:
        with (
            dask.config.set(LOCAL_CONFIG),
            LocalCluster(
                n_workers=n,
                threads_per_worker=1,
                processes=True,
                dashboard_address=None,
                silence_logs=40,
            ) as cluster,
            Client(cluster) as client,
        ):
            yield client
        return
    try:
        client = Client(address, timeout=30)
    except (OSError, TimeoutError, ValueError) as exc:
        raise Diagnostic(
            "CLUSTER-CONNECT", f"cannot reach the scheduler at {address}: {exc}", Location()
        ) from None
    try:
        yield client
    finally:
        client.close()


def workers(client: Client) -> int:
    """How many worker threads the cluster has now (at least 1)."""
    info = client.scheduler_info()["workers"]
    return max(1, sum(int(w.get("nthreads", 1)) for w in info.values()))


TARGET_SECONDS = 0.5  # work per task a batch is sized for: Dask's ~10 ms per task is then noise
MAX_BATCH = 512  # programs per task at most (bounds a retry and the results in flight)
TASKS_PER_WORKER = 4  # tasks in flight per worker thread: one running, the others queued


@dataclass(slots=True)
class Sizer:
    """How many programs the next task gets: 1 at first, then what the measured time per
    program says fills :data:`TARGET_SECONDS`, growing at most 2x a step and capped at
    :data:`MAX_BATCH`, so a library of long programs stays one program a task and one of
    tiny ones pays the per-task cost once per hundreds of programs."""

    size: int = 1
    per_program: float | None = None  # seconds, running mean over finished batches

    def learn(self, count: int, seconds: float) -> None:
        """Take a finished batch of ``count`` programs that took ``seconds`` on its worker."""
        each = seconds / max(count, 1)
        self.per_program = each if self.per_program is None else 0.7 * self.per_program + 0.3 * each
        want = int(TARGET_SECONDS / max(self.per_program, 1e-6))
        self.size = max(1, min(want, 2 * self.size, MAX_BATCH))


#: per worker process: the last ``shared`` values unpickled, by batch tag
_SHARED: dict[str, Any] = {}


def _shared(tag: str, blob: bytes) -> Any:
    """``shared`` of the stream ``tag``, unpickled once per worker process."""
    if tag not in _SHARED:
        if len(_SHARED) >= 4:
            _SHARED.clear()
        _SHARED[tag] = pickle.loads(blob)  # noqa: S301 - our own client's bytes
    return _SHARED[tag]


def run_batch(
    task: Callable[[T, Any], R], batch: list[tuple[int, T]], tag: str, blob: bytes
) -> tuple[list[tuple[int, R]], float]:
    """The Dask task: ``task(item, shared)`` for each ``(index, item)`` of ``batch``, in
    order (``shared`` is ``blob`` unpickled), and the seconds it took. The results come back
    together, so a batch run again after its worker died cannot give a result twice."""
    t0 = time.perf_counter()
    shared = _shared(tag, blob)
    out = [(i, task(item, shared)) for i, item in batch]
    return out, time.perf_counter() - t0


def map_stream(
    client: Client,
    task: Callable[[T, Any], R],
    items: Sequence[T],
    shared: Any,
    on_error: Callable[[T, BaseException], R],
    order: Sequence[int] | None = None,
) -> Iterator[tuple[int, R]]:
    """Run ``task(items[i], shared)`` for every i on the cluster; yield ``(i, result)`` as
    each finishes, in ``order`` of submission (default: as given). See :func:`stream`."""
    order = order if order is not None else range(len(items))
    yield from stream(client, task, ((i, items[i]) for i in order), shared, on_error)


def stream(
    client: Client,
    task: Callable[[T, Any], R],
    pairs: Iterable[tuple[int, T]],
    shared: Any,
    on_error: Callable[[T, BaseException], R],
) -> Iterator[tuple[int, R]]:
    """Run ``task(item, shared)`` for every ``(index, item)`` of ``pairs`` (read lazily, so a
    generated library need not exist as a list) on the cluster, in batches sized by
    :class:`Sizer`; yield ``(index, result)`` as each batch finishes. ``shared`` goes into
    every batch pickled once, and is unpickled once per worker process. A batch the cluster
    gives up on (its workers died ``allowed-failures`` times) is split into one task per
    program, so only a program that kills its worker every time becomes
    ``on_error(item, exception)``. At most :data:`TASKS_PER_WORKER` tasks per worker thread
    are in flight: the client holds a bounded number of items and results whatever the size
    of the library.
    """
    source = iter(pairs)
    first = list(islice(source, 1))
    if not first:
        return
    window = TASKS_PER_WORKER * workers(client)
    sizer = Sizer()
    batches: dict[str, list[tuple[int, T]]] = {}
    retry: list[list[tuple[int, T]]] = []  # singles of a batch the cluster gave up on
    tag = uuid.uuid4().hex[:12]
    count = 0
    # ``shared`` travels pickled once, as bytes inside every batch (a few KiB), not as
    # scattered data or a task the batches depend on: data held only by workers is lost
    # when they die, and a dependency counts its workers' deaths against every batch
    blob = pickle.dumps(shared, protocol=pickle.HIGHEST_PROTOCOL)

    def submit(batch: list[tuple[int, T]]) -> Any:
        nonlocal count
        count += 1
        fut = client.submit(run_batch, task, batch, tag, blob, pure=False, key=f"cnc-{tag}-{count}")
        batches[fut.key] = batch
        return fut

    def next_batch() -> list[tuple[int, T]]:
        if retry:
            return retry.pop()
        return list(islice(source, sizer.size))

    pending = as_completed([submit(first)])
    for _ in range(window - 1):
        batch = next_batch()
        if not batch:
            break
        pending.add(submit(batch))
    for fut in pending:
        batch = batches.pop(fut.key)
        try:
            results, seconds = fut.result()
        except Exception as exc:  # noqa: BLE001 - e.g. KilledWorker: retry alone, then one row each
            fut.release()
            if len(batch) > 1:
                retry.extend([pair] for pair in batch)
            else:
                yield batch[0][0], on_error(batch[0][1], exc)
        else:
            fut.release()
            sizer.learn(len(batch), seconds)
            yield from results
        while pending.count() < window:
            nxt = next_batch()
            if not nxt:
                break
            pending.add(submit(nxt))
