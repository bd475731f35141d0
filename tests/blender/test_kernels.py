"""The compiled kernels work inside Blender on the wheels the extension ships (tests/blender/kernels_session.py in
Blender-equivalent processes): numba imports after bpy from the installed extension, the first process compiles the
kernels into the user's cache folder and a later one loads them from there, Solve Pose gives the same pose as with
MANIKIN_KERNELS=numpy, and where numba cannot import the add-on solves on NumPy and says so once in the Solve report
and always in the Result panel ("Solver kernels: ...")."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

NUMBA = "Numba 0.62.1"  # blender_manifest.toml's wheel


@pytest.fixture(scope="module")
def session(tmp_path_factory, run_session) -> dict:
    return run_session(tmp_path_factory.mktemp("kernels"), "kernels_session.py")


def _later(session: dict, mode: str) -> dict:
    later = session["later"][mode]
    assert later["code"] == 0, later["log"]
    return later


def _reports(seen: dict) -> list[str]:
    """Solve Pose's reports, in order (background Blender prints them)."""
    return [line for line in seen["log"].splitlines() if line.startswith(("Info: Converged", "Warning: Not conv"))]


def test_numba_imports_after_bpy_from_the_extension_s_wheels(session: dict) -> None:
    assert session["numba_file"].startswith(str(Path(session["work"], "user")))  # not a developer's environment
    assert session["active"] and session["status"].startswith(NUMBA)
    cache = Path(session["work"], "cache", "manikin", "numba")  # the user's folder (XDG_CACHE_HOME) ...
    assert Path(session["cache"]).parent == cache and Path(session["cache"]).name.endswith(".manikin.solver")
    assert session["cache"] in session["status"]  # ... and in it one for the solver's import name in Blender
    assert any(name.endswith(".nbc") for name in session["cached"]), session["cached"]  # compiled and kept


def test_a_later_blender_loads_the_cached_kernels(session: dict) -> None:
    again = _later(session, "again")
    assert again["active"] and again["status"] == session["status"]
    assert again["cached"] == session["cached"]  # the same files, untouched: loaded, not compiled again


def test_solve_pose_gives_the_numpy_pose(session: dict) -> None:
    """The same kernels give the same pose; NumPy's gives the same pose to the comfort phase's own tolerance: the
    statics kernels sum the joint loads in tree order, and where comfort's optimum is flat that rounding can end a
    solve at another point of the plateau (``python -m bench.kernels_ab`` counts them: ~1 in 6 random trials)."""
    for mode, exact in (("again", True), ("warm", True), ("numpy", False), ("blocked", False)):
        for mine, theirs in zip(session["solves"], _later(session, mode)["solves"], strict=True):
            assert mine["done"] == theirs["done"] == ["FINISHED"] and mine["summary"]["converged"]
            a, b = mine["summary"], theirs["summary"]
            assert b["converged"], mode
            if exact:
                assert a["iterations"] == b["iterations"], mode
            close = 1e-9 if exact else 1e-3
            np.testing.assert_allclose(a["com"], b["com"], rtol=0, atol=close, err_msg=mode)  # m
            assert abs(a["comfort"] - b["comfort"]) <= close * max(1.0, abs(a["comfort"])), mode
            forces = [np.array([c["force"] for c in s["contacts"]]) for s in (a, b)]  # N, the smallest ~0.2
            atol = 1e-9 * np.abs(forces[0]).max() if exact else 1.0  # 1 N: the balance rows' tolerance
            np.testing.assert_allclose(*forces, rtol=0, atol=atol, err_msg=mode)
            # the bones' channels are stored in single precision
            atol = 1e-6 if exact else 0.01  # rad
            np.testing.assert_allclose(mine["channels"], theirs["channels"], rtol=0, atol=atol, err_msg=mode)


def test_the_result_panel_names_the_kernels(session: dict) -> None:
    assert all(s["summary"]["kernels"] == session["status"] for s in session["solves"])  # the solve's, kept with it
    assert f"Solver kernels: {session['status']}" in session["panel"]
    assert f"Solver kernels: {_later(session, 'numpy')['status']}" in _later(session, "numpy")["panel"]
    assert "Solver kernels: NumPy (MANIKIN_KERNELS=numpy)" in _later(session, "numpy")["panel"]


