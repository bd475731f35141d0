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


@pytest.mark.slow
@pytest.mark.skipif(platform.machine().lower() not in ("x86_64", "amd64"), reason="x86-64 kernel names")
@pytest.mark.parametrize("setting", list(SETTINGS))
def test_a_sample_of_the_suite_passes_with_other_kernels(setting: str) -> None:
    env = {k: v for k, v in os.environ.items() if k not in ("NPY_DISABLE_CPU_FEATURES", "OPENBLAS_CORETYPE")}
    env |= SETTINGS[setting]
    command = [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "-m", "not slow", *SAMPLE]
    done = subprocess.run(command, cwd=ROOT, env=env, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stdout[-4000:] + done.stderr[-2000:]
