"""Long motions (issue 19): result files written and read frame by frame in both formats, the progress line, and
Ctrl-C during ``python -m solver solve`` keeping the solved frames in a valid file."""

from __future__ import annotations

import gc
import json
import signal
import subprocess
import sys
import time
import weakref
from itertools import islice
from pathlib import Path

import numpy as np
import pytest
from helpers import leaves, same_frames

import solver
from bench.long_motion import write_long_motion
from solver.errors import ResultFileError, UsageError
from solver.io.result import scan as result_scan
from solver.io.result.document import result_document
from solver.io.result.read import ResultStream
from solver.io.result.write import ResultWriter, interrupts_held
from solver.progress import Progress, clock, progress_line

REPO = Path(__file__).resolve().parents[4]
BOX_LIFT_MOTION = REPO / "presets" / "scenarios" / "box_lift_motion.toml"


@pytest.fixture(scope="module")
def motion() -> tuple[solver.Scenario, list[tuple[int, solver.Result]]]:
    scenario = solver.load_motion(BOX_LIFT_MOTION)
    return scenario, list(islice(solver.solve_motion(scenario), 6))


def check_frames(read: solver.ResultFile, solved: list[tuple[int, solver.Result]]) -> None:
    assert len(read.frames) == len(solved)
    for frame, (number, result) in zip(read.frames, solved, strict=True):
        same_frames(frame, solver.frame_of_result(result, number))


# ---------------------------------------------------------------------------------------------- writing, reading


def test_streamed_json_equals_the_whole_document_and_reads_back(motion, tmp_path: Path) -> None:
    scenario, solved = motion
    path = solver.write_result(tmp_path / "m.json", iter(solved), scenario.path)  # an iterator, written as it goes
    whole = json.loads(json.dumps(result_document(solved, scenario.path)))
    assert json.loads(path.read_text(encoding="utf-8")) == whole
    read = solver.read_result(path)
    assert read.scenario == str(scenario.path) and read.interrupted is None
    check_frames(read, solved)
    assert not temporary_files(tmp_path)


@pytest.mark.parametrize("name, compact", [("m.jsonl", None), ("m.json", True)])
def test_compact_file_reads_back_the_same_frames(motion, tmp_path: Path, name: str, compact: bool | None) -> None:
    scenario, solved = motion
    path = solver.write_result(tmp_path / name, solved, scenario.path, compact=compact)
    lines = path.read_text(encoding="utf-8").splitlines()
    assert len(lines) == 1 + len(solved) and json.loads(lines[0])["format"] == "manikin-result-lines"
    assert all("joints" not in json.loads(line) and "links" not in json.loads(line) for line in lines[1:])
    read = solver.read_result(path)
    assert read.scenario == str(scenario.path)
    check_frames(read, solved)
    full = solver.read_result(solver.write_result(tmp_path / "full.json", solved, scenario.path))
    assert path.stat().st_size * 5 < (tmp_path / "full.json").stat().st_size
    model = solved[0][1].problem.model
    assert leaves(solver.evaluate(read, model=model)["frames"]) == pytest.approx(
        leaves(solver.evaluate(full, model=model)["frames"]), rel=1e-9, abs=1e-9
    )


def test_old_layouts_read_back(motion, tmp_path: Path, monkeypatch) -> None:
    """Indented files of the old writer, the scenario after the frames, and chunks that cut every value."""
    scenario, solved = motion
    document = result_document(solved[:3], scenario.path)
    indented = tmp_path / "old.json"
    indented.write_text(json.dumps(document, indent=1), encoding="utf-8")
    check_frames(solver.read_result(indented), solved[:3])
    last = tmp_path / "last.json"
    last.write_text(json.dumps({"frames": document["frames"], "scenario": "s.toml"}), encoding="utf-8")
    assert solver.read_result(last).scenario == "s.toml"
    monkeypatch.setattr(result_scan, "CHUNK", 4093)  # frames are ~100 kB: most are cut
    check_frames(solver.read_result(indented), solved[:3])


