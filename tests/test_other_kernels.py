"""The suite's verdicts do not hang on which CPU kernels NumPy and OpenBLAS pick: a representative sample runs again
in a subprocess with other kernels, which round some products and functions differently in the last bits.

The sample: the collision geometry (batched distance queries through BLAS and SIMD kernels, compared across batch
sizes) and the stepping reach searches (solves at the edge of reach, then a solve with comfort there). The kernels:
NumPy's AVX-512 loops switched off (AVX2's ``exp``, ``log``, ``arctan2`` differ by 1-3 ulp), and OpenBLAS's kernels
of older cores (Sandybridge: AVX without FMA; Prescott: SSE3), as an unknown CPU model gets them. Each setting once
made one of these tests fail before its comparison or search was made robust. x86-64 only (the kernels' names).
"""

from __future__ import annotations

import os
import platform
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
SAMPLE = [
    "tests/solver/collision/test_collision_geometry.py",
    "tests/solver/envelope/test_envelope_stepping.py::test_a_stepping_reach_is_farther_in_bounds_and_in_balance",
]
AVX512 = "AVX512F AVX512CD AVX512_SKX AVX512_CLX AVX512_CNL AVX512_ICL"
SETTINGS = {
    "numpy_without_avx512": {"NPY_DISABLE_CPU_FEATURES": AVX512},
    "openblas_sandybridge": {"OPENBLAS_CORETYPE": "Sandybridge"},
    "openblas_prescott": {"OPENBLAS_CORETYPE": "Prescott"},
}


X86 = platform.machine().lower() in ("x86_64", "amd64")


@pytest.fixture(scope="module")
def started(tmp_path_factory) -> dict[str, tuple[subprocess.Popen, Path]]:
    """The sample under each setting, all started at once (on a second core where there is one: they take ~10 s
    each); each process and the file its output goes to (a file: a full pipe would stop a process not yet read)."""
    folder = tmp_path_factory.mktemp("other_kernels")
    base = {k: v for k, v in os.environ.items() if k not in ("NPY_DISABLE_CPU_FEATURES", "OPENBLAS_CORETYPE")}
    command = [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "-m", "not slow", *SAMPLE]
    processes = {}
    for setting, changes in SETTINGS.items():
        with open(folder / f"{setting}.log", "wb") as log:
            process = subprocess.Popen(command, cwd=ROOT, env=base | changes, stdout=log, stderr=subprocess.STDOUT)
        processes[setting] = (process, folder / f"{setting}.log")
    yield processes
    for process, _ in processes.values():
        if process.poll() is None:  # a test that failed early left it running
            process.kill()
            process.wait()


@pytest.mark.slow
@pytest.mark.skipif(not X86, reason="x86-64 kernel names")
@pytest.mark.parametrize("setting", list(SETTINGS))
def test_a_sample_of_the_suite_passes_with_other_kernels(setting: str, started) -> None:
    process, log = started[setting]
    code = process.wait(timeout=600)
    assert code == 0, log.read_text(encoding="utf-8", errors="replace")[-6000:]
