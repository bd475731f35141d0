"""The hostile-input corpus (``tests/hostile/``) run against every command: each command line of CASES exits 2 with
exactly one line on stderr starting with ``error:``, no traceback, and every input and pre-existing output file
left as it was (no file modified, deleted or added). The few hostile-looking inputs that must be accepted (a UTF-8
byte-order mark, ``/dev/null``, a FIFO, ``-o -``) are accepted.

The command lines run in process (``solver.cli.main.main``) for speed; a few run as a user runs them, in a
subprocess, to prove no traceback reaches stderr.
"""

from __future__ import annotations

import json
import os
import shutil
import stat
import subprocess
import sys
import threading
from contextlib import suppress
from pathlib import Path

import pytest

from solver.cli.main import main
from solver.io.files import open_output

REPO = Path(__file__).resolve().parents[3]
HOSTILE = Path(__file__).resolve().parent / "hostile"
LONG = "a" * 300 + ".json"  # a file name longer than any file system allows (255 bytes)

# (case, command line, words the one line must contain). {in}: a copy of tests/hostile; {out}: a folder holding
# keep.json ("keep me"), the folders adir/ and r.csv/, and nothing else.
SOLVE = [
    ("weight_1e300", ["{in}/weight_1e300.toml"], ["targets[1].weight", "[1e-06, 100]", "1e+300"]),
    ("weight_zero", ["{in}/weight_zero.toml"], ["targets[1].weight", "[1e-06, 100]"]),
    ("operator_zero_row", ["{in}/operator_zero_row.toml"], ["targets[1].operator[0]", "[1e-06, 1000]"]),
    ("operator_1e300", ["{in}/operator_1e300.toml"], ["targets[1].operator[0]", "1e+300"]),
    ("operator_seven_rows", ["{in}/operator_seven_rows.toml"], ["targets[1].operator", "1 to 6 rows"]),
    ("lock_and_operator", ["{in}/lock_and_operator.toml"], ["targets[1].lock", "not both"]),
    ("loop_lock_and_operator", ["{in}/loop_lock_and_operator.toml"], ["loops[0].lock", "not both"]),
    ("friction_100", ["{in}/friction_100.toml"], ["targets[0].friction", "[0, 10]", "100"]),
    ("priority_3", ["{in}/priority_3.toml"], ["targets[1].priority", "1 (must hold) or 2", "3"]),
    ("sole_1000_m", ["{in}/sole_1000_m.toml"], ["targets[0].sole", "+-10 m"]),
    ("position_1e308", ["{in}/position_1e308.toml"], ["targets[1].position", "+-1000 m"]),
    ("position_nan", ["{in}/position_nan.toml"], ["targets[1].position", "finite"]),
    ("rotation_1e300", ["{in}/rotation_1e300.toml"], ["targets[1].rotation", "+-1e+06"]),
    ("rotation_zero", ["{in}/rotation_zero.toml"], ["targets[1].rotation", "non-zero quaternion"]),
    ("unknown_tcp", ["{in}/unknown_tcp.toml"], ["targets[1].tcp", "hand_r"]),
    ("comfort_weight_1e300", ["{in}/comfort_weight_1e300.toml"], ["comfort.load", "[0, 100]"]),
    ("max_iterations_fraction", ["{in}/max_iterations_fraction.toml"], ["solver.max_iterations", "whole number"]),
    ("max_iterations_1e9", ["{in}/max_iterations_1e9.toml"], ["solver.max_iterations", "[1, 100000]"]),
    ("restarts_99", ["{in}/restarts_99.toml"], ["solver.restarts", "[0, 10]", "99"]),
    ("frame_1e300", ["{in}/frame_1e300.toml"], ["frame", "whole frame number in [-1048574, 1048574]"]),
    ("motion_step_zero", ["{in}/motion_step_zero.toml"], ["motion.step", "[1, 100000]"]),
    ("motion_million_frames", ["{in}/motion_million_frames.toml"], ["motion.end", "at most 100000 frames"]),
    ("max_joint_change_zero", ["{in}/max_joint_change_zero.toml"], ["motion.max_joint_change", "rad", "got 0"]),
    ("max_root_shift_1e300", ["{in}/max_root_shift_1e300.toml"], ["motion.max_root_shift", "[1e-06, 100] m"]),
    ("key_frame_fraction", ["{in}/key_frame_fraction.toml"], ["targets[1].keys[0].frame", "whole frame", "1.5"]),
    ("load_mass_1e300", ["{in}/load_mass_1e300.toml"], ["loads[0].mass", "[0, 100000] kg"]),
    ("load_mass_negative", ["{in}/load_mass_negative.toml"], ["loads[0].mass", "-5"]),
    ("load_force_1e300", ["{in}/load_force_1e300.toml"], ["loads[0].force", "+-1e+06 N"]),
    ("start_joint_1e300", ["{in}/start_joint_1e300.toml"], ["start.joints.root_tx", "[-1000, 1000] m"]),
    ("start_unknown_joint", ["{in}/start_unknown_joint.toml"], ["start.joints.knee_q", "joint name"]),
    ("unknown_top_level_key", ["{in}/unknown_top_level_key.toml"], ["colour", "unknown key"]),
    ("unknown_target_key", ["{in}/unknown_target_key.toml"], ["targets[1].wieght", "unknown key"]),
    ("unknown_preset", ["{in}/unknown_preset.toml"], ["manikin", "male_51"]),
    ("body_with_unknown_table", ["{in}/body_with_unknown_table.toml"], ["body_unknown_table.toml", "joints"]),
    ("balance_without_support", ["{in}/balance_without_support.toml"], ["support = true", "balance"]),
    ("malformed", ["{in}/malformed.toml"], ["malformed TOML"]),
    ("empty", ["{in}/empty.toml"], ["empty"]),
    ("not_utf8", ["{in}/not_utf8.toml"], ["cannot read", "utf-8"]),
    ("missing", ["{in}/missing.toml"], ["missing.toml", "not found"]),
    ("a_folder", ["{in}"], ["is a folder, expected a file"]),
    # numbers a float cannot hold, integers Python will not read, nesting its parsers cannot take (issue 34)
    ("position_400_digits", ["{in}/position_400_digits.toml"], ["targets[1].position", "finite numbers", "111"]),
    ("weight_400_digits", ["{in}/weight_400_digits.toml"], ["targets[1].weight", "[1e-06, 100]", "111"]),
    ("frame_400_digits", ["{in}/frame_400_digits.toml"], ["frame", "whole frame number"]),
    ("friction_400_digits", ["{in}/friction_400_digits.toml"], ["targets[0].friction", "[0, 10]"]),
    ("max_iterations_400_digits", ["{in}/max_iterations_400_digits.toml"], ["solver.max_iterations", "[1, 100000]"]),
    ("start_joint_400_digits", ["{in}/start_joint_400_digits.toml"], ["start.joints.seg1_rx", "rad"]),
    ("motion_end_400_digits", ["{in}/motion_end_400_digits.toml"], ["motion.end", "whole frame number"]),
    ("load_mass_400_digits", ["{in}/load_mass_400_digits.toml"], ["loads[0].mass", "kg"]),
    ("obstacle_size_400_digits", ["{in}/obstacle_size_400_digits.toml"], ["obstacles[0].size", "finite numbers"]),
    ("clearance_400_digits", ["{in}/clearance_400_digits.toml"], ["obstacles[0].clearance", "[0, 10]"]),
    ("stature_400_digits", ["{in}/stature_400_digits.toml"], ["body_stature_400_digits.toml", "stature", "[0.5, 2.5]"]),
    ("weight_5000_digits", ["{in}/weight_5000_digits.toml"], ["line 15: weight", "an integer of 5000 digits"]),
    ("weight_2000_deep", ["{in}/weight_2000_deep.toml"], ["line 15: weight", "nested more than 32 levels"]),
    ("operator_40_deep", ["{in}/operator_40_deep.toml"], ["targets[1].operator[...]", "nested more than 32"]),
    ("tables_2000_deep", ["{in}/with_2000_deep_tables.toml"], ["line 15:", "nested more than 32 levels"]),
]
SOLVE_OUTPUT = [
    ("onto_a_directory", ["{in}/ok_snake.toml", "-o", "{out}/adir"], ["-o", "adir", "is a directory"]),
    ("name_300_characters", ["{in}/ok_snake.toml", "-o", "{out}/" + LONG], ["file name too long", "at most 255"]),
    ("onto_its_input", ["{in}/ok_snake.toml", "-o", "{in}/ok_snake.toml"], ["same file as the input"]),
    ("under_a_file", ["{in}/ok_snake.toml", "-o", "{in}/ok_snake.toml/r.json"], ["ok_snake.toml", "not a directory"]),
    ("empty_name", ["{in}/ok_snake.toml", "-o", ""], ["-o: expected a file name"]),
    ("trailing_slash", ["{in}/ok_snake.toml", "-o", "{out}/new/"], ["expected a file name, got a folder"]),
    ("in_proc", ["{in}/ok_snake.toml", "-o", "/proc/r.json"], ["cannot write in /proc"]),
    ("dev_full", ["{in}/ok_snake.toml", "-o", "/dev/full"], ["/dev/full", "No space left on device"]),
]
ARGS = [
    ("no_command", [], ["required: command"]),
    ("unknown_command", ["solv"], ["invalid choice: 'solv'"]),
    ("solve_without_scenario", ["solve"], ["required: scenario", "python -m solver solve --help"]),
    ("solve_unknown_option", ["solve", "{in}/ok_snake.toml", "--bogus"], ["unrecognized arguments: --bogus"]),
    ("solve_o_without_value", ["solve", "{in}/ok_snake.toml", "-o"], ["-o/--output: expected one argument"]),
    ("ergo_frequency_not_a_number", ["ergo", "{in}/result_ok.json", "--frequency", "often"], ["invalid float"]),
    ("ergo_unknown_duration", ["ergo", "{in}/result_ok.json", "--duration", "forever"], ["invalid choice"]),
    ("ergo_origin_not_a_whole_number", ["ergo", "{in}/result_ok.json", "--origin", "1.5"], ["invalid int"]),
]
ERGO = [
    ("value_infinity", ["{in}/result_value_inf.json"], ["frames[0].joints.seg1_rx.value", "got inf"]),
    ("value_nan", ["{in}/result_value_nan.json"], ["frames[0].joints.seg1_rx.value", "got nan"]),
    ("value_string", ["{in}/result_value_string.json"], ["frames[0].joints.seg1_rx.value", "'abc'"]),
    ("value_1e300", ["{in}/result_value_1e300.json"], ["frames[0].joints.seg1_rx.value", "[-10000, 10000]"]),
    ("zero_quaternion", ["{in}/result_zero_quaternion.json"], ["frames[0].tcps.top.rotation", "non-zero"]),
    ("quaternion_1e300", ["{in}/result_quaternion_1e300.json"], ["frames[0].tcps.top.rotation", "+-1e+06"]),
    ("mass_1e300", ["{in}/result_mass_1e300.json"], ["frames[0].links[1].mass", "[0, 10000] kg"]),
    ("force_1e300", ["{in}/result_force_1e300.json"], ["frames[0].contacts.floor.force", "+-1e+07 N"]),
    ("frame_fraction", ["{in}/result_frame_fraction.json"], ["frames[0].frame", "whole frame number"]),
    ("no_frames", ["{in}/result_no_frames.json"], ["frames", "non-empty"]),
    ("not_json", ["{in}/result_not_json.json"], ["not JSON"]),
    ("missing", ["{in}/missing.json"], ["missing.json", "not found"]),
    ("unknown_manikin", ["{in}/result_ok.json", "--manikin", "nosuch"], ["manikin 'nosuch'", "unknown manikin"]),
    ("manikin_of_another_kind", ["{in}/result_ok.json", "--manikin", "male_50"], ["not the body of this result"]),
    ("manikin_bad_body_file", ["{in}/result_ok.json", "--manikin", "{in}/body_unknown_table.toml"], ["joints"]),
    ("origin_999", ["{in}/result_ok.json", "--origin", "999"], ["origin 999: not a frame of the result"]),
    ("destination_0", ["{in}/result_ok.json", "--destination", "0"], ["destination 0: not a frame"]),
    ("frequency_1e300", ["{in}/result_ok.json", "--frequency", "1e300"], ["frequency", "[0, 100]"]),
    ("frequency_nan", ["{in}/result_ok.json", "--frequency", "nan"], ["frequency"]),
    ("load_mass_negative", ["{in}/result_ok.json", "--load-mass", "-5"], ["load mass", "[0, 1000] kg"]),
    ("travel_infinite", ["{in}/result_ok.json", "--travel", "inf"], ["travel", "[0, 10] m"]),
    ("frame_400_digits", ["{in}/result_frame_400_digits.json"], ["frames[0].frame", "whole frame number"]),
    ("frame_5000_digits", ["{in}/result_frame_5000_digits.json"], ["line 1: frame", "integer of 5000 digits"]),
    ("frame_2000_deep", ["{in}/result_frame_2000_deep.json"], ["line 1: frame", "nested more than 32 levels"]),
    ("frame_40_deep", ["{in}/result_frame_40_deep.json"], ["frames[0].frame[...]", "nested more than 32 levels"]),
    ("compact_5000_digits", ["{in}/result_compact_5000_digits.jsonl"], ["line 2: frame", "5000 digits"]),
    ("compact_2000_deep", ["{in}/result_compact_2000_deep.jsonl"], ["line 2: frame", "nested more than 32"]),
    ("latin1", ["{in}/result_latin1.json"], ["result_latin1.json", "not utf-8 text: byte 0xe9"]),
    ("binary_after_header", ["{in}/result_binary_after_header.json"], ["not utf-8 text: byte 0x80"]),
    ("bom_then_binary", ["{in}/result_bom_then_binary.json"], ["not utf-8 text: byte 0x80"]),
    ("a_folder", ["{in}"], ["is a folder, expected a file"]),
]
ERGO_OUTPUT = [
    ("onto_its_input", ["{in}/result_ok.json", "-o", "{in}/result_ok.json"], ["same file as the input"]),
    ("csv_name", ["{in}/result_ok.json", "-o", "{out}/x.csv"], ["-o", "x.csv", "ending .json"]),
    ("standard_output", ["{in}/result_ok.json", "-o", "-"], ["cannot write to standard output"]),
    ("onto_a_directory", ["{in}/result_ok.json", "-o", "{out}/adir"], ["is a directory"]),
    ("name_300_characters", ["{in}/result_ok.json", "-o", "{out}/" + LONG], ["file name too long"]),
    ("csv_beside_is_a_directory", ["{in}/result_ok.json", "-o", "{out}/r.json"], ["r.csv: is a directory"]),
]
URDF = [
    ("unknown_table", ["--file", "{in}/body_unknown_table.toml"], ["joints", "unknown key"]),
    ("human_extra_table", ["--file", "{in}/body_human_extra_table.toml"], ["strength", "unknown key"]),
    ("unknown_key", ["--file", "{in}/body_unknown_key.toml"], ["unknown key 'segment'"]),
    ("segment_length_1e300", ["--file", "{in}/body_segment_length_1e300.toml"], ["segment_length", "(0, 10] m"]),
    ("mass_1e300", ["--file", "{in}/body_mass_1e300.toml"], ["mass", "[10.0, 300.0] kg"]),
    ("a_scenario", ["--file", "{in}/ok_snake.toml"], ["missing table [body]"]),
    ("unknown_preset", ["nosuch"], ["unknown manikin preset 'nosuch'"]),
    ("preset_and_file", ["snake", "--file", "{in}/body_ok.toml"], ["one of them"]),
    ("neither", [], ["one of them"]),
    ("onto_a_directory", ["snake", "-o", "{out}/adir"], ["is a directory"]),
    ("onto_its_input", ["--file", "{in}/body_ok.toml", "-o", "{in}/body_ok.toml"], ["same file as the input"]),
    ("name_300_characters", ["snake", "-o", "{out}/" + LONG], ["file name too long"]),
    ("dev_full", ["snake", "-o", "/dev/full"], ["/dev/full", "No space left on device"]),
    ("stature_400_digits", ["--file", "{in}/body_stature_400_digits.toml"], ["stature", "[0.5, 2.5] m"]),
    ("segments_5000_digits", ["--file", "{in}/body_5000_digits.toml"], ["line 4: segments", "5000 digits"]),
    ("segments_2000_deep", ["--file", "{in}/body_2000_deep.toml"], ["line 4: segments", "nested more than 32"]),
    ("a_folder", ["--file", "{in}"], ["is a folder, expected a body file"]),
]
STUDY = [
    ("value_400_digits", ["{in}/study_value_400_digits.toml"], ["scenarios[0].parameters.raise.values", "finite"]),
    ("value_5000_digits", ["{in}/study_value_5000_digits.toml"], ["line 12: values", "integer of 5000 digits"]),
    ("values_2000_deep", ["{in}/study_values_2000_deep.toml"], ["line 12: values", "nested more than 32"]),
    ("a_folder", ["{in}"], ["is a folder, expected a file"]),
]
VALIDATE = [  # --manifest: the validation's key frames
    ("manifest_5000_digits", ["{in}/body_5000_digits.toml"], ["line 4: segments", "integer of 5000 digits"]),
    ("manifest_2000_deep", ["{in}/body_2000_deep.toml"], ["line 4: segments", "nested more than 32 levels"]),
    ("manifest_a_folder", ["{in}"], ["is a folder, expected a file"]),
]
ENVELOPE = [
    ("stature_400_digits", ["{in}/body_stature_400_digits.toml"], ["stature", "[0.5, 2.5] m"]),
    ("a_folder", ["{in}"], ["is a folder, expected a body file"]),
]
KEEP = ["-o", "{out}/keep.json"]  # a pre-existing output each failing solve/ergo must leave alone
CASES = (
    [(f"solve-{c}", ["solve", "-q", *a, *KEEP], w) for c, a, w in SOLVE]
    + [(f"solve-{c}", ["solve", "-q", *a], w) for c, a, w in SOLVE_OUTPUT]
    + [(f"args-{c}", a, w) for c, a, w in ARGS]
    + [(f"ergo-{c}", ["ergo", "-q", *a, *KEEP], w) for c, a, w in ERGO]
    + [(f"ergo-{c}", ["ergo", "-q", *a], w) for c, a, w in ERGO_OUTPUT]
    + [(f"urdf-{c}", ["urdf", *a], w) for c, a, w in URDF]
    + [(f"study-{c}", ["study", "-q", *a, "-o", "{out}/study"], w) for c, a, w in STUDY]
    + [(f"envelope-{c}", ["envelope", "-q", *a, "-o", "{out}/envelope"], w) for c, a, w in ENVELOPE]
    + [(f"validate-{c}", ["validate", "-q", "--manifest", *a, "--out", "{out}/v"], w) for c, a, w in VALIDATE]
)


