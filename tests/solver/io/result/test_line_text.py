"""Compact result lines built through a per-layout template with the numbers' texts kept by their bits (issue 37):
the same characters as ``json.dumps`` of the frame's dict, whatever changes from one frame to the next (the closest
pairs, a layout, a signed zero, a number not finite, a value not a float, stepping feet)."""

from __future__ import annotations

import dataclasses
import json
from itertools import islice
from pathlib import Path

import numpy as np
import pytest

import solver
from solver.io.result.document import compact_frame_dict
from solver.io.result.line_text import CompactText, TextCache
from solver.io.scenario.read import load_scenario

BOX_LIFT_MOTION = Path(__file__).resolve().parents[4] / "presets" / "scenarios" / "box_lift_motion.toml"


def compact_json(result: solver.Result, number: int) -> str:
    return json.dumps(compact_frame_dict(result, number), separators=(",", ":"))


@pytest.fixture(scope="module")
def solved() -> list[tuple[int, solver.Result]]:
    """Frames of the furnished box lift: contacts, a load, a carried box, closest pairs."""
    return list(islice(solver.solve_motion(solver.load_motion(BOX_LIFT_MOTION)), 3))


def test_texts_kept_by_bits_are_those_json_writes() -> None:
    """A number that changes in its bits only (0.0 to -0.0), a shorter and a longer vector (the texts they share at
    the start kept), a number not finite (None, then all written again)."""
    cache = TextCache()
    values = np.array([0.0, 1.5, -2.25, 1e-17, 1e16, 0.1])
    for v in (values, values * [-1.0, 1, 1, 1, 1, 1], values[:4], np.r_[values, 7.0, -0.0], values + 1e-16, values):
        assert cache(v.copy()) == [json.dumps(x) for x in v.tolist()]
    assert cache(values * np.nan) is None and cache(np.array([])) == []
    assert cache(values.copy()) == [json.dumps(x) for x in values.tolist()]


def closer(result: solver.Result, pairs: list) -> solver.Result:
    return dataclasses.replace(result, closest=pairs)


def test_closest_pairs_that_come_go_and_touch(solved) -> None:
    """Closest pairs added, dropped, reordered, touching at -0.0 (written 0.0), with names holding the template's
    own characters: each line the JSON of its dict."""
    text = CompactText()
    number, result = solved[1]
    near = list(result.closest)
    assert len(near) >= 2
    touching = near[0]._replace(distance=-0.0, point=np.array([-0.0, 0.25, 1.0]), other='100 % "a %s wall"')
    for pairs in (near, near[::-1], near[:1], [], [touching, *near], near + near, near):
        changed = closer(result, pairs)
        assert text(changed, number, result.state) == json.dumps(
            compact_frame_dict(changed, number, result.state), separators=(",", ":")
        )
    assert '"distance":0.0' in text(closer(result, [touching]), number, result.state)


def test_another_layout_and_values_json_writes_otherwise(solved) -> None:
    """A residual renamed or an int, a comfort None, a number not finite, a note: the template's way or the dicts',
    each line as JSON writes it; and back to the first layout."""
    text = CompactText()
    number, result = solved[2]
    residuals = dict(result.residuals)
    first = next(iter(residuals))
    variants = [
        result,
        dataclasses.replace(result, residuals={**residuals, 'x "%s" %': 1.0}),
        dataclasses.replace(result, residuals={**residuals, first: 0}),
        dataclasses.replace(result, residuals={**residuals, first: np.inf}),
        dataclasses.replace(result, comfort=None, notes=["a note"], unmet=["hand_r"], shortfall={"floor": 0.5}),
        dataclasses.replace(result, time_s=float("nan")),
        result,
    ]
    for changed in variants:
        line = text(changed, number, result.state)
        assert line == json.dumps(compact_frame_dict(changed, number, result.state), separators=(",", ":"))
    assert "Infinity" in text(variants[3], number, result.state) and "NaN" in text(variants[5], number, result.state)


def test_stepping_frames_write_their_steps(tmp_path) -> None:
    scenario = load_scenario(BOX_LIFT_MOTION, feet="step")
    text = CompactText()
    frames = list(islice(solver.solve_motion(scenario), 2))
    for number, result in frames:
        line = text(result, number)
        assert line == compact_json(result, number) and '"feet":"step","steps":' in line
