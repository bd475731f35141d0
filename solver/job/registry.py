"""Every job method by name: one module per method (a :class:`.base.Method`), one ``register`` line here. The order
of the lines is the order of the report's sections and verdicts."""

from __future__ import annotations

from .base import Method
from .capable import PercentCapable
from .eaws import Eaws
from .lifft import Lifft
from .sequence import Sequence
from .shoulder_tool import ShoulderTool

METHODS: dict[str, Method] = {}


def register(method: Method) -> Method:
    """Add ``method`` to the job report; a name taken is a ValueError."""
    if method.name in METHODS:
        raise ValueError(f"job method name {method.name!r} is taken")
    METHODS[method.name] = method
    return method


register(Lifft())
register(Sequence())
register(ShoulderTool())
register(PercentCapable())
register(Eaws())
