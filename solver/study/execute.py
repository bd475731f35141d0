"""Where a study's runs are done: local worker processes (default, all cores) or a Dask distributed cluster.

Runs travel in chunks (one task each), so the cost of a task (sending it, scheduling it, its result coming back)
is shared by many runs of a few tens of milliseconds. A few chunks per worker are under way at a time, so memory
stays flat however many runs the study has, and rows come back as chunks finish (``on_rows``). Every worker runs
with single-threaded BLAS: one worker is one core, and the arithmetic, hence every row, is the same on any of them.

Dask is an optional extra (``pip install -r requirements-dask.txt``), imported only for ``--dask``.
"""

from __future__ import annotations

import signal
from collections.abc import Callable, Iterator
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool
from multiprocessing import get_context
from types import ModuleType

from ..errors import UsageError
from ..threads import end_with_parent, single_threaded_blas
from .plan import Run
from .runner import failed, head, run_chunk

IN_FLIGHT = 3  # chunks under way per worker: enough to keep it busy, few enough to hold little in memory
MAX_CHUNK = 50  # runs per chunk at most: a chunk is also what a crash or Ctrl-C can lose
CHUNKS_PER_WORKER = 8  # at least, while runs last: the last chunks then end close together
OnRows = Callable[[list[dict], bool], None]  # (rows, keep in the journal)


def chunk_size(runs: int, workers: int) -> int:
    """Runs per chunk: about CHUNKS_PER_WORKER chunks per worker, at most MAX_CHUNK runs each."""
    return max(1, min(MAX_CHUNK, runs // (max(workers, 1) * CHUNKS_PER_WORKER)))


def chunked(runs: list[Run], size: int) -> Iterator[list[Run]]:
    for i in range(0, len(runs), size):
        yield runs[i : i + size]


def lost(chunk: list[Run], why: str) -> list[dict]:
    """Rows for runs whose worker was lost: failed, with the reason."""
    reason = f"worker lost ({why}); rerun the study to retry"
    return [failed(head(r), reason) for r in chunk]


def outcome(future, chunk: list[Run]) -> tuple[list[dict], bool]:
    """A finished task's rows and whether they go in the journal: the chunk's rows, or, if its worker died or the
    task was lost, a failed row per run with the reason (left out of the journal, so a rerun retries them)."""
    try:
        return future.result(), True
    except Exception as exc:  # noqa: BLE001 (the runs say what happened; the study goes on)
        return lost(chunk, f"{type(exc).__name__}: {exc}"), False


def ignore_interrupts() -> None:
    """In a worker process: Ctrl-C is the parent's to handle (it keeps the rows done and stops the pool); a worker
    that took it too would die mid-run with a traceback. And the worker ends when the parent dies
    (:func:`~solver.threads.end_with_parent`)."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    end_with_parent()


def run_local(runs: list[Run], workers: int, size: int, on_rows: OnRows) -> None:
    """Run ``runs`` on ``workers`` fresh ("spawn") processes, ``size`` runs per chunk."""
    chunks = chunked(runs, size)
    pending: dict[Future, list[Run]] = {}
    with single_threaded_blas():
        pool = ProcessPoolExecutor(workers, mp_context=get_context("spawn"), initializer=ignore_interrupts)
    try:
        while True:
            while len(pending) < workers * IN_FLIGHT and (chunk := next(chunks, None)) is not None:
                try:
                    with single_threaded_blas():  # the processes start with the first task
                        pending[pool.submit(run_chunk, chunk)] = chunk
                except BrokenProcessPool as exc:  # a worker died: the runs not yet sent are lost too
                    on_rows(lost(chunk, f"BrokenProcessPool: {exc}"), False)
            if not pending:
                break
            done, _ = wait(pending, return_when=FIRST_COMPLETED)
            for future in done:
                on_rows(*outcome(future, pending.pop(future)))
    finally:
        pool.shutdown(wait=True, cancel_futures=True)


def run_dask(runs: list[Run], address: str, workers: int, size: int | None, on_rows: OnRows) -> int:
    """Run ``runs`` on a Dask cluster: the scheduler at ``address``, or ``"local"`` for a LocalCluster of
    ``workers`` one-thread processes. ``size`` None: chosen by the cluster's thread count. Returns the workers."""
    distributed = _import_distributed()
    cluster = None
    if address == "local":
        with single_threaded_blas():
            cluster = distributed.LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                               dashboard_address=None)  # fmt: skip
        target = cluster
    else:
        target = address
    try:
        try:
            client = distributed.Client(target, timeout="20s")
        except (OSError, TimeoutError, ValueError) as exc:
            raise UsageError(f"--dask {address}: cannot reach the Dask scheduler ({exc})") from None
        with client:
            threads = sum(client.nthreads().values()) or 1
            _dask_loop(client, distributed, runs, threads, size or chunk_size(len(runs), threads), on_rows)
        return threads
    finally:
        if cluster is not None:
            cluster.close()


def _dask_loop(client, distributed, runs: list[Run], threads: int, size: int, on_rows: OnRows) -> None:
    chunks = chunked(runs, size)
    pending: dict[str, list[Run]] = {}
    stream = distributed.as_completed()
    for _ in range(threads * IN_FLIGHT):
        if (chunk := next(chunks, None)) is not None:
            future = client.submit(run_chunk, chunk, pure=False)
            pending[future.key] = chunk
            stream.add(future)
    for future in stream:
        on_rows(*outcome(future, pending.pop(future.key)))
        future.release()
        if (chunk := next(chunks, None)) is not None:
            nxt = client.submit(run_chunk, chunk, pure=False)
            pending[nxt.key] = chunk
            stream.add(nxt)


def _import_distributed() -> ModuleType:
    try:
        import distributed
    except ImportError:
        raise UsageError(
            "--dask needs Dask distributed, which is not installed: pip install -r requirements-dask.txt"
        ) from None
    return distributed
