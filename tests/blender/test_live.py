"""Live mode follows obstacles, and a carried box follows the hands after Solve Pose and live solves
(tests/blender/live_session.py in a subprocess, the built zip installed). The body's clearance to the obstacle is
checked here, independently of the extension: the solver's collision capsules in the recorded pose against the
obstacle's recorded corners.
"""

from __future__ import annotations

import numpy as np
import pytest

from solver.collision import Box, box_distance
from solver.collision.body import capsules_of
from solver.collision.carried import carried_frame
from solver.io.scenario.bodies import load_body

MM = 1e-3
TOLERANCE = 1e-3  # m: the solver's own (a clearance row this far inside still counts as met)


@pytest.fixture(scope="module")
def session(tmp_path_factory, run_session) -> dict:
    return run_session(tmp_path_factory.mktemp("live"), "live_session.py")


@pytest.fixture(scope="module")
def model():
    return load_body(preset="male_50")


def _world(session: dict, points: np.ndarray) -> np.ndarray:
    arm = np.array(session["arm"])
    return points @ arm[:3, :3].T + arm[:3, 3]


def _gap(session: dict, state: dict, model) -> float:
    """The body's smallest surface distance (m) to the obstacle where ``state`` recorded it (an unturned box)."""
    low, high = np.array(state["post"])
    capsules = capsules_of(model)
    start, end = capsules.world(model.forward(np.array(state["x"])[: model.n]))
    proximity = box_distance(_world(session, start), _world(session, end), capsules.radius,
                             Box(center=(low + high) / 2.0, size=high - low))  # fmt: skip
    return float(proximity.distance.min())


def _check_box(session: dict, state: dict, model) -> None:
    """The carried box's recorded world matrix is the frame between the solved hands (centre within 1 mm)."""
    kin = model.forward(np.array(state["x"])[: model.n])
    hands = [_world(session, kin.tcp_frame(model.tcp(tcp))[1]) for tcp in ("hand_l", "hand_r")]
    centre, rotation = carried_frame(*hands)
    crate = np.array(state["crate"])
    assert np.linalg.norm(crate[:3, 3] - centre) < MM
    np.testing.assert_allclose(crate[:3, :3], rotation, atol=1e-4)


def test_solve_pose_puts_the_carried_box_between_the_hands(session: dict, model) -> None:
    assert session["solve"] == ["FINISHED"]
    crate = np.array(session["solved"]["crate"])
    assert np.linalg.norm(crate[:3, 3] - 3.0) > 1.0  # no longer where it was put before the solve
    _check_box(session, session["solved"], model)


def test_carried_box_is_no_obstacle(session: dict) -> None:
    """Marked as an obstacle by mistake, the box is still left out (it would push the hands away), and the pose
    write that moves it does not start another live solve."""
    assert session["obstacles"] == ["post"]  # the unmarked cube is no obstacle either
    assert session["quiet"]


def test_live_resolves_when_an_obstacle_moves(session: dict, model) -> None:
    clearance = session["clearance"]
    assert session["armed_on_move"]
    assert _gap(session, session["live_on"], model) > clearance + 0.05  # clear before the move
    assert _gap(session, session["stale"], model) < clearance - 0.005  # the old pose goes through the moved box
    assert _gap(session, session["moved"], model) >= clearance - TOLERANCE  # the new pose keeps clear of it
    _check_box(session, session["moved"], model)  # the carried box follows a live solve


def test_live_resolves_when_an_obstacle_mesh_is_edited(session: dict, model) -> None:
    clearance = session["clearance"]
    assert session["armed_on_edit"]
    edited = dict(session["edited"], x=session["moved"]["x"])  # the pose before the edit, the edited mesh
    assert _gap(session, edited, model) < clearance - 0.005
    assert _gap(session, session["edited"], model) >= clearance - TOLERANCE
    _check_box(session, session["edited"], model)


def test_live_defers_the_scores_until_the_drag_ends(session: dict) -> None:
    """A live solve writes its result without the ergonomics scores (pending, the settle timer armed); once the drag
    has ended they are added, the scores of the same pose as Solve Pose gives (issue 37)."""
    assert session["live_result"] == dict(pending=True, scores=None, armed=True)
    assert session["settle_waits"]
    scored = session["scored"]
    assert scored["pending"] is None and scored["scores"] and len(scored["verdicts"]) == len(scored["scores"])
    assert session["scored_twice_same"]
    assert session["solve_again"] == ["FINISHED"]
    assert [s.split()[0] for s in session["solved_scores"]] == [s.split()[0] for s in scored["scores"]]


def test_live_ignores_an_unmarked_object(session: dict) -> None:
    assert not session["armed_on_unmarked"] and session["unmarked_unsolved"]


def test_no_traceback(session: dict) -> None:
    assert "Traceback" not in session["log"]
