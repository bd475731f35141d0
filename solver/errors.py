"""The solver's exception hierarchy: every user-facing failure is one of these, with a one-line message.

::

    ManikinError            anything the user can fix; the CLI prints it as one line and exits 2
    ├── ModelError          a body description or model is inconsistent
    ├── ScenarioError       a scenario file (TOML) or its values
    ├── ResultFileError     a result file (JSON) that cannot be read or evaluated
    └── UsageError          a command's or job's arguments and options (``blender_manikin.batch.BadInput``)

Readers name the file, the key and what was expected: ``scene.toml: targets[0].position: expected 3 finite
numbers, got [1, 2]``. :class:`ArgumentParser` is the command lines' parser (``python -m solver`` and
``blender_manikin/batch.py``): a bad argument is one UsageError line, not argparse's usage text. This module
imports nothing heavy (the Blender add-on loads it when it enables; ``batch.py`` loads it by its path).
"""

import argparse
import math


class ManikinError(Exception):
    """Base class of all errors raised on purpose by the solver package."""


class ModelError(ManikinError):
    """A body description or model is inconsistent (unknown parent, bad axis, bad limits, ...)."""


class ScenarioError(ManikinError):
    """A scenario file or its values are invalid; the message names the file, the key and what was expected."""


class ResultFileError(ManikinError):
    """A result file cannot be read or evaluated; the message names the file, the key and what was expected."""


class UsageError(ManikinError):
    """A command or job was given invalid arguments or options (a bad flag, a wrong file suffix, ...)."""


class ArgumentParser(argparse.ArgumentParser):
    """argparse's parser, except that a bad argument raises one UsageError line (``... (see PROG --help)``)
    instead of printing the usage and exiting; subcommands' parsers are of this class too."""

    def error(self, message: str) -> None:
        raise UsageError(f"{' '.join(message.split())} (see {self.prog} --help)")


SHOWN = 120  # characters of a value an error line shows


def shown(value: object, width: int = SHOWN) -> str:
    """``repr(value)``, cut to ``width`` characters with "..." (an error line names the value, not a whole mesh)."""
    text = repr(value)
    return text if len(text) <= width else text[: width - 3] + "..."


def is_number(value: object) -> bool:
    """A finite int or float, not a bool: what every reader takes as a number. An int too large for a float (a
    400-digit ``position`` in a TOML file) is not one: ``math.isfinite`` would raise OverflowError on it."""
    if isinstance(value, bool) or not isinstance(value, int | float):
        return False
    try:
        return math.isfinite(value)
    except OverflowError:  # an int beyond +-1.8e308
        return False