@pytest.fixture
def place(tmp_path: Path) -> dict[str, Path]:
    """{in}: a copy of the corpus; {out}: pre-existing outputs (a file, two folders)."""
    shutil.copytree(HOSTILE, tmp_path / "in")
    out = tmp_path / "out"
    (out / "adir").mkdir(parents=True)
    (out / "r.csv").mkdir()
    (out / "keep.json").write_text("keep me", encoding="utf-8")
    return {"in": tmp_path / "in", "out": out}


def fill(argv: list[str], place: dict[str, Path]) -> list[str]:
    return [a.format(**{k: str(v) for k, v in place.items()}) for a in argv]


def snapshot(root: Path) -> dict[str, tuple]:
    """Every file and folder under ``root``: kind, permissions and content."""
    found = {}
    for path in sorted(root.rglob("*")):
        st = path.lstat()
        found[str(path.relative_to(root))] = (
            stat.S_IFMT(st.st_mode),
            st.st_mode,
            path.read_bytes() if path.is_file() else None,
        )
    return found


def check_one_error_line(code: int, err: str, words: list[str]) -> str:
    assert code == 2, f"exit {code}: {err}"
    assert "Traceback" not in err, err
    lines = err.splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: "), f"expected one 'error:' line, got:\n{err}"
    for word in words:
        assert word in lines[0], f"{word!r} not in {lines[0]!r}"
    return lines[0]


