"""Population studies (issue 22): the study file, key-path parameters, runs and rows, resuming, the executors.

The study here is small and quick (2 manikins x 2 handle heights of the box lift, plus one run whose parameter
makes the scenario invalid); it runs on 1 and 2 local processes and on a local Dask cluster, which must give the
same rows (all but the times).
"""

from __future__ import annotations

import csv
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from solver import load_scenario
from solver.errors import ScenarioError, UsageError
from solver.io.scenario.bodies import PRESETS_DIR
from solver.study import load_study, run_study
from solver.study.keypath import apply, check, parse
from solver.study.plan import plan
from solver.study.runner import TIMING, jittered, run_one

REPO = Path(__file__).resolve().parents[3]
LIFT = PRESETS_DIR / "scenarios" / "box_lift.toml"
STUDY = f"""
manikins = ["female_5", "male_95"]

[[scenarios]]
file = "{LIFT}"
name = "lift"
[scenarios.parameters.raise]
values = [0.0, 0.3]
add = ["targets.hand_r.position[2]", "targets.hand_l.position[2]"]

[[scenarios]]
file = "{LIFT}"
name = "slippery"
keep_manikin = true
[scenarios.parameters.friction]
values = [-1.0]   # not a friction coefficient: the run fails, its row says why
set = ["targets.foot_r.friction"]
"""


def with_head(lines: str) -> str:
    """The study with a [study] table of ``lines`` (after the top-level manikins, as TOML wants)."""
    head, rest = STUDY.split("\n\n[[scenarios]]", 1)
    return f"{head}\n\n[study]\n{lines}\n\n[[scenarios]]{rest}"


def write(folder: Path, text: str, name: str = "study.toml") -> Path:
    path = folder / name
    path.write_text(text, encoding="utf-8")
    return path


def rows_of(folder: Path, timing: bool = False) -> list[dict]:
    with open(folder / "rows.csv", encoding="utf-8") as fh:
        rows = list(csv.DictReader(fh))
    return rows if timing else [{k: v for k, v in row.items() if k not in TIMING} for row in rows]


@pytest.fixture(scope="module")
def two_processes(tmp_path_factory) -> tuple[Path, Path]:
    """The small study run on 2 local processes: (study file, output folder)."""
    folder = tmp_path_factory.mktemp("study")
    study = write(folder, STUDY)
    outcome = run_study(study, folder / "out", workers=2, quiet=True)
    assert (outcome.new, outcome.total, outcome.workers) == (5, 5, 2)
    return study, folder / "out"


# --- key paths ---------------------------------------------------------------------------------------------------


def test_key_paths_pick_entries_by_name_or_tcp_and_items_by_index():
    data = {"targets": [{"tcp": "hand_r", "position": [0.1, 0.2, 0.3]}, {"tcp": "foot_l", "friction": 0.6}],
            "obstacles": [{"name": "table top", "center": [0.0, 0.0, 0.7]}]}  # fmt: skip
    assert parse('obstacles."table top".center[2]') == ["obstacles", "table top", "center", 2]
    apply(data, "targets.hand_r.position[2]", 0.1, add=True)
    apply(data, 'obstacles."table top".center[2]', 0.9, add=False)
    apply(data, "targets[1].friction", 0.4, add=False)
    assert data["targets"][0]["position"] == [0.1, 0.2, pytest.approx(0.4)]
    assert data["obstacles"][0]["center"][2] == 0.9 and data["targets"][1]["friction"] == 0.4


@pytest.mark.parametrize(
    ("path", "values", "add", "words"),
    [
        ("targets.hand_x.position[2]", [1.0], False, ["no entry named 'hand_x'", "hand_r"]),
        ("targets.hand_r.positon[2]", [1.0], False, ["positon", "not in the scenario file"]),
        ("targets.hand_r.position[5]", [1.0], False, ["[5]", "no such item"]),
        ("targets.hand_r.tcp", [1.0], True, ["add needs a number"]),
        ("targets.hand_r.position[2]", ["high"], False, ["number", "'high'"]),
        ("targets..tcp", [1.0], False, ["missing"]),
    ],
)
def test_bad_key_paths_say_why(path, values, add, words):
    data = {"targets": [{"tcp": "hand_r", "position": [0.1, 0.2, 0.3]}]}
    with pytest.raises(ValueError) as err:
        check(data, path, values, add)
    assert all(w in str(err.value) for w in words), str(err.value)


