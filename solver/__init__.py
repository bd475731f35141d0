"""Manikin pose prediction: a balanced, comfort-maximising unified IK solver in NumPy/SciPy (no bpy).

The names below load their module on first use (PEP 562), so ``from solver.errors import ManikinError`` or
``solver.options`` costs nothing: the Blender add-on enables without importing the solver or scipy.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING

_HOMES = {
    "ComfortWeights": "comfort",
    "ExternalLoad": "problem",
    "Loop": "problem",
    "ManikinError": "errors",
    "Model": "model",
    "ModelBuilder": "model_builder",
    "ModelError": "errors",
    "Problem": "problem",
    "Result": "result",
    "ScenarioError": "errors",
    "SolverOptions": "options",
    "Target": "problem",
    "solve": "iteration",
}
__all__ = [
    "ComfortWeights",
    "ExternalLoad",
    "Loop",
    "ManikinError",
    "Model",
    "ModelBuilder",
    "ModelError",
    "Problem",
    "Result",
    "ScenarioError",
    "SolverOptions",
    "Target",
    "solve",
]

if TYPE_CHECKING:
    from .comfort import ComfortWeights
    from .errors import ManikinError, ModelError, ScenarioError
    from .iteration import solve
    from .model import Model
    from .model_builder import ModelBuilder
    from .options import SolverOptions
    from .problem import ExternalLoad, Loop, Problem, Target
    from .result import Result


def __getattr__(name: str) -> object:
    if name not in _HOMES:
        raise AttributeError(f"module 'solver' has no attribute {name!r}")
    value = getattr(importlib.import_module(f".{_HOMES[name]}", __name__), name)
    globals()[name] = value
    return value
