"""The Blender layer's scores come from the score registry (solver/ergonomics/registry.py), checked without bpy: the
baked motion's report (blender_manikin/motion/report.py: its frames, sources, summary lines and captions) and the
study table's columns (blender_manikin/study/table.py). A score made up here and registered for one test appears
in each without a line of the Blender layer changed, and the other entries stay as they were. The sidebar's words
and the drawn tables are checked in a Blender session (tests/blender/test_scores.py)."""

from __future__ import annotations

import importlib
import importlib.util
import json
import sys
from dataclasses import dataclass, field
from pathlib import Path
from types import ModuleType, SimpleNamespace
from typing import TYPE_CHECKING

import pytest

if TYPE_CHECKING:  # for the annotations only (the copy defines the same classes)
    from solver import Result
    from solver.ergonomics.options import ErgoOptions
    from solver.io.result.frame import Frame

ROOT = Path(__file__).resolve().parents[2]


def checkout_package(name: str = "manikin_checkout") -> ModuleType:
    """The checkout loaded as the package Blender loads the extension as (its root holds ``solver/`` and
    ``blender_manikin/``), so the Blender layer's relative imports of the solver resolve. Its solver is a copy of
    its own, apart from the top-level ``solver`` of the other tests: scores are registered in that copy."""
    if name not in sys.modules:
        root = str(ROOT)
        spec = importlib.util.spec_from_file_location(name, ROOT / "__init__.py", submodule_search_locations=[root])
        package = importlib.util.module_from_spec(spec)
        sys.modules[name] = package
        spec.loader.exec_module(package)
    return sys.modules[name]


def _module(path: str) -> ModuleType:
    return importlib.import_module(f"{checkout_package().__name__}.{path}")


solver = _module("solver")
report_module, table = _module("blender_manikin.motion.report"), _module("blender_manikin.study.table")
base, registry = _module("solver.ergonomics.base"), _module("solver.ergonomics.registry")
HEAD, MotionReport = report_module.HEAD, report_module.MotionReport
captions, summary_lines = report_module.captions, report_module.summary_lines
header, score_cells, score_columns, split = table.header, table.score_cells, table.score_columns, table.split
Score, MotionScore, FrameInputs = base.Score, base.MotionScore, base.FrameInputs
SCORES = registry.SCORES
panels = _module("solver.study.groups").panels
FRAMES = (1, 2, 3)


class Reach(Score):
    """Made up for the test: a float per frame (the frame number and a quarter)."""

    name = "reach_test"
    title = "Reach"
    source = "test source"

    def evaluate(self, inputs: FrameInputs) -> dict:
        return dict(score=inputs.frame.number + 0.25)


class Span(MotionScore):
    """Made up for the test: the motion's first and last frame numbers, and each frame's share of the way."""

    name = "span_test"
    title = "Span"
    source = "test source"

    def ends(self, options: ErgoOptions) -> dict[str, int | None]:
        return {"start": None, "end": None}

    def motion(self, start: Frame, end: Frame, options: ErgoOptions) -> dict:
        return dict(start=start.number, end=end.number)

    def keep(self, frame: Frame) -> int:
        return frame.number

    def at_frame(self, kept: int, motion: dict, options: ErgoOptions) -> dict:
        return dict(share=(kept - motion["start"]) / (motion["end"] - motion["start"]))

    def motion_lines(self, report: dict) -> list[str]:
        span = report[self.name]
        return [f"Span: frames {span['start']} to {span['end']}"]


@dataclass
class Record:
    """Stands in for blender_manikin.motion.bake.FrameRecord (that module needs bpy)."""

    frame: int
    converged: bool = True
    iterations: int = 3
    time_s: float = 0.01
    wall_s: float = 0.02
    unmet: list[str] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    residuals: dict[str, float] = field(default_factory=dict)


@pytest.fixture(scope="module")
def result() -> Result:
    """The box lift's pose (10 kg in the hands), taken as each frame of a three-frame motion."""
    scenario = solver.load_scenario(ROOT / "presets/scenarios/box_lift.toml")
    return solver.solve(scenario.problem_at(1), scenario.start, scenario.options)


@pytest.fixture
def throwaway(monkeypatch) -> None:
    """Reach and Span registered for one test (what register(...) in registry.py does)."""
    monkeypatch.setitem(SCORES, Reach.name, Reach())
    monkeypatch.setitem(SCORES, Span.name, Span())


