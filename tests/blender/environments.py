"""Blender-equivalent Python environments: a virtual environment holding only the ``bpy`` wheel and what it declares,
with numpy pinned to the version that Blender release bundles. That is what a user's Blender has (numpy, requests,
zstandard, cython; no scipy, no matplotlib), so the extension must bring the rest itself.

    python tests/blender/environments.py 4.2      # create .venvs/bpy-4.2.23 (if missing) and print its python
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import venv
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
VENVS = ROOT / ".venvs"

# Supported Blender series: (bpy wheel, numpy that Blender bundles). bpy 4.2 leaves numpy open (and breaks with
# numpy 2); 4.5 and 5.0 declare numpy>=1.26,<2. Blender 4.2 ships numpy 1.24.3, 4.4 to 5.0 ship 1.26.4.
BLENDERS = {
    "4.2": ("4.2.23", "1.24.3"),
    "4.5": ("4.5.15", "1.26.4"),
    "5.0": ("5.0.1", "1.26.4"),
}
DEFAULT = "5.0"
SELECT = "MANIKIN_BLENDER"  # environment variable: which series the Blender tests run on


def selected() -> str:
    """The Blender series chosen by MANIKIN_BLENDER (default 5.0)."""
    series = os.environ.get(SELECT, DEFAULT)
    if series not in BLENDERS:
        raise SystemExit(f"{SELECT}={series}: expected one of {', '.join(BLENDERS)}")
    return series


def python_of(series: str) -> Path:
    """The Python of the series' environment, created on first use (a half-made one is made again)."""
    bpy_version, numpy_version = BLENDERS[series]
    home = VENVS / f"bpy-{bpy_version}"
    python = home / ("Scripts/python.exe" if os.name == "nt" else "bin/python")
    done = home / "complete"
    if not done.is_file():
        venv.EnvBuilder(clear=True, with_pip=True).create(home)
        pins = [f"bpy=={bpy_version}", f"numpy=={numpy_version}"]
        subprocess.run([str(python), "-m", "pip", "install", "--quiet", *pins], check=True)
        done.write_text(" ".join(pins) + "\n", encoding="utf-8")
    return python


# Sessions solve on the NumPy kernels: each installs into a folder of its own, where Numba would compile every kernel
# again (seconds a session); the scripts that test the compiled kernels in Blender ask for them (COMPILED).
COMPILED = ("kernels_session.py",)


def run_python(python: Path, args: list, user: Path, cwd: Path | None = None, timeout: int = 600):
    """Run ``python args`` with ``user`` as Blender's user directory; the completed process."""
    user.mkdir(parents=True, exist_ok=True)
    compiled = Path(str(args[0])).name in COMPILED
    kernels = "auto" if compiled else os.environ.get("MANIKIN_KERNELS", "numpy")
    env = dict(os.environ, BLENDER_USER_RESOURCES=str(user), MANIKIN_KERNELS=kernels)
    return subprocess.run(
        [str(python), *map(str, args)], cwd=cwd or ROOT, env=env, capture_output=True, text=True, timeout=timeout
    )


def install_zip(python: Path, zip_path: Path, user: Path) -> None:
    """Install and enable the zip in the user folder ``user`` as a user would (its wheels go onto Blender's path)."""
    code = f"import sys; sys.path.insert(0, {str(ROOT)!r}); from blender_manikin.dev.build import install; " \
           f"install(__import__('pathlib').Path({str(zip_path)!r}))"  # fmt: skip
    done = run_python(python, ["-c", code], user)
    assert done.returncode == 0, done.stderr[-3000:]


def copy_user(installed: Path, user: Path) -> Path:
    """A copy of a user folder the zip was installed into: the extension's files and its wheels (about 230 MB)
    hard-linked, since Blender only adds and deletes those (disabling removes the wheels, enabling extracts them
    anew), never rewrites one in place; everything else (preferences, caches, repository indexes) copied."""
    linked = [installed / "extensions" / ".local", *(installed / "extensions" / "user_default").glob("[!.]*")]

    def place(source: str, target: str) -> None:
        if any(Path(source).is_relative_to(folder) for folder in linked):
            os.link(source, target)
        else:
            shutil.copy2(source, target)

    shutil.copytree(installed, user, symlinks=True, copy_function=place)
    return user


if __name__ == "__main__":
    print(python_of(sys.argv[1] if len(sys.argv) > 1 else selected()))
