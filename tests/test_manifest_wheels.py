"""The manifest's wheels: every platform gets the same packages at the same versions, one wheel each, the test
environment (requirements.txt) runs the scipy, matplotlib and numba that the extension ships, each shipped package
finds what it requires (numpy: every supported Blender's own), and what the manifest leaves
out of matplotlib's requirements (fonttools, tzdata: Blender extracts every wheel's files again on each enable) the
add-on's pictures and plots never import."""

from __future__ import annotations

import importlib.util
import os
import subprocess
import sys
import tomllib
from collections import defaultdict
from importlib import metadata
from pathlib import Path

import pytest
from packaging.requirements import Requirement
from packaging.utils import canonicalize_name

ROOT = Path(__file__).resolve().parents[1]
MANIFEST = tomllib.loads((ROOT / "blender_manifest.toml").read_text(encoding="utf-8"))


def _platform(tag: str) -> str:
    """The Blender platform of a wheel's platform tag, as the build tool maps them ("any" for pure Python)."""
    if tag == "any":
        return "any"
    if tag.startswith("macosx"):
        return "macos-arm64" if tag.endswith("arm64") else "macos-x64"
    return "windows-x64" if tag == "win_amd64" else "linux-x64"


def test_every_platform_gets_one_wheel_of_each_compiled_package() -> None:
    by_platform: dict[str, dict[str, str]] = defaultdict(dict)
    for wheel in MANIFEST["wheels"]:
        name, version, *_, tag = Path(wheel).stem.split("-")
        platform = _platform(tag.split(".")[0])
        assert name not in by_platform[platform], f"two {name} wheels for {platform}"
        by_platform[platform][name] = version
    pure = by_platform.pop("any")
    assert set(by_platform) == set(MANIFEST["platforms"])
    first = next(iter(by_platform.values()))
    assert all(packages == first for packages in by_platform.values()), by_platform
    assert {"scipy", "matplotlib", "numba", "llvmlite"} <= set(first) and not set(first) & set(pure)
    assert all(w.startswith("./wheels/") for w in MANIFEST["wheels"])


def test_the_tests_run_the_shipped_scipy_and_matplotlib() -> None:
    shipped = {Path(w).name.split("-")[0]: Path(w).name.split("-")[1] for w in MANIFEST["wheels"]}
    pins = {}
    for line in (ROOT / "requirements.txt").read_text(encoding="utf-8").splitlines():
        requirement = line.split("#")[0].strip()
        if "==" in requirement:
            name, version = requirement.split("==")
            pins[name.strip()] = version.strip()
    for name in ("scipy", "matplotlib", "pyparsing", "numba", "llvmlite"):
        assert pins[name] == shipped[name], name