@pytest.mark.parametrize("case, argv, words", CASES, ids=[c[0] for c in CASES])
def test_hostile_input_is_one_line_exit_2_and_touches_no_file(case, argv, words, place, tmp_path, capsys) -> None:
    before = snapshot(tmp_path)
    code = main(fill(argv, place))
    _, err = capsys.readouterr()
    check_one_error_line(code, err, words)
    assert snapshot(tmp_path) == before, "an input or pre-existing output was modified, deleted or added to"


@pytest.mark.parametrize("case", ["solve-weight_1e300", "args-solve_unknown_option", "urdf-dev_full"])
def test_hostile_input_as_a_user_runs_it(case, place, tmp_path) -> None:
    """``python -m solver ...`` in a subprocess: the same one line, nothing else on stderr (no traceback)."""
    _, argv, words = next(c for c in CASES if c[0] == case)
    before = snapshot(tmp_path)
    done = subprocess.run([sys.executable, "-m", "solver", *fill(argv, place)], cwd=REPO, capture_output=True,
                          text=True, timeout=120)  # fmt: skip
    check_one_error_line(done.returncode, done.stderr, words)
    assert snapshot(tmp_path) == before


def test_the_corpus_files_are_all_used() -> None:
    """Every file of tests/hostile is named by a case (or is one of the accepted inputs below)."""
    named = " ".join(" ".join(argv) for _, argv, _ in CASES)
    accepted = {"bom.toml", "body_bom.toml", "result_bom.json", "ok_snake.toml", "body_ok.toml", "result_ok.json"}
    unused = [p.name for p in HOSTILE.iterdir() if "{in}/" + p.name not in named and p.name not in accepted]
    assert not unused, unused


