"""Manikin pose prediction: a balanced, comfort-maximising unified IK solver in NumPy/SciPy (no bpy)."""

from .comfort import ComfortWeights
from .errors import ManikinError, ModelError, ScenarioError
from .model import Model, ModelBuilder
from .problem import ExternalLoad, Loop, Problem, Target
from .result import Result
from .solve import SolverOptions, solve

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
