"""The skinned human as a user meets it (tests/blender/body_session.py in a subprocess, the built zip installed): a
new male_50 shows it, its vertex groups are the armature's bones with the weights of ``rigging/skin.py``, and the
Armature modifier moves it with the pose exactly as linear blend skinning of those weights over the solver's bone
frames predicts (twist helpers included), recomputed here from the solver.
"""

from __future__ import annotations

import zipfile
from pathlib import Path

import numpy as np
import pytest

from blender_manikin.rigging.bones import RigLayout
from blender_manikin.rigging.skin import (
    TWIST_SHARE,
    SkinMesh,
    bone_transforms,
    deform,
    skin_mesh,
    twist_bones,
    twist_name,
)
from solver.bodymesh import fit_body
from solver.bodymesh.transfer import MIDLINE, side_of
from solver.io.scenario.bodies import load_body

FLOAT32 = 2e-4  # m: Blender deforms in single precision, over a chain of bone matrices
MM = 1e-3


@pytest.fixture(scope="module")
def session(tmp_path_factory, run_session) -> dict:
    return run_session(tmp_path_factory.mktemp("body"), "body_session.py")


@pytest.fixture(scope="module")
def model():
    return load_body(preset="male_50")


@pytest.fixture(scope="module")
def layout(model) -> RigLayout:
    return RigLayout(model)


@pytest.fixture(scope="module")
def fitted(model):
    return fit_body(model)


@pytest.fixture(scope="module")
def skin(fitted, layout) -> SkinMesh:
    return skin_mesh(fitted, layout)


def _array(session: dict, name: str) -> np.ndarray:
    return np.load(Path(session["work"]) / f"{name}.npy")


def test_zip_ships_the_body_mesh_data(session: dict) -> None:
    names = zipfile.ZipFile(session["zip"]).namelist()
    for needed in ("mpfb2_base.npz", "mpfb2_rigs.json", "LICENSE.md", "SOURCE.txt"):
        assert f"presets/body_mesh/{needed}" in names


def test_a_new_manikin_shows_the_skinned_human(session: dict, skin: SkinMesh) -> None:
    assert session["display"] == "HUMAN"
    body = session["body"]
    assert session["bodies"] == {"male_50.body": ["HUMAN", False, False]}  # the other displays: made when chosen
    assert body["parent"] == "male_50" and body["hide_select"] and body["smooth"]
    assert body["vertices"] == len(skin.vertices)
    assert body["materials"] == ["manikin.skin", "manikin.eye", "manikin.iris"] and body["material_index"] == [0, 1, 2]
    # The Armature modifier first (on the manikin), then a subdivision for renders only.
    assert body["modifiers"] == [["ARMATURE", "male_50", None, None], ["SUBSURF", None, 0, 1]]


def test_vertex_groups_are_the_bones_with_normalised_weights(session: dict, skin: SkinMesh, fitted,
                                                             layout: RigLayout) -> None:  # fmt: skip
    bones = session["bones"]
    groups = session["groups"]
    assert set(groups) == set(skin.groups) and set(groups) <= set(bones)
    assert set(groups) >= {b.name for b in layout.bones} - {"eyes"}  # every bone but the eyes' carries skin
    for helper in (twist_name(b) for b in twist_bones(layout)):
        assert bones[helper] == [True, True, helper.removesuffix(".twist")]  # deforming, hidden, under its bone
    weights = _array(session, "weights")
    np.testing.assert_allclose(weights.sum(axis=1), 1.0, atol=1e-5)  # every vertex, eyeballs included
    for k, name in enumerate(groups):
        index, expected = skin.groups[name]
        dense = np.zeros(len(weights))
        dense[index] = expected
        np.testing.assert_allclose(weights[:, k], dense, atol=1e-6, err_msg=name)
    # No vertex follows a bone of the other side (the side: the vertex's x on MPFB's symmetric base mesh).
    base_x = fitted.data.vertices[:, 0]
    for k, name in enumerate(groups):
        side = side_of(name.removesuffix(".twist"))
        if side is None:
            continue
        on = np.flatnonzero(weights[: len(base_x), k] > 0.0)
        wrong = base_x[on] < -MIDLINE if side == "l" else base_x[on] > MIDLINE
        assert not wrong.any(), name


