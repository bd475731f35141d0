"""The I/O layer through the public API (``import solver``; the scenario TOML round trip is in
test_scenario_export): the result JSON round trip, the typed frames of a Result equal those read back from its file,
the ergonomics of a Result equal those of its file, and bad input is one line of the error hierarchy naming the
file and the key."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from helpers import leaves, same_frames

import solver
from solver.errors import ManikinError, ModelError, ResultFileError, ScenarioError, UsageError

PRESETS = Path(__file__).resolve().parents[3] / "presets"
BOX_LIFT = PRESETS / "scenarios" / "box_lift.toml"
SNAKE_MOTION = PRESETS / "scenarios" / "snake_motion.toml"


@pytest.fixture(scope="module")
def box_lift() -> tuple[solver.Scenario, solver.Result]:
    scenario = solver.load_scenario(BOX_LIFT)
    return scenario, solver.solve(scenario.problem, scenario.start, scenario.options)


@pytest.fixture(scope="module")
def result_file(box_lift, tmp_path_factory) -> Path:
    scenario, result = box_lift
    return solver.write_result(tmp_path_factory.mktemp("io") / "box_lift.json", [(7, result)], scenario.path)






# ---------------------------------------------------------------------------------------------- round trips


def test_result_file_read_back_gives_the_frames_of_the_result(box_lift, result_file: Path) -> None:
    scenario, result = box_lift
    read = solver.read_result(result_file)
    assert read.scenario == str(scenario.path) and read.path == result_file and len(read.frames) == 1
    same_frames(read.frames[0], solver.frame_of_result(result, 7))
    assert json.loads(result_file.read_text())["frames"][0] == json.loads(json.dumps(solver.result_to_dict(result, 7)))


def test_evaluating_a_result_equals_evaluating_its_file(box_lift, result_file: Path) -> None:
    _, result = box_lift
    model = result.problem.model
    direct = solver.evaluate([(7, result)], model=model)
    from_file = solver.evaluate(solver.read_result(result_file), model=model)
    assert direct["frames"][0]["frame"] == 7 and direct["result"] is None and from_file["result"] == str(result_file)
    assert leaves(direct["frames"]) == pytest.approx(leaves(from_file["frames"]), rel=1e-9, abs=1e-12)
    assert leaves(direct["niosh"]) == pytest.approx(leaves(from_file["niosh"]), rel=1e-9, abs=1e-12)
    assert direct["working_area"] is not None  # the result's own manikin gives the working area
    own = solver.evaluate(result)
    assert own["manikin"] == f"model {model.name} of the result" and own["frames"][0]["rula"]["score"] >= 1
    by_name = solver.evaluate(solver.read_result(result_file))  # the scenario named in the file gives the manikin
    assert by_name["manikin"].startswith("manikin of scenario") and by_name["working_area"] == own["working_area"]


def test_a_motion_loads_solves_and_evaluates_frame_by_frame(tmp_path: Path) -> None:
    motion = solver.load_motion(SNAKE_MOTION)
    short = solver.Scenario(**{**vars(motion), "frames": motion.frames[:3]})
    solved = list(solver.solve_motion(short))
    assert [frame for frame, _ in solved] == motion.frames[:3]
    report = solver.evaluate(solved)
    assert [f["frame"] for f in report["frames"]] == motion.frames[:3]
    read = solver.read_result(solver.write_result(tmp_path / "m.json", solved, motion.path))
    for frame, (number, result) in zip(read.frames, solved, strict=True):
        same_frames(frame, solver.frame_of_result(result, number))


def test_load_preset_takes_a_name_or_a_body_file(tmp_path: Path) -> None:
    assert solver.load_preset("male_50").name == "male_50"
    body = tmp_path / "tall.toml"
    body.write_text('[body]\nkind = "human"\nsex = "female"\nstature = 1.80\nmass = 70.0\n', encoding="utf-8")
    assert (
        solver.load_preset(body).name == "tall" and solver.load_preset(str(body)).n == solver.load_preset("male_50").n
    )
    with pytest.raises(ModelError, match="male_51"):
        solver.load_preset("male_51")


# ---------------------------------------------------------------------------------------------- bad input


def one_line(exc: pytest.ExceptionInfo, *words: str) -> str:
    message = str(exc.value)
    assert isinstance(exc.value, ManikinError) and "\n" not in message, message
    for word in words:
        assert word in message, f"{word!r} not in {message!r}"
    return message


def test_a_single_pose_is_not_a_motion() -> None:
    with pytest.raises(ScenarioError) as exc:
        solver.load_motion(BOX_LIFT)
    one_line(exc, str(BOX_LIFT), "motion", "keyed targets")


@pytest.mark.parametrize(
    ("change", "key", "expected"),
    [
        (('preset = "male_50"', 'preset = "male_50"\nfile = "x.toml"'), "manikin.preset", "exactly one of"),
        (("[solver]", "[solver]\nrestarts = 99"), "solver.restarts", "a whole number in [0, 10]"),
        (("[solver]", "[comfort]\nrange = -1\n\n[solver]"), "comfort.range", "a number in [0, 100]"),
        (('tcp = "hand_r"', 'tcp = "hand_q"'), "targets[0].tcp", "a TCP of the manikin"),
        (('lock = ["x", "y", "z", "rx", "ry"]', 'lock = ["x", "w"]'), "targets[0].lock", "a list of axes"),
        (("mass = 5.0", 'mass = "heavy"'), "loads[0].mass", "a number in [0, 100000] kg"),
        (("[solver]", "[start.joints]\nknee_q = 0.1\n\n[solver]"), "start.joints.knee_q", "a joint name"),
    ],
)
def test_bad_scenarios_name_file_and_key(tmp_path: Path, change: tuple[str, str], key: str, expected: str) -> None:
    text = BOX_LIFT.read_text(encoding="utf-8")
    assert change[0] in text
    path = tmp_path / "bad.toml"
    path.write_text(text.replace(change[0], change[1], 1), encoding="utf-8")
    with pytest.raises(ScenarioError) as exc:
        solver.load_scenario(path)
    one_line(exc, f"{path}: {key}: expected {expected}")


@pytest.mark.parametrize(
    ("keys", "value", "where", "expected"),
    [
        ((), {"frames": []}, "frames", "a non-empty array of tables"),
        (("links",), None, "frames[0].links", "a value (missing)"),
        (("links", 2, "mass"), -1.0, "frames[0].links[2].mass", "a number in [0, 10000] kg"),
        (("joints", "root_tx", "axis"), [0, 0], "frames[0].joints.root_tx.axis", "3 finite numbers"),
        (("joints", "root_tx", "axis"), [0, 0, 0], "frames[0].joints.root_tx.axis", "a non-zero vector"),
        (("joints", "root_tx", "link"), "nowhere", "frames[0].joints.root_tx.link", "one of the links' names"),
        (("joints", "root_tx", "strength"), [1], "frames[0].joints.root_tx.strength", "[negative, positive]"),
        (("tcps", "hand_r", "rotation"), [0, 0, 0, 0], "frames[0].tcps.hand_r.rotation", "a non-zero quaternion"),
        (("loads", 0, "tcp"), "paw", "frames[0].loads[0].tcp", "a TCP name"),
        (("contacts", "paw"), {}, "frames[0].contacts.paw", "a contact at one of the TCPs"),
        (("gravity",), [0, 0, "down"], "frames[0].gravity", "3 finite numbers"),
    ],
)
def test_bad_result_files_name_file_and_key(result_file: Path, tmp_path: Path, keys, value, where, expected) -> None:
    data = json.loads(result_file.read_text(encoding="utf-8"))
    if not keys:
        data = value
    else:
        table = data["frames"][0]
        for key in keys[:-1]:
            table = table[key]
        if value is None:
            del table[keys[-1]]
        else:
            table[keys[-1]] = value
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(data), encoding="utf-8")
    with pytest.raises(ResultFileError) as exc:
        solver.read_result(path)
    message = one_line(exc, str(path), where, f"expected {expected}")
    assert message.index(str(path)) == 0


@pytest.mark.parametrize(("text", "says"), [(None, "file not found"), ("{oops", "not JSON"), ("[1]", "JSON object")])
def test_unreadable_result_files_are_one_line(tmp_path: Path, text: str | None, says: str) -> None:
    path = tmp_path / "r.json"
    if text is not None:
        path.write_text(text, encoding="utf-8")
    with pytest.raises(ResultFileError) as exc:
        solver.read_result(path)
    one_line(exc, str(path), says)


def test_bad_ergonomics_options_are_a_usage_error(box_lift) -> None:
    with pytest.raises(UsageError) as exc:
        solver.evaluate(box_lift[1], solver.ErgoOptions(coupling="sticky"))
    one_line(exc, "options: coupling")


def test_every_user_error_is_a_manikin_error() -> None:
    for error in (ModelError, ScenarioError, ResultFileError, UsageError):
        assert issubclass(error, ManikinError) and getattr(solver, error.__name__) is error
