"""Bad job files: one line naming the file and the key (exit 2 on the command line)."""

from __future__ import annotations

from pathlib import Path

import pytest

from solver.cli.main import main
from solver.errors import UsageError
from solver.job import read_job

EXAMPLE = Path(__file__).resolve().parents[3] / "presets" / "jobs" / "box_lift_job.toml"


GOOD = f'name = "t"\n[motion]\nscenario = "{EXAMPLE.parent / "../scenarios/box_lift_motion.toml"}"\n'
WORK = "[work]\ncycle_time = 30.0\nrepetitions = 800\nshift = 8.0\n"
LOAD = "[load]\nmass = 10.0\n"


@pytest.mark.parametrize(
    ("text", "key"),
    [
        (GOOD + LOAD, "work"),  # no [work]
        (GOOD + WORK.replace("800", "-1") + LOAD, "work.repetitions"),
        (GOOD + WORK.replace("800", "2.5") + LOAD, "work.repetitions"),
        (GOOD + WORK.replace("800", "1000") + LOAD, "work.repetitions"),  # 1000 x 30 s > 8 h
        (GOOD + WORK.replace("30.0", "0") + LOAD, "work.cycle_time"),
        (GOOD + WORK + "[load]\nmass = -3\n", "load.mass"),
        (GOOD + WORK + LOAD + 'hands = "three"\n', "load.hands"),
        (GOOD + 'result = "x.json"\n' + WORK + LOAD, "motion.scenario"),  # both
        ('[motion]\nscenario = "nowhere.toml"\n' + WORK + LOAD, "motion.scenario"),
        (GOOD + WORK + LOAD + "colour = 1\n", "load.colour"),
    ],
)
def test_a_bad_job_file_is_one_line_naming_file_and_key(tmp_path: Path, capsys, text: str, key: str) -> None:
    path = tmp_path / "bad.toml"
    path.write_text(text)
    with pytest.raises(UsageError) as info:
        read_job(path)
    message = str(info.value)
    assert "\n" not in message and message.startswith(f"{path}: {key}:"), message
    assert main(["job", str(path), "-o", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and key in err


def test_a_cycle_shorter_than_the_motion_is_refused(tmp_path: Path, short_result, write_job) -> None:
    """3 frames at 24 fps last 0.125 s: a 0.1 s cycle cannot hold them."""
    job = write_job(tmp_path, short_result([1, 30, 60]), cycle_time=0.1, repetitions=10)
    assert main(["job", str(job), "-o", str(tmp_path / "out")]) == 2


def test_the_example_job_reads() -> None:
    job = read_job(EXAMPLE)
    assert (job.cycle_time, job.repetitions, job.shift, job.load_mass, job.lifts) == (30.0, 800, 8.0, 10.0, 800)
    assert job.hands == ("hand_r", "hand_l") and job.scenario is not None and job.result is None
