"""Manikin pose prediction: a balanced, comfort-maximising unified IK solver in NumPy/SciPy (no bpy).

The public API (every name loads its module on first use, PEP 562, so ``import solver``, ``solver.errors``,
``solver.options`` and ``solver.presets`` cost nothing: the Blender add-on enables without NumPy or SciPy)::

    model = solver.load_preset("male_50")            # or a body TOML path -> Model
    scenario = solver.load_scenario("scene.toml")    # -> Scenario (model, problem, options, start, frames, limits)
    solved = list(solver.solve_motion(scenario))     # [(frame, Result), ...]: what python -m solver solve does
    result = solver.solve(scenario.problem_at(frame), scenario.start, scenario.options)  # one pose -> Result
    motion = solver.load_motion("lift.toml")         # a Scenario that has keyed targets or a frame range
    report = solver.evaluate(result)                 # ergonomics: loads, RULA, REBA, OWAS, NIOSH, worksheet
    solver.write_result("result.json", solved, scenario.path)   # the result file (docs/reference/result-file.md)
    frames = solver.read_result("result.json")       # -> ResultFile: its typed frames; solver.evaluate takes it
    text = solver.dumps_scenario(solver.scenario_to_dict(problem, {"preset": "male_50"}))  # scenario TOML

Building blocks: ``Model``/``ModelBuilder``, ``Problem(model, ProblemSpec(targets=[Target(...)], ...))`` with
``Target``, ``Loop``, ``ExternalLoad``, ``ComfortWeights``, ``SolverOptions``, ``Frame`` (a solved pose as world
arrays: ``frame_of_result``), ``ErgoOptions``. Every user error is a ``ManikinError``: ``ModelError``,
``ScenarioError``, ``ResultFileError``, ``UsageError`` (:mod:`solver.errors`), with a one-line message naming the
file, the key and what was expected.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from .lazy import lazy_attributes

_HOMES = {
    "ComfortWeights": "comfort",
    "ErgoOptions": "ergonomics",
    "ExternalLoad": "problem.problem",
    "Frame": "io.result.frame",
    "Loop": "problem.problem",
    "ManikinError": "errors",
    "Model": "body.model",
    "ModelBuilder": "body.builder",
    "ModelError": "errors",
    "Problem": "problem.problem",
    "ProblemSpec": "problem.specs",
    "Result": "iteration.result",
    "ResultFile": "io.result.read",
    "ResultFileError": "errors",
    "Scenario": "problem.scenario",
    "ScenarioError": "errors",
    "SolverOptions": "options",
    "Target": "problem.problem",
    "UsageError": "errors",
    "dumps_scenario": "io.scenario.write",
    "evaluate": "ergonomics",
    "frame_of_result": "io.result.frame",
    "load_motion": "io.scenario.read",
    "load_preset": "io.scenario.bodies",
    "load_scenario": "io.scenario.read",
    "read_result": "io.result.read",
    "result_to_dict": "io.result.document",
    "scenario_to_dict": "io.scenario.write",
    "solve": "iteration",
    "solve_motion": "motion.frames",
    "write_result": "io.result.write",
    "write_scenario": "io.scenario.write",
}
__all__ = [
    "ComfortWeights",
    "ErgoOptions",
    "ExternalLoad",
    "Frame",
    "Loop",
    "ManikinError",
    "Model",
    "ModelBuilder",
    "ModelError",
    "Problem",
    "ProblemSpec",
    "Result",
    "ResultFile",
    "ResultFileError",
    "Scenario",
    "ScenarioError",
    "SolverOptions",
    "Target",
    "UsageError",
    "dumps_scenario",
    "evaluate",
    "frame_of_result",
    "load_motion",
    "load_preset",
    "load_scenario",
    "read_result",
    "result_to_dict",
    "scenario_to_dict",
    "solve",
    "solve_motion",
    "write_result",
    "write_scenario",
]

if TYPE_CHECKING:
    from .body.builder import ModelBuilder
    from .body.model import Model
    from .comfort import ComfortWeights
    from .ergonomics import ErgoOptions, evaluate
    from .errors import ManikinError, ModelError, ResultFileError, ScenarioError, UsageError
    from .io.result.document import result_to_dict
    from .io.result.frame import Frame, frame_of_result
    from .io.result.read import ResultFile, read_result
    from .io.result.write import write_result
    from .io.scenario.bodies import load_preset
    from .io.scenario.read import load_motion, load_scenario
    from .io.scenario.write import dumps_scenario, scenario_to_dict, write_scenario
    from .iteration import solve
    from .iteration.result import Result
    from .motion.frames import solve_motion
    from .options import SolverOptions
    from .problem.problem import ExternalLoad, Loop, Problem, Target
    from .problem.scenario import Scenario
    from .problem.specs import ProblemSpec


__getattr__ = lazy_attributes(__name__, _HOMES, globals())
