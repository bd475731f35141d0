"""Blender's own console output kept out of a headless run's output (no bpy).

Blender's operators talk on the process's standard output and error: C code writes "Info: Saved copy as ..." and
"Read blend: ..." straight to file descriptors 1 and 2, the glTF exporter logs through a handler that holds the
stream it found at start-up, the FBX exporter prints a debug tuple. None of that is ours to show, so
:func:`quietly` runs an operator with descriptors 1 and 2 pointed at a temporary file (Python's own
``redirect_stdout`` would miss all but plain prints) and, when the call fails, puts the tail of what Blender
said into the one-line error.
"""

from __future__ import annotations

import ctypes
import os
import sys
import tempfile
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import TypeVar

T = TypeVar("T")
TAIL_CHARS = 300  # of Blender's output kept in an error message


def _flush_all() -> None:
    """Flush Python's streams and C's stdio buffers (a pipe is block-buffered: unflushed C output would surface
    after the descriptors are restored)."""
    for stream in (sys.stdout, sys.stderr):
        if stream is not None:
            stream.flush()
    try:
        libc = ctypes.CDLL("ucrtbase" if os.name == "nt" else None)
        libc.fflush(None)
    except (OSError, AttributeError):  # no C runtime to flush: nothing was buffered there by us
        pass


class Captured:
    """What was written to descriptors 1 and 2 inside :func:`captured_output` (``text``, set on exit)."""

    text: str = ""


@contextmanager
def captured_output() -> Iterator[Captured]:
    """Descriptors 1 and 2 go to a temporary file for the block and are restored after it; its text in ``.text``.
    Where the process has no descriptor 1 or 2 (a windowed Blender on Windows) the block runs as it is."""
    captured = Captured()
    _flush_all()
    try:
        saved = [os.dup(1), os.dup(2)]
    except OSError:
        yield captured
        return
    with tempfile.TemporaryFile() as sink:
        try:
            os.dup2(sink.fileno(), 1)
            os.dup2(sink.fileno(), 2)
            yield captured
        finally:
            _flush_all()
            os.dup2(saved[0], 1)
            os.dup2(saved[1], 2)
            for fd in saved:
                os.close(fd)
            sink.seek(0)
            captured.text = sink.read().decode("utf-8", errors="replace")


def tail(text: str, known: str = "") -> str:
    """The last lines of ``text`` that ``known`` (an error message) does not already hold, as one line of at most
    TAIL_CHARS characters."""
    lines = [part.strip() for part in text.splitlines() if part.strip() and part.strip() not in known]
    line = " | ".join(lines)
    return line if len(line) <= TAIL_CHARS else "..." + line[-TAIL_CHARS:]


def quietly(call: Callable[..., T], *args, **kwargs) -> T:
    """``call(*args, **kwargs)`` with its console output captured; what it returns. An error it raises (a
    ManikinError, an operator's RuntimeError) is raised again once the output is restored, its one-line message
    ending in the tail of what Blender said that the message does not already say (unless the error is
    ``complete``: a file that could not be written, where Blender's output would only repeat a traceback)."""
    with captured_output() as out:
        try:
            return call(*args, **kwargs)
        except BaseException as exc:  # raised again below, once the descriptors are back
            failed = exc
    said = tail(out.text, str(failed))
    if said and isinstance(failed, Exception) and not getattr(failed, "complete", False):  # not Ctrl-C, an exit
        if len(failed.args) == 1 and isinstance(failed.args[0], str):
            failed.args = (f"{failed.args[0].strip()} (Blender: {said})",)
        else:  # a message built from several arguments (OSError): shown with its traceback, if any
            failed.add_note(f"Blender: {said}")
    raise failed
