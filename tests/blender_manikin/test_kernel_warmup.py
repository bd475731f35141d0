"""When enabling the add-on starts the kernels' background warm-up (blender_manikin/scene/kernel_warmup.py, no bpy):
only on a cache without kernels written since the solver's files, not under MANIKIN_KERNELS=numpy, not while a
live warm-up's marker is there; and the child imports the solver under Blender's import name. The warm-up itself,
in Blender: tests/blender/test_kernels.py."""

from __future__ import annotations

import importlib
import importlib.util
import os
import subprocess
import sys
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def _checkout_module(path: str, name: str = "manikin_checkout"):
    """``path`` of the checkout loaded as the package Blender loads the extension as (as in test_supports.py)."""
    if name not in sys.modules:
        spec = importlib.util.spec_from_file_location(
            name, ROOT / "__init__.py", submodule_search_locations=[str(ROOT)]
        )
        package = importlib.util.module_from_spec(spec)
        sys.modules[name] = package
        spec.loader.exec_module(package)
    return importlib.import_module(f"{name}.{path}")


warmup = _checkout_module("blender_manikin.scene.kernel_warmup")


def _touch(path: Path, when: float) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.touch()
    os.utime(path, (when, when))
    return path


def test_the_cache_is_cold_until_it_holds_kernels_written_after_the_solver_s_files(tmp_path: Path) -> None:
    now = time.time()
    source = _touch(tmp_path / "solver" / "kernels" / "forward.py", now - 100)
    cache = tmp_path / "cache"
    assert warmup.is_cold(cache, tmp_path / "solver")  # no folder yet
    _touch(cache / "kernels_x" / "forward.link_frames-10.py311.nbi", now - 50)
    assert not warmup.is_cold(cache, tmp_path / "solver")
    os.utime(source, (now, now))  # the extension updated: Numba compiles again
    assert warmup.is_cold(cache, tmp_path / "solver")


def test_a_marker_counts_while_its_process_lives_and_is_fresh(tmp_path: Path) -> None:
    marker = tmp_path / warmup.MARKER
    assert warmup.running(tmp_path) is None
    marker.write_text(f"{os.getpid()}\n", encoding="utf-8")
    assert warmup.running(tmp_path) == os.getpid()
    os.utime(marker, (time.time() - warmup.STALE_S - 1,) * 2)
    assert warmup.running(tmp_path) is None  # stale, whatever its process
    ended = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True, text=True)
    marker.write_text(ended.stdout, encoding="utf-8")
    if os.name == "posix":
        assert warmup.running(tmp_path) is None  # its process ended
    marker.write_text("not a pid", encoding="utf-8")
    assert warmup.running(tmp_path) is None


def test_no_warm_up_under_numpy_kernels_on_a_warm_cache_or_beside_a_live_one(tmp_path, monkeypatch) -> None:
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path))
    monkeypatch.setenv("MANIKIN_KERNELS", "numpy")
    assert warmup.decide() == "MANIKIN_KERNELS=numpy"
    monkeypatch.setenv("MANIKIN_KERNELS", "auto")
    monkeypatch.setenv("MANIKIN_WARMUP", "0")  # as batch.py sets it: a headless run compiles what it solves
    assert warmup.decide() == "MANIKIN_WARMUP=0"
    monkeypatch.delenv("MANIKIN_WARMUP")
    folder = warmup._solver().cache_folder()
    assert folder == tmp_path / "manikin_checkout.solver"
    assert warmup.decide() == ""  # empty: one is needed
    _touch(folder / warmup.MARKER, time.time()).write_text(str(os.getpid()), encoding="utf-8")
    assert warmup.decide() == "already running"
    _touch(folder / "kernels_x" / "f-1.py311.nbi", time.time() + 10)
    assert warmup.decide() == "cache warm"


@pytest.mark.skipif(os.name != "posix", reason="a symlinked extension folder")
def test_the_child_imports_the_solver_under_blender_s_name(tmp_path: Path) -> None:
    """Without bpy: ``bl_ext`` and ``bl_ext.<repo>`` made by hand, the extension's own package imported from the
    repository folder, so the kernels' cache folder is the one the add-on uses inside Blender."""
    (tmp_path / "repo").mkdir()
    (tmp_path / "repo" / "manikin").symlink_to(ROOT, target_is_directory=True)
    code = (
        "import importlib.util, sys; from pathlib import Path; "
        f"spec = importlib.util.spec_from_file_location('warm', {str(Path(warmup.__file__))!r}); "
        "warm = importlib.util.module_from_spec(spec); spec.loader.exec_module(warm); "
        f"solver = warm.import_as('bl_ext.repo.manikin.solver', Path({str(tmp_path / 'repo' / 'manikin')!r})); "
        "kernels = importlib.import_module(solver.__name__ + '.kernels'); "
        "print(kernels.PACKAGE, 'bpy' in sys.modules, 'numba' in sys.modules)"
    )
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "NUMBA_CACHE_DIR")}
    done = subprocess.run([sys.executable, "-P", "-c", code], cwd=tmp_path, env=env, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert done.stdout.split() == ["bl_ext.repo.manikin.solver", "False", "False"]
