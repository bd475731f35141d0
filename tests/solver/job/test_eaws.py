"""EAWS inputs: the form's traffic light (Ergonomic Assessment Worksheet v1.3.6, stored copy: "0-25 Points Green",
">25-50 Points Yellow", ">50 Points Red") at its edges, and the posture bands' times from the motion's frames, with the
time in holds of at least 4 s (section 1 rates static postures: "Körperhaltungen mit einer jeweiligen Dauer von
mindestens 4s", Haufe, "EAWS Modul 1: Körperhaltungen"; postures "die eine Dauer von weniger als 4 Sekunden
einnehmen" are rated with the cycle's main posture, ema user manual, "Ergonomie-Zwischenwerte"). No points: the
form's point tables were not read first-hand (docs/guide/job.md)."""

from __future__ import annotations

from pathlib import Path

import pytest

from solver.job.eaws import band_times, traffic_light


def test_the_forms_traffic_light_at_its_edges() -> None:
    assert [traffic_light(p) for p in (0.0, 25.0)] == [("green", 0)] * 2
    assert [traffic_light(p) for p in (25.5, 50.0)] == [("yellow", 1)] * 2
    assert traffic_light(50.5) == ("red", 2)


def _posture(trunk: float, arm: float = 10.0, above: bool = False) -> dict:
    side = {"upper_arm_elevation": arm, "hand_above_shoulder": above}
    return {"trunk_flexion": trunk, "l": side, "r": dict(side)}


def test_band_edges_and_seconds_per_minute() -> None:
    """20 and 60 deg belong to the 20-60 band; 1 frame of 1 s in a 30 s cycle is 2 s per minute."""
    frames = [_posture(19.9), _posture(20.0), _posture(60.0), _posture(60.1), _posture(0.0, 90.0, True), None]
    bands = band_times(frames, 1.0, 30.0)
    assert [bands[k]["frames"] for k in ("trunk_under_20", "trunk_20_60", "trunk_over_60")] == [2, 2, 1]
    assert bands["elbow_at_or_above_shoulder"]["frames"] == bands["hand_above_shoulder"]["frames"] == 1
    assert bands["trunk_over_60"]["s_per_min"] == pytest.approx(2.0)


def test_holds_of_at_least_4_s_are_static_shorter_ones_are_not() -> None:
    """Section 1 rates postures held >= 4 s: 4 frames of 1 s in a row are static (the edge counts), 3 are not, and
    an unmeasured frame ends a hold; 4 s in a 30 s cycle is 8 s per minute."""
    bent, upright = _posture(40.0), _posture(5.0)
    frames = [bent] * 4 + [upright] + [bent] * 3 + [None] + [bent] * 2 + [upright] * 4
    bands = band_times(frames, 1.0, 30.0)
    assert bands["trunk_20_60"]["frames"] == 9 and bands["trunk_20_60"]["static_frames"] == 4
    assert bands["trunk_20_60"]["static_seconds"] == pytest.approx(4.0)
    assert bands["trunk_20_60"]["static_s_per_min"] == pytest.approx(8.0)
    assert bands["trunk_under_20"]["static_frames"] == 4 and bands["trunk_over_60"]["static_frames"] == 0
    half = band_times([bent] * 7, 0.5, 30.0)["trunk_20_60"]  # 7 frames of 0.5 s: 3.5 s, not static
    assert half["frames"] == 7 and half["static_frames"] == 0
    assert band_times([bent] * 8, 0.5, 30.0)["trunk_20_60"]["static_frames"] == 8


def test_the_example_job_gives_inputs_and_no_score(example: tuple[dict, Path]) -> None:
    report, out = example
    eaws = report["methods"]["eaws"]
    assert eaws["scored"] is False and eaws["verdict"]["severity"] is None
    assert sum(eaws["bands"][k]["frames"] for k in ("trunk_under_20", "trunk_20_60", "trunk_over_60")) == 60
    assert eaws["handlings_per_shift"] == 800 and eaws["load_kg"] == 10.0
    assert "not scored" in eaws["verdict"]["text"] and "EAWS section 1 inputs" in (out / "job.html").read_text()
    assert all(0 <= b["static_frames"] <= b["frames"] for b in eaws["bands"].values())
    assert "in holds >= 4 s" in eaws["verdict"]["text"] and "s in holds &gt;= 4 s" in (out / "job.html").read_text()


def test_zero_repetitions_and_one_frame(one_frame: tuple[dict, str]) -> None:
    eaws = one_frame[0]["methods"]["eaws"]
    assert eaws["handlings_per_shift"] == 0
    assert sum(b["frames"] for k, b in eaws["bands"].items() if k.startswith("trunk")) == 1
