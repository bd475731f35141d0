"""The LAPACK routines the solver calls (dgesv, dpotrf, dpotrs, dtrtri): scipy's own Fortran wrappers,
``scipy.linalg._flapack``, the very functions ``scipy.linalg.lapack`` exports, loaded without running the
``scipy.linalg`` package. That package also imports scipy.sparse and the rest of scipy.linalg, which the solver never
uses: 0.2-0.5 s of the first solve in Blender. Where scipy.linalg is loaded already, or this scipy keeps its
wrappers elsewhere, they come from ``scipy.linalg.lapack`` as before.
"""

from __future__ import annotations

import importlib.machinery
import importlib.util
import sys
from pathlib import Path
from types import ModuleType

NAME = "scipy.linalg._flapack"


def flapack() -> ModuleType:
    """scipy's LAPACK wrappers; loaded once, under their own name, so a later ``import scipy.linalg`` takes them."""
    if NAME in sys.modules:
        return sys.modules[NAME]
    if "scipy.linalg" not in sys.modules:
        import scipy  # scipy's own set-up first: its numpy check and (Windows) the folder of its bundled OpenBLAS

        folder = Path(scipy.__file__).parent / "linalg"
        for suffix in importlib.machinery.EXTENSION_SUFFIXES:
            spec = importlib.util.spec_from_file_location(NAME, folder / f"_flapack{suffix}")
            if spec is not None and spec.loader is not None and Path(spec.origin or "").is_file():
                module = importlib.util.module_from_spec(spec)
                spec.loader.exec_module(module)
                sys.modules[NAME] = module
                return module
    from scipy.linalg import lapack

    return lapack


_lapack = flapack()
dgesv, dpotrf, dpotrs, dtrtri = _lapack.dgesv, _lapack.dpotrf, _lapack.dpotrs, _lapack.dtrtri
