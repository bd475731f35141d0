"""The hidden temporary files an output is written into beside it, and the removal of those a killed run left.

An output is written to ``.manikin-PID@HOST-XXXXXXXX.tmp`` in its folder and renamed onto its name when done
(:mod:`.files`). A run killed outright (SIGKILL, a power cut) cannot remove its temporary file; the next run that
writes into the same folder does: a temporary file of this machine (HOST: a hash of its name) whose writer (PID)
is no longer running is removed at once; one of another machine (a shared folder) or of an older version (no PID
in its name) only when nothing has written to it for :data:`STALE_AFTER` seconds. A live writer's file is never
touched, and nothing but these names is.
"""

from __future__ import annotations

import hashlib
import os
import re
import socket
import tempfile
import time
from contextlib import suppress
from pathlib import Path

PREFIX = ".manikin-"
STALE_AFTER = 24 * 3600.0  # s without a write after which a temporary file of unknown writer is left over
_NAME = re.compile(r"\.manikin-(?:(\d+)@([0-9a-f]{8})-)?[\w-]*\.tmp")
_CLEANED: set[str] = set()  # folders this process has looked at (once each: a study writes many files into one)


def host_tag() -> str:
    """This machine's tag in a temporary file's name: 8 hex digits of a hash of its host name."""
    return hashlib.sha1(socket.gethostname().encode("utf-8", "replace")).hexdigest()[:8]


def make_temporary(folder: Path) -> tuple[int, str]:
    """A new temporary file in ``folder``, after removing the stale ones there: (descriptor, path); mode 0600."""
    remove_stale(folder)
    return tempfile.mkstemp(prefix=f"{PREFIX}{os.getpid()}@{host_tag()}-", suffix=".tmp", dir=folder)


def pid_alive(pid: int) -> bool:
    """Whether a process ``pid`` runs on this machine (when unsure: yes)."""
    if pid <= 0:
        return True
    if os.name == "nt":
        return _windows_pid_alive(pid)
    try:
        os.kill(pid, 0)  # signal 0: no signal, only the check
    except ProcessLookupError:
        return False
    except OSError:  # EPERM: another user's process
        return True
    return True


def _windows_pid_alive(pid: int) -> bool:
    import ctypes

    kernel32 = ctypes.WinDLL("kernel32", use_last_error=True)  # type: ignore[attr-defined]
    handle = kernel32.OpenProcess(0x1000, False, pid)  # PROCESS_QUERY_LIMITED_INFORMATION
    if not handle:
        return ctypes.get_last_error() != 87  # type: ignore[attr-defined]  # ERROR_INVALID_PARAMETER: no such pid
    try:
        code = ctypes.c_ulong()
        return not kernel32.GetExitCodeProcess(handle, ctypes.byref(code)) or code.value == 259  # STILL_ACTIVE
    finally:
        kernel32.CloseHandle(handle)


def is_stale(folder: Path, name: str) -> bool:
    """Whether ``name`` in ``folder`` is a temporary file of ours that its writer left (see the module docstring)."""
    match = _NAME.fullmatch(name)
    if match is None:
        return False
    pid, host = match.groups()
    if pid is not None and host == host_tag():
        return int(pid) != os.getpid() and not pid_alive(int(pid))
    try:
        return time.time() - os.stat(Path(folder) / name).st_mtime > STALE_AFTER
    except OSError:
        return False


def remove_stale(folder: Path) -> list[str]:
    """Remove the stale temporary files in ``folder`` (the first time this process writes there); their names."""
    key = os.path.realpath(folder)
    if key in _CLEANED:
        return []
    _CLEANED.add(key)
    try:
        names = [n for n in os.listdir(folder) if n.startswith(PREFIX) and n.endswith(".tmp")]
    except OSError:
        return []
    removed = []
    for name in names:
        if is_stale(folder, name):
            with suppress(OSError):  # gone meanwhile, or not ours to remove
                os.unlink(Path(folder) / name)
                removed.append(name)
    return removed


def forget_folders() -> None:
    """Look at every folder again on its next write (a test, or a long session that wants it)."""
    _CLEANED.clear()