@pytest.mark.parametrize("name", ["c.json", "c.jsonl"])
def test_a_file_cut_short_is_one_line(motion, tmp_path: Path, name: str) -> None:
    scenario, solved = motion
    path = solver.write_result(tmp_path / name, solved[:2], scenario.path)
    text = path.read_text(encoding="utf-8")
    path.write_text(text[: len(text) * 3 // 4], encoding="utf-8")
    with pytest.raises(ResultFileError) as exc:
        solver.read_result(path)
    assert str(path) in str(exc.value) and "not JSON" in str(exc.value) and "\n" not in str(exc.value)


def test_an_interrupted_writer_keeps_a_valid_file(motion, tmp_path: Path) -> None:
    scenario, solved = motion
    for name in ("i.json", "i.jsonl"):
        writer = ResultWriter(tmp_path / name, scenario.path)
        for number, result in solved[:3]:
            writer.add(number, result)
        assert writer.close(interrupted_at=4) == tmp_path / name
        read = solver.read_result(tmp_path / name)
        assert read.interrupted == {"at_frame": 4, "solved": 3, "reason": "interrupted"}
        check_frames(read, solved[:3])
    (tmp_path / "keep.json").write_text("old", encoding="utf-8")
    empty = ResultWriter(tmp_path / "keep.json")
    assert empty.close(interrupted_at=1) is None and (tmp_path / "keep.json").read_text(encoding="utf-8") == "old"
    assert not temporary_files(tmp_path)
    with pytest.raises(UsageError, match="no frames to write"):
        solver.write_result(tmp_path / "keep.json", [])
    assert (tmp_path / "keep.json").read_text(encoding="utf-8") == "old"


def test_an_error_inside_the_writer_block_keeps_the_frames(motion, tmp_path: Path) -> None:
    scenario, solved = motion
    with pytest.raises(RuntimeError), ResultWriter(tmp_path / "e.jsonl", scenario.path) as writer:
        writer.add(*solved[0])
        raise RuntimeError("disk on fire")
    read = solver.read_result(tmp_path / "e.jsonl")
    assert len(read.frames) == 1 and read.interrupted["reason"] == "RuntimeError"


@pytest.mark.parametrize("name", ["flat.json", "flat.jsonl"])
def test_neither_side_holds_the_frames(motion, tmp_path: Path, name: str) -> None:
    """Memory flat in the number of frames, checked by structure: the writer keeps no Result it was given and its
    state does not grow; the stream keeps no Frame it yielded."""
    scenario, solved = motion
    writer = ResultWriter(tmp_path / name, scenario.path)
    number, result = solved[0]
    copy = solver.Result(**vars(result))
    gone = weakref.ref(copy)
    writer.add(number, copy)
    del copy
    gc.collect()
    assert gone() is None
    sizes = sorted((k, sys.getsizeof(v)) for k, v in vars(writer).items())
    for number, result in solved[1:]:
        writer.add(number, result)
    assert sorted((k, sys.getsizeof(v)) for k, v in vars(writer).items()) == sizes
    writer.close()
    stream = ResultStream(tmp_path / name)
    frames = iter(stream)
    first = weakref.ref(next(frames))
    next(frames)
    gc.collect()
    assert first() is None
    assert [f.number for f in stream] == [n for n, _ in solved] and stream.count == len(solved)


def test_ctrl_c_inside_a_held_block_comes_when_it_ends() -> None:
    reached = []
    with pytest.raises(KeyboardInterrupt):
        with interrupts_held():
            with interrupts_held():  # nested (a frame written inside a baked frame's bookkeeping)
                signal.raise_signal(signal.SIGINT)  # to this thread: handled before the next line, no wait needed
                reached.append("inner")
            reached.append("outer")
    assert reached == ["inner", "outer"] and signal.getsignal(signal.SIGINT) is signal.default_int_handler
    with interrupts_held():
        pass  # nothing pending is left over from before
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        with interrupts_held():
            assert signal.getsignal(signal.SIGINT) is signal.SIG_IGN  # another handler is left alone
    finally:
        signal.signal(signal.SIGINT, previous)


# ---------------------------------------------------------------------------------------------- progress


def test_progress_line_says_done_rate_and_time_left() -> None:
    assert progress_line(120, 10000, 0.3) == "frames 120/10000 (1 %), 400 frames/s, 0:25 left"
    assert progress_line(5000, 10000, 10.0, failed=3) == "frames 5000/10000 (50 %), 500 frames/s, 0:10 left, " \
                                                         "3 not converged"  # fmt: skip
    assert progress_line(0, 10, 0.0).endswith("0 frames/s, ? left")
    assert (clock(59.6), clock(61), clock(3725)) == ("1:00", "1:01", "1:02:05")


class FakeStream(list):
    def __init__(self, terminal: bool) -> None:
        super().__init__()
        self.terminal = terminal

    def write(self, text: str) -> None:
        self.append(text)

    def flush(self) -> None:
        pass

    def isatty(self) -> bool:
        return self.terminal


def test_progress_is_a_line_every_few_seconds_in_a_log_and_one_updating_line_in_a_terminal() -> None:
    t = [0.0]
    log = FakeStream(terminal=False)
    progress = Progress(1000, stream=log, now=lambda: t[0])
    for done in range(1, 1001):
        t[0] = done * 0.02  # 50 frames/s: 20 s in all
        progress.update(done)
    assert len(log) == 4 and all(line.endswith("\n") and line.count("\n") == 1 for line in log)
    assert log[0] == "frames 250/1000 (25 %), 50 frames/s, 0:15 left\n"
    screen = FakeStream(terminal=True)
    progress = Progress(1000, stream=screen, now=lambda: t[0])
    for done in range(1, 101):
        t[0] = 20 + done * 0.02
        progress.update(done)
    progress.clear()
    assert len(screen) > 5 and all(text.startswith("\r") and "\n" not in text for text in screen)
    assert screen[-1].strip() == "" and len(screen[-1]) == len(screen[-2]) + 1
    quiet = FakeStream(terminal=True)
    progress = Progress(1000, enabled=False, stream=quiet, now=lambda: t[0])
    t[0] += 100
    progress.update(10)
    progress.clear()
    assert quiet == []


# ---------------------------------------------------------------------------------------------- the command


def run_cli(*args: str, cwd: Path = REPO) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "solver", *args], cwd=cwd, capture_output=True, text=True, timeout=300)