# --- the study file ----------------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("change", "words"),
    [
        (
            ("targets.hand_r.position[2]", "targets.hand_q.position[2]"),
            ["scenarios[0].parameters.raise.add[0]", "hand_q"],
        ),
        (('name = "lift"', 'name = "lift"\ncolour = 1'), ["scenarios[0].colour", "unknown key"]),
        (('"female_5"', '"female_55"'), ["manikins[0]", "female_55"]),
        (('"male_95"', '"female_5"'), ["manikins", "distinct manikin names"]),
        (("values = [0.0, 0.3]", "values = []"), ["raise.values", "non-empty"]),
        (('name = "lift"', 'name = "lift"\nwith = { carried = 3 }'), ["scenarios[0].with.carried", "a table"]),
        (
            ('name = "lift"', 'name = "lift"\nwith = { carried = { size = [0.3], tcps = ["hand_r", "hand_l"] } }'),
            ["scenarios[0].with", "a valid scenario", "size"],
        ),
        (('name = "slippery"', 'name = "lift"'), ["scenarios", "distinct scenario names"]),
        (
            ('manikins = ["female_5", "male_95"]', '[study]\nmanikins = ["female_5"]'),
            ["study.manikins", "before [study]"],
        ),
    ],
)
def test_a_bad_study_file_is_one_scenario_error_naming_the_key(tmp_path, change, words):
    study = write(tmp_path, STUDY.replace(*change))
    with pytest.raises(ScenarioError) as err:
        load_study(study)
    message = str(err.value)
    assert "\n" not in message and str(study) in message and all(w in message for w in words), message


def test_a_scenario_can_be_given_the_box_its_hands_hold(tmp_path):
    """``with`` puts tables into the scenario's data: with the box between the handles raised to 0.9 m, the smallest
    manikin lifts it in front of her (a finite NIOSH lifting index); without it her feet slide past the handles and
    she holds them behind her back (asymmetry 180 deg: the NIOSH multipliers reach zero, the index infinity) with
    the standard model (trunk 0); the behaviour model (the default) holds them in front without the box too."""
    box = 'with = { carried = { name = "box", size = [0.35, 0.26, 0.24], tcps = ["hand_r", "hand_l"] } }'
    text = STUDY.replace("values = [0.0, 0.3]", "values = [0.45]").replace('name = "lift"', f'name = "lift"\n{box}')
    text = text.replace('manikins = ["female_5", "male_95"]', 'manikins = ["female_5"]')
    lift = plan(load_study(write(tmp_path, text)))[0]
    assert lift.scenario.data["carried"]["size"] == [0.35, 0.26, 0.24]
    held = run_one(lift)
    assert held["status"] == "converged" and 0.0 < held["niosh_li"] < 1.0
    standard = 'with = { comfort = { trunk = 0.0 } }'
    behind = run_one(plan(load_study(write(tmp_path, text.replace(box, standard), "bare.toml")))[0])
    assert behind["niosh_li"] == np.inf
    bare = run_one(plan(load_study(write(tmp_path, text.replace(box, ""), "bare_default.toml")))[0])
    assert bare["status"] == "converged" and 0.0 < bare["niosh_li"] < 1.0


