"""Compiling the solver's kernels in the background when the add-on is enabled, so the first Solve Pose after
installing loads them instead of freezing Blender for the ~20 s Numba takes to compile them.

Numba keeps a cache folder per import name of the solver (:data:`solver.kernels.PACKAGE`): inside Blender
``bl_ext.<repo>.manikin.solver``. :func:`start_if_cold` (called by ``addon.register``) starts ONE detached process
with Blender's Python (the environment of :mod:`.background`: the extension's wheels, numba included) that runs
this file as a script: it imports the solver under that same name (the ``bl_ext`` packages made by hand as Blender
makes them, no bpy) and solves the presets ``python -m solver kernels --compile`` solves (box_lift, two more and a
motion's first frames: the kernels a Solve Pose and a Bake Motion use), so Numba writes the cache the add-on's own
solves then load. Its output goes to ``warmup.log`` in the cache folder; while it runs, ``warmup.pid`` there holds
its process id.

A solve that starts before the warm-up ends compiles in Blender as before, both processes writing the same cache
files: Numba writes each to a temporary name and renames it (a reader never sees half a file), and both compile the
same argument types of each kernel, so the two write the same entries. Nothing starts when the cache already holds
kernels newer than the solver's files, under MANIKIN_KERNELS=numpy or MANIKIN_WARMUP=0 (``batch.py`` and the
demo set it: a headless run compiles what it solves itself), or while another warm-up lives. Only the
standard library at module level: the script runs without bpy, and enabling stays fast (numba and the solver's
heavy modules load in the child only).
"""

from __future__ import annotations

import argparse
import importlib
import os
import subprocess
import sys
import time
import types
from pathlib import Path

MARKER, LOG = "warmup.pid", "warmup.log"  # in the kernels' cache folder
SWITCH = "MANIKIN_WARMUP"  # "0": no warm-up (a headless batch compiles what it solves; a second process would too)
STALE_S = 600.0  # s: a marker this old is ignored whatever its process (a warm-up takes ~20-60 s)
_state: dict = {"process": None, "decision": ""}  # the warm-up this process started; what register decided


def _solver() -> types.ModuleType:
    """The solver's light ``kernels`` module (standard library only: no numba until a kernel is used)."""
    from ...solver import kernels

    return kernels


def _alive(pid: int) -> bool:
    """Whether process ``pid`` runs (POSIX; elsewhere the marker's age alone decides)."""
    process = _state["process"]
    if process is not None and process.pid == pid:
        return process.poll() is None  # ours: poll also reaps it (a finished child is a zombie until then)
    if os.name != "posix":
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:
        return True  # exists, another user's
    return True


def running(folder: Path | None = None) -> int | None:
    """The process id of the warm-up under way for the cache ``folder`` (default the add-on's), or None."""
    marker = (folder or _solver().cache_folder()) / MARKER
    try:
        pid = int(marker.read_text(encoding="utf-8").split()[0])
        fresh = time.time() - marker.stat().st_mtime < STALE_S
    except (OSError, ValueError, IndexError):
        return None
    return pid if fresh and _alive(pid) else None


def status_line() -> str:
    """What the panels say while a warm-up runs, else "". Only where enabling started one or found one running: a
    panel draws often, and otherwise there is no marker to read."""
    if not _state["decision"].startswith(("started", "already running")):
        return ""
    try:
        return "Compiling the solver's kernels in the background" if running() else ""
    except Exception:  # a panel's draw must not fail on it
        return ""


def is_cold(folder: Path, solver_dir: Path) -> bool:
    """Whether the cache ``folder`` lacks compiled kernels for the solver at ``solver_dir``: no Numba index file
    (``*.nbi``) at all, or none written since the solver's files were (an updated extension: Numba compiles again)."""
    newest = max((p.stat().st_mtime for p in solver_dir.rglob("*.py")), default=0.0)
    return not any(p.stat().st_mtime >= newest for p in folder.rglob("*.nbi"))


