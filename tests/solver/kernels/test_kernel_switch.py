"""The compiled kernels' switch: MANIKIN_KERNELS picks Numba or NumPy, a wrong value falls back with a reason, and
Numba's machine code goes to the user's cache folder."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from solver import kernels

ROOT = Path(__file__).resolve().parents[3]


def _status(value: str) -> str:
    env = dict(os.environ, MANIKIN_KERNELS=value, PYTHONPATH=str(ROOT))
    code = "from solver import kernels; print(kernels.active(), kernels.status())"
    return subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True).stdout


def test_numpy_is_chosen_by_name_and_a_wrong_choice_says_what_is_wrong() -> None:
    assert _status("numpy").startswith("False NumPy (MANIKIN_KERNELS=numpy)")
    wrong = _status("fortran")
    assert wrong.startswith("False") and "'fortran' is not one of auto, numba, numpy" in wrong


def test_auto_uses_numba_where_it_imports_and_caches_in_the_users_folder() -> None:
    pytest.importorskip("numba")
    line = _status("auto")
    assert line.startswith("True Numba") and str(kernels.cache_folder()) in line


def test_using_switches_within_a_block_and_restores() -> None:
    before = kernels.active()
    with kernels.using(False):
        assert not kernels.active()
    assert kernels.active() == before


@pytest.mark.parametrize("choice", ["numpy", "auto"])
def test_the_kernels_command_says_which_and_compile_solves_the_box_lift(choice: str) -> None:
    if choice == "auto":
        pytest.importorskip("numba")
    env = dict(os.environ, MANIKIN_KERNELS=choice, PYTHONPATH=str(ROOT))
    done = subprocess.run(
        [sys.executable, "-m", "solver", "kernels", "--compile"], env=env, capture_output=True, text=True, timeout=300
    )
    assert done.returncode == 0, done.stderr
    lines = done.stdout.splitlines()
    assert lines[0] == ("kernels: NumPy (MANIKIN_KERNELS=numpy)" if choice == "numpy" else f"kernels: {_numba_line()}")
    assert lines[1].startswith("box_lift solved (converged) in ")
    # two more presets and a motion reach the kernels box_lift does not (the step's clamping rounds, a box obstacle,
    # the check of the way between two frames)
    assert [line.split()[0] for line in lines[1:]] == ["box_lift", "deep_squat", "cabinet_reach", "box_lift_motion"]
    assert lines[-1].startswith("box_lift_motion 12 frames solved (converged) in ")


def _numba_line() -> str:
    import numba

    return f"Numba {numba.__version__} (cache {kernels.cache_folder()})"


def test_compiling_is_timed_and_a_cached_kernel_is_not(tmp_path: Path) -> None:
    pytest.importorskip("numba")
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path), PYTHONPATH=str(ROOT), MANIKIN_KERNELS="auto")
    code = ("import numpy as np; from solver import kernels; from solver.io.scenario.bodies import load_body; "
            "m = load_body(preset='male_50'); m.forward(np.zeros(m.n)); print(kernels.compile_seconds())")  # fmt: skip
    first, again = (
        float(subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True).stdout)
        for _ in range(2)
    )
    assert first > 0.0 and again == 0.0
    assert (tmp_path / "solver").is_dir()  # the cache folder of this import name


CALLEE = "from solver.kernels import kernel\n\n\n@kernel\ndef part(x: float) -> float:\n    return x * {factor}\n"
CALLER = (
    "from solver.kernels import kernel\n\nfrom .callee import part\n\n\n"
    "@kernel\ndef whole(x: float) -> float:\n    return part(x) + 1.0\n"
)


def test_a_kernel_calls_another_modules_kernel_and_its_cache_follows_that_file(tmp_path: Path) -> None:
    """A kernel calling a kernel of another file: loaded from the cache by the next process (not compiled again), and
    compiled again when the callee's file changes (Numba itself checks only the caller's file)."""
    pytest.importorskip("numba")
    package = tmp_path / "code" / "nested"
    package.mkdir(parents=True)
    (package / "__init__.py").write_text("")
    (package / "caller.py").write_text(CALLER)
    env = dict(
        os.environ, NUMBA_CACHE_DIR=str(tmp_path / "cache"), MANIKIN_KERNELS="auto",
        PYTHONPATH=os.pathsep.join((str(ROOT), str(tmp_path / "code"))),
    )  # fmt: skip
    code = "from solver import kernels; from nested.caller import whole; print(whole(2.0), kernels.compile_seconds())"

    def run(factor: int) -> tuple[float, float]:
        (package / "callee.py").write_text(CALLEE.format(factor=factor))
        done = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
        value, seconds = done.stdout.split()
        return float(value), float(seconds)

    first, again, changed = run(3), run(3), run(5)
    assert first[0] == again[0] == 7.0 and first[1] > 0.0 and again[1] == 0.0
    assert changed[0] == 11.0 and changed[1] > 0.0