def test_a_family_folder_gives_each_body_file_and_skips_its_index(tmp_path):
    family = tmp_path / "fam"
    family.mkdir()
    for name, stature in (("short", 1.55), ("tall", 1.90)):
        write(family, f'[body]\nkind = "human"\nsex = "female"\nstature = {stature}\nmass = 60.0\n', f"{name}.toml")
    index = '[family]\nsurvey = "x"\n[[members]]\nname = "short"\nfile = "short.toml"\nsex = "female"\n'
    write(family, index + 'role = "sample"\nmeasurements = { stature = 1.55, mass = 60.0 }\n', "family.toml")
    study = load_study(write(tmp_path, STUDY.replace('["female_5", "male_95"]', '["male_50", "fam"]')))
    assert [m.name for m in study.manikins] == ["male_50", "fam/short", "fam/tall"]
    assert study.manikins[2].file == (family / "tall.toml").resolve() and study.manikins[0].preset == "male_50"
    assert study.manikins[1].member["role"] == "sample" and study.manikins[2].member == {}  # not in the index


def test_rows_of_a_family_folder_say_each_member_s_role_and_measurements(tmp_path):
    from solver.population import make_family, read_family, write_family

    members = make_family(("female",), coverage=0.9, points=3)
    write_family(members, tmp_path / "fam", {"source": "ANSUR II", "coverage": 0.9, "seed": 0})
    text = STUDY.replace('["female_5", "male_95"]', '["male_50", "fam"]').split("\n\n[[scenarios]]\nfile")[0]
    text += f'\n\n[study]\nrecord = ["shortfall"]\n\n[[scenarios]]\nfile = "{LIFT}"\n'
    outcome = run_study(write(tmp_path, text), tmp_path / "out", workers=1, quiet=True)
    assert outcome.total == 5
    rows = rows_of(tmp_path / "out")
    assert list(rows[0])[3:9] == ["manikin", "role", "sex", "stature_m", "mass_kg", "sitting_height_m"]
    assert rows[0]["role"] == "" and rows[0]["manikin"] == "male_50"  # a preset: no family facts
    family = read_family(tmp_path / "fam")
    assert [(r["manikin"], r["role"], r["sex"]) for r in rows[1:]] == [
        (f"fam/{m.name}", m.role, m.sex) for m in family.members
    ]
    assert [float(r["stature_m"]) for r in rows[1:]] == [m.stature for m in family.members]
    assert [float(r["mass_kg"]) for r in rows[1:]] == [m.mass for m in family.members]
    assert all(r["status"] == "converged" for r in rows)
    (tmp_path / "fam" / "family.toml").write_text('[[members]]\nname = "x"\n', encoding="utf-8")
    with pytest.raises(ScenarioError, match=r"manikins\[1\].*family.toml reads"):
        load_study(tmp_path / "study.toml")


def test_runs_have_stable_distinct_ids_and_seeds_that_follow_the_inputs(tmp_path):
    runs = plan(load_study(write(tmp_path, STUDY)))
    assert [(r.scenario.name, r.manikin_name, r.parameters) for r in runs[:3]] == [
        ("lift", "female_5", {"raise": 0.0}), ("lift", "female_5", {"raise": 0.3}), ("lift", "male_95", {"raise": 0.0})
    ]  # fmt: skip
    assert runs[4].manikin_name == "male_50"  # the scenario keeps its own manikin
    again = plan(load_study(write(tmp_path, STUDY)))
    assert [r.run_id for r in runs] == [r.run_id for r in again] and len({r.run_id for r in runs}) == 5
    changed = plan(load_study(write(tmp_path, STUDY.replace("[0.0, 0.3]", "[0.0, 0.31]"))))
    assert changed[0].run_id == runs[0].run_id and changed[1].run_id != runs[1].run_id
    repeated = plan(load_study(write(tmp_path, with_head("repeats = 2"))))
    assert len(repeated) == 10 and len({r.seed for r in repeated}) == 10 and len({r.run_id for r in repeated}) == 10


# --- runs and rows -----------------------------------------------------------------------------------------------


def test_a_run_that_fails_is_a_row_with_its_reason(tmp_path, monkeypatch):
    runs = plan(load_study(write(tmp_path, STUDY)))
    row = run_one(runs[4])
    assert row["status"] == "failed" and "friction" in row["failure"] and str(LIFT) in row["failure"]

    def broken(scenario):
        raise RuntimeError("solver\nexploded")

    monkeypatch.setattr("solver.motion.frames.solve_motion", broken)
    row = run_one(runs[0])
    assert (row["status"], row["failure"], row["manikin"]) == ("failed", "RuntimeError: solver exploded", "female_5")


