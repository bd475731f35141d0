"""The scenes with obstacles: the cabinet reach and the box lift (shelf, table, a box carried by its sides), and the
carried box as a clearance the solver keeps (every body part but the holding hands stays out of it).

Every check recomputes distances from the result JSON alone (the capsules it lists, the obstacles of the
scenario), or from the solved pose, independently of the solver's own clearance rows.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from collision_check import box_edges as edges_of
from collision_check import carried_distance, carried_obstacle

import solver
from solver.body.spatial import quat_to_matrix
from solver.collision import Box, HalfSpace, Mesh, box_distance, obstacle_distance
from solver.collision.body import capsules_of
from solver.collision.carried import Carried, carried_box, carried_frame
from solver.errors import ScenarioError
from solver.io.scenario.bodies import load_body
from solver.problem.priorities import ranked
from solver.problem.problem import Problem, ProblemSpec, Target

SCENARIOS = Path(__file__).resolve().parents[3] / "presets" / "scenarios"
TOLERANCE = 1e-3  # m: no penetration beyond this
FLOOR = HalfSpace(np.zeros(3), np.array([0.0, 0.0, 1.0]), name="floor")


def solved_frames(path: Path, tmp_path: Path) -> tuple[solver.Scenario, list[dict]]:
    """The scenario and the frames of its result JSON."""
    scenario = solver.load_scenario(path)
    out = tmp_path / "result.json"
    solver.write_result(out, list(solver.solve_motion(scenario)), scenario.path)
    return scenario, json.loads(out.read_text(encoding="utf-8"))["frames"]


def capsules(frame: dict) -> tuple[list[str], np.ndarray, np.ndarray, np.ndarray]:
    shapes = frame["collision_shapes"]
    p0, p1 = (np.array([s[k] for s in shapes]) for k in ("start", "end"))
    return [s["link"] for s in shapes], p0, p1, np.array([s["radius"] for s in shapes])


def box_edges(box: Box) -> tuple[np.ndarray, np.ndarray]:
    """The 12 edges of ``box`` as segments (world, m), by the independent check's own construction."""
    return edges_of(dict(center=box.center, size=box.size, rotation_matrix=box.rotation))


def assert_clear_of_obstacles(scenario: solver.Scenario, frames: list[dict]) -> None:
    for frame in frames:
        links, p0, p1, radii = capsules(frame)
        for obstacle in [*scenario.problem.obstacles, FLOOR]:
            distance = obstacle_distance(p0, p1, radii, obstacle).distance
            worst = int(np.argmin(distance))
            assert distance[worst] >= -TOLERANCE, (frame["frame"], links[worst], obstacle.name, distance[worst])
        listed = [c for c in frame["closest"] if c["other"] in {ob.name for ob in scenario.problem.obstacles}]
        assert all(c["distance"] >= c["clearance"] - TOLERANCE for c in listed), frame["frame"]


def test_the_cabinet_reach_converges_inside_the_cabinet_without_touching_it(tmp_path):
    scenario, frames = solved_frames(SCENARIOS / "cabinet_reach.toml", tmp_path)
    (frame,) = frames
    assert frame["converged"]
    hand = np.array(frame["tcps"]["hand_r"]["position"])
    assert np.allclose(hand, scenario.problem.all_targets[0].position, atol=1e-3)
    assert_clear_of_obstacles(scenario, frames)
    assert any(c["other"] == "cabinet shelf" for c in frame["closest"])  # the shelf board's edge is in the way


