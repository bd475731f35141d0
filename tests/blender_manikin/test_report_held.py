"""The bake's report computes a held pose's ergonomics once (solver/ergonomics/held.py): a frame whose solver state
has the frame before's kinematics takes that frame's posed arrays and report, and the report written is the one
of every frame computed afresh, character for character (checked without bpy)."""

from __future__ import annotations

import dataclasses
from pathlib import Path
from types import SimpleNamespace

import pytest
from test_scores_follow_registry import ROOT, MotionReport, Record, solver

ORDER = (0, 0, 0, 1, 1, 0)  # which result each baked frame holds
HELD = [False, True, True, False, True, False]


@pytest.fixture(scope="module")
def results() -> list:
    out = []
    for name in ("box_lift", "box_lift_high"):
        scenario = solver.load_scenario(ROOT / f"presets/scenarios/{name}.toml")
        out.append(solver.solve(scenario.problem_at(1), scenario.start, scenario.options))
    return out


def _bake(results: list, path: Path, reuse: bool) -> tuple[str, list[bool]]:
    """(the report's text, whether each frame was held) of the frames ORDER names; frame 3 did not converge."""
    report = MotionReport(results[0].problem.model, "male_50", path, plots=False)
    report._parts._reuse = reuse
    records, held = [Record(n, converged=n != 3) for n in range(1, len(ORDER) + 1)], []
    for record, i in zip(records, ORDER, strict=True):
        result = results[i] if record.converged else dataclasses.replace(results[i], converged=False)
        report.add(record, result)
        held.append(report._parts.held)
    baker = SimpleNamespace(records=records, arm=SimpleNamespace(name="male_50"), frames=[r.frame for r in records])
    report.write(baker, dict(scenario="box_lift.toml", blend=None))
    return path.read_text(encoding="utf-8"), held


def test_held_frames_write_the_report_of_each_frame_computed_afresh(results, tmp_path: Path) -> None:
    reused, held = _bake(results, tmp_path / "reused.json", reuse=True)
    afresh, none = _bake(results, tmp_path / "afresh.json", reuse=False)
    assert held == HELD and not any(none)
    assert reused == afresh and '"converged": false' in reused