def test_solve_prints_no_line_per_frame_and_ergo_reads_the_compact_file(tmp_path: Path) -> None:
    out = tmp_path / "lift.jsonl"
    done = run_cli("solve", str(BOX_LIFT_MOTION), "-o", str(out))
    assert done.returncode == 0, done.stderr
    assert "frame 2:" not in done.stdout and len(done.stdout.splitlines()) < 25 and "Traceback" not in done.stderr
    assert "60 frames in" in done.stdout and f"wrote {out}" in done.stdout
    assert len(solver.read_result(out).frames) == 60
    quiet = run_cli("solve", str(BOX_LIFT_MOTION), "-q", "--format", "compact", "-o", str(tmp_path / "q.json"))
    assert quiet.returncode == 0 and quiet.stdout == "" and quiet.stderr == ""
    assert (tmp_path / "q.json").read_text(encoding="utf-8").startswith('{"format": "manikin-result-lines"')
    ergo = run_cli("ergo", str(out), "-o", str(tmp_path / "ergo.json"), "--no-plots")
    assert ergo.returncode == 0, ergo.stderr
    report = json.loads((tmp_path / "ergo.json").read_text(encoding="utf-8"))
    assert len(report["frames"]) == 60 and report["niosh"]["LI"] is not None
    assert len((tmp_path / "ergo.csv").read_text(encoding="utf-8").splitlines()) == 61


def temporary_files(folder: Path) -> list[Path]:
    """The temporary files an output is written into before it is renamed into place (solver.io.files)."""
    return sorted(folder.glob(".manikin-*.tmp"))


def interrupt_after(command: list[str], folder: Path, lines: int, cwd: Path = REPO) -> tuple[int, str]:
    """Start ``command``, wait until its result file (still the temporary one in ``folder``) holds ``lines`` lines,
    then send Ctrl-C (SIGINT); the exit code and standard error."""
    proc = subprocess.Popen(command, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 240
    while time.monotonic() < deadline and proc.poll() is None:
        tmp = temporary_files(folder)
        if tmp and tmp[0].read_bytes().count(b"\n") >= lines:
            break
        time.sleep(0.05)
    assert proc.poll() is None, "finished before it could be interrupted"
    proc.send_signal(signal.SIGINT)
    _, stderr = proc.communicate(timeout=120)
    return proc.returncode, stderr


@pytest.mark.parametrize("name", ["long.json", "long.jsonl"])
def test_ctrl_c_keeps_the_solved_frames_and_says_where_in_one_line(tmp_path: Path, name: str) -> None:
    scenario = write_long_motion(tmp_path / "long.toml", 20000)
    out = tmp_path / name
    code, stderr = interrupt_after([sys.executable, "-m", "solver", "solve", str(scenario), "-o", str(out)],
                                   tmp_path, lines=4)  # fmt: skip
    assert code == 130, stderr
    lines = stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in stderr, stderr
    read = solver.read_result(out)
    kept = len(read.frames)
    assert kept >= 3 and [f.number for f in read.frames] == list(range(1, kept + 1))
    assert lines[0] == f"interrupted at frame {kept + 1}; kept {kept} solved frames in {out}"
    assert read.interrupted["at_frame"] == kept + 1 and read.interrupted["solved"] == kept
    assert not temporary_files(tmp_path)
    assert np.isfinite(read.frames[-1].joint_value).all()


def test_ergo_streams_the_same_report_as_the_whole_evaluation(motion, tmp_path: Path) -> None:
    """``ergo`` (solver.ergonomics.run) reads the file frame by frame and writes frame by frame: the same JSON and
    CSV as evaluating every frame in memory; it hands back only the frames a summary shows."""
    scenario, solved = motion
    more = solved + list(islice(solver.solve_motion(scenario), 6, 12))
    path = solver.write_result(tmp_path / "twelve.jsonl", more, scenario.path)
    from solver.ergonomics import run
    from solver.ergonomics.report import csv_rows

    summary = run(path, tmp_path / "ergo.json", plots=False)
    whole = solver.evaluate(solver.read_result(path))
    assert json.loads((tmp_path / "ergo.json").read_text(encoding="utf-8")) == json.loads(json.dumps(whole))
    header, rows = csv_rows(whole)
    written = (tmp_path / "ergo.csv").read_text(encoding="utf-8").splitlines()
    assert written[0].split(",") == header and len(written) == 1 + len(rows) == 13
    assert summary["frame_count"] == 12 and [f["frame"] for f in summary["frames"]] == [1, 12]
    best = max(whole["frames"], key=lambda f: f["reba"]["score"] or 0)
    assert summary["highest_reba"] == best and summary["niosh"] == whole["niosh"]