def test_the_box_lift_holds_the_box_by_its_sides_between_a_shelf_and_a_table(tmp_path):
    scenario, frames = solved_frames(SCENARIOS / "box_lift_motion.toml", tmp_path)
    assert [f["frame"] for f in frames] == list(range(1, 61)) and all(f["converged"] for f in frames)
    names = {ob.name for ob in scenario.problem.obstacles}
    assert {"shelf", "table"} <= names
    assert_clear_of_obstacles(scenario, frames)
    carried = scenario.carried
    assert carried is not None and carried.tcps == ("hand_r", "hand_l")
    shelf, table = (next(ob for ob in scenario.problem.obstacles if ob.name == n) for n in ("shelf", "table"))
    boxes = []
    for frame in frames:
        tcps = frame["tcps"]
        box = carried_box(carried, *(np.array(tcps[t]["position"]) for t in carried.tcps))
        boxes.append(box)
        links, p0, p1, radii = capsules(frame)
        distance = box_distance(p0, p1, radii, box).distance
        worst = int(np.argmin(distance))
        assert distance[worst] >= -TOLERANCE, (frame["frame"], links[worst], distance[worst])
        for side in ("r", "l"):  # the hands on the box's sides: within 1.5 cm of them, not through
            d = distance[links.index(f"hand_{side}")]
            assert -TOLERANCE <= d <= 0.015, (frame["frame"], side, d)
            assert distance[links.index(f"forearm_{side}")] >= -TOLERANCE
        for obstacle in (shelf, table):  # the box does not go through the shelf or the table either
            a, b = box_edges(box)
            assert box_distance(a, b, np.zeros(len(a)), obstacle).distance.min() >= -TOLERANCE
            a, b = box_edges(obstacle)
            assert box_distance(a, b, np.zeros(len(a)), box).distance.min() >= -TOLERANCE
        assert np.allclose(frame["carried"]["center"], box.center) and frame["carried"]["excluded"] == [
            "hand_r",
            "hand_l",
        ]
    near = {c["part"] for frame in frames for c in frame["closest"] if c["other"] == "box"}
    assert {"forearm_r", "forearm_l"} <= near  # the solver sees the box: the wrists pass just outside its sides
    bottom = [b.center[2] - b.half[2] for b in boxes]
    assert bottom[0] == pytest.approx(shelf.center[2] + shelf.half[2], abs=0.01)  # starts standing on the shelf
    assert bottom[-1] == pytest.approx(table.center[2] + table.half[2], abs=0.01)  # ends standing on the table


def solved_pose(problem: Problem, tmp_path: Path) -> tuple[solver.Result, dict]:
    """``problem`` solved, and its frame as the result JSON gives it."""
    result = solver.solve(problem)
    out = tmp_path / "result.json"
    solver.write_result(out, result)
    (frame,) = json.loads(out.read_text(encoding="utf-8"))["frames"]
    return result, frame


def held_low(model, carried: Carried | None) -> Problem:
    """Feet on the floor, the palms on the sides of a box held low in front of the hips (hands at 0.8 m, 15 cm
    ahead of the ankles: a box 30 cm deep reaches back over the hips)."""
    targets = [Target(f"foot_{s}", np.array([x, 0.0, 0.0]), lock=("z", "rx", "ry"), support=True)
               for s, x in (("r", -0.083), ("l", 0.083))]  # fmt: skip
    for side, x, turn in (("r", -0.202, 1.0), ("l", 0.202, -1.0)):
        palm = quat_to_matrix(np.array([np.sqrt(0.5), 0.0, turn * np.sqrt(0.5), 0.0]))  # its normal towards the box
        targets.append(Target(f"hand_{side}", np.array([x, -0.15, 0.8]), palm, lock=("x", "y", "z", "rx", "ry")))
    return Problem(model, ProblemSpec(targets, carried=carried))


def box_gaps(model, result, carried: Carried) -> dict[str, float]:
    """Each capsule's surface distance (m) to the box between the solved hands, recomputed from the pose."""
    kin = result.state.kin
    capsules = capsules_of(model)
    box = carried_box(carried, *(kin.tcp_frame(model.tcp(t))[1] for t in carried.tcps))
    distance = box_distance(*capsules.world(kin), capsules.radius, box).distance
    return dict(zip(capsules.names, distance.tolist(), strict=True))


def test_the_body_keeps_out_of_a_box_carried_low_in_front_of_the_hips():
    """Unseen, the box would hold the hips and thighs 14-16 cm deep inside it; seen, the body moves out of it (the
    hips back), converged, every part but the holding hands at least at the box's surface, the nearest listed."""
    model = load_body(preset="male_50")
    box = Carried(np.array([0.35, 0.30, 0.24]), ("hand_r", "hand_l"), "box")
    unseen = box_gaps(model, solver.solve(held_low(model, None)), box)
    assert unseen["pelvis"] < -0.1 and unseen["thigh_r"] < -0.1
    result = solver.solve(held_low(model, box))
    assert result.converged and not result.unmet
    seen = box_gaps(model, result, box)
    assert min(d for part, d in seen.items() if part not in ("hand_r", "hand_l")) >= -TOLERANCE, seen
    assert "pelvis vs box" in {c.pair for c in result.closest}


