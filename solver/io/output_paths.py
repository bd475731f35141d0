"""Output paths checked before any work starts (the CLI and ``blender_manikin/batch.py``), each problem one line.

A path is refused when it is an existing folder, its name is too long, its folder cannot be created or written,
it has the wrong suffix, or it is the same file as another output or an input. A path that exists and is not a
regular file (``/dev/null``, a FIFO) is accepted: :func:`solver.io.files.open_output` writes it in place.
"""

from __future__ import annotations

import os
from collections.abc import Iterable, Sequence
from pathlib import Path

from ..errors import UsageError
from .files import STDOUT, writes_in_place
from .temporaries import make_temporary

NAME_MAX, PATH_MAX = 255, 4096  # bytes, Linux's limits where the file system does not say


def shown(path: str | Path) -> str:
    """``path`` for a message: at most 80 characters (a 300-character name is cut in the middle)."""
    text = str(path)
    return text if len(text) <= 80 else f"{text[:40]}...{text[-30:]} ({len(text)} characters)"


def check_output(path: str | Path, flag: str, suffixes: Sequence[str] = (), stdout: bool = False) -> None:
    """Refuse ``path`` (given with the option ``flag``, e.g. ``"-o"``) unless it can be written; ``suffixes``
    (e.g. ``(".json",)``) are the accepted endings, ``stdout`` whether ``-`` (standard output) is accepted."""
    text = str(path)
    where = f"{flag} {shown(text)}"
    if text == STDOUT:
        if not stdout:
            raise UsageError(f"{where}: cannot write to standard output, expected a file name")
        return
    if not text.strip():
        raise UsageError(f"{flag}: expected a file name, got {text!r}")
    if text.endswith(("/", os.sep)):
        raise UsageError(f"{where}: expected a file name, got a folder")
    path = Path(os.path.abspath(text))
    _check_lengths(path, where)
    if path.is_dir():
        raise UsageError(f"{where}: is a directory, expected a file name")
    if suffixes and path.suffix.lower() not in suffixes:
        raise UsageError(f"{where}: expected a file name ending {' or '.join(suffixes)}")
    if writes_in_place(path):
        return  # a device or FIFO: written where it is, its folder is not touched
    if path.exists() and not os.access(path, os.W_OK):
        raise UsageError(f"{where}: the file is read-only")
    _check_folder(path.parent, where)


def _check_lengths(path: Path, where: str) -> None:
    """Each name at most NAME_MAX bytes, the whole path at most PATH_MAX (the file system's own limits)."""
    folder = _existing_ancestor(path.parent)
    name_max, path_max = _limit(folder, "PC_NAME_MAX", NAME_MAX), _limit(folder, "PC_PATH_MAX", PATH_MAX)
    for part in path.parts:
        size = len(os.fsencode(part))
        if size > name_max:
            raise UsageError(f"{where}: file name too long ({size} bytes, at most {name_max})")
    if len(os.fsencode(str(path))) >= path_max:
        raise UsageError(f"{where}: path too long (at most {path_max - 1} bytes)")


def _limit(folder: Path, name: str, default: int) -> int:
    """The file system's limit ``name`` at ``folder`` (os.pathconf), else ``default`` (Windows has no pathconf)."""
    try:
        return int(os.pathconf(folder, name))
    except (AttributeError, OSError, ValueError, TypeError):
        return default


def _existing_ancestor(folder: Path) -> Path:
    while not os.path.lexists(folder) and folder != folder.parent:
        folder = folder.parent
    return folder


def _check_folder(folder: Path, where: str) -> None:
    """The nearest existing folder of the output is a folder, writable (the missing ones are created there)."""
    existing = _existing_ancestor(folder)
    if not existing.is_dir():
        raise UsageError(f"{where}: {shown(existing)} is not a directory")
    try:  # a file made and removed there: the one test that holds for root, read-only mounts and /proc alike
        fd, probe = make_temporary(existing)
        os.close(fd)
        os.unlink(probe)
    except OSError as exc:
        raise UsageError(f"{where}: cannot write in {shown(existing)} ({exc.strerror or exc})") from None


def _identity(path: str | Path) -> tuple:
    """What two paths share when they are the same file: device and inode if it exists, else the real path."""
    try:
        st = os.stat(path)
        return ("file", st.st_dev, st.st_ino)
    except OSError:
        return ("path", os.path.realpath(path))


def check_distinct(outputs: Iterable[tuple[str, str | Path]], inputs: Iterable[tuple[str, str | Path]] = ()) -> None:
    """Refuse two outputs that are one file, and an output that is one of the inputs (``(flag, path)`` pairs;
    standard output and ``/dev/null`` may repeat)."""
    seen: dict[tuple, str] = {}
    for flag, path in inputs:
        if path is not None and str(path) != STDOUT:
            seen.setdefault(_identity(path), " ".join(filter(None, ("the input", flag, shown(path)))))
    for flag, path in outputs:
        if path is None or str(path) in (STDOUT, os.devnull):
            continue
        key = _identity(path)
        if key in seen:
            raise UsageError(f"{flag} {shown(path)}: the same file as {seen[key]}; choose another name")
        seen[key] = f"{flag} {shown(path)}"
