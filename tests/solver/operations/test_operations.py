"""Operations: the tables read, grasps proposed, MTM-1 timing and minimum-jerk numbers, bad operations named in
one line (exit 2), and a short get/place generated and solved end to end."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from solver.cli.main import main
from solver.operations import timing
from solver.operations.generate import load_operations

HEAD = """
name = "ops test"
[manikin]
preset = "male_50"
[operate]
fps = {fps}
[[obstacles]]
name = "table"
kind = "box"
center = [0.0, -0.55, 0.73]
size = [1.2, 0.5, 0.04]
[[objects]]
name = "box"
kind = "box"
center = [0.0, -0.45, 0.871]
size = [0.30, 0.22, 0.24]
mass = 4.0
"""


def write(tmp_path: Path, operations: str, fps: int = 24, extra: str = "") -> Path:
    path = tmp_path / "ops.toml"
    path.write_text(HEAD.format(fps=fps) + extra + operations, encoding="utf-8")
    return path


GET_PLACE = """
[[operations]]
do = "get"
object = "box"
[[operations]]
do = "place"
object = "box"
to = [0.25, -0.45, 0.871]
"""


def test_min_jerk_profile_numbers():
    assert timing.min_jerk(0.0) == 0.0 and timing.min_jerk(1.0) == 1.0
    assert timing.min_jerk(0.5) == pytest.approx(0.5)
    assert timing.min_jerk(0.25) == pytest.approx(0.103515625)  # 10/64 - 15/256 + 6/1024
    # peak speed 1.875 D / T at the middle, zero at both ends
    assert timing.min_jerk_speed(0.5, 1.0, 1.0) == pytest.approx(1.875)
    assert timing.min_jerk_speed(0.0, 1.0, 1.0) == 0.0 and timing.min_jerk_speed(1.0, 1.0, 1.0) == 0.0


def test_mtm1_durations():
    assert timing.TMU == pytest.approx(0.036)
    assert timing.reach_time(10 * timing.INCH, "B") == pytest.approx(11.5 * 0.036)  # R10B: 11.5 TMU
    assert timing.reach_time(30 * timing.INCH, "A") == pytest.approx(17.5 * 0.036)
    assert timing.reach_time(10 * timing.INCH, "C") > timing.reach_time(10 * timing.INCH, "B")  # more precision
    assert timing.move_time(20 * timing.INCH, "B", 0.0) == pytest.approx(18.2 * 0.036)
    # 10 kg = 22 lb: dynamic factor 1.22, static 7.4 TMU
    assert timing.move_time(20 * timing.INCH, "B", 10.0) == pytest.approx((18.2 * 1.22 + 7.4) * 0.036)
    assert timing.walk_time(2) == pytest.approx(2 * 15 * 0.036)


def test_mtm1_weight_per_hand_and_side_step():
    """Checked against transcriptions of the MTM-1 card (docs/guide/operations.md, "Timing"): the weight allowance
    is per hand, and a sideways step is the card's side step SS-C2, not a walking pace."""
    # 20 kg in two hands: 10 kg (22 lb) per hand, the 22.5 lb row (x 1.22 + 7.4 TMU), not the 47.5 lb row
    assert timing.move_time(20 * timing.INCH, "B", 20.0, hands=2) == pytest.approx((18.2 * 1.22 + 7.4) * 0.036)
    assert timing.move_time(20 * timing.INCH, "B", 20.0) == pytest.approx((18.2 * 1.50 + 16.0) * 0.036)
    assert timing.side_step_time(0.30) == pytest.approx(34.1 * 0.036)  # SS-C2, 30 cm
    assert timing.side_step_time(0.40) == pytest.approx((34.1 + 0.4 * 10) * 0.036)  # 0.4 TMU per cm beyond


def test_box_both_hands_close_on_stays_an_obstacle(tmp_path):
    """While both hands close on the box it is an obstacle narrowed 3 cm on each side face (room for the palms;
    left out, the trunk bent by the behaviour model leaned into it), not left out."""
    from solver.operations.posing import Poser

    job = load_operations(write(tmp_path, GET_PLACE))
    poser = Poser(job.scenario.problem, job.plan)
    closing = next(s for s in job.plan.segments if s.taking is not None)
    problem = poser.problem_at(0.5 * (closing.t0 + closing.t1))
    boxes = [ob for ob in problem.obstacles if ob.name == "box"]
    assert len(boxes) == 1
    assert np.asarray(boxes[0].size) == pytest.approx([0.30 - 0.06, 0.22 - 0.06, 0.24])


def test_grasps_proposed_and_said(tmp_path):
    job = load_operations(write(tmp_path, GET_PLACE))
    box = job.objects["box"]
    assert set(box.grasps) == {"both sides", "hand_r side", "hand_l side"}
    both = box.grasps["both sides"]
    # across the narrower horizontal side (x, 0.30 m): palms 2.7 cm outside the faces
    assert both.hands["hand_r"].position[0] == pytest.approx(-0.177)
    assert both.hands["hand_l"].position[0] == pytest.approx(0.177)
    assert any("proposed" in note and "both sides" in note for note in job.notes)
    assert job.plan.duration > 1.0
    labels = [label for label, _, _ in job.plan.spans]
    assert labels == ["operations[0] (get box)", "operations[1] (place box)"]