def test_a_box_too_big_to_hold_leaves_a_hand_short_not_the_body_inside():
    """Priority 1 like every clearance: a box 1.4 m deep and 1 m high between hands 15 cm ahead of the ankles cannot
    be held with the body out of it; the ranked solve leaves a hand short (priority 2) and the body out."""
    model = load_body(preset="male_50")
    box = Carried(np.array([0.35, 1.4, 1.0]), ("hand_r", "hand_l"), "box")
    problem = held_low(model, box)
    assert problem.carried_constraint in ranked(problem).constraints
    result = solver.solve(problem)
    assert not result.converged and result.broken == [] and set(result.unmet) <= {"hand_r", "hand_l"}
    assert result.shortfall and max(s["position_m"] for s in result.shortfall.values()) > 0.05
    seen = box_gaps(model, result, box)
    assert min(d for part, d in seen.items() if part not in ("hand_r", "hand_l")) >= -TOLERANCE, seen


def test_hands_set_the_box_down_inside_a_table_leave_it_on_the_table_top(tmp_path):
    """Hand targets that would sink the box's bottom 4 cm into a table top end unmet (priority 2): the box rests on
    the table top, recomputed from the result JSON alone (the box from its hands, its edges against the table's and
    the table's against it), and the result lists "box vs table" among the closest pairs."""
    model = load_body(preset="male_50")
    box = Carried(np.array([0.35, 0.30, 0.24]), ("hand_r", "hand_l"), "box")
    table = Box(np.array([0.0, -0.35, 0.70]), np.array([0.8, 0.5, 0.04]), name="table")  # top at 0.72 m
    problem = Problem(model, ProblemSpec(held_low(model, box).all_targets, carried=box, obstacles=[table]))
    result, frame = solved_pose(problem, tmp_path)
    assert not result.converged and set(result.unmet) == {"hand_r", "hand_l"}
    placed = carried_box(box, *(np.array(frame["tcps"][t]["position"]) for t in box.tcps))
    a, b = box_edges(placed)
    gap = box_distance(a, b, np.zeros(12), table).distance.min()
    a, b = box_edges(table)
    assert min(gap, box_distance(a, b, np.zeros(12), placed).distance.min()) >= -TOLERANCE
    assert gap <= 0.002  # on the top, not held above it
    assert frame["tcps"]["hand_r"]["position"][2] == pytest.approx(0.84, abs=0.002)  # 4 cm above its target
    assert "box vs table" in {c["pair"] for c in frame["closest"]}


def spike(tip, height: float = 0.3, half: float = 0.1) -> Mesh:
    """A closed square pyramid standing on the floor side, its tip (m) up: base ``half`` (m) wide each way,
    ``height`` (m) below the tip."""
    tip = np.asarray(tip, dtype=float)
    base = [tip + [x * half, y * half, -height] for x, y in ((-1, -1), (1, -1), (1, 1), (-1, 1))]
    faces = [[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4], [0, 2, 1], [0, 3, 2]]  # counter-clockwise from outside
    return Mesh(np.array([*base, tip]), np.array(faces), name="spike")


def test_a_mesh_corner_poking_into_the_middle_of_a_box_face_is_measured():
    """A pyramid's tip 1 cm up into the middle of the box's bottom face touches none of the box's edges; the rows
    see it (the mesh's own edges against the box) at -1 cm, and the box counts as inside it."""
    model = load_body(preset="male_50")
    box = Carried(np.array([0.35, 0.30, 0.24]), ("hand_r", "hand_l"), "box")
    centre, rotation = np.array([0.0, -0.3, 0.9]), np.eye(3)
    pyramid = spike(centre - [0.0, 0.0, 0.11])
    rows = Problem(model, ProblemSpec(held_low(model, box).all_targets, carried=box, obstacles=[pyramid]))
    rows = rows.carried_obstacle_constraint
    a, b = box_edges(Box(centre, box.size, rotation))
    assert obstacle_distance(a, b, np.zeros(12), pyramid).distance.min() > 0.05  # the box's edges are far from it
    distance, on_box, normal, on_other = rows.gaps(centre, rotation)
    deepest = int(np.argmin(distance))
    assert distance[deepest] == pytest.approx(-0.01, abs=1e-9)
    assert np.allclose(normal[deepest], [0.0, 0.0, 1.0]) and np.allclose(on_other[deepest], pyramid.vertices[4])
    assert np.allclose(on_box[deepest], pyramid.vertices[4] - [0.0, 0.0, 0.01])  # on the bottom face, under the tip
    assert rows.inside(centre, rotation, 1e-3) == ["spike"]
    assert rows.inside(centre + [0.0, 0.0, 0.02], rotation, 1e-3) == []


