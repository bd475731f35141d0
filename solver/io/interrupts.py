"""Ctrl-C and SIGTERM: the two ways to stop a run that keep what it did.

Ctrl-C raises KeyboardInterrupt (Python's own handler); the commands catch it, keep the frames or rows done and
say where they stopped. While a command line runs (:func:`sigterm_as_interrupt`, entered by
:func:`solver.cli.main.main` only), SIGTERM (what ``timeout``, ``kill`` and CI send) takes the same path. Inside
:func:`interrupts_held` (a frame being written) either one waits for the block to end, so a frame is in the file
whole or not at all.
"""

from __future__ import annotations

import _signal  # the C functions behind signal.signal and getsignal, without their enum conversions (~2 us a call)
import signal
import threading
from collections.abc import Iterator
from contextlib import contextmanager


class _Held:
    """Ctrl-C held by :func:`interrupts_held`: how deep the blocks are nested and whether one came meanwhile."""

    depth = 0
    pending = False


class _Stop:
    """What stopped the command line: None (nothing yet, or Ctrl-C) or "SIGTERM"."""

    by: str | None = None


def _hold(signum: int, frame: object) -> None:
    _Held.pending = True


def terminate(signum: int, frame: object) -> None:
    """SIGTERM's handler while a command line runs: Ctrl-C's KeyboardInterrupt (held inside
    :func:`interrupts_held`)."""
    _Stop.by = "SIGTERM"
    if _Held.depth:
        _Held.pending = True
        return
    raise KeyboardInterrupt


_MAIN = threading.main_thread()  # the only thread Python runs handlers in


def _main_thread() -> bool:
    return threading.current_thread() is _MAIN


@contextmanager
def sigterm_as_interrupt() -> Iterator[None]:
    """SIGTERM handled as Ctrl-C inside the block; the handler before it is back after (in the main thread only:
    elsewhere, and for an embedding application such as Blender, nothing changes)."""
    if not _main_thread() or not hasattr(signal, "SIGTERM"):
        yield
        return
    previous = signal.signal(signal.SIGTERM, terminate)
    _Stop.by = None
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous)


def stopped_by() -> str:
    """What interrupted the command line: "SIGTERM" or "Ctrl-C"."""
    return _Stop.by or "Ctrl-C"


def ignore_stops() -> None:
    """While what was done is being kept: a second Ctrl-C or SIGTERM waits for it (SIGKILL does not)."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    if _main_thread() and signal.getsignal(signal.SIGTERM) is terminate:
        signal.signal(signal.SIGTERM, signal.SIG_IGN)


class interrupts_held:  # noqa: N801 (used as the function it was: ``with interrupts_held():``)
    """Ctrl-C (SIGINT) or a SIGTERM handled as one arriving inside the block raises KeyboardInterrupt when the
    block ends, not inside it.

    A Python-level handler, not a signal mask: in a process with other threads (Blender's) the kernel hands the
    signal to a thread that does not block it, and Python would still raise inside the block. Only Python's own
    Ctrl-C handler is replaced (in the main thread); with any other (ignored, an application's) Ctrl-C is left as
    it is, and without :func:`terminate` for SIGTERM the block runs as it is. A class, not a generator: it is
    entered once a frame written (~1 us saved a frame)."""

    __slots__ = ("outer", "own_int", "active")

    def __enter__(self) -> None:
        self.outer = outer = _Held.depth == 0
        main = outer and threading.current_thread() is _MAIN
        self.own_int = main and _signal.getsignal(signal.SIGINT) is signal.default_int_handler
        self.active = not outer or self.own_int or (main and _signal.getsignal(signal.SIGTERM) is terminate)
        if not self.active:
            return
        if self.own_int:
            _signal.signal(signal.SIGINT, _hold)
        _Held.depth += 1

    def __exit__(self, kind: type[BaseException] | None, exc: BaseException | None, tb: object) -> None:
        if not self.active:
            return
        _Held.depth -= 1
        if self.own_int:
            _signal.signal(signal.SIGINT, signal.default_int_handler)
        if self.outer:
            pending, _Held.pending = _Held.pending, False
            if pending and kind is None:  # (an exception from the block goes on instead)
                raise KeyboardInterrupt
