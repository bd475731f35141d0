"""Job columns in a study (issue 38, solver/study/job_columns.py): a [[scenarios]] entry's ``job`` rates each run's
solved motion as that job on the run's manikin, with every registered job method, as ``manikin job`` does; a study
without a job has no job columns; a bad job file or a cycle shorter than the motion is one line."""

from __future__ import annotations

import csv
import math
from pathlib import Path

import pytest

from solver.errors import ScenarioError
from solver.io.scenario.bodies import PRESETS_DIR
from solver.job.registry import METHODS
from solver.study import load_study, run_study
from solver.study.job_columns import job_columns

MOTION = PRESETS_DIR / "scenarios" / "box_lift_motion.toml"
JOB = PRESETS_DIR / "jobs" / "box_lift_job.toml"
STUDY = f"""
manikins = ["female_5", "male_95"]

[[scenarios]]
file = "{MOTION}"
name = "lift"
job = "{JOB}"
"""


def rows_of(folder: Path) -> list[dict]:
    with open(folder / "rows.csv", encoding="utf-8") as fh:
        return list(csv.DictReader(fh))


@pytest.fixture(scope="module")
def rows(tmp_path_factory) -> list[dict]:
    folder = tmp_path_factory.mktemp("study_job")
    (folder / "study.toml").write_text(STUDY, encoding="utf-8")
    run_study(folder / "study.toml", folder / "out", workers=1, quiet=True)
    return rows_of(folder / "out")


def test_every_registered_method_has_a_level_column_and_its_headline_numbers(rows) -> None:
    columns = job_columns()
    assert [c for c in columns if c.endswith("_level")] == [f"job_{name}_level" for name in METHODS]
    assert {"job_lifft_probability_high_risk", "job_lifft_cumulative_damage", "job_lifft_peak_load_moment_Nm",
            "job_shoulder_tool_probability_clinic_visit", "job_sequence_rula_worst"} <= set(columns)  # fmt: skip
    assert [r["manikin"] for r in rows] == ["female_5", "male_95"]
    for row in rows:
        assert row["status"] == "converged", row["failure"]
        assert set(columns) <= set(row)
        p = float(row["job_lifft_probability_high_risk"])
        assert 0.0 < p < 1.0 and row["job_lifft_level"] == ("2" if p >= 0.5 else "")
        assert float(row["job_lifft_peak_load_moment_Nm"]) > 0.0
        assert row["job_sequence_rula_worst"] in ("1", "2", "3", "4")


def test_each_member_is_rated_on_its_own_body(rows) -> None:
    small, tall = (float(r["job_lifft_peak_load_moment_Nm"]) for r in rows)
    assert not math.isclose(small, tall, rel_tol=1e-3)  # the same job, another reach out to the table


def test_a_study_without_a_job_has_no_job_columns(tmp_path) -> None:
    study = tmp_path / "study.toml"
    study.write_text(STUDY.replace(f'job = "{JOB}"\n', ""), encoding="utf-8")
    assert "job" not in load_study(study).record
    study.write_text(STUDY, encoding="utf-8")
    assert "job" in load_study(study).record


def test_a_bad_job_file_is_one_line(tmp_path) -> None:
    study = tmp_path / "study.toml"
    study.write_text(STUDY.replace(str(JOB), str(tmp_path / "nope.toml")), encoding="utf-8")
    with pytest.raises(ScenarioError, match=r"scenarios\[0\]\.job: expected a valid job file \(.*nope\.toml"):
        load_study(study)


@pytest.mark.filterwarnings("error")  # the plots of a study whose every run failed draw without warnings
def test_a_cycle_shorter_than_the_motion_fails_the_run_with_its_reason(tmp_path) -> None:
    job = tmp_path / "short.toml"
    job.write_text(JOB.read_text(encoding="utf-8").replace("cycle_time = 30.0", "cycle_time = 1.0")
                   .replace("../scenarios/box_lift_motion.toml", str(MOTION)), encoding="utf-8")  # fmt: skip
    study = tmp_path / "study.toml"
    study.write_text(STUDY.replace(str(JOB), str(job)).replace('["female_5", "male_95"]', '["male_50"]'),
                     encoding="utf-8")  # fmt: skip
    run_study(study, tmp_path / "out", workers=1, quiet=True)
    (row,) = rows_of(tmp_path / "out")
    assert row["status"] == "failed"
    assert "work.cycle_time: expected at least the motion's 60 frames at 24 fps (2.50 s), got 1" in row["failure"]