def test_hands_set_the_box_down_onto_a_spike_leave_it_on_the_tip(tmp_path):
    """Hand targets that would push a pyramid's tip 4 cm up into the middle of the box's bottom face end unmet: the
    box rests on the tip, recomputed from the result JSON by the independent check (the mesh's edges against the
    box too). The default (behaviour) model: its semi-squat start passes this; the deep crouch it started from before
    held the box beside the spike below its tip (docs/TUNING.md, "The semi-squat revision")."""
    model = load_body(preset="male_50")
    box = Carried(np.array([0.35, 0.30, 0.24]), ("hand_r", "hand_l"), "box")
    pyramid = spike([0.0, -0.24, 0.72], height=0.2, half=0.04)  # the box's bottom held at 0.68 m
    problem = Problem(model, ProblemSpec(held_low(model, box).all_targets, carried=box, obstacles=[pyramid]))
    result, frame = solved_pose(problem, tmp_path)
    assert not result.converged and set(result.unmet) == {"hand_r", "hand_l"}
    placed, _, wrong = carried_obstacle(frame)
    table = dict(kind="mesh", name="spike", triangles=pyramid.vertices[pyramid.faces], closed=True, clearance=0.0)
    assert wrong == [] and -TOLERANCE <= carried_distance(placed, table) <= 0.002  # on the tip, not above it
    assert frame["carried"]["center"][2] == pytest.approx(0.84, abs=0.002)  # 4 cm above where the hands would hold it
    assert "box vs spike" in {c["pair"] for c in frame["closest"]}


def test_the_box_stays_above_the_floor():
    """The floor is an obstacle for the box too: hands held 5 cm above it would put the box's bottom 7 cm below."""
    model = load_body(preset="male_50")
    box = Carried(np.array([0.35, 0.30, 0.24]), ("hand_r", "hand_l"), "box")
    targets = [t if not t.tcp.startswith("hand") else Target(t.tcp, t.position * [1, 1, 0] + [0, -0.25, 0.05],
               t.rotation, lock=t.lock) for t in held_low(model, box).all_targets]  # fmt: skip
    result = solver.solve(Problem(model, ProblemSpec(targets, carried=box)))
    kin = result.state.kin
    placed = carried_box(box, *(kin.tcp_frame(model.tcp(t))[1] for t in box.tcps))
    a, b = box_edges(placed)
    assert obstacle_distance(a, b, np.zeros(12), FLOOR).distance.min() >= -TOLERANCE
    assert "hand_r" in result.unmet


def plate_drop(resolve: bool, plate_y: float = -0.15) -> dict:
    """Two frames solved with no per-frame bound: the box held 13 cm above a thin plate (between the hands), then
    where it would be 8 cm below it. {frame: result}."""
    from solver.motion.between_frames import MotionSweep
    from solver.motion.frames import solve_frames

    model = load_body(preset="male_50")
    box = Carried(np.array([0.35, 0.30, 0.24]), ("hand_r", "hand_l"), "box")
    plate = Box(np.array([0.0, plate_y, 0.75]), np.array([0.2, 0.2, 0.01]), name="plate")

    def held_at(height: float) -> Problem:
        targets = [t if not t.tcp.startswith("hand") else Target(t.tcp, t.position * [1, 1, 0] + [0, 0, height],
                   t.rotation, lock=t.lock) for t in held_low(model, box).all_targets]  # fmt: skip
        return Problem(model, ProblemSpec(targets, carried=box, obstacles=[plate]))

    problems = {1: held_at(1.0), 2: held_at(0.55)}
    start = problems[1].start(None)
    return dict(solve_frames(problems.get, [1, 2], start, limits=None, sweep=MotionSweep(resolve=resolve)))


def test_a_box_dropped_through_a_plate_between_two_frames_is_named_when_not_re_solved():
    """Each frame alone is clear of the plate; the way between is not, and the frame names it. The plate moved out
    of the way: both converge."""
    frames = plate_drop(resolve=False)
    assert frames[1].converged and not frames[2].converged
    assert frames[2].unmet == ["box passes through plate between frames 1 and 2"]
    assert all(f.converged for f in plate_drop(resolve=False, plate_y=0.6).values())