def decide() -> str:
    """Why no warm-up is needed, or "" when one is."""
    choice = os.environ.get("MANIKIN_KERNELS", "auto").strip().lower() or "auto"
    if choice not in ("auto", "numba"):
        return f"MANIKIN_KERNELS={choice}"
    if os.environ.get(SWITCH, "").strip().lower() in ("0", "off", "no"):
        return f"{SWITCH}=0"  # batch.py and the demo: they compile what they solve themselves
    kernels = _solver()
    folder = kernels.cache_folder()
    if not is_cold(folder, Path(kernels.__file__).parents[1]):
        return "cache warm"
    if running(folder):
        return "already running"
    return ""


def start_if_cold() -> str:
    """Start the warm-up when :func:`decide` says so; what was decided (also kept for the tests). Never raises:
    without a warm-up the first solve compiles the kernels itself."""
    try:
        why = decide()
        if not why:
            why = f"started {start().pid}"
    except Exception as error:
        why = f"failed: {type(error).__name__}: {error}"
    _state["decision"] = why
    return why


def last_decision() -> str:
    """What :func:`start_if_cold` decided last in this process ("started <pid>", "cache warm", ...; "" if never)."""
    return _state["decision"]


def start() -> subprocess.Popen:
    """Start the warm-up process (it outlives a Blender that quits, at a lower priority) and write its marker."""
    from .background import ROOT, child_env

    kernels = _solver()
    folder = kernels.cache_folder()
    folder.mkdir(parents=True, exist_ok=True)
    # -P: the script's folder stays off sys.path (its modules are no top-level names)
    command = [sys.executable, "-P", str(Path(__file__).resolve()), kernels.PACKAGE, str(ROOT)]
    # a process group of its own (Ctrl-C in Blender's terminal does not reach it) in Blender's session: on Linux a
    # new session is a scheduler group of its own, where its lower priority (warm) would not count against Blender
    detached = dict(process_group=0) if os.name == "posix" else dict(creationflags=_WINDOWS_FLAGS)
    with open(folder / LOG, "wb") as log:  # the child keeps its own handle
        process = subprocess.Popen(
            command, cwd=str(folder), env=child_env(), stdin=subprocess.DEVNULL, stdout=log, stderr=log, **detached
        )
    _state["process"] = process
    (folder / MARKER).write_text(f"{process.pid}\n", encoding="utf-8")
    return process


# no console window, Ctrl-C in Blender's console does not reach it, and Blender's own work first
_WINDOWS_FLAGS = sum(
    getattr(subprocess, flag, 0)
    for flag in ("CREATE_NO_WINDOW", "CREATE_NEW_PROCESS_GROUP", "BELOW_NORMAL_PRIORITY_CLASS")
)


def import_as(package: str, extension: Path) -> types.ModuleType:
    """Import the solver as ``package`` (e.g. ``bl_ext.user_default.manikin.solver``) from the extension folder
    ``extension``: its ancestors made as Blender makes them (``bl_ext`` and ``bl_ext.<repo>``, the latter's path the
    extensions repository, the parent of ``extension``), so Numba's cache names the same modules."""
    parts = package.split(".")
    for k in range(1, len(parts) - 1):
        name = ".".join(parts[:k])
        if name not in sys.modules:
            module = types.ModuleType(name)
            module.__path__ = [str(extension.parent)] if k == len(parts) - 2 else []
            sys.modules[name] = module
    if len(parts) == 2:  # a legacy add-on folder: its parent on the path
        sys.path.insert(0, str(extension.parent))
    return importlib.import_module(package)


def warm(package: str, extension: Path) -> int:
    """The child: compile (or load) the kernels under ``package`` as ``kernels --compile`` does; its exit code."""
    if os.name == "posix":
        os.nice(10)  # Blender's own work first
    import_as(package, extension)
    kernels = importlib.import_module(f"{package}.kernels")
    marker = kernels.cache_folder() / MARKER
    try:
        if not kernels.active():  # Numba does not import here: nothing to compile
            print(f"kernels: {kernels.status()}", flush=True)
            return 0
        return importlib.import_module(f"{package}.cli.kernels").run(argparse.Namespace(compile=True))
    finally:
        try:
            if marker.read_text(encoding="utf-8").split()[0] == str(os.getpid()):
                marker.unlink()
        except (OSError, IndexError):
            pass


if __name__ == "__main__":
    sys.exit(warm(sys.argv[1], Path(sys.argv[2])))