def bake_report(result: Result, path: Path) -> tuple[dict, dict]:
    """(the report written, the summary kept) of the three frames, as the headless bake makes them."""
    report = MotionReport(result.problem.model, "male_50", path, plots=False)
    records = [Record(frame) for frame in FRAMES]
    for record in records:
        report.add(record, result)
    baker = SimpleNamespace(records=records, arm=SimpleNamespace(name="male_50"), frames=list(FRAMES))
    report.write(baker, dict(scenario="box_lift.toml", blend=None))
    return json.loads(path.read_text(encoding="utf-8")), report.summary()


def test_the_report_holds_the_registered_scores(result, tmp_path: Path) -> None:
    """Without a new score: the entries the report has always had (the shipped scores first, in their order)."""
    written, summary = bake_report(result, tmp_path / "report.json")
    assert [f["frame"] for f in written["frames"]] == list(FRAMES)
    names = [s.name for s in registry.in_frame_order()]
    assert names[:4] == ["rula", "reba", "owas", "worksheet"] and "niosh" in names
    assert all(list(f["ergonomics"]) == ["posture", "joint_loads", *names] for f in written["frames"])
    motion = {s.name for s in registry.motion_scores()}
    assert set(written) == set(HEAD) - {"interrupted"} | motion and written["niosh"]["LI"] > 0
    assert set(written["ergonomics_sources"]) >= {*names, "joint_loads", "l4_l5", "strength"}
    lines = summary_lines(summary)
    assert lines[0].startswith("highest RULA ") and ", highest REBA " in lines[0] and lines == summary_lines(written)
    assert any(line.startswith("NIOSH lift: RWL ") for line in lines)
    first = written["frames"][0]["ergonomics"]
    assert captions(summary)[1].startswith(f"RULA {first['rula']['score']} · REBA {first['reba']['score']}")


def test_a_new_score_is_in_the_report_without_a_blender_edit(result, tmp_path: Path, throwaway) -> None:
    written, summary = bake_report(result, tmp_path / "report.json")
    for number, frame in zip(FRAMES, written["frames"], strict=True):
        e = frame["ergonomics"]
        assert list(e)[-4:] == ["worksheet", "reach_test", "niosh", "span_test"]  # frame scores, then motion
        assert e["reach_test"] == {"score": number + 0.25} and e["span_test"] == {"share": (number - 1) / 2}
    assert written["span_test"] == {"start": 1, "end": 3} and written["ergonomics_sources"]["span_test"] == Span.source
    lines = summary_lines(summary)
    assert lines[0].endswith(", highest Reach 3.25 (frame 3)") and lines[-1] == "Span: frames 1 to 3"
    assert captions(summary)[2].splitlines()[0].endswith(" · Reach 2.25")


def test_a_new_score_leaves_the_other_entries_as_they_were(result, tmp_path: Path, monkeypatch) -> None:
    before, _ = bake_report(result, tmp_path / "before.json")
    monkeypatch.setitem(SCORES, Reach.name, Reach())
    monkeypatch.setitem(SCORES, Span.name, Span())
    after, _ = bake_report(result, tmp_path / "after.json")
    new = {"reach_test", "span_test"}

    def without(report: dict) -> dict:
        frames = [dict(f, ergonomics={k: v for k, v in f["ergonomics"].items() if k not in new}, wall_s=None)
                  for f in report["frames"]]  # fmt: skip
        sources = {k: v for k, v in report["ergonomics_sources"].items() if k not in new}
        kept = {k: v for k, v in report.items() if k not in new and k != "timing"}
        return dict(kept, frames=frames, ergonomics_sources=sources)

    assert without(after) == without(before)


def test_the_study_table_shows_each_score_with_one_number_per_frame(monkeypatch) -> None:
    shipped = score_columns()
    assert shipped[:2] == [("RULA", "rula_peak"), ("REBA", "reba_peak")]  # the columns tests/blender check
    monkeypatch.setitem(SCORES, Reach.name, Reach())
    monkeypatch.setitem(SCORES, Span.name, Span())  # a motion score: no column (its study columns are not peaks)
    columns = score_columns()
    assert columns == [*shipped, ("Reach", "reach_test_peak")]
    # the scores a study's scores plot draws, in its order (solver.study.groups.panels)
    assert [c for _, c in columns] == [column for group, column, *_ in panels() if group in SCORES]
    titles = "\t".join(title for title, _ in columns)
    assert header(titles) == ("Manikin", "Role", "Values", *(t for t, _ in columns), "L4/L5 N", "Short mm")
    row = dict(rula_peak=5, reba_peak=None, reach_test_peak=3.256, niosh_li=0.5)
    cells = dict(zip([c for _, c in columns], split(score_cells(row, columns)), strict=True))
    assert (cells["rula_peak"], cells["reba_peak"], cells["reach_test_peak"]) == ("5", "-", "3.26")
    assert split(score_cells(dict(rula_peak=float("inf")), columns[:1])) == ["-"] and split("") == []