def test_a_box_dropped_through_a_plate_between_two_frames_is_re_solved_in_sub_steps_and_stops_on_it():
    """By default the frame is solved again in sub-steps: the box comes down onto the plate and stays there, the
    hands short of their targets (not converged, nothing passes through), the note saying so."""
    frame = plate_drop(resolve=True)[2]
    assert not frame.converged and set(frame.unmet) == {"hand_r", "hand_l"}
    kin, model = frame.state.kin, frame.problem.model
    placed = carried_box(frame.problem.carried, *(kin.tcp_frame(model.tcp(t))[1] for t in ("hand_r", "hand_l")))
    assert placed.center[2] - placed.half[2] == pytest.approx(0.755, abs=0.002)  # on the plate's top
    assert any("went box through plate" in note and "re-solved" in note for note in frame.notes), frame.notes


def test_every_frame_of_a_motion_keeps_the_carried_box():
    """problem_at shares the carried box's rows across frames; other supports (a new problem) keep it too."""
    scenario = solver.load_scenario(SCENARIOS / "box_lift_motion.toml")
    rows = scenario.problem.carried_constraint
    assert rows is not None and rows.carried is scenario.carried and rows.excluded == ("hand_r", "hand_l")
    assert all(scenario.problem_at(f).carried_constraint is rows for f in (1, 30, 60))
    assert rows in scenario.problem_at(30).constraints
    one_foot = [t for t in scenario.problem.all_targets if t.tcp != "foot_l"]
    again = scenario.problem.with_targets(one_foot)
    assert again.carried_constraint is not rows and again.carried_constraint.carried is scenario.carried


def test_the_carried_frame_is_upright_between_the_two_points():
    centre, rotation = carried_frame([0.0, 0.0, 1.0], [0.4, 0.0, 1.2])
    assert np.allclose(centre, [0.2, 0.0, 1.1])
    assert np.allclose(rotation.T @ rotation, np.eye(3)) and np.linalg.det(rotation) > 0
    assert np.allclose(rotation[:, 0], np.array([0.4, 0.0, 0.2]) / np.hypot(0.4, 0.2))
    assert rotation[2, 2] > 0.89 and abs(rotation[:, 2] @ rotation[:, 0]) < 1e-12
    _, vertical = carried_frame([0.0, 0.0, 0.0], [0.0, 0.0, 1.0])  # hands one above the other: still a rotation
    assert np.allclose(vertical.T @ vertical, np.eye(3))


def test_carried_is_written_back_and_read_again(tmp_path):
    scenario = solver.load_scenario(SCENARIOS / "box_lift_motion.toml")
    data = solver.scenario_to_dict(scenario.problem, {"preset": "male_50"})  # the problem's own carried box
    path = tmp_path / "again.toml"
    solver.write_scenario(path, data)
    again = solver.load_scenario(path).carried
    assert isinstance(again, Carried) and again.name == "box" and again.tcps == ("hand_r", "hand_l")
    assert np.allclose(again.size, [0.35, 0.26, 0.24])
    assert solver.load_scenario(SCENARIOS / "box_lift.toml").carried is None


@pytest.mark.parametrize(
    ("entry", "says"),
    [
        ('size = [0.3, 0.2]\ntcps = ["hand_r", "hand_l"]', "carried.size: expected 3 finite numbers"),
        ('size = [0.3, 0.0, 0.2]\ntcps = ["hand_r", "hand_l"]', "carried.size: expected 3 edge lengths > 0"),
        ('size = [0.3, 0.2, 0.2]\ntcps = ["hand_r"]', "carried.tcps: expected two TCPs of the manikin"),
        ('size = [0.3, 0.2, 0.2]\ntcps = ["hand_r", "paw"]', "carried.tcps: expected two TCPs of the manikin"),
        ('size = [0.3, 0.2, 0.2]\ntcps = ["hand_r", "hand_r"]', "carried.tcps: expected two different TCPs"),
        ('size = [0.3, 0.2, 0.2]\ntcps = ["hand_r", "hand_l"]\nmass = 3', "mass"),
        ('tcps = ["hand_r", "hand_l"]', "carried.size"),
    ],
)
def test_a_bad_carried_table_is_one_line(tmp_path, entry: str, says: str):
    base = (SCENARIOS / "box_lift.toml").read_text(encoding="utf-8")
    path = tmp_path / "bad.toml"
    path.write_text(base + "\n[carried]\n" + entry + "\n", encoding="utf-8")
    with pytest.raises(ScenarioError) as info:
        solver.load_scenario(path)
    message = str(info.value)
    assert "\n" not in message and says in message and str(path) in message