# ------------------------------------------------------------------------------------------ accepted inputs


@pytest.mark.parametrize(
    "argv",
    [
        ["solve", "-q", "{in}/ok_snake.toml", "-o", "{out}/r.json"],
        ["solve", "-q", "{in}/bom.toml", "-o", "{out}/r.json"],  # a UTF-8 byte-order mark
        ["urdf", "--file", "{in}/body_bom.toml", "-o", "{out}/r.urdf"],
        ["ergo", "-q", "--no-plots", "{in}/result_ok.json", "-o", "{out}/e.json"],  # the corpus' base is current
        ["ergo", "-q", "--no-plots", "{in}/result_bom.json", "-o", "{out}/e.json"],
    ],
    ids=["ok_scenario", "bom_scenario", "bom_body", "ok_result", "bom_result"],
)
def test_accepted_inputs_exit_0(argv, place, capsys) -> None:
    code = main(fill(argv, place))
    _, err = capsys.readouterr()
    assert code == 0 and not err, err
    written = sorted(p.name for p in place["out"].iterdir())
    assert not [n for n in written if n.endswith(".tmp")], written


def test_dev_null_stays_a_device(place, capsys) -> None:
    """Run as root, writing replaced /dev/null with a JSON file; it is written in place and stays a device."""
    before = os.stat("/dev/null")
    assert main(fill(["solve", "-q", "{in}/ok_snake.toml", "-o", "/dev/null"], place)) == 0
    after = os.stat("/dev/null")
    assert stat.S_ISCHR(after.st_mode) and (after.st_rdev, after.st_ino) == (before.st_rdev, before.st_ino)
    assert main(["urdf", "snake", "-o", "/dev/null"]) == 0 and stat.S_ISCHR(os.stat("/dev/null").st_mode)


