"""What a score tells the sidebar of one frame (issue 33): its words, the level they stand for and a severity
(:meth:`solver.ergonomics.base.Score.verdict`), its number on a motion's graph and its detail lines, for every
registered score; the bands agree with the scores plot's."""

from __future__ import annotations

import math

import pytest
from test_ergonomics import G, frame_dict, pose

from solver.ergonomics import ErgoOptions, evaluate
from solver.ergonomics.base import Score, Verdict
from solver.ergonomics.registry import SCORES, frame_scores, motion_scores
from solver.io.result.read import frame_from_dict
from solver.io.scenario.bodies import load_body


@pytest.fixture(scope="module")
def report() -> dict:
    """Arms hanging, then arms straight forward at shoulder height, 10 kg in the hands."""
    male = load_body(preset="male_50")
    hands = (("hand_l", (0.0, 0.0, -5 * G)), ("hand_r", (0.0, 0.0, -5 * G)))
    poses = [male.zero_pose(), pose(male, shoulder_l_flexion=math.pi / 2, shoulder_r_flexion=math.pi / 2)]
    frames = [frame_from_dict(frame_dict(male, t, loads=hands) | {"frame": k + 1}, "lift") for k, t in enumerate(poses)]
    return evaluate(frames, ErgoOptions(coupling="good", frequency=0.2), model=male)


def test_every_frame_score_rates_a_frame_with_its_words(report: dict) -> None:
    for frame in report["frames"]:
        for score in frame_scores():
            verdict = score.verdict(frame)
            assert isinstance(verdict, Verdict) and verdict.text == score.brief(frame)
            assert verdict.severity in (0, 1, 2) and verdict.level, score.name
        assert all(s.verdict(frame) is None and s.graph(frame) is None for s in motion_scores())


def test_the_levels_name_the_method_s_own_terms(report: dict) -> None:
    low, high = report["frames"]
    assert SCORES["owas"].verdict(low).level.startswith("action category 1: normal posture")
    assert SCORES["rula"].verdict(low) == Verdict(
        "RULA 3", "action level 2: further investigation needed, changes may be required", 1
    )
    assert SCORES["reba"].verdict(low) == Verdict("REBA 1", "negligible risk", 0)
    sheet = SCORES["worksheet"].verdict(high)  # the item at fault is named with its value, not only "red"
    assert (
        sheet.severity == 2 and sheet.level.startswith("worst level red: ") and "right shoulder 90 deg" in sheet.level
    )
    assert SCORES["owas"].verdict(high).severity == min(high["owas"]["action_category"] - 1, 2)


def test_the_graph_numbers(report: dict) -> None:
    low, high = report["frames"]
    assert SCORES["rula"].graph(low) == pytest.approx(low["rula"]["score"])
    assert SCORES["owas"].graph(high) == high["owas"]["action_category"]
    assert (SCORES["worksheet"].graph(low), SCORES["worksheet"].graph(high)) == (0.0, 2.0)


def test_the_worksheet_lists_each_item_with_its_level(report: dict) -> None:
    high = report["frames"][1]
    lines = dict(SCORES["worksheet"].details(high))
    items = [k for k in high["worksheet"] if k != "overall"]
    assert len(lines) == len(items)
    right = next(text for text in lines if text.startswith("right shoulder "))
    assert lines[right] == 2 and "red (green 0-20" in right
    assert SCORES["rula"].details(high) == []


def test_a_score_without_a_verdict_of_its_own_is_its_words_unrated() -> None:
    class Plain(Score):
        name, title, source = "plain", "Plain", "-"

        def evaluate(self, inputs) -> dict:
            return {}

    assert Plain().verdict({"plain": {"score": 3}}) == Verdict("Plain 3", None, None)
    assert Plain().graph({"plain": {"score": 3}}) == 3.0 and Plain().graph({"plain": {"score": None}}) is None
