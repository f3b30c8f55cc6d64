"""Programs as tasks on a Dask cluster (``--scheduler``): the fleet-scale path of ``cnc check``
and ``cnc run``.

The task function is the one the local ``--jobs`` pool runs, so a program gives the same
result either way. Inputs are *paths*: each worker opens the program itself, so every worker
must see the files at the same path as the client (a shared filesystem: NFS, SMB, a cluster
file system). Results stream back as they finish; at most a bounded window of tasks is in
flight, so the client's memory does not grow with the size of the library. A worker that
dies loses nothing: the scheduler hands its tasks to another worker (Dask's
``allowed-failures`` retries), and each program's result is taken once, from the future that
finished.

Dask is imported by this module only; ``cli/check.py`` and ``cli/run.py`` import it when
``--scheduler`` is given, so a plain ``cnc check`` does not pay for it at start-up.
"""

from __future__ import annotations

import uuid
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from typing import Any, TypeVar

import dask
from distributed import Client, LocalCluster, as_completed

from kernel.diagnostics import Diagnostic, Location

R = TypeVar("R")

LOCAL_PREFIX = "local:"
WINDOW_PER_WORKER = 64  # tasks in flight per worker: keeps workers busy, bounds client memory


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


@contextmanager
def connect(address: str) -> Iterator[Client]:
    """A client of the scheduler at ``address``, or of a fresh ``LocalCluster`` for
    ``local:N`` (N worker processes of one thread each, no dashboard), closed on exit."""
    n = parse_local(address)
    if n is not None:
        # programs are independent tasks: let the scheduler hand each worker a queue of them
        # instead of one per thread (Dask's root-task queuing), so no worker waits a round
        # trip to the scheduler between two programs
        with (
            dask.config.set({"distributed.scheduler.worker-saturation": "inf"}),
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


def map_stream(
    client: Client,
    task: Callable[..., R],
    items: Sequence[str],
    shared: Any,
    on_error: Callable[[str, BaseException], R],
    order: Sequence[int] | None = None,
) -> Iterator[tuple[int, R]]:
    """Run ``task(items[i], shared)`` for every i on the cluster; yield ``(i, result)`` as
    each finishes. ``shared`` is sent to every worker once; ``order`` is the submission
    order (default: as given). A task the cluster gives up on (its workers died
    ``allowed-failures`` times) becomes ``on_error(item, exception)``. At most
    ``WINDOW_PER_WORKER`` tasks per worker
    are in flight.
    """
    order = list(order) if order is not None else list(range(len(items)))
    if not order:
        return
    [shared_f] = client.scatter([shared], broadcast=True, hash=False)
    window = WINDOW_PER_WORKER * workers(client)
    pending = iter(order)
    index: dict[str, int] = {}
    batch = uuid.uuid4().hex[:12]

    def submit(i: int) -> Any:
        fut = client.submit(task, items[i], shared_f, pure=False, key=f"cnc-{batch}-{i}")
        index[fut.key] = i
        return fut

    first = [submit(i) for _, i in zip(range(window), pending, strict=False)]
    stream = as_completed(first)
    for fut in stream:
        i = index.pop(fut.key)
        try:
            result = fut.result()
        except Exception as exc:  # noqa: BLE001 - e.g. KilledWorker: one failed row, not a crash
            result = on_error(items[i], exc)
        fut.release()
        nxt = next(pending, None)
        if nxt is not None:
            stream.add(submit(nxt))
        yield i, result
