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
import re
import signal
import site
import subprocess
import sys
import time
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
    site-packages where this process has none (Blender's default). Its compiled kernels go to a cache folder of
    their own: it imports the solver as ``solver`` (:data:`solver.kernels.PACKAGE`)."""
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


class CommandJob:
    """A ``python -m solver ...`` command under way, watched without waiting on it (a reach envelope, a generated
    motion): ``state`` running, cancelling, done, cancelled or failed; ``done`` of ``total`` from the command's
    progress lines (:attr:`PROGRESS` in ``log``); ``error`` its one line when it failed. Cancel asks it to stop as
    Ctrl-C does and kills it after :attr:`GRACE_S`. A subclass names its command's words (:attr:`WORDS`) and says
    when an exit is a finished run (:meth:`ended_well`)."""

    GRACE_S = 5.0  # s a cancelled command has to stop by itself before it is killed
    PROGRESS = re.compile(r"(\d+)/(\d+)")  # a subclass's: solver.progress.progress_line with its own word
    # the status line's words: the command's name, running verb, unit, what a cancel leaves, the failure's label
    WORDS = dict(command="solver", verb="Running", unit="steps", cancelled="nothing kept", failed="Run")

    def begin(self, command: list[str], cwd: Path, log: Path, total: int) -> None:
        """Start ``command`` in ``cwd``, its standard error into ``log``, ``total`` progress steps expected."""
        self.log, self.total = log, total
        self.state, self.error, self.done = "running", "", 0
        self._cancelled_at: float | None = None
        self.started = time.monotonic()
        self.process = start(command, cwd, log)

    def ended_well(self, code: int) -> bool:
        """Whether exit ``code`` left a finished run."""
        return code == 0

    def failure(self, code: int) -> str:
        """The one line a failed run ends with: the command's own error line, or its exit code."""
        return last_line(self.log).removeprefix("error: ") or f"the {self.WORDS['command']} command exited with {code}"

    def poll(self) -> bool:
        """Read the progress so far and see whether the command ended; True while it runs."""
        self._read_progress()
        code = self.process.poll()
        if code is None:
            if self._cancelled_at is not None and time.monotonic() - self._cancelled_at > self.GRACE_S:
                kill(self.process)
            return True
        if self._cancelled_at is not None:
            self.state = "cancelled"
        elif self.ended_well(code):
            self.state, self.done = "done", self.total
        else:
            self.state, self.error = "failed", self.failure(code)
        return False

    def cancel(self) -> None:
        """Ask the command to stop; :meth:`poll` says when it has."""
        if self.process.poll() is not None or self._cancelled_at is not None:
            return
        self._cancelled_at = time.monotonic()
        self.state = "cancelling"
        interrupt(self.process)

    def _read_progress(self) -> None:
        """The count of the command's last progress line."""
        try:
            text = self.log.read_text(encoding="utf-8", errors="replace")
        except OSError:
            return
        found = self.PROGRESS.findall(text)
        if found:
            self.done = int(found[-1][0])

    def line(self) -> str:
        """The status line the panel shows while it runs, or how it ended."""
        words, seconds = self.WORDS, time.monotonic() - self.started
        if self.state in ("running", "cancelling"):
            what = "Stopping" if self.state == "cancelling" else words["verb"]
            return f"{what}: {self.done} of {self.total} {words['unit']}, {seconds:.0f} s"
        if self.state == "failed":
            return f"{words['failed']} failed: {self.error}"
        if self.state == "cancelled":
            return f"Cancelled after {seconds:.0f} s: {words['cancelled']}"
        return f"Done: {self.total} {words['unit']} in {seconds:.0f} s"
