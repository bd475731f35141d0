"""Blender's console output kept out of a headless run (blender_manikin/motion/quiet.py, no bpy): what is written
to descriptors 1 and 2 inside the capture, by Python or by C, is captured and not shown; a failing call's error
ends in the tail of that output. Each case runs in a fresh Python, whose sys.stdout is descriptor 1 as in Blender
(pytest's own capture would take Python's prints before they reach it). The real Blender exporters are checked in
tests/blender/test_batch.py.
"""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
CHATTY = """
import ctypes, os, sys
from blender_manikin.motion.quiet import captured_output, quietly

def chatty(code=0):  # writes as Blender's exporters do
    print("glTF | INFO: Starting glTF 2.0 export")
    sys.stderr.write("(bpy.data.armatures['snake'], 'POSE')\\n")
    os.write(1, b'Info: Saved copy as "s.blend"\\n')
    os.write(2, b"BVH Exported: s.bvh frames:4\\n")
    ctypes.CDLL(None).printf(b"export finished in %d sec.\\n", code)  # C stdio
    return code
"""
BLENDER_SAID = ("Starting glTF", "armatures['snake']", "Saved copy", "BVH Exported", "export finished in")


def run(code: str) -> subprocess.CompletedProcess:
    """``code`` after CHATTY in a fresh Python at the repository root; the finished process."""
    script = CHATTY + textwrap.dedent(code)
    return subprocess.run([sys.executable, "-c", script], cwd=ROOT, capture_output=True, text=True, timeout=60)


pytestmark = pytest.mark.skipif(os.name == "nt", reason="printf of the process's C library")


def test_everything_written_inside_is_captured_and_nothing_shown() -> None:
    done = run("""
        print("before", flush=True)
        with captured_output() as out:
            chatty()
        print("after")
        sys.stderr.write(out.text)
    """)
    assert done.returncode == 0, done.stderr
    assert done.stdout == "before\nafter\n"
    captured = done.stderr.splitlines()  # what the block wrote, shown only once the block ended
    assert len(captured) == len(BLENDER_SAID) and all(any(s in line for line in captured) for s in BLENDER_SAID)


def test_quietly_returns_the_result_and_shows_nothing() -> None:
    done = run("""
        assert quietly(chatty, 7) == 7
    """)
    assert (done.returncode, done.stdout, done.stderr) == (0, "", "")


def test_a_failure_says_what_blender_said_in_one_line() -> None:
    done = run("""
        def failing():
            chatty()
            raise RuntimeError("the exporter wrote nothing")

        try:
            quietly(failing)
        except RuntimeError as exc:
            print(exc)
    """)
    assert done.returncode == 0 and done.stderr == "", done.stderr
    lines = done.stdout.splitlines()
    assert len(lines) == 1 and lines[0].startswith("the exporter wrote nothing (Blender: ")
    assert all(said in lines[0] for said in BLENDER_SAID) and " | " in lines[0]


def test_a_failure_does_not_repeat_what_its_message_says() -> None:
    done = run("""
        def failing():
            print('Error: Cannot save blend file, path "x.blend" is a directory')
            raise RuntimeError('Error: Cannot save blend file, path "x.blend" is a directory')

        try:
            quietly(failing)
        except RuntimeError as exc:
            print(exc)
    """)
    assert done.stdout == 'Error: Cannot save blend file, path "x.blend" is a directory\n', done.stderr


def test_output_is_shown_again_after_a_failure() -> None:
    done = run("""
        try:
            quietly(lambda: int("x"))
        except ValueError:
            pass
        print("visible")
        os.write(2, b"visible too\\n")
    """)
    assert (done.stdout, done.stderr) == ("visible\n", "visible too\n")
