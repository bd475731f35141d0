"""What the commands share: their exit codes, and the checks of their outputs and counts made before any work
(each problem one UsageError line, which :func:`solver.cli.main.main` prints and exits 2 on)."""

from __future__ import annotations

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
