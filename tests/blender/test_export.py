"""Export Motion as a user meets it (tests/blender/export_session.py in a subprocess, the built zip installed): the
baked range of the manikin and its carried box to FBX, glTF and BVH, each re-imported into an empty file with the
settings docs/guide/exports.md gives, lands on the same frames with every bone head where it was; and the help
buttons of the sidebar panels.
"""

from __future__ import annotations

import numpy as np
import pytest

from blender_manikin.scene.help import DOCS_URL

MM = 1e-3
START, END = 3, 8  # export_session.py's baked range


@pytest.fixture(scope="module")
def session(tmp_path_factory, run_session) -> dict:
    return run_session(tmp_path_factory.mktemp("export"), "export_session.py")


def test_export_before_a_bake_says_so(session: dict) -> None:
    assert "has no baked motion: Bake Motion first" in session["unbaked"]


def test_export_motion_writes_each_format_and_leaves_the_scene_as_it_was(session: dict) -> None:
    assert session["bake"] == ["FINISHED"]
    assert session["export"] == {"fbx": ["FINISHED"], "glb": ["FINISHED"], "bvh": ["FINISHED"]}
    assert session["files"] == ["motion.bvh", "motion.fbx", "motion.glb"]  # the Format gave .glb; .bvh won over it
    assert session["state_after"] == session["state_before"]  # range, current frame, selection
    assert session["keys_after"] == session["keys_before"]  # the FBX's one-frame move of the keys was undone


@pytest.mark.parametrize("fmt", ["fbx", "glb", "bvh"])
def test_reimport_lands_on_the_baked_frames(session: dict, fmt: str) -> None:
    """The imported animation spans the baked frames, and at each of them every bone head (and the carried box, for
    FBX and glTF) is within 1 mm of where the baked manikin had it."""
    assert session[f"{fmt}_import"] == ["FINISHED"]
    np.testing.assert_allclose(session[f"{fmt}_range"], [START, END], atol=1e-3)
    assert session[f"{fmt}_objects"].count("ARMATURE") == 1  # only the manikin: no targets, no obstacles
    if fmt != "bvh":
        assert "MESH" in session[f"{fmt}_objects"]  # the body (and the box) went along
        np.testing.assert_allclose(session[f"{fmt}_box_range"], [START, END], atol=1e-3)
    for frame, baked in session["original"].items():
        again = session[fmt][frame]
        assert set(again["bones"]) == set(baked["bones"])
        for name, head in baked["bones"].items():
            assert np.linalg.norm(np.subtract(again["bones"][name], head)) < MM, (fmt, frame, name)
        if fmt != "bvh":
            assert np.linalg.norm(np.subtract(again["box"], baked["box"])) < MM, (fmt, frame)


def test_every_panel_has_a_help_button(session: dict) -> None:
    assert session["help"] and all(len(urls) == 1 for urls in session["help"].values()), session["help"]
    assert all(urls[0].startswith(DOCS_URL) for urls in session["help"].values())
    assert session["help"]["MANIKIN_PT_motion"][0].endswith("#motions-in-blender-bake-batch-exports")


def test_no_traceback(session: dict) -> None:
    assert "Traceback" not in session["log"]
