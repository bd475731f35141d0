"""The solver's exception hierarchy: every user-facing failure is one of these, with a one-line message."""

from pathlib import Path


class ManikinError(Exception):
    """Base class of all errors raised on purpose by the solver package."""


class ModelError(ManikinError):
    """A body description or model is inconsistent (unknown parent, bad axis, bad limits, ...)."""


class ScenarioError(ManikinError):
    """A scenario file or its values are invalid; the message names the file, the key and what was expected."""


def read_text(path: Path, error: type[ManikinError] = ManikinError) -> str:
    """A text file's content; a missing or unreadable file raises ``error`` with one line naming it."""
    try:
        return path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise error(f"{path}: file not found") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise error(f"{path}: cannot read ({exc})") from None
