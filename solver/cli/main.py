"""Command line: ``python -m solver COMMAND ...`` (the ``manikin`` script): ``solve SCENARIO.toml [-o RESULT.json]``,
``ergo RESULT.json -o ERGO.json``, ``study STUDY.toml -o OUT/``, ``urdf PRESET -o OUT.urdf``, ``presets``,
``family ... -o DIR``, ``envelope [MANIKIN ...] -o DIR``, ``kernels [--compile]``.

Each command is a module of this package named as the command, with ``add_parser(sub)``, which adds its subparser
and sets ``run``, and its ``run(args) -> exit code``. Adding a command is its module and one entry in
:data:`COMMAND_MODULES`. A command module imports its numerics inside ``run``, so that ``--help`` loads neither
numpy nor scipy.

Exit codes (:mod:`.common`): 0 every frame converged, 3 some frame did not (the JSON is still written), 2 bad input
(one line on stderr naming the file, the key and what was expected), 130 interrupted (Ctrl-C; the frames solved so
far are kept in the result file, which says where the run stopped), 143 stopped by SIGTERM (``timeout``, ``kill``,
CI: handled as Ctrl-C, the same is kept), 141 the reader of the output left (``| head``).
"""

from __future__ import annotations

import argparse
import os
import sys

from ..errors import ArgumentParser, ManikinError
from ..io.interrupts import sigterm_as_interrupt, stopped_by
from . import envelope, ergo, family, job, kernels, operate, presets, solve, study, urdf, validate
from .common import EXIT_BAD_INPUT, EXIT_BROKEN_PIPE, EXIT_INTERRUPTED, EXIT_TERMINATED

# in the order --help lists them
COMMAND_MODULES = (solve, operate, ergo, job, study, urdf, presets, family, envelope, validate, kernels)
COMMANDS = tuple(module.__name__.rpartition(".")[2] for module in COMMAND_MODULES)  # the command names


def build_parser() -> argparse.ArgumentParser:
    """The command line's parser; a bad argument raises one UsageError line instead of printing the usage."""
    parser = ArgumentParser(prog="python -m solver", description="Manikin pose prediction solver")
    sub = parser.add_subparsers(dest="command", required=True)
    for module in COMMAND_MODULES:
        module.add_parser(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Run one command; its exit code (bad input: one line on stderr starting ``error:``, exit 2)."""
    try:
        with sigterm_as_interrupt():  # SIGTERM takes Ctrl-C's path while the command runs (its handler back after)
            args = build_parser().parse_args(argv)
            code = args.run(args)
        return EXIT_TERMINATED if code == EXIT_INTERRUPTED and stopped_by() == "SIGTERM" else code
    except ManikinError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except BrokenPipeError:  # the reader of our output stopped (``| head``): quiet, as other tools are
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())  # so Python's own flush at exit is quiet too
        return EXIT_BROKEN_PIPE
    except OSError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except KeyboardInterrupt:
        if stopped_by() == "SIGTERM":
            print("terminated (SIGTERM)", file=sys.stderr)
            return EXIT_TERMINATED
        print("interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED


if __name__ == "__main__":
    sys.exit(main())
