"""The add-on's subprocesses (a study, a reach envelope, Generate Motion: blender_manikin/scene/background.py) keep
their compiled kernels apart from Blender's. Blender imports the kernels' files as ``bl_ext.<repo>.manikin.solver``,
the subprocess as the top-level ``solver``; Numba finds a cached kernel by its file's path and loads it by importing
the module that compiled it, so one folder for both breaks whichever process comes second: each import name keeps
a folder of its own (``solver.kernels.cache_folder``). Shown here without Blender: a copy of ``solver/kernels``
compiled as ``ext.solver.kernels`` and then run as ``solver.kernels``, both given the same NUMBA_CACHE_DIR."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PROBE = """import numpy as np

from . import kernel


@kernel
def add_one(x):
    one = np.empty(1)  # an allocation: the cached kernel then names its module
    one[0] = 1.0
    for i in range(x.shape[0]):
        x[i] += one[0]
"""
CALL = "import numpy as np; from {package}.kernels.probe import add_one; x = np.zeros(3); add_one(x); print(x.sum())"


def _run(tmp: Path, path: Path, package: str, cache: str) -> subprocess.CompletedProcess:
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "NUMBA_CACHE_DIR", "MANIKIN_KERNELS")}
    env.update(PYTHONPATH=str(path), NUMBA_CACHE_DIR=cache)
    code = CALL.format(package=package)
    return subprocess.run([sys.executable, "-c", code], cwd=tmp, env=env, capture_output=True, text=True, timeout=300)


@pytest.mark.slow  # three processes import Numba, two compile: ~5-10 s
def test_a_subprocess_runs_kernels_that_blender_compiled(tmp_path: Path) -> None:
    pytest.importorskip("numba")
    package = tmp_path / "ext" / "solver"
    shutil.copytree(ROOT / "solver" / "kernels", package / "kernels", ignore=shutil.ignore_patterns("__pycache__"))
    (package / "kernels" / "probe.py").write_text(PROBE, encoding="utf-8")
    for folder in (package, package.parent):
        (folder / "__init__.py").write_text("", encoding="utf-8")
    away = tmp_path / "elsewhere"  # the working folder: where ``ext`` cannot be imported from
    away.mkdir()
    cache = tmp_path / "cache"
    first = _run(away, tmp_path, "ext.solver", str(cache))  # "Blender": compiles into its cache folder
    assert first.returncode == 0 and first.stdout.strip() == "3.0", first.stderr[-2000:]
    child = _run(away, tmp_path / "ext", "solver", str(cache))  # the subprocess: the same NUMBA_CACHE_DIR
    assert child.returncode == 0 and child.stdout.strip() == "3.0", child.stderr[-2000:]
    assert {p.name for p in cache.iterdir()} == {"ext.solver", "solver"}  # a folder per import name
    again = _run(away, tmp_path, "ext.solver", str(cache))  # "Blender" again: loads its own
    assert again.returncode == 0 and again.stdout.strip() == "3.0", again.stderr[-2000:]
