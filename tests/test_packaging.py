"""The tools run from any directory once set up: ``pip install -e .`` (the last line of requirements.txt) makes the
checkout a package with a ``manikin`` command. The install is made as the README's setup makes it (pip builds it with
setuptools from the package index) into a throwaway environment that sees this one's numpy and scipy, from a copy of
the package files, so neither the shared environment nor the checkout is touched; the commands then run from another
folder and find the presets."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import sysconfig
import tomllib
import venv
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGE_FILES = ("pyproject.toml", "README.md", "LICENSE", "solver", "blender_manikin", "presets")


def _toml(name: str) -> dict:
    return tomllib.loads((ROOT / name).read_text(encoding="utf-8"))


def test_the_package_is_the_extension_s_version_and_requirements_install_it() -> None:
    project = _toml("pyproject.toml")["project"]
    assert project["version"] == _toml("blender_manifest.toml")["version"]
    assert project["scripts"]["manikin"] == "solver.cli.main:main"
    text = (ROOT / "requirements.txt").read_text(encoding="utf-8")
    assert "-e ." in [line.split("#")[0].strip() for line in text.splitlines()]


@pytest.fixture(scope="module")
def installed(tmp_path_factory) -> Path:
    """The bin folder of a fresh environment with a copy of the checkout installed editable (as the README's setup
    does, without the dependencies: they come from this environment)."""
    base = tmp_path_factory.mktemp("package")
    source = base / "checkout"
    source.mkdir()
    for name in PACKAGE_FILES:
        if (ROOT / name).is_dir():
            shutil.copytree(ROOT / name, source / name, ignore=shutil.ignore_patterns("__pycache__"))
        else:
            shutil.copy2(ROOT / name, source / name)
    env = base / "env"
    venv.EnvBuilder(with_pip=False).create(env)
    bin_dir = env / ("Scripts" if os.name == "nt" else "bin")
    python = bin_dir / ("python.exe" if os.name == "nt" else "python")
    purelib = subprocess.run(
        [python, "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"],
        capture_output=True, text=True, check=True,
    ).stdout.strip()  # fmt: skip
    # this environment's packages (numpy, scipy) behind the new one's own
    Path(purelib, "outer.pth").write_text(sysconfig.get_paths()["purelib"] + "\n", encoding="utf-8")
    done = subprocess.run(
        [sys.executable, "-m", "pip", "--python", python, "install", "-q", "--no-deps",
         "-e", source],
        capture_output=True, text=True, timeout=300,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr[-3000:]
    return bin_dir


def _run(command: list, cwd: Path) -> subprocess.CompletedProcess:
    return subprocess.run([str(c) for c in command], cwd=cwd, capture_output=True, text=True, timeout=120)


@pytest.mark.slow  # the checkout installed into a fresh environment (the fixture): ~5 s
def test_the_manikin_command_runs_from_any_directory(installed: Path, tmp_path: Path) -> None:
    manikin = installed / ("manikin.exe" if os.name == "nt" else "manikin")
    done = _run([manikin, "presets"], tmp_path)
    assert done.returncode == 0, done.stderr
    lines = dict(line.split(": ", 1) for line in done.stdout.splitlines())
    assert {"female_5", "male_50", "male_95", "snake"} <= set(lines["manikins"].split(", "))
    scenarios = [Path(p) for p in lines["scenarios"].split(", ")]
    assert scenarios and all(p.is_absolute() and p.is_file() for p in scenarios)  # usable from here
    # a scenario of the user's, here, naming a preset manikin: solved and written here
    shutil.copy(next(p for p in scenarios if p.name == "box_lift.toml"), tmp_path / "mine.toml")
    done = _run([manikin, "solve", "mine.toml", "-o", "mine.json", "-q"], tmp_path)
    assert done.returncode == 0 and (tmp_path / "mine.json").is_file(), done.stderr
    done = _run([manikin, "solve", "missing.toml"], tmp_path)
    assert done.returncode == 2 and "missing.toml" in done.stderr  # main()'s exit code reaches the shell


@pytest.mark.slow
def test_python_dash_m_solver_runs_from_any_directory(installed: Path, tmp_path: Path) -> None:
    python = installed / ("python.exe" if os.name == "nt" else "python")
    done = _run([python, "-m", "solver", "presets"], tmp_path)
    assert done.returncode == 0 and "male_50" in done.stdout, done.stderr
    code = "import importlib.metadata as m; print(m.version('manikin'))"
    assert _run([python, "-c", code], tmp_path).stdout.strip() == _toml("blender_manifest.toml")["version"]