def test_given_grasp_read(tmp_path):
    extra = """
[[objects.grasps]]
name = "right only"
hand_r = { position = [-0.177, 0.0, 0.0], rotation = [0.7071068, 0.0, 0.7071068, 0.0] }
"""
    job = load_operations(write(tmp_path, GET_PLACE, extra=extra))
    assert list(job.objects["box"].grasps) == ["right only"]
    assert not any("proposed" in note for note in job.notes)


BAD = {
    "unknown object": ('[[operations]]\ndo = "get"\nobject = "crate"\n',
                       "operations[0] (get crate): no object named 'crate'"),
    # a place 2.5 m away is stepped to now (test_far_place_steps_first); 2.5 m up is out of anyone's reach
    "unreachable place": (GET_PLACE.replace("[0.25, -0.45, 0.871]", "[0.25, -0.45, 2.5]"),
                          "operations[1] (place box): the place for box"),
    "grasp inside an obstacle": (GET_PLACE, "operations[0] (get box): grasp 'both sides' of box: hand_r would be "
                                            "inside post"),
    "place inside an obstacle": (GET_PLACE.replace("[0.25, -0.45, 0.871]", "[0.0, -0.55, 0.75]"),
                                 "operations[1] (place box): box placed at"),
}
POST = '\n[[obstacles]]\nname = "post"\nkind = "box"\ncenter = [-0.19, -0.45, 0.87]\nsize = [0.03, 0.03, 0.3]\n'


@pytest.mark.parametrize("case", list(BAD))
def test_bad_operation_is_one_line_exit_2(tmp_path, capsys, case):
    operations, expected = BAD[case]
    extra = POST if case == "grasp inside an obstacle" else ""
    path = tmp_path / "ops.toml"
    text = HEAD.format(fps=24)
    path.write_text(text.replace("[[objects]]", extra + "[[objects]]", 1) + operations, encoding="utf-8")
    assert main(["operate", str(path), "-o", str(tmp_path / "out"), "-q"]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and expected in err, err


def test_get_place_end_to_end(tmp_path):
    """A short get and place solved every frame: converged, no penetration, the result file as a motion's. The box
    is pushed forward on the table: placed to the side, the right forearm is pinched between the box and the trunk and
    cuts into the lumbar between two frames on some CPUs (docs/guide/operations.md, "Known limits")."""
    forward = GET_PLACE.replace("[0.25, -0.45, 0.871]", "[0.0, -0.62, 0.871]")
    path = write(tmp_path, forward, fps=12, extra="[motion]\nmax_joint_change = 0.6\nmax_root_shift = 0.15\n")
    out = tmp_path / "out"
    code = main(["operate", str(path), "-o", str(out), "-q"])
    summary = (out / "summary.txt").read_text()
    assert code == 0, summary
    frames = json.loads((out / "result.json").read_text())["frames"]
    assert_clean(frames)
    assert "cycle time" in summary and "operations[1] (place box)" in summary
    assert np.isfinite([f["frame"] for f in frames]).all()


def assert_clean(frames: list[dict]) -> None:
    """Every frame converged, nothing penetrates (floor, obstacles, self) and nothing sweeps through anything
    between frames (the swept check's crossings are unmet rows and notes)."""
    assert frames and all(f["converged"] for f in frames), [(f["frame"], f["unmet"]) for f in frames if f["unmet"]]
    for f in frames:
        shortfall = [f["residuals"][k] for k in ("floor.shortfall", "obstacles.shortfall") if k in f["residuals"]]
        assert max(shortfall, default=0.0) < 1e-3, (f["frame"], f["residuals"])
        crossed = [s for s in [*f["unmet"], *f["broken"], *f["notes"]] if "between frames" in s]
        assert not crossed, (f["frame"], crossed)


def test_far_place_steps_first(tmp_path):
    """A place beyond a comfortable planted reach: the manikin walks up and the stance finder takes the last step
    (noted in the summary), then places; every frame clean."""
    far = GET_PLACE.replace("[0.25, -0.45, 0.871]", "[-1.6, -0.45, 0.871]")
    extra = ('[[obstacles]]\nname = "far table"\nkind = "box"\ncenter = [-1.6, -0.55, 0.73]\n'
             "size = [0.8, 0.5, 0.04]\n")
    path = write(tmp_path, far, fps=12, extra=extra + "[motion]\nmax_joint_change = 0.6\nmax_root_shift = 0.15\n")
    out = tmp_path / "out"
    code = main(["operate", str(path), "-o", str(out), "-q"])
    summary = (out / "summary.txt").read_text()
    assert code == 0, summary
    assert "operations[1] (place box): stepped first to a stance found for it" in summary
    result = json.loads((out / "result.json").read_text())["frames"]
    assert_clean(result)
    feet = np.array([f["tcps"]["foot_r"]["position"] for f in result])
    assert feet[-1][0] < -1.0  # it walked there


PRESETS = Path(__file__).resolve().parents[3] / "presets" / "operations"


def test_bin_to_fixture_preset_end_to_end(tmp_path):
    """The one-handed preset (a part from a bin into a fixture, four operations) from its file alone: every frame
    converged, nothing penetrates or sweeps through anything (the other presets: bench/operations.py)."""
    out = tmp_path / "out"
    code = main(["operate", str(PRESETS / "bin_to_fixture.toml"), "-o", str(out), "-q"])
    summary = (out / "summary.txt").read_text()
    assert code == 0, summary
    assert "operations[3] (place part)" in summary and "4 operations" in summary
    assert_clean(json.loads((out / "result.json").read_text())["frames"])
