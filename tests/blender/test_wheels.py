"""The extension draws every picture and plot with only the wheels it ships (tests/blender/wheels_session.py in a
subprocess, the built zip installed into a Blender-equivalent Python that has numpy and nothing else): the bake's
ergonomics plots and key-pose picture, a study's summary plots and its envelope pictures. matplotlib's optional
helpers that the manifest leaves out (fonttools: PDF/PS/SVG fonts; tzdata: python-dateutil's time zones) are not
there, and nothing needed them."""

from __future__ import annotations

import tomllib
from pathlib import Path

import numpy as np
import pytest
from environments import ROOT

MANIFEST = tomllib.loads((ROOT / "blender_manifest.toml").read_text(encoding="utf-8"))
LINUX = {Path(w).name.split("-")[0].lower() for w in MANIFEST["wheels"] if "win" not in w and "macos" not in w}
LEFT_OUT = ("fontTools", "tzdata")


@pytest.fixture(scope="module")
def session(tmp_path_factory, run_session) -> dict:
    return run_session(tmp_path_factory.mktemp("wheels"), "wheels_session.py")


def _drawn(path: Path) -> float:
    """The spread of a PNG's colours (0 for a blank image)."""
    import matplotlib.image

    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", path
    return float(np.std(matplotlib.image.imread(path)[:, :, :3]))


def test_blender_installs_exactly_the_shipped_wheels(session: dict) -> None:
    assert set(session["installed"]) == LINUX and not {"fonttools", "tzdata"} & LINUX
    user = str(Path(session["work"], "user"))
    for name in ("matplotlib", "PIL", "dateutil"):
        assert session["found"][name].startswith(user), (name, session["found"][name])
    assert all(session["found"][name] is None for name in LEFT_OUT), session["found"]


def test_the_bake_draws_its_plots_and_its_picture(session: dict) -> None:
    work = Path(session["work"])
    assert session["bake"] == 0, session["log"][-3000:]
    for name in ("poses.png", "ergo_loads.png", "ergo_scores.png", "ergo_back.png"):
        assert _drawn(work / name) > 0.05, name


def test_the_study_draws_its_plots_and_its_envelope_pictures(session: dict) -> None:
    assert session["study"]["code"] == 0, session["study"]["log"]
    pictures = [Path(p) for p in session["study"]["pictures"]]
    names = {p.name for p in pictures}
    assert {"feasibility.png", "scores.png", "envelopes.png"} <= names and len(names) == 4, names  # + the envelope's
    assert all(_drawn(p) > 0.02 for p in pictures)
    assert "matplotlib" in session["loaded"] and not set(LEFT_OUT) & set(session["loaded"])  # the bake drew here