def test_the_rows_say_who_can_do_it_and_how_hard(two_processes):
    _, out = two_processes
    rows = rows_of(out, timing=True)
    assert [r["status"] for r in rows] == ["converged"] * 4 + ["failed"]
    lift = rows[0]
    assert lift["converged"] == "true" and lift["unmet"] == "" and float(lift["shortfall_m"]) == 0.0
    assert 1 <= int(lift["rula_peak"]) <= 7 and 1 <= int(lift["reba_peak"]) <= 15
    assert 300 < float(lift["l4_l5_peak_N"]) < 6400 and 0 < float(lift["strength_peak_pct"]) < 200
    assert 0 < float(lift["niosh_li"]) < 3 and float(lift["solve_s"]) > 0 and lift["failure"] == ""
    assert rows[4]["rula_peak"] == "" and "friction" in rows[4]["failure"]
    table = np.load(out / "rows.npz")
    assert list(table["__columns__"]) == list(rows[0])
    assert table["converged"].dtype == bool and table["l4_l5_peak_N"].dtype == float and not table["converged"][4]
    assert np.isnan(table["l4_l5_peak_N"][4]) and table["failure"][4] == rows[4]["failure"]
    assert (out / "feasibility.png").stat().st_size > 5000 and (out / "scores.png").stat().st_size > 5000


@pytest.mark.slow  # starts a local dask cluster: ~4 s
def test_one_process_and_a_local_dask_cluster_give_the_same_rows(two_processes, tmp_path):
    study, out = two_processes
    run_study(study, tmp_path / "one", workers=1, quiet=True)
    assert rows_of(tmp_path / "one") == rows_of(out)
    pytest.importorskip("distributed", reason="Dask is an optional extra: pip install -r requirements-dask.txt")
    outcome = run_study(study, tmp_path / "dask", workers=2, dask="local", quiet=True)
    assert outcome.workers == 2 and rows_of(tmp_path / "dask") == rows_of(out)


def test_a_rerun_skips_the_finished_runs_and_redoes_a_lost_one(two_processes, tmp_path):
    study, out = two_processes
    folder = tmp_path / "again"
    folder.mkdir()
    lines = (out / "runs.jsonl").read_text().splitlines()
    (folder / "runs.jsonl").write_text("\n".join(lines[:3]) + "\n" + lines[3][:40])  # a crash cut the 4th line
    outcome = run_study(study, folder, workers=1, quiet=True)
    assert (outcome.kept, outcome.new) == (3, 2) and rows_of(folder) == rows_of(out)
    outcome = run_study(study, folder, workers=1, quiet=True)
    assert (outcome.kept, outcome.new, outcome.failed) == (5, 0, 1)
    outcome = run_study(study, folder, workers=1, quiet=True, retry_failed=True)
    assert (outcome.kept, outcome.new) == (4, 1)


def test_a_seeded_start_jitter_is_reproducible(tmp_path):
    runs = plan(load_study(write(tmp_path, with_head("start_jitter = 0.05\nrepeats = 2"))))
    scenario = load_scenario(LIFT)
    same = jittered(scenario, runs[0].seed, 0.05), jittered(scenario, runs[0].seed, 0.05)
    other = jittered(scenario, runs[1].seed, 0.05)
    assert np.array_equal(*same) and not np.allclose(same[0], other) and not np.allclose(same[0], scenario.start)
    first, again = run_one(runs[0]), run_one(runs[0])
    assert {k: v for k, v in first.items() if k not in TIMING} == {k: v for k, v in again.items() if k not in TIMING}


# --- the command ---------------------------------------------------------------------------------------------------


def run_cli(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "solver", *args], cwd=REPO, capture_output=True, text=True,
                          timeout=120)  # fmt: skip


