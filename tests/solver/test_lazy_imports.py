"""``import solver`` is cheap (the Blender add-on enables on it) and its names are the documented objects whatever
was imported first (the function ``solve``, not a module of that name)."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def _run(code: str, timeout: float = 60, **env: str) -> str:
    environment = dict(os.environ, **env)
    done = subprocess.run(
        [sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, timeout=timeout, env=environment
    )
    assert done.returncode == 0, done.stderr
    return done.stdout.strip()


def test_light_modules_load_neither_the_numerics_nor_scipy() -> None:
    code = "import sys, solver, solver.errors, solver.options, solver.presets; " \
           "print(sorted(m for m in sys.modules if m.startswith(('solver', 'scipy', 'numpy'))))"  # fmt: skip
    assert _run(code) == str(["solver", "solver.errors", "solver.lazy", "solver.options", "solver.presets"])


def test_package_names_are_the_objects_whatever_loaded_first() -> None:
    code = "import solver.motion.frames, solver.problem.scenario; from solver import solve, Problem, SolverOptions; " \
           "print(callable(solve), solve.__module__, Problem.__module__, SolverOptions().max_iterations)"  # fmt: skip
    assert _run(code) == "True solver.iteration.phases solver.problem.problem 100"


def test_io_api_names_are_the_functions_whatever_loaded_first() -> None:
    code = "import solver.io.result.read, solver.ergonomics, solver.problem.scenario; import solver; " \
           "print(*(getattr(solver, n).__module__ for n in ('read_result', 'evaluate', 'load_scenario', " \
           "'write_result', 'load_preset', 'solve_motion', 'Scenario')))"  # fmt: skip
    expected = ("solver.io.result.read solver.ergonomics solver.io.scenario.read solver.io.result.write "
                "solver.io.scenario.bodies solver.motion.frames solver.problem.scenario")  # fmt: skip
    assert _run(code) == expected
    assert _run("import solver; print(all(getattr(solver, n) is not None for n in solver.__all__))") == "True"


def test_ergonomics_and_the_result_reader_load_no_scipy() -> None:
    """The Blender layer imports the ergonomics (worksheet bands) when it enables, in a Blender without scipy."""
    code = "import sys, solver.ergonomics.worksheet, solver.io.result.read; " \
           "print(sorted(m for m in sys.modules if m.startswith('scipy')))"  # fmt: skip
    assert _run(code) == "[]"


def test_a_solve_loads_scipy_s_lapack_wrappers_only() -> None:
    """A first solve in Blender loads scipy's Fortran LAPACK wrappers, not the scipy.linalg package (which also
    imports scipy.sparse: 0.2-0.5 s that a solve never uses); a later ``import scipy.linalg`` takes the same ones.
    With the NumPy kernels: Numba's own linear-algebra support imports scipy.linalg as Numba loads (docs/BENCHMARKS.md
    states that first-solve cost)."""
    code = "import sys, solver; scenario = solver.load_scenario('presets/scenarios/box_lift.toml'); " \
           "[(_, r)] = solver.solve_motion(scenario); " \
           "print(r.converged, sorted(m for m in sys.modules if m.startswith(('scipy.linalg', 'scipy.sparse')))); " \
           "from scipy.linalg import lapack, solve; from solver.iteration import lapack as mine; " \
           "print(lapack.dpotrf is mine.dpotrf, solve([[2.0]], [4.0])[0])"  # fmt: skip
    assert _run(code, MANIKIN_KERNELS="numpy").splitlines() == ["True ['scipy.linalg._flapack']", "True 2.0"]


def test_a_solve_with_compiled_kernels_loads_scipy_s_blas_alone_too() -> None:
    """Numba's check for a BLAS (its first kernel load) finds scipy.linalg.cython_blas loaded by itself, not through
    the scipy.linalg package; the kernels that call it (np.dot) give the NumPy path's pose, and a later
    ``import scipy.linalg`` takes the same module."""
    pytest.importorskip("numba")
    code = "\n".join(
        [
            "import sys, numpy, solver",
            "from solver import kernels",
            "scenario = solver.load_scenario('presets/scenarios/box_lift.toml')",
            "[(_, r)] = solver.solve_motion(scenario)",
            "print(r.converged, sorted(m for m in sys.modules if m.startswith(('scipy.linalg', 'scipy.sparse'))))",
            "blas = sys.modules['scipy.linalg.cython_blas']",
            "import scipy.linalg.cython_blas as again",
            "with kernels.using(False):",
            "    [(_, plain)] = solver.solve_motion(scenario)",
            "from solver.kernels.bounded_step import bounded_step",  # calls np.dot: the BLAS
            "print(bounded_step._compiled is not None, again is blas, 'dgemm' in blas.__pyx_capi__)",
            "print(numpy.allclose(r.x, plain.x, rtol=0, atol=1e-6))",
        ]
    )
    lines = _run(code, timeout=300, MANIKIN_KERNELS="auto").splitlines()  # a first run compiles the kernels
    assert lines == ["True ['scipy.linalg._flapack', 'scipy.linalg.cython_blas']", "True True True", "True"]
