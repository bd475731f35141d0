"""A study row's job columns (issue 38): a ``[[scenarios]]`` entry with ``job = "JOB.toml"`` rates each run's solved
motion as that job (its ``[work]`` and ``[load]``; the job file's own ``[motion]`` is not used: the run's motion is
the study's scenario, solved on the run's manikin) with every method of :mod:`solver.job.registry`, as ``manikin
job`` does, so a family study answers "which share of our workforce can do this job".

Per registered method: ``job_<method>_level`` (its verdict's severity: 0 green, 1 yellow, 2 red, empty not rated),
then its headline numbers ``job_<method>_<key>`` (:data:`HEADLINE`, or a method's own ``study_keys``): the LiFFT
probability of a high-risk job (0-1), cumulative damage and peak load moment (N*m); The Shoulder Tool's probability
of a clinic visit (0-1) and cumulative damage; the worst RULA action level, REBA risk and OWAS action category over
the motion; % capable's minimum share of men and of women (%). A method registered later gets its level column
without a line here.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ..job.registry import METHODS

if TYPE_CHECKING:
    from ..body.model import Model
    from ..job.spec import Job

GROUP = "job"
HEADLINE: dict[str, tuple[str, ...]] = {  # method -> keys of its result (a dotted key: inside a table)
    "lifft": ("probability_high_risk", "cumulative_damage", "peak_load_moment_Nm"),
    "shoulder_tool": ("probability_clinic_visit", "cumulative_damage"),
    "sequence": ("rula.worst", "reba.worst", "owas.worst"),
    "capable": ("minimum_men_pct", "minimum_women_pct"),
}


def keys_of(name: str) -> tuple[str, ...]:
    """The headline keys of the registered method ``name``."""
    return tuple(getattr(METHODS[name], "study_keys", ()) or HEADLINE.get(name, ()))


def _column(name: str, key: str) -> str:
    return f"job_{name}_{key.replace('.', '_')}"


def job_columns() -> list[str]:
    """The job group's columns, in the registry's order."""
    return [c for name in METHODS for c in (f"job_{name}_level", *(_column(name, k) for k in keys_of(name)))]


def _value(result: dict, key: str):
    for part in key.split("."):
        result = result.get(part) if isinstance(result, dict) else None
    return result if isinstance(result, int | float | str) or result is None else None


def job_row(job: Job, solved: list, model: Model | None) -> dict:
    """The job columns of a run's solved motion (``solved``: (frame, Result) pairs) rated as ``job`` on ``model``
    (None: the scenario's own). A motion longer than the job's cycle is one UsageError line."""
    from ..io.result.frame import frame_of_result
    from ..io.result.read import ResultFile
    from ..job.run import evaluate_job

    frames = [frame_of_result(result, number) for number, result in solved]
    model = model if model is not None else solved[0][1].problem.model
    report = evaluate_job(job, ResultFile(None, None, frames), model)
    row: dict = {}
    for name, result in report["methods"].items():
        row[f"job_{name}_level"] = result["verdict"]["severity"]
        row |= {_column(name, k): _value(result, k) for k in keys_of(name)}
    return row
