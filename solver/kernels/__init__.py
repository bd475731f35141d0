"""Compiled kernels for the solver's hot loops (Numba), with the NumPy code kept as the reference path.

Each kernel module defines plain-Python loop functions decorated with :func:`kernel`; callers ask
:func:`active` and take either the kernel or their NumPy code, which computes the same numbers to rounding
(tests compare the two). ``MANIKIN_KERNELS`` picks: ``auto`` (the default: Numba when it imports), ``numba`` (the
same, and a note when it cannot) or ``numpy``. Numba is imported and a kernel compiled only on first use, and the
machine code is cached in the user's folder (:func:`cache_folder`), so a later process loads it instead of
compiling again.
"""

from __future__ import annotations

import gc
import hashlib
import importlib.machinery
import importlib.util
import os
import sys
import time
import types
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from types import ModuleType

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
    _scipy_blas_alone()
    _state["why"] = f"Numba {numba.__version__} (cache {cache_folder()})"
    return True


def _scipy_blas_alone() -> None:
    """Load ``scipy.linalg.cython_blas`` (the BLAS that compiled ``np.dot`` calls) without the scipy.linalg package.
    Numba's first kernel load imports it to check that there is a BLAS, and that import would also run scipy.linalg's
    ``__init__``, which loads the rest of scipy.linalg and scipy.sparse (~30 ms here, 0.2-0.3 s in Blender) that the
    kernels never use. Without scipy, Numba finds no BLAS either way."""
    if "scipy.linalg" in sys.modules:
        return
    try:
        import scipy  # scipy's own set-up first, as solver.iteration.lapack does
    except ImportError:
        return
    extension_alone("scipy.linalg.cython_blas", Path(scipy.__file__).parent / "linalg")


def extension_alone(name: str, folder: Path) -> ModuleType | None:
    """The compiled extension module ``name`` (e.g. "scipy.linalg._flapack") loaded from its file in ``folder`` under
    that name, without running its package's ``__init__`` (which may import much more), and kept in ``sys.modules``
    so that a later import of it takes this one; the one already loaded if any; None where ``folder`` has no such
    file. Here, not in a module above, as this package imports nothing else of the solver."""
    if name in sys.modules:
        return sys.modules[name]
    stem = name.rpartition(".")[2]
    for suffix in importlib.machinery.EXTENSION_SUFFIXES:
        spec = importlib.util.spec_from_file_location(name, folder / f"{stem}{suffix}")
        if spec is not None and spec.loader is not None and Path(spec.origin or "").is_file():
            module = importlib.util.module_from_spec(spec)
            spec.loader.exec_module(module)
            sys.modules[name] = module
            return module
    return None


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
    """A loop function compiled by Numba on its first call (``njit``, no Python objects, cached on disk). It may call
    other kernels by their names: compiled, they call each other's machine code."""

    def __init__(self, function: Callable) -> None:
        self.python = function
        self._compiled: Callable | None = None
        self._dispatcher: Callable | None = None
        self.__name__ = function.__name__
        self.__doc__ = function.__doc__

    def __call__(self, *args):
        if self._compiled is None:
            return self._first_call(*args)
        return self._compiled(*args)

    def callees(self) -> dict[str, Kernel]:
        """The kernels this one calls, by the names it calls them."""
        names = self.python.__globals__
        return {name: names[name] for name in self.python.__code__.co_names if isinstance(names.get(name), Kernel)}

    def sources(self) -> set[str]:
        """The files of this kernel and of every kernel it calls, directly or not."""
        found = {self.python.__code__.co_filename}
        for callee in self.callees().values():
            found |= callee.sources()
        return found

    def dispatcher(self) -> Callable:
        """Numba's dispatcher of this kernel (compiled on its first call), the kernels it calls bound to theirs."""
        if self._dispatcher is None:
            import numba

            function, folder = self.python, cache_folder()
            callees = self.callees()
            if callees:
                names = {**function.__globals__, **{name: k.dispatcher() for name, k in callees.items()}}
                function = types.FunctionType(
                    function.__code__, names, function.__name__, function.__defaults__, function.__closure__
                )
                function.__kwdefaults__ = self.python.__kwdefaults__
                function.__qualname__, function.__module__ = self.python.__qualname__, self.python.__module__
                # Numba checks only the caller's file before loading its cache: the callees' files name the folder
                others = sorted(self.sources() - {self.python.__code__.co_filename})
                if others:
                    digest = hashlib.sha256(b"".join(Path(f).read_bytes() for f in others)).hexdigest()[:16]
                    folder = folder / f"calls-{digest}"
            # Numba takes its cache folder from its config as the dispatcher is made: ours, only for our kernels
            saved, numba.config.CACHE_DIR = numba.config.CACHE_DIR, str(folder)
            try:
                self._dispatcher = numba.njit(cache=True, nogil=True, error_model="numpy")(function)
            finally:
                numba.config.CACHE_DIR = saved
        return self._dispatcher

    def _first_call(self, *args):
        start = time.perf_counter()
        compiled = self.dispatcher()
        out = compiled(*args)  # compiles (or loads the cache) for these argument types
        self._compiled = compiled
        if sum(compiled.stats.cache_misses.values()):
            _state["compile_s"] += time.perf_counter() - start
            if not gc.isenabled():  # a caller holding the collector off (a command's start-up): compiling's garbage now
                gc.collect()
        return out


def kernel(function: Callable) -> Kernel:
    """Decorator: ``function`` (loops over float64 arrays) as a lazily compiled :class:`Kernel`."""
    return Kernel(function)
