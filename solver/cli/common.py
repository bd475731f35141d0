"""What the commands share: their exit codes, and the checks of their outputs and counts made before any work
(each problem one UsageError line, which :func:`solver.cli.main.main` prints and exits 2 on)."""

from __future__ import annotations

import gc
from types import TracebackType

from ..errors import UsageError
from ..io.output_paths import check_distinct, check_output

EXIT_OK, EXIT_BAD_INPUT, EXIT_NOT_CONVERGED, EXIT_INTERRUPTED = 0, 2, 3, 130
EXIT_BROKEN_PIPE = 141  # 128 + SIGPIPE, what a shell reports for a writer whose reader left
EXIT_TERMINATED = 143  # 128 + SIGTERM: stopped by SIGTERM (kept what was done, as on Ctrl-C)


def check_file_output(output: str | None, source: str | None) -> None:
    """``-o FILE`` of a command that writes one file (``-``: standard output; None: not given): writable, and not
    the input file ``source`` (None: none)."""
    if output is None:
        return
    check_output(output, "-o", stdout=True)
    check_distinct([("-o", output)], [("", source)])


def check_folder_name(output: str) -> None:
    """``-o DIR`` of a command that fills a folder: a name, not blank."""
    if not str(output).strip():
        raise UsageError("-o: expected a folder name, got ''")


def check_count(value: int | None, flag: str) -> None:
    """A count option such as ``--workers``: None (its default) or a whole number >= 1."""
    if value is not None and value < 1:
        raise UsageError(f"{flag}: expected a whole number >= 1, got {value}")


class StartupWithoutGC:
    """A command's start-up without Python's cyclic garbage collector: the imports, Numba's registries and the loaded
    kernels make ~10^5 objects that live as long as the process, and the collector walks them again and again as they
    pile up, and all at exit, finding next to no garbage (0.1-0.2 s of a 0.8 s solve). :meth:`over` (at the latest on
    leaving the block) puts them out of every later collection, exit's included (``gc.freeze``), and turns the
    collector back on."""

    def __enter__(self) -> StartupWithoutGC:
        from .. import kernels

        self._was_enabled = gc.isenabled()
        self._compile_s = kernels.compile_seconds()
        self._over = False
        gc.disable()
        return self

    def over(self) -> None:
        """The start-up is done: freeze what it made, collector on again (as it was before the block)."""
        if self._over:
            return
        self._over = True
        from .. import kernels

        if kernels.compile_seconds() > self._compile_s:  # compiling leaves much garbage: free it, do not freeze it
            gc.collect()
        gc.freeze()
        if self._was_enabled:
            gc.enable()

    def __exit__(
        self, kind: type[BaseException] | None, error: BaseException | None, traceback: TracebackType | None
    ) -> None:
        self.over()