def _blender_numpys() -> list[str]:
    """The numpy versions the supported Blenders bundle (tests/blender/environments.py)."""
    spec = importlib.util.spec_from_file_location("environments", ROOT / "tests" / "blender" / "environments.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return sorted({numpy for _, numpy in module.BLENDERS.values()})


def test_each_shipped_wheel_finds_what_it_requires_in_every_blender() -> None:
    """numpy is Blender's own (1.24.3 in 4.2: numba 0.62 needs >= 1.22, scipy 1.15 >= 1.23.5); everything else a
    shipped package requires is shipped at a version it accepts, or left out knowingly (fonttools, tzdata). The
    requirements are read from this environment's install of the same version (requirements.txt pins them)."""
    shipped = {canonicalize_name(Path(w).name.split("-")[0]): Path(w).name.split("-")[1] for w in MANIFEST["wheels"]}
    checked = []
    for name, version in shipped.items():
        try:
            if metadata.version(name) != version:
                continue  # another version here (contourpy, packaging): its requirements may differ
        except metadata.PackageNotFoundError:
            continue
        checked.append(name)
        for requirement in map(Requirement, metadata.requires(name) or []):
            if requirement.marker is not None and not requirement.marker.evaluate({"extra": ""}):
                continue
            wanted = canonicalize_name(requirement.name)
            if wanted == "numpy":
                assert all(requirement.specifier.contains(v) for v in _blender_numpys()), (name, str(requirement))
            elif wanted in shipped:
                assert requirement.specifier.contains(shipped[wanted], prereleases=True), (name, str(requirement))
            else:
                assert wanted in {"fonttools", "tzdata"}, (name, str(requirement))
    assert {"scipy", "matplotlib", "numba", "llvmlite"} <= set(checked), checked


# Run first thing in every Python the test starts (a sitecustomize module on PYTHONPATH, so the study's worker
# processes block them too): importing a left-out package, or any module of it, is an ImportError.
BLOCKER = """import importlib.abc, sys
LEFT_OUT = {left_out!r}
class LeftOut(importlib.abc.MetaPathFinder):
    def find_spec(self, name, path=None, target=None):
        if name.split(".")[0] in LEFT_OUT:
            raise ImportError(f"{{name}}: not shipped with the extension (blender_manifest.toml)")
sys.meta_path.insert(0, LeftOut())
"""
# What motion/picture.py does with matplotlib besides what the solver's plots do (it needs bpy for the tiles).
PICTURE = """import numpy as np, matplotlib.image, sys
from matplotlib.figure import Figure
fig = Figure(figsize=(4, 2), dpi=50)
for ax in fig.subplots(1, 2, squeeze=False)[0]:
    ax.imshow(np.random.default_rng(0).random((8, 8, 3))); ax.set_axis_off(); ax.set_title("frame 1")
    ax.text(0.5, -0.015, "RULA 5, REBA 7", transform=ax.transAxes, ha="center", va="top")
fig.suptitle("key poses"); fig.savefig(sys.argv[1])
assert matplotlib.image.imread(sys.argv[1]).shape[:2] == (100, 200)
"""
# The bpy-free tests that draw the add-on's plots: ergonomics (loads, scores, back), a study's feasibility and
# scores, a reach envelope study's envelopes and per-row sections.
PLOT_TESTS = [
    "tests/solver/ergonomics/test_ergonomics.py::test_cli_ergo_writes_json_csv_and_plots",
    "tests/solver/study/test_study.py::test_the_rows_say_who_can_do_it_and_how_hard",
    "tests/solver/study/test_study_envelope.py::test_each_row_has_its_summary_and_its_meshes",
]


def left_out_modules() -> set[str]:
    """The top-level modules of what matplotlib (and what it needs, transitively) requires but the manifest does not
    ship, as this environment (the same matplotlib, requirements.txt) installs them."""
    shipped = {Path(w).name.split("-")[0].lower().replace("_", "-") for w in MANIFEST["wheels"]}
    needed, todo = set(), ["matplotlib"]
    while todo:
        for requirement in metadata.requires(todo.pop()) or []:
            req = Requirement(requirement)
            name = canonicalize_name(req.name)
            if (req.marker is None or req.marker.evaluate({"extra": ""})) and name not in needed:
                needed.add(name)
                todo.append(name)
    modules = {dist: set() for dist in needed - shipped - {"numpy"}}  # numpy: Blender's own
    for module, dists in metadata.packages_distributions().items():
        for dist in dists:
            if canonicalize_name(dist) in modules:
                modules[canonicalize_name(dist)].add(module)
    assert all(modules.values()), modules  # each left-out requirement is installed here, so it can be blocked
    return {m for found in modules.values() for m in found}


def test_matplotlib_s_requirements_left_out_are_the_ones_named() -> None:
    """A matplotlib upgrade that requires something new fails here until the manifest ships it or leaves it out
    knowingly (and test_the_add_on_draws_without_what_is_left_out proves it may)."""
    assert left_out_modules() == {"fontTools", "tzdata"}


@pytest.mark.slow  # a solve, an ergonomics report, two small studies: 10-35 s
def test_the_add_on_draws_without_what_is_left_out(tmp_path: Path) -> None:
    (tmp_path / "sitecustomize.py").write_text(BLOCKER.format(left_out=sorted(left_out_modules())), encoding="utf-8")
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(tmp_path), str(ROOT)]))
    probe = "import fontTools"
    blocked = subprocess.run([sys.executable, "-c", probe], env=env, capture_output=True, text=True)
    assert "not shipped with the extension" in blocked.stderr  # the blocker works
    picture = subprocess.run([sys.executable, "-c", PICTURE, str(tmp_path / "p.png")], env=env, capture_output=True,
                             text=True, cwd=ROOT)  # fmt: skip
    assert picture.returncode == 0, picture.stderr[-3000:]
    tests = [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "-W", "error::ImportWarning",
             "--basetemp", str(tmp_path / "t"), *PLOT_TESTS]  # fmt: skip
    done = subprocess.run(tests, env=env, capture_output=True, text=True, cwd=ROOT, timeout=600)
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
