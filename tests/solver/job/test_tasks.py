"""A job of several tasks ([[tasks]]): each method combines them as its published form does, checked against a
hand computation from the single-task numbers; the one-task forms agree; hand forces reach the joint moments; bad
task keys are one line naming file and key."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from solver.cli.main import main
from solver.errors import UsageError
from solver.job import read_job
from solver.job.motions import add_forces, motions_of, with_forces
from solver.job.run import evaluate_job
from solver.job.tasks import Force

REPO = Path(__file__).resolve().parents[3]
WORK = "[work]\ncycle_time = 30.0\nrepetitions = 400\nshift = 8.0\n"


def _task(name: str, result: Path, extra: str = "", load: str = "mass = 10.0\n") -> str:
    return f'[[tasks]]\nname = "{name}"\nresult = "{result}"\n{extra}[tasks.load]\n{load}'


@pytest.fixture(scope="module")
def two(short_result, tmp_path_factory, pictures_left_out) -> tuple[dict, Path]:
    """Two tasks cut from the example's box lift: a 3-frame one twice per cycle with 10 kg in both hands, a
    2-frame one 150 times a shift with 4 kg in the right hand, 2 lifts a repetition."""
    folder = tmp_path_factory.mktemp("two")
    a, b = short_result([1, 30, 60]), short_result([20, 48])
    text = (
        'name = "two"\n'
        + WORK
        + _task("lift", a, "repetitions_per_cycle = 2\n")
        + _task("reach", b, "repetitions_per_shift = 150\nlifts_per_repetition = 2\n", 'mass = 4.0\nhands = "right"\n')
    )
    path = folder / "job.toml"
    path.write_text(text)
    with pictures_left_out():  # the tests read numbers and sections; test_the_two_task_example draws them all
        assert main(["job", str(path), "-o", str(folder / "out"), "-q"]) == 0
    return json.loads((folder / "out" / "job.json").read_text()), folder / "out"


def test_lifft_and_the_shoulder_tool_sum_the_tasks_damage(two: tuple[dict, Path]) -> None:
    """CD = sum over tasks of lifts x damage per lift (Gallagher et al. 2017; LiFFT v1.4.0's multi-task sheet),
    computed here from each task's PLM with the workbook's equation written out again."""
    report = two[0]
    lift, reach = (t["methods"] for t in report["tasks"])
    assert (lift["lifft"]["lifts_per_shift"], reach["lifft"]["lifts_per_shift"]) == (800, 300)

    def damage(plm: float) -> float:  # LiFFT v1.4.0: 10^(-5.81636 + 0.0222878 M), M in ft*lb
        return 10 ** (-5.81636221052493 + 0.0222878437409416 * plm / 1.3558179483314004)

    cd = 800 * damage(lift["lifft"]["peak_load_moment_Nm"]) + 300 * damage(reach["lifft"]["peak_load_moment_Nm"])
    job = report["methods"]["lifft"]
    assert job["cumulative_damage"] == pytest.approx(cd, rel=1e-9)
    y = 1.7229 + 1.0239 * math.log10(cd)
    assert job["probability_high_risk"] == pytest.approx(math.exp(y) / (1 + math.exp(y)), rel=1e-9)
    assert report["verdicts"]["lifft"]["task"] == "lift" and "lift " in report["verdicts"]["lifft"]["text"]
    assert sum(r["share_of_damage_pct"] for r in job["per_task"]) == pytest.approx(100.0)
    # The Shoulder Tool: the right shoulder's CD is both tasks', the left only the lift's (the reach is right-handed)
    st = report["methods"]["shoulder_tool"]
    right = lift["shoulder_tool"]["shoulders"]["r"]["cumulative_damage"] + \
        reach["shoulder_tool"]["shoulders"]["r"]["cumulative_damage"]  # fmt: skip
    assert st["cumulative_damage_right"] == pytest.approx(right, rel=1e-9)
    assert st["cumulative_damage_left"] == pytest.approx(lift["shoulder_tool"]["shoulders"]["l"]["cumulative_damage"])
    assert "l" not in reach["shoulder_tool"]["shoulders"]
    # the reach: 4 kg in one hand, 2 lifts x 150 repetitions
    assert reach["shoulder_tool"]["load_per_hand_N"] == pytest.approx(4.0 * 9.81, rel=1e-3)


def test_sequence_capable_and_eaws_over_the_tasks(two: tuple[dict, Path]) -> None:
    report = two[0]
    lift, reach = (t["methods"] for t in report["tasks"])
    seq = report["methods"]["sequence"]
    for score in ("rula", "reba", "owas"):  # minutes per shift: each task's seconds x its repetitions per shift
        for i, row in enumerate(seq[score]["levels"]):
            minutes = (lift["sequence"][score]["levels"][i]["seconds"] * 800
                       + reach["sequence"][score]["levels"][i]["seconds"] * 150) / 60  # fmt: skip
            assert row["minutes_per_shift"] == pytest.approx(minutes)
        assert sum(r["percent_of_task_time"] for r in seq[score]["levels"]) == pytest.approx(100.0)
    cap = report["methods"]["capable"]
    for sex in ("men", "women"):
        assert cap[f"minimum_{sex}_pct"] == min(lift["capable"][f"minimum_{sex}_pct"],
                                                reach["capable"][f"minimum_{sex}_pct"])  # fmt: skip
    eaws = report["methods"]["eaws"]  # s per minute of the 30 s cycle: the lift twice, the reach 150/400 times
    for key, band in eaws["bands"].items():
        s = lift["eaws"]["bands"][key]["seconds"] * 2 + reach["eaws"]["bands"][key]["seconds"] * 150 / 400
        assert band["s_per_min"] == pytest.approx(60 * s / 30)
    assert eaws["handlings_per_shift"] == 800 + 300
    assert report["motion_time_s"] == pytest.approx(2 * 3 / 24 + 150 / 400 * 2 / 24)


def test_every_verdict_names_its_task_and_the_csv_and_html_have_a_section_each(two: tuple[dict, Path]) -> None:
    report, out = two
    assert all(v["task"] in ("lift", "reach") for v in report["verdicts"].values() if v["frames"])
    rows = (out / "job.csv").read_text().splitlines()
    assert rows[0].startswith("task,frame,time_s,") and len(rows) == 1 + 3 + 2
    assert [r.split(",")[0] for r in rows[1:]] == ["lift"] * 3 + ["reach"] * 2
    html = (out / "job.html").read_text()
    assert html.index("<h2>Verdicts") < html.index("totals over its tasks") < html.index("Task: lift") < \
        html.index("Task: reach")  # fmt: skip


def test_one_task_in_either_form_gives_the_same_report(short_result, tmp_path: Path, write_job) -> None:
    result = short_result([1, 30, 60])
    single = read_job(write_job(tmp_path, result))
    (tmp_path / "t").mkdir()
    listed = tmp_path / "t" / "job.toml"
    listed.write_text('name = "t"\n' + WORK.replace("400", "800") + _task("t", result))
    a = evaluate_job(single, motions_of(single.tasks, tmp_path))
    b = evaluate_job(read_job(listed), motions_of(read_job(listed).tasks, tmp_path))
    assert a["methods"] == a["tasks"][0]["methods"]  # one task: the job's result is the task's
    for name in ("lifft", "shoulder_tool", "capable", "sequence", "eaws"):
        assert json.dumps(a["methods"][name], sort_keys=True) == json.dumps(b["methods"][name], sort_keys=True)


def test_a_push_at_the_hand_changes_the_shoulder_moment_by_force_times_lever(short_result) -> None:
    """50 N forward on the right hand of a result file: the moment about the right shoulder joint changes by
    (hand - shoulder) x F, the moment about L4/L5 by (hand - L4/L5) x F; the legs' do not (their contact forces are
    the result's)."""
    from solver.ergonomics import ErgoOptions, evaluate
    from solver.io.result.read import read_result

    path = short_result([30, 48])
    plain, pushed = read_result(path), read_result(path)
    force = np.array([0.0, -50.0, 0.0])
    add_forces(pushed, (Force("hand_r", tuple(force), (48, 48)),))
    before = evaluate(plain, ErgoOptions(load_mass=10.0))["frames"]
    after = evaluate(pushed, ErgoOptions(load_mass=10.0))["frames"]
    frame = plain.frames[1]
    for joint in ("shoulder_r_flexion", "l4_rx"):
        lever = frame.tcp_position["hand_r"] - frame.pos(joint)
        change = np.subtract(after[1]["joint_loads"][joint]["moment"], before[1]["joint_loads"][joint]["moment"])
        assert np.allclose(change, np.cross(lever, force), atol=1e-6)
        assert np.linalg.norm(change) == pytest.approx(50.0 * np.linalg.norm(np.cross(lever, force / 50.0)))
        assert np.linalg.norm(change) > 5.0  # N*m: a lever of at least 10 cm
    assert after[0]["joint_loads"] == before[0]["joint_loads"]  # frame 30: outside the force's frames
    assert after[1]["joint_loads"]["knee_r_flexion"] == before[1]["joint_loads"]["knee_r_flexion"]


def test_a_force_is_one_more_load_of_the_problem_in_its_frames_when_solved() -> None:
    from solver.io.scenario.read import load_scenario

    scenario = load_scenario(REPO / "presets" / "scenarios" / "box_lift_motion.toml")
    at = with_forces(scenario.problem_at, (Force("hand_r", (0.0, -50.0, 0.0), (10, 20)),))
    before, inside, after = at(9), at(10), at(21)
    assert len(inside.loads) == len(before.loads) + 1 == len(after.loads) + 1
    assert inside.loads[-1].tcp.name == "hand_r" and np.allclose(inside.loads[-1].force, [0, -50, 0])
    assert at(15).loads[-1].tcp.name == "hand_r" and at(20).targets  # every frame in range, targets kept


GOOD = f'[[tasks]]\nname = "a"\nscenario = "{REPO / "presets/scenarios/box_lift_motion.toml"}"\n'
OPS = f'[[tasks]]\nname = "b"\noperations = "{REPO / "presets/operations/bin_to_fixture.toml"}"\n'
LOAD = "[tasks.load]\nmass = 10.0\n"
FORCE = '[[tasks.forces]]\nhand = "right"\n'


@pytest.mark.parametrize(
    ("text", "key"),
    [
        (WORK + GOOD + "[tasks.load]\nmass = -1\n", "tasks[0].load.mass"),
        (WORK + GOOD, "tasks[0].load"),
        (
            WORK + GOOD + "repetitions_per_cycle = 1\nrepetitions_per_shift = 9\n" + LOAD,
            "tasks[0].repetitions_per_shift",
        ),
        (WORK + GOOD + "repetitions_per_shift = 2.5\n" + LOAD, "tasks[0].repetitions_per_shift"),
        (WORK + GOOD + 'result = "x.json"\n' + LOAD, "tasks[0].scenario"),
        (WORK + '[[tasks]]\nresult = "nowhere.json"\n' + LOAD, "tasks[0].result"),
        (WORK + GOOD + LOAD + OPS + "fps = 30\n" + LOAD, "tasks[1].fps"),
        (WORK + GOOD + LOAD + GOOD + LOAD, "tasks[1].name"),
        (
            WORK + GOOD + LOAD + OPS + LOAD + '[[tasks.forces]]\nhand = "foot"\nforce = [0, 0, 1]\n',
            "tasks[1].forces[0].hand",
        ),
        (WORK + GOOD + LOAD + FORCE + "force = [0, 1]\n", "tasks[0].forces[0].force"),
        (WORK + GOOD + LOAD + FORCE + "magnitude = 50\ndirection = [0, 0, 0]\n", "tasks[0].forces[0].direction"),
        (WORK + GOOD + LOAD + FORCE + "force = [0, 0, 1]\nframes = [20, 10]\n", "tasks[0].forces[0].frames"),
        (WORK + GOOD + LOAD + FORCE + "force = [0, 0, 1]\ndirection = [0, 0, 1]\n", "tasks[0].forces[0].direction"),
        (WORK + GOOD + LOAD + FORCE, "tasks[0].forces[0].force"),
        (WORK + GOOD + LOAD + "colour = 1\n", "tasks[0].load.colour"),
        (WORK.replace("[work]", "[work]\nlifts_per_cycle = 2") + GOOD + LOAD, "work.lifts_per_cycle"),
        ('[motion]\nresult = "x.json"\n' + WORK + GOOD + LOAD, "motion"),
        ("tasks = []\n" + WORK, "tasks"),
    ],
)
def test_a_bad_task_is_one_line_naming_file_and_key(tmp_path: Path, capsys, text: str, key: str) -> None:
    path = tmp_path / "bad.toml"
    path.write_text(text)
    with pytest.raises(UsageError) as info:
        read_job(path)
    message = str(info.value)
    assert "\n" not in message and message.startswith(f"{path}: {key}:"), message
    assert main(["job", str(path), "-o", str(tmp_path / "out")]) == 2
    assert capsys.readouterr().err.strip().count("\n") == 0


def test_tasks_that_do_not_fit_the_cycle_or_the_shift_are_refused(short_result, tmp_path: Path) -> None:
    result = short_result([1, 30, 60])  # 0.125 s
    for extra, key in (("repetitions_per_cycle = 300\n", "work.cycle_time"),  # 37.5 s in a 30 s cycle
                       ("repetitions_per_shift = 300000\n", "tasks")):  # 10.4 h in an 8 h shift  # fmt: skip
        path = tmp_path / "job.toml"
        path.write_text(WORK + _task("a", result, extra))
        job = read_job(path)
        with pytest.raises(UsageError, match=rf"^{path}: {key}:"):
            evaluate_job(job, motions_of(job.tasks, tmp_path))


def test_a_force_outside_its_task_s_frames_is_one_line(short_result, tmp_path: Path) -> None:
    path = tmp_path / "job.toml"
    force = '[[tasks.forces]]\nhand = "left"\nforce = [0, 0, 1]\nframes = [61, 90]\n'
    path.write_text(WORK + _task("a", short_result([1, 30, 60])) + force)
    with pytest.raises(UsageError, match=rf"^{path}: tasks\[0\]\.forces\[0\]\.frames: expected frames of the task's"):
        motions_of(read_job(path).tasks, tmp_path, path)


def test_a_study_or_blender_motion_rates_only_a_one_task_job(short_result) -> None:
    from solver.io.result.read import read_result

    job = read_job(REPO / "presets" / "jobs" / "two_task_job.toml")
    with pytest.raises(UsageError, match="one motion rates a job of one task; this job has 2"):
        evaluate_job(job, read_result(short_result([1, 30, 60])))


@pytest.mark.slow
def test_the_two_task_example(tmp_path: Path) -> None:
    """presets/jobs/two_task_job.toml: the box lift and the operations preset solved (~15 s), the press force in
    the part's frames 100-112."""
    assert main(["job", str(REPO / "presets/jobs/two_task_job.toml"), "-o", str(tmp_path), "-q"]) == 0
    data = json.loads((tmp_path / "job.json").read_text())
    assert [t["name"] for t in data["tasks"]] == ["box lift", "part to fixture"]
    lifts = [t["methods"]["lifft"]["lifts_per_shift"] for t in data["tasks"]]
    assert lifts == [800, 1600] and data["methods"]["lifft"]["lifts_per_shift"] == 2400
    from solver.io.result.read import read_result

    frames = {f.number: f for f in read_result(tmp_path / "motion_2.json").frames}
    pressed = [np.allclose(ld[2], [0, 0, 50]) for ld in frames[105].loads]
    assert any(pressed) and not any(np.allclose(ld[2], [0, 0, 50]) for ld in frames[99].loads)