def test_the_command_reports_bad_input_in_one_line_with_exit_2(tmp_path):
    study = write(tmp_path, STUDY.replace("hand_l.position[2]", "hand_l.position[3]"))
    proc = run_cli("study", str(study), "-o", str(tmp_path / "out"))
    assert proc.returncode == 2 and proc.stderr.count("\n") == 1 and "add[1]" in proc.stderr, proc.stderr
    (tmp_path / "file").write_text("x")
    proc = run_cli("study", str(write(tmp_path, STUDY)), "-o", str(tmp_path / "file"))
    assert proc.returncode == 2 and "is a file" in proc.stderr, proc.stderr


def test_without_dask_the_dask_option_is_one_line(tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "distributed", None)  # as if not installed
    with pytest.raises(UsageError, match="pip install -r requirements-dask.txt"):
        run_study(write(tmp_path, STUDY), tmp_path / "out", dask="local", quiet=True)


def test_the_command_prints_one_summary_line_and_exits_3_when_a_run_did_not_converge(two_processes, tmp_path):
    study, out = two_processes
    folder = tmp_path / "out"
    folder.mkdir()
    (folder / "runs.jsonl").write_bytes((out / "runs.jsonl").read_bytes())  # every run done: nothing to run
    proc = run_cli("study", str(study), "-o", str(folder))
    assert proc.returncode == 3, proc.stderr
    assert proc.stdout.startswith(
        "study study: 5 of 5 runs (all 5 from before): 4 converged, 0 not converged, 1 failed"
    )
    assert proc.stdout.count("\n") == 1 and rows_of(folder) == rows_of(out)


def test_the_solver_and_the_study_do_not_import_dask():
    code = ("import sys, solver, solver.study, solver.study.execute, solver.study.runner; "
            "sys.exit(bool({'dask', 'distributed'} & set(sys.modules)))")  # fmt: skip
    assert subprocess.run([sys.executable, "-c", code], cwd=REPO).returncode == 0


def test_two_study_runs_cannot_write_one_folder_at_once(tmp_path):
    from solver.study.outputs import Journal

    held = Journal(tmp_path / "out")
    try:
        with pytest.raises(UsageError, match="another study is writing this folder"):
            run_study(write(tmp_path, STUDY), tmp_path / "out", workers=1, quiet=True)
    finally:
        held.close()


def test_a_row_s_scenario_file_solves_to_the_row_again(tmp_path):
    from solver import evaluate, solve_motion
    from solver.study.export import row_scenario
    from solver.study.runner import outcome, scores

    study = write(tmp_path, with_head("start_jitter = 0.05"))
    run = plan(load_study(study))[1]  # female_5, the handles 0.3 m higher, a jittered start
    row = run_one(run)
    path = tmp_path / "sub" / "row.toml"
    path.parent.mkdir()
    path.write_text(row_scenario(study, run.run_id[:6]), encoding="utf-8")
    solved = list(solve_motion(load_scenario(path)))
    again = outcome([r for _, r in solved]) | scores(evaluate(solved))
    assert again == {k: row[k] for k in again} and row["status"] == "converged"
    with pytest.raises(UsageError, match="no run of the study has that id"):
        row_scenario(study, "zzz")


def test_the_benchmark_report_states_the_speed_ups_against_the_target_and_the_100k_study(tmp_path):
    from bench.study import CASES, section, study_text

    assert len(plan(load_study(write(tmp_path, study_text(30), "bench.toml")))) == 30
    rates = {1: 20.0, 2: 38.0}  # 1.9x on local processes; Dask below the target
    results = {label: [dict(rate=rates[w] if engine == "local" else 10.0 * w ** 0.5, startup=1.0, workers=w,
                            run_s=0.045) for _ in range(3)] for label, engine, w, _ in CASES}  # fmt: skip
    paper = dict(runs=100_000, read_s=1.0, plan_s=2.0, peak_mb=40.0)
    text = section(results, 600, 3, paper, "test machine", (0.1, 0.2))
    assert "local processes: 1.90x (target 1.8x: met)" in text and "local Dask cluster: 1.41x" in text
    assert "**not met**" in text and "| 100 | 50 | 2,000 |" in text and "100,000 runs" in text
