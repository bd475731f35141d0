"""Files a writer takes by path (blender_manikin/motion/written.py, no bpy): a writer that fails half way (a full
disk) leaves the old file and no temporary file, and says so in one line naming the file; a file cut short is
caught by its format's cheap check; a .gltf's .bin is renamed with it and named inside it. The real exporters on
a full disk are in tests/blender/test_batch_faults.py.
"""

from __future__ import annotations

import errno
import importlib
import json
import os
import struct
from pathlib import Path

import pytest
from test_scores_follow_registry import checkout_package

written = importlib.import_module(f"{checkout_package().__name__}.blender_manikin.motion.written")  # as Blender has it
FBX_HEAD, FBX_END, PNG_HEAD, PNG_END = written.FBX_HEAD, written.FBX_END, written.PNG_HEAD, written.PNG_END
problem, reason, written_by_path, ManikinError = (
    written.problem,
    written.reason,
    written.written_by_path,
    written.ManikinError,
)

FBX = FBX_HEAD + b"\x00" * 100 + FBX_END
GLB = b"glTF" + struct.pack("<II", 2, 20) + b"\x00" * 8
PNG = PNG_HEAD + b"\x00" * 40 + b"\x00\x00\x00\x00" + PNG_END
BVH = b"HIERARCHY\nROOT a\n{\n}\nMOTION\nFrames: 2\nFrame Time: 0.04\n0 0 0\n1 1 1\n"
GOOD = {
    ".fbx": FBX,
    ".glb": GLB,
    ".png": PNG,
    ".bvh": BVH,
    ".blend": b"BLENDER-v405" + b"\x00" * 40 + b"ENDB" + b"\x00" * 20,
}


def half_then_full(path: Path, data: bytes) -> None:
    """Write half of ``data`` to ``path``, then fail as a full disk does."""
    with open(path, "wb") as fh:
        fh.write(data[: len(data) // 2])
    raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))


def only(folder: Path) -> list[str]:
    return sorted(os.listdir(folder))


@pytest.mark.parametrize("suffix", sorted(GOOD))
def test_a_writer_failing_half_way_leaves_the_old_file_and_no_temporary(tmp_path: Path, suffix: str) -> None:
    path = tmp_path / f"motion{suffix}"
    path.write_bytes(b"OLD")
    with pytest.raises(ManikinError) as caught, written_by_path(path) as work:
        half_then_full(work, GOOD[suffix])
    assert str(caught.value) == f"{path}: cannot write (No space left on device)"
    assert path.read_bytes() == b"OLD" and only(tmp_path) == [path.name]


def test_an_operator_error_with_an_oserror_inside_is_the_systems_reason(tmp_path: Path) -> None:
    path = tmp_path / "m.glb"
    blender = 'Error: Python: Traceback (most recent call last):\n  File "x.py", line 1\nOSError: [Errno 28] No ' \
              "space left on device\nLocation: ops.py:109\n"  # fmt: skip
    with pytest.raises(ManikinError, match=r"m.glb: cannot write \(No space left on device\)$"):
        with written_by_path(path, ".glb") as work:
            Path(str(work)).write_bytes(GLB[:7])  # the exporter's own name for it: the temporary's + ".glb"
            raise RuntimeError(blender)
    assert only(tmp_path) == []
    assert (
        reason(RuntimeError("Error: Python: Traceback\nValueError: no armature\nLocation: x"))
        == "ValueError: no armature"
    )


