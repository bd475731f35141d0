"""Benchmarks that write docs/BENCHMARKS.md: preset scenarios (``scenarios``), random targets
(``random_targets``, thesis §6.1.2) and collision distance queries (``collision``)."""

import os
import sys

from .scenarios import run_benchmarks, write_section

__all__ = ["one_core", "run_benchmarks", "write_section"]

from solver.threads import BLAS_THREADS


def one_core(module: str) -> None:
    """Run this process on one core with single-threaded BLAS: pin it, and if BLAS may use more threads, start
    ``python -m module`` again with them limited (the thread count is fixed once NumPy is loaded). Two BLAS threads
    fighting over one pinned core would make every matrix product several times slower."""
    if any(os.environ.get(k) != "1" for k in BLAS_THREADS):
        env = dict(os.environ, **{k: "1" for k in BLAS_THREADS})
        os.execve(sys.executable, [sys.executable, "-m", module, *sys.argv[1:]], env)
    if hasattr(os, "sched_setaffinity"):
        os.sched_setaffinity(0, {sorted(os.sched_getaffinity(0))[0]})
