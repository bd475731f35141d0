"""One run of a study, in whatever process it lands in: build the scenario, solve it (every frame of a motion),
evaluate its ergonomics and return its row. A run that cannot be done is a row with its reason, never an exception.

A row's columns (docs/tutorials/study.md); units m, N, kg, s; peaks are the largest over a motion's frames::

    run_id, seed, scenario, manikin, p_<parameter> ...    what was run
    role, sex, stature_m, mass_kg, <measurement>_m ...   a family member's facts (a family folder with an index)
    status, converged, held, frames, frames_converged    "converged" / "not converged" / "failed" (converged false,
                                                         the rest empty); held: supports, loops and balance
                                                         (priority 1) held in every frame
    unmet, shortfall_m                                   unmet targets (space-separated), their summed position
                                                         shortfall (m), at its worst frame
    rula_peak, reba_peak                                 each registered score's study columns (:mod:`.groups`)
    l4_l5_peak_N, strength_peak_pct, strength_joint      the peak L4/L5 compression, percent of strength, its joint
    niosh_li, niosh_rwl_kg                               a motion score's: only when the hands carry a load, else empty;
                                                         LI inf where the RWL is 0 (outside the equation's limits)
    job_lifft_level, job_lifft_probability_high_risk ... a scenario with a ``job``: each job method's level and
                                                         headline numbers (:mod:`.job_columns`)
    balanced_mean_m, ..., mesh                           an [envelope] run's columns (:mod:`.envelope_runs`)
    solve_s, eval_s, run_s, failure                      times (s, not reproducible: solving, the ergonomics, the
                                                         whole run with building the scenario), why a run failed
"""

from __future__ import annotations

import math
import time
from typing import TYPE_CHECKING, Any

import numpy as np

from ..ergonomics.base import peak
from ..ergonomics.registry import SCORES
from .envelope_runs import ENVELOPE_COLUMNS, envelope_row
from .groups import LOADS, ergonomic, groups
from .job_columns import GROUP as JOB
from .job_columns import job_row
from .plan import Run

if TYPE_CHECKING:
    from ..body.model import Model
    from ..problem.scenario import Scenario
    from .spec import Manikin

OUTCOME = ["status", "converged", "held", "frames", "frames_converged"]
TIMING = ["solve_s", "eval_s", "run_s"]  # the columns that differ between two runs of the same inputs
MODEL_CACHE = 8  # bodies a worker keeps built (the runs of a chunk mostly share one: see plan.py)
MODELS: dict[str, Model] = {}  # body key -> Model, oldest first


def columns(
    parameters: list[str],
    record: tuple[str, ...],
    members: list[str] | None = None,
    scenarios: bool = True,
    envelope: bool = False,
) -> list[str]:
    """The row's columns for a study with these parameter names that records these groups (``members``: the
    family members' fact columns, :func:`.spec.member_columns`), with ``scenarios`` and (or) an ``envelope``."""
    out = ["run_id", "seed", "scenario", "manikin", *(members or [])] + [f"p_{name}" for name in parameters]
    out += OUTCOME if scenarios else OUTCOME[:2]
    columns_of = groups()
    for group in record if scenarios else ():
        out += columns_of[group]
    out += ENVELOPE_COLUMNS if envelope else []
    return out + TIMING + ["failure"]


def run_chunk(runs: list[Run]) -> list[dict]:
    """The rows of ``runs``, in order (one task of a process pool or a Dask cluster)."""
    return [run_one(run) for run in runs]


def head(run: Run) -> dict[str, Any]:
    """What a row says of its run: ids, scenario, manikin (and its family facts), parameter values."""
    row: dict[str, Any] = dict(run_id=run.run_id, seed=run.seed, scenario=run.kind, manikin=run.manikin_name)
    row |= run.manikin.member if run.manikin is not None else {}
    return row | {f"p_{k}": v for k, v in run.parameters.items()}


def run_one(run: Run) -> dict:
    """The row of one run; a run that fails (a bad scenario after substitution, a solver exception) says why."""
    row = head(run)
    t0 = time.perf_counter()
    try:
        row |= envelope_row(run, _model(run.manikin)) if run.envelope is not None else _scenario_columns(run)
    except Exception as exc:  # noqa: BLE001 (any failure of one run is its row's reason; the study goes on)
        row = failed(row, _reason(exc))
    row["run_s"] = round(time.perf_counter() - t0, 4)
    return row


