"""A disk that fills while a command writes: one line naming the file that could not be written (exit 2), no
traceback, no temporary file left. Two ways to fill it: a small tmpfs (ENOSPC, where this machine lets the tests
mount one: root on Linux) and a file size limit (RLIMIT_FSIZE: EFBIG, the same write failing, on any POSIX)."""

from __future__ import annotations

import os
import shutil
import signal
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[3]
HOSTILE = Path(__file__).resolve().parent / "hostile"
POSIX = pytest.mark.skipif(os.name != "posix", reason="RLIMIT_FSIZE and tmpfs are POSIX")
STUDY = """manikins = ["snake"]
[study]
name = "small"
[[scenarios]]
file = "ok_snake.toml"
name = "reach"
[scenarios.parameters.raise]
values = [0.0, 0.05, 0.1]
add = ["targets.top.position[2]"]
"""

# (name, command line; {in}: a copy of the corpus, {out}: the folder that fills)
COMMANDS = [
    ("solve", ["solve", "-q", "{in}/ok_snake.toml", "-o", "{out}/r.json"]),
    ("ergo", ["ergo", "-q", "{in}/result_ok.json", "-o", "{out}/e.json"]),
    ("urdf", ["urdf", "snake", "-o", "{out}/s.urdf"]),
    ("study", ["study", "-q", "--workers", "1", "{in}/small_study.toml", "-o", "{out}/study"]),
    ("family", ["family", "-q", "--sex", "female", "--points", "4", "-o", "{out}/family"]),
]


def run_filling(argv: list[str], place: dict[str, Path], file_size: int | None) -> subprocess.CompletedProcess:
    """``python -m solver ARGV`` with files limited to ``file_size`` bytes (None: no limit)."""

    def limit() -> None:
        if file_size is not None:
            import resource

            signal.signal(signal.SIGXFSZ, signal.SIG_IGN)  # a write past the limit fails (EFBIG) instead of killing
            resource.setrlimit(resource.RLIMIT_FSIZE, (file_size, file_size))

    argv = [a.format(**{k: str(v) for k, v in place.items()}) for a in argv]
    env = {**os.environ, "PYTHONPATH": str(REPO), "PYTHONDONTWRITEBYTECODE": "1"}
    return subprocess.run([sys.executable, "-m", "solver", *argv], cwd=REPO, env=env, preexec_fn=limit,
                          capture_output=True, text=True, timeout=300)  # fmt: skip


def check_named_failure(done: subprocess.CompletedProcess, out: Path, reason: str) -> None:
    err = done.stderr
    assert done.returncode == 2, f"exit {done.returncode}: {err}"
    assert "Traceback" not in err and "Exception ignored" not in err, err
    lines = [line for line in err.splitlines() if line.startswith("error: ")]
    assert len(lines) == 1, err
    assert f"{out}{os.sep}" in lines[0] and "cannot write" in lines[0] and reason in lines[0], lines[0]
    assert not list(out.rglob(".manikin-*.tmp")), "a temporary file was left behind"


@pytest.fixture
def inputs(tmp_path: Path) -> Path:
    folder = tmp_path / "in"
    shutil.copytree(HOSTILE, folder)
    (folder / "small_study.toml").write_text(STUDY, encoding="utf-8")
    return folder


@pytest.fixture
def small_disk(tmp_path: Path) -> Iterator[Path]:
    """A 16 kB tmpfs (a full disk), unmounted after; skipped where it cannot be mounted."""
    disk = tmp_path / "disk"
    disk.mkdir()
    if sys.platform != "linux" or shutil.which("mount") is None:
        pytest.skip("a tmpfs is mounted on Linux only")
    done = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=16k", "tmpfs", str(disk)], capture_output=True,
                          text=True)  # fmt: skip
    if done.returncode != 0:
        pytest.skip(f"cannot mount a small tmpfs here ({done.stderr.strip() or 'not root'})")
    try:
        yield disk
    finally:
        subprocess.run(["umount", "-l", str(disk)], capture_output=True)


# the limits that stop each command at a different file: the result, the report or its PNG, the study's journal,
# its rows.npz or its PNG, a family's body files
LIMITS = {"solve": [3000], "ergo": [3000, 30000], "urdf": [3000], "study": [800, 3000, 30000], "family": [800]}
SLOW = [("study", 30000), ("study", None)]  # a study's plots take a few seconds more: with the slow tests
LIMITED = [pytest.param(name, argv, size, id=f"{name}-{size}", marks=[pytest.mark.slow] * ((name, size) in SLOW))
           for name, argv in COMMANDS for size in LIMITS[name]]  # fmt: skip


@POSIX
@pytest.mark.parametrize("name, argv, file_size", LIMITED)
def test_a_file_size_limit_is_one_line_naming_the_file(name, argv, file_size, inputs, tmp_path) -> None:
    out = tmp_path / "out"
    out.mkdir()
    check_named_failure(run_filling(argv, {"in": inputs, "out": out}, file_size), out, "File too large")


FILLING = [pytest.param(name, argv, id=name, marks=[pytest.mark.slow] * ((name, None) in SLOW))
           for name, argv in COMMANDS if name not in ("solve", "urdf")]  # fmt: skip  (theirs fit in 16 kB)


@POSIX
@pytest.mark.parametrize("name, argv", FILLING)
def test_a_full_disk_is_one_line_naming_the_file(name, argv, inputs, small_disk) -> None:
    check_named_failure(run_filling(argv, {"in": inputs, "out": small_disk}, None), small_disk,
                        "No space left on device")  # fmt: skip


@pytest.mark.slow
@POSIX
@pytest.mark.parametrize("file_size", [2000, 30000])
def test_envelope_files_past_a_size_limit_are_named(file_size, tmp_path) -> None:
    out = tmp_path / "out"
    argv = ["envelope", "-q", "female_5", "--frequency", "1", "-o", "{out}/envelope"]
    check_named_failure(run_filling(argv, {"out": out}, file_size), out, "File too large")
