"""Fixtures of the Blender tests: everything runs in a Blender-equivalent environment (only the ``bpy`` wheel and
numpy, see environments.py; series chosen by MANIKIN_BLENDER, default 5.0) on the linux-x64 zip that environment
built, installed once into a user directory of which each session gets its own copy (installing took ~3 s a
session). bpy never enters the pytest process, whose own environment (with scipy) only checks the results."""

from __future__ import annotations

import json
import subprocess
from pathlib import Path

import pytest
from environments import ROOT, copy_user, install_zip, python_of, run_python, selected

# Sessions that install the zip into an empty user folder themselves: what the zip ships and where Blender puts it.
INSTALL_FROM_THE_ZIP = {"session.py", "wheels_session.py"}


@pytest.fixture(scope="session")
def blender_python() -> Path:
    return python_of(selected())


@pytest.fixture(scope="session")
def extension_zip(blender_python: Path, tmp_path_factory) -> Path:
    """The linux-x64 zip, built by the Blender environment's own build tool (wheels fetched by its pip)."""
    out = tmp_path_factory.mktemp("dist")
    done = subprocess.run(
        [str(blender_python), "-m", "blender_manikin.dev.build", "--output-dir", str(out), "--platform", "linux-x64"],
        cwd=ROOT, capture_output=True, text=True, timeout=900,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr[-3000:]
    return Path(done.stdout.strip())


@pytest.fixture(scope="session")
def installed_user(blender_python: Path, extension_zip: Path, tmp_path_factory) -> Path:
    """A user directory with the zip installed and enabled (as Install from Disk does); copy it, never use it."""
    folder = tmp_path_factory.mktemp("installed") / "user"
    install_zip(blender_python, extension_zip, folder)
    return folder


@pytest.fixture(scope="session")
def run_session(blender_python: Path, extension_zip: Path, installed_user: Path):
    """Run ``tests/blender/<script> <zip> <seen.json> <work>`` with a copy of the installed user directory (the
    script's ``session_tools.install`` enables the extension there) or, for the scripts that check the install
    itself, an empty one; what the script recorded."""

    def run(work: Path, script: str) -> dict:
        here = Path(__file__).resolve().parent
        args = [here / script, extension_zip, work / "seen.json", work]
        if script not in INSTALL_FROM_THE_ZIP:
            copy_user(installed_user, work / "user")
        done = run_python(blender_python, args, work / "user")
        assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
        seen = json.loads((work / "seen.json").read_text(encoding="utf-8"))
        seen.update(zip=str(extension_zip), work=str(work), log=done.stdout + done.stderr)
        return seen

    return run


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    """Every test here runs Blender sessions in subprocesses: all slow (``pytest -m "not slow"`` leaves them out)."""
    here = Path(__file__).resolve().parent
    for item in items:
        if here in item.path.parents:
            item.add_marker(pytest.mark.slow)