def test_a_fifo_is_written_not_replaced(place, capsys) -> None:
    fifo = place["out"] / "pipe"
    os.mkfifo(fifo)
    got = []
    reader = threading.Thread(target=lambda: got.append(fifo.read_bytes()), daemon=True)
    reader.start()
    code = main(fill(["solve", "-q", "{in}/ok_snake.toml", "-o", str(fifo)], place))
    with suppress(OSError):  # a reader still waiting (nothing was written) ends now; ENXIO: none waits
        os.close(os.open(fifo, os.O_WRONLY | os.O_NONBLOCK))
    reader.join(timeout=60)
    assert code == 0 and stat.S_ISFIFO(os.lstat(fifo).st_mode)
    assert json.loads(got[0])["frames"][0]["converged"] is True
    assert sorted(p.name for p in place["out"].iterdir()) == ["adir", "keep.json", "pipe", "r.csv"]


@pytest.mark.parametrize("command", [["solve", "{in}/ok_snake.toml"], ["urdf", "snake"]])
def test_dash_o_dash_writes_standard_output_alone(command, place) -> None:
    """``-o -``: the result JSON (or URDF) on standard output and nothing else there; no file named '-'."""
    env = {**os.environ, "PYTHONPATH": str(REPO)}
    argv = [sys.executable, "-m", "solver", *fill(command, place), "-o", "-"]
    done = subprocess.run(argv, cwd=place["out"], env=env, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    if command[0] == "solve":
        assert json.loads(done.stdout)["frames"][0]["converged"] is True
    else:
        assert done.stdout.startswith("<?xml") and done.stdout.rstrip().endswith("</robot>")
    assert not (place["out"] / "-").exists()


def test_dev_stdout_redirected_to_a_file(place, tmp_path) -> None:
    """``-o /dev/stdout`` with standard output redirected to a file: the JSON lands in that file."""
    target = tmp_path / "redirected.json"
    with target.open("w") as fh:
        argv = [sys.executable, "-m", "solver", "solve", "-q", str(place["in"] / "ok_snake.toml"), "-o", "/dev/stdout"]
        done = subprocess.run(argv, cwd=REPO, stdout=fh, stderr=subprocess.PIPE, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert json.loads(target.read_text(encoding="utf-8"))["frames"][0]["converged"] is True


# ------------------------------------------------------------------------------------------ atomic writes


def test_a_failed_write_keeps_the_old_file_and_leaves_no_temporary_file(tmp_path) -> None:
    path = tmp_path / "r.json"
    path.write_text("old", encoding="utf-8")
    with pytest.raises(RuntimeError), open_output(path) as fh:
        fh.write("half")
        raise RuntimeError("interrupted")
    assert path.read_text(encoding="utf-8") == "old" and sorted(tmp_path.iterdir()) == [path]


def test_replacing_keeps_permissions_and_symbolic_links(tmp_path) -> None:
    target = tmp_path / "real.json"
    target.write_text("old", encoding="utf-8")
    target.chmod(0o640)
    link = tmp_path / "link.json"
    link.symlink_to(target)
    with open_output(link) as fh:
        fh.write("new")
    assert link.is_symlink() and target.read_text(encoding="utf-8") == "new"
    assert stat.S_IMODE(target.stat().st_mode) == 0o640
    assert sorted(p.name for p in tmp_path.iterdir()) == ["link.json", "real.json"]
