"""The solver's exception hierarchy: every user-facing failure is one of these, with a one-line message."""


class ManikinError(Exception):
    """Base class of all errors raised on purpose by the solver package."""


class ModelError(ManikinError):
    """A body description or model is inconsistent (unknown parent, bad axis, bad limits, ...)."""


class ScenarioError(ManikinError):
    """A scenario file or its values are invalid; the message names the file, the key and what was expected."""
