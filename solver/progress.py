"""Progress of a long run on standard error: done / total, rate and time left, on one line that updates itself in
a terminal (at most five times a second) and as a plain line every few seconds in a log (never one per frame)."""

from __future__ import annotations

import sys
import time
from collections.abc import Callable
from typing import TextIO

TERMINAL_EVERY_S = 0.2
LOG_EVERY_S = 5.0


def clock(seconds: float | None) -> str:
    """A duration as m:ss or h:mm:ss ("?" when unknown)."""
    if seconds is None or seconds != seconds or seconds == float("inf"):
        return "?"
    s = int(round(seconds))
    return f"{s // 3600}:{s // 60 % 60:02d}:{s % 60:02d}" if s >= 3600 else f"{s // 60}:{s % 60:02d}"


def progress_line(done: int, total: int, elapsed_s: float, failed: int = 0, what: str = "frames") -> str:
    """``frames 120/10000 (1 %), 410 frames/s, 0:24 left[, 3 not converged]``: the rate is the mean since the start."""
    rate = done / elapsed_s if elapsed_s > 0 else 0.0
    left = (total - done) / rate if rate > 0 else None
    percent = 100 * done / total if total else 100
    line = f"{what} {done}/{total} ({percent:.0f} %), {rate:.0f} {what}/s, {clock(left)} left"
    return line + (f", {failed} not converged" if failed else "")


class Progress:
    """Shows :func:`progress_line` on ``stream`` (default standard error) as work gets done; silent when disabled."""

    def __init__(
        self,
        total: int,
        enabled: bool = True,
        stream: TextIO | None = None,
        what: str = "frames",
        now: Callable[[], float] = time.perf_counter,
    ) -> None:
        self.total, self.enabled, self.what, self.now = total, enabled, what, now
        self.stream = sys.stderr if stream is None else stream
        isatty = getattr(self.stream, "isatty", None)
        self.terminal = bool(isatty and isatty())
        self.every = TERMINAL_EVERY_S if self.terminal else LOG_EVERY_S
        self.start = self.shown_at = now()
        self.width = 0  # of the line on screen (terminal)

    def update(self, done: int, failed: int = 0) -> None:
        """Record ``done`` items (``failed`` of them not converged); shows a line when it is time to."""
        t = self.now()
        if not self.enabled or t - self.shown_at < self.every:
            return
        self.shown_at = t
        line = progress_line(done, self.total, t - self.start, failed, self.what)
        if self.terminal:
            self.stream.write("\r" + line.ljust(self.width))
            self.width = len(line)
        else:
            self.stream.write(line + "\n")
        self.stream.flush()

    def clear(self) -> None:
        """Remove the line from the terminal (before other output)."""
        if self.enabled and self.terminal and self.width:
            self.stream.write("\r" + " " * self.width + "\r")
            self.stream.flush()
            self.width = 0

    def elapsed(self) -> float:
        return self.now() - self.start