def test_without_numba_the_add_on_solves_on_numpy_and_says_so_once(session: dict) -> None:
    blocked = _later(session, "blocked")
    assert not blocked["active"] and blocked["status"].startswith("NumPy (Numba does not import: ImportError")
    line = f"Solver kernels: {blocked['status']}"
    assert line in blocked["panel"]
    first, second = _reports(blocked)
    assert first.endswith("; " + line) and "Solver kernels" not in second  # once a process
    numpy = _later(session, "numpy")
    first, second = _reports(numpy)
    assert first.endswith("; Solver kernels: NumPy (MANIKIN_KERNELS=numpy)") and "Solver kernels" not in second
    assert not any("Solver kernels" in line for line in _reports(session))  # on Numba: only the panel says it


def test_the_first_solve_says_how_long_compiling_took_and_a_cached_start_does_not(session: dict) -> None:
    """The first Blender after installing compiles the kernels (seconds): its first Solve Pose says so, once; a later
    Blender loads them from the cache (well under a second: the Solve says nothing)."""
    first, second = _reports(session)
    assert "the solver's kernels were compiled for this machine first (" in first, first
    assert "kernels" not in second
    assert not any("kernels" in line for line in _reports(_later(session, "again")))


WARMING = "Compiling the solver's kernels in the background"  # the panels' line while the warm-up runs


def test_enabling_compiles_the_kernels_in_the_background_and_the_first_solve_loads_them(session: dict) -> None:
    """Enabling the add-on on an empty cache starts one process that compiles the kernels under the add-on's own
    import name (kernel_warmup.py); a Solve Pose after it ended compiles nothing and says nothing of kernels."""
    warm = _later(session, "warm")
    w = warm["warmup"]
    assert w["decision"].startswith("started "), w
    assert w["line"] == WARMING  # the panels say it while it runs ...
    assert w["running"] is None and w["line_after"] == "" and w["wait_s"] < 120, w  # ... and not once it ended
    assert "box_lift solved (converged)" in w["log"], w["log"]
    assert Path(warm["cache"]).parent == Path(session["work"], "cache_warm", "manikin", "numba")
    assert Path(warm["cache"]).name == Path(session["cache"]).name  # bl_ext.<repo>.manikin.solver, as Blender's
    assert any(name.endswith(".nbi") for name in warm["cached"]), warm["cached"]
    assert warm["compile_s"] == 0  # every kernel loaded from what the warm-up wrote
    assert [s["done"] for s in warm["solves"]] == [["FINISHED"]] * 2
    assert not any("kernels" in line for line in _reports(warm))
    assert WARMING not in warm["panel"]
    assert w["decision_again"] == "cache warm"  # enabled again: no second warm-up


def test_no_warm_up_on_a_warm_cache_nor_with_numpy_kernels(session: dict) -> None:
    """The first Blender, enabled with MANIKIN_WARMUP=0 (it compiles in the foreground: the real warm-up runs in
    ``warm``), starts none; on its cold cache without the switch one would start, and where another's marker names a
    live process enabling finds it running and the main panel says so below Solve Pose until it ends. Later starts on
    its cache, or with MANIKIN_KERNELS=numpy, start none."""
    w = session["warmup"]
    assert w["decision"] == "MANIKIN_WARMUP=0" and w["line"] == ""
    assert w["would"] == "" and w["found"] == "already running", w  # "": one is needed
    assert WARMING in session["main_panel"] and WARMING not in session["main_panel_after"]  # below Solve Pose
    assert w["running"] is None  # its process ended: the marker it left counts no more
    assert _later(session, "again")["warmup"]["decision"] == "cache warm"
    assert _later(session, "blocked")["warmup"]["decision"] == "cache warm"
    assert _later(session, "numpy")["warmup"]["decision"] == "MANIKIN_KERNELS=numpy"
