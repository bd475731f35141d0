"""Compiled kernels for the solver's hot loops (Numba), with the NumPy code kept as the reference path.

Each kernel module defines plain-Python loop functions decorated with :func:`kernel`; callers ask
:func:`active` and take either the kernel or their NumPy code, which computes the same numbers to rounding
(tests compare the two). ``MANIKIN_KERNELS`` picks: ``auto`` (the default: Numba when it imports), ``numba`` (the
same, and a note when it cannot) or ``numpy``. Numba is imported and a kernel compiled only on first use, and the
machine code is cached in the user's folder (:func:`cache_folder`), so a later process loads it instead of
compiling again.
"""

from __future__ import annotations

import os
import sys
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path

CHOICES = ("auto", "numba", "numpy")
# "solver", or "bl_ext.<repo>.manikin.solver" inside Blender: Numba finds a cached kernel by its file's path but
# loads it by importing the module that compiled it, so each import name keeps a cache folder of its own
PACKAGE = __name__.rpartition(".")[0]

# available: None until decided, then bool; compile_s: seconds spent compiling kernels (not loading them) so far
_state: dict = {"available": None, "active": False, "why": "", "compile_s": 0.0}


def cache_folder() -> Path:
    """Where compiled kernels are kept: ``NUMBA_CACHE_DIR`` if set, else ``manikin/numba`` in the platform's per-user
    cache folder; in either, a folder named as this package is imported (:data:`PACKAGE`)."""
    if os.environ.get("NUMBA_CACHE_DIR"):
        return Path(os.environ["NUMBA_CACHE_DIR"]) / PACKAGE
    if sys.platform == "win32":
        base = Path(os.environ.get("LOCALAPPDATA") or Path.home() / "AppData" / "Local")
    elif sys.platform == "darwin":
        base = Path.home() / "Library" / "Caches"
    else:
        base = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache")
    return base / "manikin" / "numba" / PACKAGE


def _decide() -> bool:
    choice = os.environ.get("MANIKIN_KERNELS", "auto").strip().lower() or "auto"
    if choice not in CHOICES:
        _state["why"] = f"MANIKIN_KERNELS={choice!r} is not one of {', '.join(CHOICES)}: NumPy kernels used"
        return False
    if choice == "numpy":
        _state["why"] = "NumPy (MANIKIN_KERNELS=numpy)"
        return False
    try:
        import numba
    except Exception as error:  # not installed, or its LLVM does not load on this machine
        _state["why"] = f"NumPy (Numba does not import: {type(error).__name__}: {error})"
        return False
    _state["why"] = f"Numba {numba.__version__} (cache {cache_folder()})"
    return True


def active() -> bool:
    """True when compiled kernels are in use (decided once per process, on the first call)."""
    if _state["available"] is None:
        _state["available"] = _state["active"] = _decide()
    return _state["active"]


def status() -> str:
    """One line: which kernels are in use and why."""
    active()
    return _state["why"]


def compile_seconds() -> float:
    """s this process spent compiling kernels (first calls that missed the cache; loading a cached one is not
    counted)."""
    return _state["compile_s"]


@contextmanager
def using(compiled: bool) -> Iterator[None]:
    """Within the block, compiled kernels on or off (off always works; on only where Numba imports)."""
    saved = active()
    _state["active"] = compiled and _state["available"]
    try:
        yield
    finally:
        _state["active"] = saved


class Kernel:
    """A loop function compiled by Numba on its first call (``njit``, no Python objects, cached on disk)."""

    def __init__(self, function: Callable) -> None:
        self.python = function
        self._compiled: Callable | None = None
        self.__name__ = function.__name__
        self.__doc__ = function.__doc__

    def __call__(self, *args):
        if self._compiled is None:
            return self._first_call(*args)
        return self._compiled(*args)

    def _first_call(self, *args):
        import numba

        start = time.perf_counter()
        # Numba takes its cache folder from its config as the dispatcher is made: ours, only for our kernels
        saved, numba.config.CACHE_DIR = numba.config.CACHE_DIR, str(cache_folder())
        try:
            compiled = numba.njit(cache=True, nogil=True, error_model="numpy")(self.python)
        finally:
            numba.config.CACHE_DIR = saved
        out = compiled(*args)  # compiles (or loads the cache) for these argument types
        self._compiled = compiled
        if sum(compiled.stats.cache_misses.values()):
            _state["compile_s"] += time.perf_counter() - start
        return out


def kernel(function: Callable) -> Kernel:
    """Decorator: ``function`` (loops over float64 arrays) as a lazily compiled :class:`Kernel`."""
    return Kernel(function)