def _check_pose(session: dict, key: str, skin: SkinMesh, layout: RigLayout) -> np.ndarray:
    """The evaluated mesh in the recorded pose equals linear blend skinning over the solver's bone frames."""
    theta = np.array(session[key]["x"])[: layout.model.n]
    shown = _array(session, key)
    expected = deform(skin, layout, theta)
    assert np.abs(shown - expected).max() < FLOAT32
    assert np.linalg.norm(shown - skin.vertices, axis=1).max() > 0.15  # the pose did move the mesh
    return shown


def test_the_posed_mesh_follows_the_bones(session: dict, skin: SkinMesh, layout: RigLayout) -> None:
    np.testing.assert_allclose(_array(session, "rest"), skin.vertices, atol=FLOAT32)
    assert session["solve"] == ["FINISHED"]
    np.testing.assert_allclose(_array(session, "keyed"), _array(session, "twisted"), atol=FLOAT32)  # played back
    assert session["keyed_rest"] < FLOAT32
    for key in ("twisted", "lift"):
        shown = _check_pose(session, key, skin, layout)
        # A vertex of the hand (all its weight on hand_r) keeps its place on the hand bone, whatever the pose.
        index, weight = skin.groups["hand_r"]
        rigid = index[weight > 0.999]
        head_rest = next(b for b in layout.bones if b.name == "hand_r").head
        vertex = rigid[np.argmin(np.linalg.norm(skin.vertices[rigid] - head_rest, axis=1))]
        head_now = np.array(session[key]["bones"]["hand_r"])[:3, 3]
        rest_offset = np.linalg.norm(skin.vertices[vertex] - head_rest)
        assert rest_offset < 0.1
        assert abs(np.linalg.norm(shown[vertex] - head_now) - rest_offset) < MM


def test_twist_helpers_turn_half_the_twist(session: dict, skin: SkinMesh, layout: RigLayout) -> None:
    """The drivers hold each helper at TWIST_SHARE of its bone's twist (the forearm turned 60 degrees here)."""
    pose = session["twisted"]
    bones = {name: np.array(m) for name, m in pose["bones"].items()}
    maps = bone_transforms(layout, np.array(pose["x"])[: layout.model.n], skin.twists)
    rest = {b.name: b.matrix() for b in layout.bones}
    for helper, bone in skin.twists.items():
        np.testing.assert_allclose(bones[helper], maps[helper] @ rest[bone], atol=FLOAT32, err_msg=helper)
    theta = np.array(pose["x"])[: layout.model.n]
    b = next(i for i, bone in enumerate(layout.bones) if bone.name == "forearm_r")
    twist = np.degrees(layout.channel_values(theta)[1][b, 1])
    assert abs(twist) == pytest.approx(60.0)  # the forearm's pronation is its y channel
    relative = np.linalg.solve(bones["forearm_r"], bones["forearm_r.twist"])[:3, :3]
    turned = np.degrees(np.arctan2(relative[0, 2], relative[0, 0]))
    assert turned == pytest.approx(-(1.0 - TWIST_SHARE) * twist, abs=0.01)


def test_display_switches_between_human_capsules_and_solids(session: dict) -> None:
    names = {"HUMAN": "male_50.body", "CAPSULES": "male_50.capsules", "SOLIDS": "male_50.solids"}
    made = {"CAPSULES": ["HUMAN", "CAPSULES"], "SOLIDS": list(names), "HUMAN": list(names)}  # each when first chosen
    for mode, shown in session["modes"].items():
        assert set(shown) == {names[m] for m in made[mode]}
        for name, (display, hide_viewport, hide_render) in shown.items():
            assert display == next(m for m, n in names.items() if n == name)
            assert hide_viewport == hide_render == (name != names[mode]), (mode, name)
    assert session["capsule_groups"] == [1] and session["capsule_weights"] == [1.0]  # rigid, one bone each


def test_a_snake_gets_the_solids(session: dict) -> None:
    assert session["snake"] == dict(display="SOLIDS", bodies={"snake.body": ["SOLIDS", False, False]})
    assert session["snake_human"] == session["snake"]
    # A manikin from before the displays: its untagged ``.body`` counts as the solids (not built a second time).
    assert session["snake_legacy"] == {
        "snake.body": ["SOLIDS", False, False],
        "snake.capsules": ["CAPSULES", True, True],
    }
    assert "Traceback" not in session["log"]
