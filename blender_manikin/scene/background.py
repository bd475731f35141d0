"""The solver run in a subprocess of the Python that runs Blender (what a population study and a reach envelope
computed from the sidebar share; no bpy at module level, only inside :func:`wheel_folder`).

The subprocess needs what the add-on uses inside Blender: the extension's own ``solver`` package (at the extension's
root, beside ``blender_manikin``) and the wheels the extension ships (scipy, matplotlib), which Blender installs into
``<user extensions>/.local/lib/python3.11/site-packages`` and puts on its own ``sys.path`` only. So the child gets a
PYTHONPATH of exactly those folders, plus wherever this process finds scipy, matplotlib and numpy (the same copies
Blender loads); the user's own site-packages stay out, as in Blender. In a real Blender ``sys.executable`` is its
bundled Python (``<version>/python/bin/python3.11``).

Cancelling asks the child to stop as Ctrl-C does (SIGINT: the solver's commands keep what they finished and exit
130); :func:`kill` ends its whole process group (the child and its worker processes) when it does not stop.
"""

from __future__ import annotations

import importlib.util
import os
import signal
import site
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]  # the extension root: solver/, blender_manikin/, presets/


def wheel_folder() -> Path | None:
    """Where Blender installs the wheels of extensions (as Blender's addon_utils names it), if it exists."""
    import bpy

    version = f"python{sys.version_info.major}.{sys.version_info.minor}"
    path = Path(bpy.utils.user_resource("EXTENSIONS"), ".local", "lib", version, "site-packages")
    return path if path.is_dir() else None


def module_home(name: str) -> Path | None:
    """The folder holding the top-level module ``name`` as this process would import it (not importing it)."""
    spec = importlib.util.find_spec(name)
    if spec is None or not spec.origin or spec.origin in ("built-in", "frozen"):
        return None
    origin = Path(spec.origin)
    return origin.parent.parent if spec.submodule_search_locations else origin.parent


def python_path(root: Path = ROOT) -> list[str]:
    """The child's PYTHONPATH: the extension root, Blender's wheel folder, and the homes of scipy, matplotlib, numpy."""
    found = [root, wheel_folder(), *(module_home(name) for name in ("scipy", "matplotlib", "numpy"))]
    return list(dict.fromkeys(str(p) for p in found if p is not None))


def child_env(root: Path = ROOT) -> dict[str, str]:
    """The subprocess's environment: this one, its PYTHONPATH replaced by :func:`python_path`, no user
    site-packages where this process has none (Blender's default)."""
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(python_path(root)))
    if not site.ENABLE_USER_SITE:
        env["PYTHONNOUSERSITE"] = "1"
    return env


def solver_command(*args: str) -> list[str]:
    """``python -m solver ARGS`` with the Python that runs Blender."""
    return [sys.executable, "-m", "solver", *args]


def start(command: list[str], cwd: Path, log: Path) -> subprocess.Popen:
    """Start ``command`` in ``cwd`` with :func:`child_env`, its standard error into ``log``, in a session of its
    own (so :func:`kill` reaches its workers)."""
    with open(log, "wb") as out:  # the child keeps its own handle
        return subprocess.Popen(
            command, cwd=str(cwd), env=child_env(), stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=out,
            start_new_session=os.name == "posix",
        )  # fmt: skip


def interrupt(process: subprocess.Popen) -> None:
    """Ask ``process`` to stop as Ctrl-C does."""
    if os.name == "posix":
        process.send_signal(signal.SIGINT)
    else:
        process.terminate()


def kill(process: subprocess.Popen) -> None:
    """End ``process`` and its process group (its workers)."""
    try:
        if os.name == "posix":
            os.killpg(process.pid, signal.SIGKILL)
        else:
            process.kill()
    except OSError:
        pass  # already gone


def last_line(path: Path) -> str:
    """The last non-empty line of a text file ("" if none or unreadable)."""
    try:
        lines = path.read_text(encoding="utf-8", errors="replace").splitlines()
    except OSError:
        return ""
    return next((line.strip() for line in reversed(lines) if line.strip()), "")