def _scenario_columns(run: Run) -> dict:
    """A scenario run's columns: solved, its outcome and (if recorded) its scores, with the times."""
    solved, solve_s = _solve(run)
    row = outcome([result for _, result in solved]) | {"solve_s": solve_s}
    if any(group in run.record for group in ergonomic()):
        t1 = time.perf_counter()
        row |= scores(_evaluate(solved, run))
        row["eval_s"] = round(time.perf_counter() - t1, 4)
    if JOB in run.record and run.scenario.job is not None:
        row |= job_row(run.scenario.job, solved, _model(run.manikin))
    return row


def failed(row: dict, reason: str) -> dict:
    """``row`` of a run that failed: not converged, ``reason`` in one line."""
    return row | dict(status="failed", converged=False, failure=" ".join(reason.split()))


def _reason(exc: Exception) -> str:
    from ..errors import ManikinError

    text = " ".join(str(exc).split())
    return text if isinstance(exc, ManikinError) and text else f"{type(exc).__name__}: {text}"


def _solve(run: Run) -> tuple[list, float]:
    """Every frame of the run's scenario solved (frame, Result), and the time it took (s)."""
    from ..errors import ScenarioError
    from ..io.scenario.read import scenario_from_dict
    from ..motion.frames import solve_motion

    try:
        tables = run.tables()
    except ValueError as exc:
        raise ScenarioError(f"{run.scenario.path}: {exc}") from None
    scenario = scenario_from_dict(tables, run.scenario.path, _model(run.manikin))
    if run.start_jitter > 0:
        scenario.start = jittered(scenario, run.seed, run.start_jitter)
    t0 = time.perf_counter()
    solved = list(solve_motion(scenario))
    return solved, round(time.perf_counter() - t0, 4)


def _model(manikin: Manikin | None) -> Model | None:
    """The study manikin's body, built once per worker process for the runs that follow (None: the scenario's own)."""
    if manikin is None:
        return None
    key = manikin.key
    if key not in MODELS:
        if len(MODELS) >= MODEL_CACHE:
            MODELS.pop(next(iter(MODELS)))
        MODELS[key] = manikin.model()
    return MODELS[key]


def jittered(scenario: Scenario, seed: int, spread: float) -> np.ndarray:
    """The scenario's start with every rotational joint moved by a seeded normal draw of ``spread`` rad (then put
    back in its range): the same seed, the same start."""
    problem, n = scenario.problem, scenario.model.n
    theta = np.array(scenario.start[:n], dtype=float)
    rng = np.random.default_rng(seed)
    theta += np.where(scenario.model.prismatic, 0.0, rng.normal(0.0, spread, n))
    return problem.to_x(problem.start(theta))


def _evaluate(solved: list, run: Run) -> dict:
    from ..ergonomics import ErgoOptions, evaluate

    return evaluate(solved, ErgoOptions(**run.scenario.ergonomics))


def outcome(results: list) -> dict:
    """Convergence, what held and the reach shortfall over the frames' results."""
    converged = sum(bool(r.converged) for r in results)
    unmet = sorted({name for r in results for name in r.unmet})
    short = max((sum(p.get("position_m", 0.0) for p in r.shortfall.values()) for r in results), default=0.0)
    return dict(
        status="converged" if converged == len(results) else "not converged",
        converged=converged == len(results),
        held=not any(r.broken for r in results),
        frames=len(results),
        frames_converged=converged,
        unmet=" ".join(unmet),
        shortfall_m=round(float(short), 6),
    )


def scores(report: dict) -> dict:
    """A study row's ergonomic columns from an ergonomics report (:func:`solver.evaluate`), in the order of
    :func:`.groups.groups`: each score's (:meth:`~solver.ergonomics.base.Score.summarise`: the RULA and REBA peaks,
    the NIOSH lift), the peak L4/L5 compression (N) and percent of strength (and its joint); None where the body or
    the task has none."""
    row: dict = {}
    loads = _loads(report)
    for group in ergonomic():
        row |= {c: loads[c] for c in LOADS[group]} if group in LOADS else SCORES[group].summarise(report)
    return row


def _loads(report: dict) -> dict:
    """The peak L4/L5 compression (N) and the peak percent of strength with its joint."""
    worst, joint = None, None
    for f in report["frames"]:
        for name, load in f["joint_loads"].items():
            p = load.get("percent_strength") if name != "l4_l5" else None
            if p is not None and math.isfinite(p) and (worst is None or p > worst):
                worst, joint = p, name
    compression = peak([f["joint_loads"]["l4_l5"].get("compression") for f in report["frames"]])
    return dict(
        l4_l5_peak_N=None if compression is None else round(compression, 2),
        strength_peak_pct=None if worst is None else round(worst, 2),
        strength_joint=joint,
    )
