"""The LAPACK routines the solver calls (dgesv, dpotrf, dpotrs, dtrtri): scipy's own Fortran wrappers,
``scipy.linalg._flapack``, the very functions ``scipy.linalg.lapack`` exports, loaded without running the
``scipy.linalg`` package. That package also imports scipy.sparse and the rest of scipy.linalg, which the solver never
uses: 0.2-0.5 s of the first solve in Blender. Where scipy.linalg is loaded already, or this scipy keeps its
wrappers elsewhere, they come from ``scipy.linalg.lapack`` as before.
"""

from __future__ import annotations

import sys
from pathlib import Path
from types import ModuleType

from ..kernels import extension_alone

NAME = "scipy.linalg._flapack"


def flapack() -> ModuleType:
    """scipy's LAPACK wrappers; loaded once, under their own name, so a later ``import scipy.linalg`` takes them."""
    if NAME in sys.modules:
        return sys.modules[NAME]
    if "scipy.linalg" not in sys.modules:
        import scipy  # scipy's own set-up first: its numpy check and (Windows) the folder of its bundled OpenBLAS

        module = extension_alone(NAME, Path(scipy.__file__).parent / "linalg")
        if module is not None:
            return module
    from scipy.linalg import lapack

    return lapack


_lapack = flapack()
dgesv, dpotrf, dpotrs, dtrtri = _lapack.dgesv, _lapack.dpotrf, _lapack.dpotrs, _lapack.dtrtri
