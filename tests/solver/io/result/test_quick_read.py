"""Reading a compact result file quickly, with every check kept: ``ResultStream.numbered`` tells the frame numbers
without parsing a frame line that starts with its number (the kept ones are parsed, and checked, when built), and
a frame's lists of floats are checked in one pass (anything else goes through the reader's own checks and
messages)."""

from __future__ import annotations

import json
from itertools import islice
from pathlib import Path

import numpy as np
import pytest

import solver
from solver.errors import ResultFileError
from solver.io.result import scan as result_scan
from solver.io.result.read import ResultStream
from solver.io.result.scan import FrameLine

BOX_LIFT_MOTION = Path(__file__).resolve().parents[4] / "presets" / "scenarios" / "box_lift_motion.toml"


@pytest.fixture(scope="module")
def lines(tmp_path_factory) -> list[str]:
    scenario = solver.load_motion(BOX_LIFT_MOTION)
    solved = list(islice(solver.solve_motion(scenario), 3))
    path = solver.write_result(tmp_path_factory.mktemp("quick") / "three.jsonl", solved, scenario.path)
    return path.read_text(encoding="utf-8").splitlines(keepends=True)


def _file(tmp_path: Path, lines: list[str], name: str = "r.jsonl") -> Path:
    path = tmp_path / name
    path.write_text("".join(lines), encoding="utf-8")
    return path


def _same(a: solver.Frame, b: solver.Frame) -> None:
    """The same frame, bit for bit."""
    for name in ("joint_value", "joint_position", "joint_axis", "link_com", "joint_strength", "gravity"):
        assert np.array_equal(getattr(a, name), getattr(b, name)), name
    assert (a.number, a.converged, a.unmet, a.broken) == (b.number, b.converged, b.unmet, b.broken)
    for x, y in zip(a.contacts + a.loads, b.contacts + b.loads, strict=True):
        assert x[0] == y[0] and all(np.array_equal(u, v) for u, v in zip(x[1:], y[1:], strict=True))


def test_numbered_gives_the_numbers_and_frames_of_the_full_read(lines: list[str], tmp_path: Path) -> None:
    """A line as the writer starts it is left unparsed, one that does not (spaces, "frame" not first, the key
    twice, also spelled with an escape: JSON takes the last) is parsed on the way; each builds the frame the full
    read builds."""
    spaced = json.loads(lines[2])
    moved = {k: v for k, v in spaced.items() if k != "frame"} | {"frame": 7}
    twice = lines[3].rstrip("\n")[:-1] + ', "frame": 9}\n'
    escaped = lines[3].rstrip("\n")[:-1] + ', "fr\\u0061me": 11}\n'
    lines = [lines[0], lines[1], json.dumps(spaced) + "\n", json.dumps(moved) + "\n", twice, escaped]
    path = _file(tmp_path, lines)
    stream = ResultStream(path)
    numbered = list(stream.numbered())
    raw = list(stream.raw())
    assert [n for _, n, _ in numbered] == [r.get("frame", 1) for _, r in raw] == [1, 2, 7, 9, 11]
    assert [type(r) for _, _, r in numbered] == [FrameLine, dict, dict, dict, dict] and stream.count == 5
    for (i, _, quick), (j, full) in zip(numbered, raw, strict=True):
        assert i == j
        _same(stream.frame(i, quick), stream.frame(j, full))


def test_the_quick_pass_parses_only_the_frames_it_keeps(lines: list[str], tmp_path: Path, monkeypatch) -> None:
    """``ergo``'s first pass (motion_of) parses the header and the first and last frames, not every line."""
    from solver.ergonomics import ErgoOptions
    from solver.ergonomics.stream import motion_of

    frames = [json.loads(lines[1]) | {"frame": n} for n in range(1, 9)]
    path = _file(tmp_path, [lines[0]] + [json.dumps(f, separators=(",", ":")) + "\n" for f in frames])
    stream = ResultStream(path)
    parsed: list[int] = []
    line_value = result_scan._line_value
    monkeypatch.setattr(result_scan, "_line_value", lambda line, n, *a: parsed.append(n) or line_value(line, n, *a))
    motion, first = motion_of(stream, ErgoOptions())
    assert sorted(parsed) == [1, 2, 9] and first.number == 1 and motion["niosh"]["destination"]["frame"] == 8


