"""Reach envelopes as a study kind (a study file's ``[envelope]``): a small study (one manikin, a coarse half sphere,
feet planted and stepping) writes one row per setting with its summary columns and its meshes, resumes without
running anything again, and a bad key is one line naming it (exit 2) before any work."""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
import pytest

from solver.cli.main import main
from solver.envelope import read_envelope
from solver.study import load_study, run_study
from solver.study.plan import plan

STUDY = """
manikins = ["female_5"]

[study]
name = "reach"

[envelope]
name = "reach"
hand = "right"
load_kg = 0.0
feet = ["planted", "step"]
frequency = 1
hemisphere = "front"
"""


def write(folder: Path, text: str) -> Path:
    path = folder / "study.toml"
    path.write_text(text, encoding="utf-8")
    return path


def rows_of(folder: Path) -> list[dict]:
    with open(folder / "rows.csv", encoding="utf-8") as fh:
        return list(csv.DictReader(fh))


@pytest.fixture(scope="module")
def done(tmp_path_factory) -> tuple[Path, Path]:
    """The small envelope study run on 2 local processes: (study file, output folder)."""
    folder = tmp_path_factory.mktemp("envelope_study")
    study = write(folder, STUDY)
    outcome = run_study(study, folder / "out", workers=2, quiet=True)
    assert (outcome.new, outcome.total, outcome.converged) == (2, 2, 2)
    return study, folder / "out"


def test_the_study_plans_one_run_per_manikin_and_setting(tmp_path):
    study = load_study(write(tmp_path, STUDY))
    runs = plan(study)
    assert [r.parameters for r in runs] == [
        {"hand": "right", "load_kg": 0.0, "feet": "planted", "sole_scale": 1.0},
        {"hand": "right", "load_kg": 0.0, "feet": "step", "sole_scale": 1.0},
    ]
    assert len({r.run_id for r in runs}) == 2 and all(r.kind == "reach" and r.manikin_name == "female_5" for r in runs)


@pytest.mark.slow  # the study's two envelopes (the ``done`` fixture): ~10 s
def test_each_row_has_its_summary_and_its_meshes(done):
    _, out = done
    planted, stepping = rows_of(out)
    assert (planted["p_feet"], stepping["p_feet"]) == ("planted", "step")
    for row in (planted, stepping):
        assert row["status"] == "converged" and row["scenario"] == "reach" and row["manikin"] == "female_5"
        low, mean, high = (float(row[f"balanced_{k}_m"]) for k in ("min", "mean", "max"))
        assert 0.3 < low <= mean <= high and mean <= float(row["kinematic_mean_m"])
        assert 0.0 <= float(row["volume_lost"]) < 1.0 and float(row["volume_balanced_m3"]) > 0.0
        meshes = read_envelope(out / (row["mesh"] + ".glb"))
        assert meshes.info["feet"] == row["p_feet"] and meshes.info["manikin"] == "female_5"
        assert (out / (row["mesh"] + ".obj")).is_file() and (out / (row["mesh"] + ".png")).is_file()
    assert planted["planted_mean_m"] == "" and float(stepping["planted_mean_m"]) == float(planted["balanced_mean_m"])
    assert float(stepping["balanced_mean_m"]) >= float(planted["balanced_mean_m"]) + 0.1
    assert float(stepping["stepping_gain_m"]) == pytest.approx(
        float(stepping["balanced_mean_m"]) - float(stepping["planted_mean_m"]), abs=2e-4
    )
    stepped = read_envelope(out / (stepping["mesh"] + ".glb"))
    assert [m.name for m in stepped.meshes] == ["balanced", "kinematic", "planted"]
    both = [read_envelope(out / (r["mesh"] + ".obj")).meshes[0].vertices for r in (planted, stepping)]
    assert np.allclose(both[0], stepped.meshes[2].vertices, atol=1e-5)  # the step row's planted mesh: the planted one
    assert (out / "envelopes.png").is_file() and not (out / "feasibility.png").exists()


@pytest.mark.slow
def test_a_rerun_runs_nothing_again_and_keeps_the_files(done):
    study, out = done
    meshes = sorted((out / "envelopes").iterdir())
    before = {p.name: p.stat().st_mtime_ns for p in meshes}
    outcome = run_study(study, out, workers=1, quiet=True)
    assert (outcome.new, outcome.kept, outcome.converged) == (0, 2, 2)
    assert {p.name: p.stat().st_mtime_ns for p in sorted((out / "envelopes").iterdir())} == before
    assert len(rows_of(out)) == 2


@pytest.mark.slow
def test_an_envelope_row_has_no_scenario_to_write(done, capsys):
    study, out = done
    run_id = rows_of(out)[0]["run_id"]
    assert main(["study", str(study), "--scenario-of", run_id]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "that run is a reach envelope" in err


@pytest.mark.parametrize(
    ("change", "expected"),
    [
        (('feet = ["planted", "step"]', 'feet = "hop"'), 'envelope.feet: expected "planted" or "step"'),
        (("frequency = 1", "frequncy = 1"), "envelope.frequncy: expected one of feet, frequency, hand"),
        (("load_kg = 0.0", "load_kg = [0.0, -1.0]"), "envelope.load_kg: expected kg in [0, 100]"),
        (('hemisphere = "front"', 'hemisphere = "inside"'), "envelope.hemisphere: expected one of all, front"),
        (('hand = "right"', 'hand = ["right", "right"]'), "envelope.hand: expected a hand"),
        (('hand = "right"', "rotation = [0, 0, 0, 0]"), "envelope.rotation: expected a non-zero quaternion"),
        (("frequency = 1", "frequency = 13"), "envelope.frequency: expected a whole number in [1, 12]"),
        (('manikins = ["female_5"]', ""), "manikins: expected at least one manikin for the [envelope]"),
    ],
)
def test_a_bad_envelope_key_is_one_line_naming_it_and_exit_2(change, expected, tmp_path, capsys):
    old, new = change
    assert old in STUDY
    study = write(tmp_path, STUDY.replace(old, new))
    assert main(["study", str(study), "-o", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and expected in err, err
    assert not (tmp_path / "out").exists()


def test_the_preset_envelope_study_reads_and_plans_every_manikin_and_setting():
    study = load_study(Path(__file__).resolve().parents[3] / "presets" / "studies" / "reach_envelopes.toml")
    runs = plan(study)
    assert study.envelope is not None and not study.scenarios and len(runs) == 3 * 2 * 2
    assert {r.manikin_name for r in runs} == {"female_5", "male_50", "male_95"}
    assert {(r.parameters["load_kg"], r.parameters["feet"]) for r in runs} == {
        (load, feet) for load in (0.0, 10.0) for feet in ("planted", "step")
    }