@pytest.mark.parametrize("suffix", sorted(GOOD))
def test_a_file_cut_short_is_refused_and_a_whole_one_replaces_the_old(tmp_path: Path, suffix: str) -> None:
    path = tmp_path / f"motion{suffix}"
    path.write_bytes(b"OLD")
    os.chmod(path, 0o640)
    with pytest.raises(ManikinError, match="cannot write .*(cut short|malformed|empty)"):
        with written_by_path(path) as work:
            work.write_bytes(GOOD[suffix][: len(GOOD[suffix]) // 2])  # stopped half way without an error
    assert path.read_bytes() == b"OLD" and only(tmp_path) == [path.name]
    with written_by_path(path) as work:
        work.write_bytes(GOOD[suffix])
    assert path.read_bytes() == GOOD[suffix] and only(tmp_path) == [path.name]
    assert os.stat(path).st_mode & 0o777 == 0o640  # the replaced file's permissions
    assert problem(path, suffix) is None


def test_an_empty_file_is_refused(tmp_path: Path) -> None:
    with pytest.raises(ManikinError, match="the file is empty"), written_by_path(tmp_path / "m.fbx") as work:
        work.write_bytes(b"")
    with pytest.raises(ManikinError, match=r"m.fbx: cannot write \(nothing was written\)$"):
        with written_by_path(tmp_path / "m.fbx"):
            pass  # the writer wrote nothing
    assert only(tmp_path) == []


def test_a_gltf_and_its_bin_are_renamed_together_and_the_gltf_names_the_bin(tmp_path: Path) -> None:
    path = tmp_path / "my motion.gltf"
    (tmp_path / "my motion.bin").write_bytes(b"OLD")
    with written_by_path(path, ".gltf") as work:
        assert work.name.endswith(".gltf") and work.parent == tmp_path
        uri = work.with_suffix(".bin").name.replace("@", "%40")  # the exporter's URI: its .bin's name, quoted
        work.write_text(json.dumps({"buffers": [{"uri": uri, "byteLength": 4}]}), encoding="utf-8")
        work.with_suffix(".bin").write_bytes(b"\x01\x02\x03\x04")
    assert only(tmp_path) == ["my motion.bin", "my motion.gltf"]
    assert json.loads(path.read_text(encoding="utf-8"))["buffers"][0]["uri"] == "my%20motion.bin"
    assert (tmp_path / "my motion.bin").read_bytes() == b"\x01\x02\x03\x04"


def test_a_gltf_whose_bin_is_cut_short_keeps_both_old_files(tmp_path: Path) -> None:
    path = tmp_path / "m.gltf"
    path.write_text("OLD", encoding="utf-8")
    (tmp_path / "m.bin").write_bytes(b"OLD")
    with pytest.raises(
        ManikinError, match=r"m.gltf: cannot write \(its .bin \(the buffer beside it\) is missing or cut short\)$"
    ):
        with written_by_path(path, ".gltf") as work:
            uri = work.with_suffix(".bin").name.replace("@", "%40")
            work.write_text(json.dumps({"buffers": [{"uri": uri, "byteLength": 400}]}), encoding="utf-8")
            work.with_suffix(".bin").write_bytes(b"\x01\x02")
    assert path.read_text(encoding="utf-8") == "OLD" and (tmp_path / "m.bin").read_bytes() == b"OLD"
    assert only(tmp_path) == ["m.bin", "m.gltf"]


def test_a_full_temporary_folder_under_the_report_is_one_line_naming_the_report(tmp_path: Path) -> None:
    """The report keeps its frames in a temporary file of the system's folder until the end: that folder full is
    one line naming the report (was an OSError naming no file)."""
    from test_scores_follow_registry import FRAMES, MotionReport, Record, solver

    scenario = solver.load_scenario(Path(__file__).resolve().parents[2] / "presets/scenarios/box_lift.toml")
    result = solver.solve(scenario.problem_at(1), scenario.start, scenario.options)
    report = MotionReport(result.problem.model, "male_50", tmp_path / "report.json", plots=False)

    class Full:
        def write(self, text: str) -> int:
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    report._frames = Full()
    with pytest.raises(ManikinError) as caught:
        report.add(Record(FRAMES[0]), result)
    assert str(caught.value) == (
        f"{tmp_path / 'report.json'}: cannot write (its frames' temporary file: No space left on device)"
    )
