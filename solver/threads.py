"""BLAS threads of worker processes: one per process, so a process is one core.

NumPy reads the thread count once, as it loads: a worker started with these variables set keeps single-threaded
BLAS; a forked one inherits the parent's (two BLAS threads per worker on two cores made small dense solves several
times slower).
"""

from __future__ import annotations

import os
from collections.abc import Iterator
from contextlib import contextmanager

BLAS_THREADS = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS")


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
