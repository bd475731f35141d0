"""A study's runs: every scenario x its parameter grid x manikin x repeat, in a fixed order, each with its inputs,
its seed and its run id (a hash of the inputs, so a rerun knows which rows it has and a changed input is a new run).

Order: scenario, then manikin, then the parameter grid (the first parameter varying slowest), then repeat (a
chunk of runs then mostly shares one body, which a worker builds once). The
seed of a run is a hash of its inputs, the study's seed and the repeat number; the run id hashes the inputs and
the seed. Inputs are the substituted scenario tables, the manikin's body tables, the parameter values, the task
facts, the start jitter and what is recorded (not files a scenario names, such as an obstacle mesh: change one,
and start in a new output folder).

A study's ``[envelope]`` adds, after the scenarios' runs, one run per manikin and combination of its settings (hand,
load, feet, sole scale; no repeats: an envelope is deterministic), its id a hash of the settings and the body.
"""

from __future__ import annotations

import copy
import datetime
import itertools
from dataclasses import dataclass
from typing import Any

from ..errors import ScenarioError
from . import keypath
from .envelope_spec import PARAMETERS, EnvelopeStudy, mesh_name
from .spec import Manikin, Study, StudyScenario, digest


@dataclass(frozen=True)
class Run:
    """Everything one run needs, small to send: the scenario and manikin are shared objects (pickled once per
    chunk of runs), the parameters go into the scenario's tables in the worker (:meth:`tables`)."""

    index: int  # its row's place in the study's outputs
    run_id: str
    seed: int
    scenario: StudyScenario | None  # None: an envelope run
    manikin: Manikin | None  # None: the scenario's own
    manikin_name: str
    parameters: dict[str, Any]
    start_jitter: float = 0.0
    record: tuple[str, ...] = ()
    envelope: EnvelopeStudy | None = None  # an envelope run: its [envelope]; ``parameters`` are its settings

    @property
    def kind(self) -> str:
        """The rows' ``scenario`` column: the scenario's name or the envelope's."""
        return self.scenario.name if self.scenario is not None else self.envelope.name

    def tables(self) -> dict:
        """The scenario's tables with the parameters and the manikin put in (ValueError if a value does not go)."""
        if self.scenario is None:
            raise ValueError(f"run {self.run_id} is a reach envelope ([envelope] {self.envelope.name}): no scenario")
        return substitute(self.scenario, self.parameters, self.manikin)


def grid(scenario: StudyScenario) -> list[dict[str, Any]]:
    """Every combination of the scenario's parameter values ([{}] without parameters)."""
    names = [p.name for p in scenario.parameters]
    return [
        dict(zip(names, combo, strict=True)) for combo in itertools.product(*(p.values for p in scenario.parameters))
    ]


def substitute(scenario: StudyScenario, values: dict[str, Any], manikin: Manikin | None) -> dict:
    """The scenario's tables with each parameter's value set or added at its key paths and, unless the scenario
    keeps its own, the study's manikin in [manikin]; ValueError if a value does not go in."""
    data = tables_copy(scenario.data)
    for p in scenario.parameters:
        for path in p.set:
            keypath.apply(data, path, values[p.name], add=False)
        for path in p.add:
            keypath.apply(data, path, values[p.name], add=True)
    if manikin is not None:
        data["manikin"] = manikin.table()
    return data


def tables_copy(value: Any) -> Any:
    """A copy of parsed TOML tables: every table and list new, the values (str, numbers, dates: immutable) shared;
    copy.deepcopy's result for these types, without its memo (a study copies its scenario's tables every run)."""
    kind = type(value)
    if kind is dict:
        return {key: tables_copy(item) for key, item in value.items()}
    if kind is list:
        return [tables_copy(item) for item in value]
    return value if kind in _IMMUTABLE else copy.deepcopy(value)


_IMMUTABLE = {str, int, float, bool, datetime.datetime, datetime.date, datetime.time, type(None)}


def own_manikin(scenario: StudyScenario) -> str:
    """The row name of a scenario's own manikin: its preset, or its body file's stem."""
    table = scenario.data.get("manikin", {})
    return str(table.get("preset") or str(table.get("file", "?")).rsplit("/", 1)[-1].removesuffix(".toml"))


def plan(study: Study) -> list[Run]:
    """Every run of ``study``, in the order of its rows."""
    runs: list[Run] = []
    for scenario in study.scenarios:
        use_own = scenario.keep_manikin or not study.manikins
        manikins: list[Manikin | None] = [None] if use_own else list(study.manikins)
        inputs = digest(dict(scenario=scenario.name, data=scenario.data, ergonomics=scenario.ergonomics,
                             parameters=[[p.name, p.set, p.add] for p in scenario.parameters],
                             start_jitter=study.start_jitter, record=study.record))  # fmt: skip
        for manikin in manikins:
            name, body = (manikin.name, manikin.key) if manikin else (own_manikin(scenario), None)
            for values in grid(scenario):
                base = digest([inputs, values, name, body])
                for repeat in range(study.repeats):
                    seed = int(digest([base, study.seed, repeat])[:8], 16) & 0x7FFFFFFF
                    runs.append(Run(len(runs), digest([base, seed])[:16], seed, scenario, manikin, name, values,
                                    study.start_jitter, study.record))  # fmt: skip
    if study.envelope is not None:
        runs += envelope_runs(study, study.envelope, len(runs))
    return runs


def envelope_runs(study: Study, envelope: EnvelopeStudy, first: int) -> list[Run]:
    """The runs of the study's ``envelope``: per manikin, every combination of its settings; ``first`` is the
    first run's row index."""
    inputs = digest(envelope.inputs())
    runs: list[Run] = []
    for manikin in study.manikins:
        for values in envelope.grid():
            base = digest([inputs, values, manikin.name, manikin.key])
            seed = int(digest([base, study.seed, 0])[:8], 16) & 0x7FFFFFFF
            runs.append(Run(first + len(runs), digest([base, seed])[:16], seed, None, manikin, manikin.name, values,
                            envelope=envelope))  # fmt: skip
    names = [mesh_name(r.manikin_name, r.parameters) for r in runs]
    if len(set(names)) < len(names):
        twice = sorted({n for n in names if names.count(n) > 1})[0]
        raise ScenarioError(f"{study.path}: manikins: names whose envelope files would be the same ({twice}); "
                            'rename one with {preset|file|family = "...", name = "..."}')  # fmt: skip
    return runs


def parameter_names(study: Study) -> list[str]:
    """Every parameter name of the study's scenarios, in order of first appearance (one column each)."""
    names: list[str] = []
    for scenario in study.scenarios:
        names += [p.name for p in scenario.parameters if p.name not in names]
    if study.envelope is not None:
        names += [name for name in PARAMETERS if name not in names]
    return names
