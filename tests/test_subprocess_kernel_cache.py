"""The add-on's subprocesses (a study, a reach envelope, Generate Motion: blender_manikin/scene/background.py) keep
their compiled kernels apart from Blender's. Blender imports the kernels' files as ``bl_ext.<repo>.manikin.solver``,
the subprocess as the top-level ``solver``; Numba finds a cached kernel by its file's path and loads it by importing
the module that compiled it, so a shared cache folder breaks whichever process comes second. Shown here without
Blender: a copy of ``solver/kernels`` compiled as ``ext.solver.kernels`` and then run as ``solver.kernels``."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from blender_manikin.scene.background import kernel_cache

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
    blender = str(tmp_path / "cache" / "manikin" / "numba")
    first = _run(away, tmp_path, "ext.solver", blender)  # "Blender": compiles into its cache folder
    assert first.returncode == 0 and first.stdout.strip() == "3.0", first.stderr[-2000:]
    child = _run(away, tmp_path / "ext", "solver", kernel_cache(blender, tmp_path / "unused"))
    assert child.returncode == 0 and child.stdout.strip() == "3.0", child.stderr[-2000:]
    shared = _run(away, tmp_path / "ext", "solver", blender)  # what the child did before it had its own folder
    assert shared.returncode != 0 and "No module named 'ext'" in shared.stderr
