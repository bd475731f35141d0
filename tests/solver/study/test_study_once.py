"""What a study's worker keeps from run to run (the groups of the registries, the manikin's key, parsed key paths,
the problem parts of :mod:`solver.problem.parts`) gives what building it anew gives: a run after runs of other
inputs has the row it has alone, and a changed registry or a bad value is seen at once."""

from __future__ import annotations

import copy
import datetime
from pathlib import Path

import pytest

from solver.constraints import per_model
from solver.ergonomics.registry import SCORES
from solver.ergonomics.rula import Rula
from solver.io.scenario.bodies import PRESETS_DIR
from solver.study import groups, keypath
from solver.study.plan import plan, tables_copy
from solver.study.runner import TIMING, run_chunk
from solver.study.spec import digest, load_study

LIFT = PRESETS_DIR / "scenarios" / "box_lift.toml"
STUDY = f"""
manikins = ["female_5"]

[[scenarios]]
file = "{LIFT}"
name = "lift"
[scenarios.parameters.mass]
values = [2.0, 9.0, -1.0]   # -1: not a mass, the run fails and its row says why
set = ["loads.hand_r.mass"]
[scenarios.parameters.friction]
values = [0.6, 0.2]
set = ["targets.foot_r.friction"]
"""


def untimed(row: dict) -> dict:
    return {k: v for k, v in row.items() if k not in TIMING}


def test_a_run_after_runs_of_other_inputs_has_the_row_it_has_alone(tmp_path: Path):
    (tmp_path / "study.toml").write_text(STUDY, encoding="utf-8")
    runs = plan(load_study(tmp_path / "study.toml"))
    together = run_chunk(runs)  # one worker: every run after the others, the parts kept
    alone = []
    for run in runs:
        per_model._PER_MODEL.clear()  # nothing kept: built as a first run builds them
        alone.append(run_chunk([run])[0])
    assert [untimed(r) for r in together] == [untimed(r) for r in alone]
    failed = [r for r in together if r["status"] == "failed"]
    assert len(failed) == 2 and all("mass" in r["failure"] for r in failed)
    assert len({r["l4_l5_peak_N"] for r in together if r["status"] != "failed"}) == 4  # each load and friction its own


def test_the_groups_follow_a_score_registered_later(monkeypatch):
    before = groups.groups()
    assert groups.groups() == before and groups.groups() is not groups.groups()  # a new dict each time
    late = Rula()
    late.name = "rula_late"
    monkeypatch.setitem(SCORES, late.name, late)
    assert groups.groups()["rula_late"] == ["rula_late_peak"] and "rula_late" in groups.ergonomic()
    monkeypatch.delitem(SCORES, late.name)
    assert groups.groups() == before


def test_the_manikin_key_is_the_digest_of_its_body(tmp_path: Path):
    (tmp_path / "study.toml").write_text(STUDY, encoding="utf-8")
    manikin = load_study(tmp_path / "study.toml").manikins[0]
    assert manikin.key == digest(manikin.body) and manikin.key is manikin.key


def test_tables_copy_is_deepcopy_for_toml_tables():
    data = {"a": [1, 2.5, {"b": "x", "c": [True, None]}], "d": {"e": datetime.date(2026, 1, 2)}, "f": (1, [2])}
    copied = tables_copy(data)
    assert copied == copy.deepcopy(data)
    copied["a"][2]["c"].append(3)
    copied["f"][1].append(3)
    assert data["a"][2]["c"] == [True, None] and data["f"] == (1, [2])


def test_a_malformed_key_path_fails_every_time_with_its_reason():
    for _ in range(2):
        with pytest.raises(ValueError, match="keys must be separated"):
            keypath.apply({"a": [1]}, "a b", 1, add=False)
    data = {"a": [1, 2]}
    keypath.apply(data, "a[1]", 5, add=True)
    keypath.apply(data, "a[1]", 5, add=True)
    assert data == {"a": [1, 12]}
