"""One row of a study as a scenario file of its own: ``python -m solver study STUDY.toml --scenario-of RUN_ID``.

The scenario with the row's parameters and manikin put in, its file paths (a body file, an obstacle mesh) made
absolute so it can be saved anywhere, and, with a start jitter, the row's start pose written out as
[start.joints]: ``python -m solver solve`` on it gives the row's pose again (and ``ergo`` its scores).
"""

from __future__ import annotations

from pathlib import Path

from ..errors import ScenarioError, UsageError
from ..io.toml_write import dumps_toml
from .plan import Run, plan
from .runner import jittered
from .spec import load_study


def find_run(runs: list[Run], run_id: str) -> Run:
    """The run whose id is ``run_id`` or starts with it (a unique prefix); one UsageError line if none or many."""
    found = [r for r in runs if r.run_id.startswith(run_id)] if run_id else []
    if len(found) != 1:
        why = "no run of the study has" if not found else f"{len(found)} runs of the study have"
        raise UsageError(f"--scenario-of {run_id}: {why} that id (the rows' run_id column)")
    return found[0]


def absolute_paths(data: dict, folder: Path) -> None:
    """Make the scenario's relative file paths (its [manikin] body file, its obstacles' mesh files) absolute."""
    tables = [data.get("manikin", {})] + [o for o in data.get("obstacles", []) if isinstance(o, dict)]
    for table in tables:
        if isinstance(table, dict) and isinstance(table.get("file"), str) and not Path(table["file"]).is_absolute():
            table["file"] = str((folder / table["file"]).resolve())


def row_scenario(study_file: str | Path, run_id: str) -> str:
    """The scenario TOML of the run ``run_id`` of the study (see the module docstring)."""
    from ..io.scenario.read import scenario_from_dict

    run = find_run(plan(load_study(study_file)), run_id)
    if run.envelope is not None:
        raise UsageError(
            f"--scenario-of {run_id}: that run is a reach envelope ([envelope] {run.envelope.name}), "
            "not a scenario; its meshes are in the output folder's envelopes/ (the rows' mesh column)"
        )
    try:
        data = run.tables()
    except ValueError as exc:
        raise ScenarioError(f"{run.scenario.path}: {exc}") from None
    absolute_paths(data, run.scenario.path.parent)
    if run.start_jitter > 0:
        scenario = scenario_from_dict(data, run.scenario.path)
        theta = jittered(scenario, run.seed, run.start_jitter)[: scenario.model.n]
        data["start"] = {"joints": dict(zip(scenario.model.joint_names, map(float, theta), strict=True))}
    values = ", ".join(f"{k} = {v!r}" for k, v in run.parameters.items()) or "none"
    head = (f"# Run {run.run_id} of the study {Path(study_file).name} (seed {run.seed}): scenario {run.scenario.name}"
            f" ({run.scenario.path}), manikin {run.manikin_name}, parameters: {values}.\n")  # fmt: skip
    return head + dumps_toml(data, ScenarioError)
