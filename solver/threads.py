"""Worker processes: BLAS threads one per process, so a process is one core; and a worker ends with its parent.

NumPy reads the thread count once, as it loads: a worker started with these variables set keeps single-threaded
BLAS; a forked one inherits the parent's (two BLAS threads per worker on two cores made small dense solves several
times slower).
"""

from __future__ import annotations

import os
import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager

BLAS_THREADS = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS")
PARENT_POLL = 0.5  # s: how soon a worker whose parent died ends (at the latest)
ORPHANED = 70  # a worker's exit code when it ends because its parent is gone


@contextmanager
def single_threaded_blas() -> Iterator[None]:
    """Processes started inside inherit BLAS limited to one thread; the environment is restored after."""
    saved = {k: os.environ.get(k) for k in BLAS_THREADS}
    os.environ.update({k: "1" for k in BLAS_THREADS})
    try:
        yield
    finally:
        for k, v in saved.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v


def end_with_parent() -> None:
    """In a worker process (a pool's initializer): end it at once when the process that started it is gone, so a
    study or envelopes killed from outside (SIGKILL, a crash) leave no workers computing for nobody and holding
    the output pipes open (``manikin study ... | tee`` would wait for them). A daemon thread waits on the parent's
    sentinel (multiprocessing's: a pipe on Linux and macOS, the process handle on Windows) and, where there are
    parent ids, also ends the worker when its parent id changes (re-parented)."""
    import multiprocessing
    from multiprocessing.connection import wait

    parent = multiprocessing.parent_process()
    ppid = os.getppid()

    def watch() -> None:
        while True:
            if parent is not None and parent.sentinel is not None:
                if wait([parent.sentinel], timeout=PARENT_POLL):
                    break
            else:
                time.sleep(PARENT_POLL)
            if os.name != "nt" and os.getppid() != ppid:
                break
        os._exit(ORPHANED)  # no cleanup to wait for: the rows of a lost worker are done again by a rerun

    threading.Thread(target=watch, name="end-with-parent", daemon=True).start()
