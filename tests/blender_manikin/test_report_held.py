"""The bake's report computes a held pose's ergonomics once (solver/ergonomics/held.py): a frame whose solver state
has the frame before's kinematics takes that frame's posed arrays, report and joint loads' text, and each frame
written is the report of that frame computed on its own (checked without bpy)."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path
from types import SimpleNamespace

import pytest
from test_scores_follow_registry import ROOT, MotionReport, Record, _module, solver

ORDER = (0, 0, 0, 1, 1, 0)  # which result each baked frame holds
HELD = [False, True, True, False, True, False]
frame_module, report = _module("solver.io.result.frame"), _module("solver.ergonomics.report")


@pytest.fixture(scope="module")
def results() -> list:
    out = []
    for name in ("box_lift", "box_lift_high"):
        scenario = solver.load_scenario(ROOT / f"presets/scenarios/{name}.toml")
        out.append(solver.solve(scenario.problem_at(1), scenario.start, scenario.options))
    return out


def test_held_frames_write_the_report_of_each_frame_computed_on_its_own(results, tmp_path: Path) -> None:
    made = MotionReport(results[0].problem.model, "male_50", tmp_path / "report.json", plots=False)
    records, baked, held = [Record(n, converged=n != 3) for n in range(1, len(ORDER) + 1)], [], []
    for record, i in zip(records, ORDER, strict=True):  # frame 3: a held pose that did not converge
        result = results[i] if record.converged else dataclasses.replace(results[i], converged=False)
        made.add(record, result)
        baked.append(result)
        held.append(made._parts.held)
    baker = SimpleNamespace(records=records, arm=SimpleNamespace(name="male_50"), frames=[r.frame for r in records])
    written = json.loads(made.write(baker, dict(scenario="box_lift.toml", blend=None)).read_text(encoding="utf-8"))
    assert held == HELD
    for record, result, frame in zip(records, baked, written["frames"], strict=True):
        f = frame_module.frame_of_result(result, record.frame)  # nothing kept from another frame
        alone = report.frame_report(f, made.options, made.model, made.area, None)[0]
        ergonomics = {k: v for k, v in frame["ergonomics"].items() if k in alone}
        assert json.dumps(ergonomics) == json.dumps({k: alone[k] for k in ergonomics})
        assert set(alone) - set(ergonomics) == set(report.HEAD_KEYS) and frame["converged"] is record.converged