def test_a_broken_line_left_unparsed_fails_as_the_full_read_does(lines: list[str], tmp_path: Path) -> None:
    """A frame line cut short: the quick pass goes over it, building its frame (or reading the file) says the
    same one line."""
    path = _file(tmp_path, [lines[0], lines[1], lines[2][: len(lines[2]) // 2] + "\n", lines[3]])
    stream = ResultStream(path)
    numbered = list(stream.numbered())
    with pytest.raises(ResultFileError) as full:
        list(stream.raw())
    with pytest.raises(ResultFileError) as quick:
        stream.frame(*[(i, r) for i, _, r in numbered][1])
    assert str(quick.value) == str(full.value) and "line 3: not JSON" in str(full.value)


@pytest.mark.parametrize(
    "key, bad, message",
    [
        ("joint_values", 2, None),  # an int: taken as the float
        ("joint_values", 1e5, "numbers within"),
        ("joint_values", "NaN", "finite numbers"),
        ("joint_values", "x", "finite numbers"),
        ("point", 2, None),
        ("point", 2e4, "numbers within"),
        ("point", True, "finite numbers"),
    ],
)
def test_values_not_plain_floats_go_through_the_readers_checks(lines, tmp_path, key, bad, message) -> None:
    frame = json.loads(lines[1])
    target = frame if key == "joint_values" else next(iter(frame["contacts"].values()))
    target[key] = list(target[key])
    target[key][1] = bad
    text = json.dumps(frame).replace('"NaN"', "NaN")
    stream = ResultStream(_file(tmp_path, [lines[0], text + "\n"]))
    if message is None:
        built = next(iter(stream))
        got = built.joint_value[1] if key == "joint_values" else built.contacts[0][1][1]
        assert got == float(bad) and type(got) is np.float64
    else:
        with pytest.raises(ResultFileError, match=rf"frames\[0\]\.(contacts\.\w+\.)?{key}: expected .*{message}"):
            next(iter(stream))


@pytest.fixture(scope="module")
def json_frames(tmp_path_factory) -> list[dict]:
    scenario = solver.load_motion(BOX_LIFT_MOTION)
    path = solver.write_result(
        tmp_path_factory.mktemp("quick") / "three.json", islice(solver.solve_motion(scenario), 3)
    )
    return json.loads(path.read_text(encoding="utf-8"))["frames"]


def test_a_result_json_quick_pass_leaves_the_nesting_check_to_the_frames_built(json_frames, tmp_path: Path) -> None:
    """The quick pass over a result JSON's numbers does not walk its frames for their nesting: a frame built from
    it is checked then, and is the frame the full read builds."""
    path = tmp_path / "r.json"
    path.write_text(json.dumps({"frames": json_frames}), encoding="utf-8")
    stream = ResultStream(path)
    numbered, raw = list(stream.numbered()), list(stream.raw())
    assert [n for _, n, _ in numbered] == [1, 2, 3] and all(
        isinstance(r, result_scan.UncheckedFrame) for *_, r in numbered
    )
    for (i, _, quick), (j, full) in zip(numbered, raw, strict=True):
        _same(stream.frame(i, quick), stream.frame(j, full))


@pytest.mark.parametrize("where", ["frame", "notes"])
def test_a_result_json_frame_too_deep_or_a_list_for_its_number_is_one_line(json_frames, tmp_path, where) -> None:
    """ergo on a result JSON whose second frame holds a value nested 40 deep (its number, or its notes), or a list
    for its number: the one line naming it (a number that is a list once broke the quick pass with a TypeError)."""
    deep: object = 1
    for _ in range(40):
        deep = [deep]
    for value, message in ((deep, f"frames[1].{where}[...]: arrays or tables nested more than 32"), ([2], None)):
        if message is None and where != "frame":
            continue
        frames = [dict(f) for f in json_frames]
        frames[1][where] = value
        path = tmp_path / "r.json"
        path.write_text(json.dumps({"frames": frames}), encoding="utf-8")
        with pytest.raises(ResultFileError) as caught:
            solver.ergonomics.run(path, tmp_path / "e.json", plots=False)
        assert (message or "frames[1].frame: expected a whole frame number") in str(caught.value)
        assert not list(tmp_path.glob("e.*"))
