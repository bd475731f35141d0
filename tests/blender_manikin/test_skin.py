"""The skinned human's mesh and weights for the armature (blender_manikin/rigging/skin.py, NumPy only) and how it
deforms: eyeballs closed and facing out, weights normalised and on the right side, the twist helpers taking the
pinch out of a twisted forearm, the elbow and knee keeping most of their section when bent (numbers in
docs/BODY_MESH.md). Also the capsule display mesh and the mesh measures it relies on."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from blender_manikin.rigging.body_mesh import capsule_mesh
from blender_manikin.rigging.bones import RigLayout
from blender_manikin.rigging.skin import SkinMesh, deform, eyeball, skin_mesh, twist_bones, twist_name
from solver.bodymesh import fit_body
from solver.bodymesh.measure import edges, section_area, smooth
from solver.bodymesh.transfer import MIDLINE, side_of
from solver.collision.body import capsules_of
from solver.io.scenario.bodies import load_body


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


def _dense(skin: SkinMesh) -> tuple[list[str], np.ndarray]:
    names = sorted(skin.groups)
    weights = np.zeros((len(skin.vertices), len(names)))
    for k, name in enumerate(names):
        index, weight = skin.groups[name]
        weights[index, k] = weight
    return names, weights


def _untwisted(skin: SkinMesh) -> SkinMesh:
    """The same skin with every helper's weight back on its bone: the whole segment twists as one."""
    groups = dict(skin.groups)
    for helper, bone in skin.twists.items():
        dense = np.zeros(len(skin.vertices))
        for index, weight in (groups.pop(helper), groups[bone]):
            dense[index] += weight
        index = np.flatnonzero(dense)
        groups[bone] = (index, dense[index])
    return replace(skin, groups=groups, twists={})


def test_eyeball_is_closed_and_faces_outwards() -> None:
    centre = np.array([0.1, -0.2, 1.6])
    vertices, polygons, slots = eyeball(centre, 0.012)
    np.testing.assert_allclose(np.linalg.norm(vertices - centre, axis=1), 0.012)
    sides = {}
    for polygon in polygons:
        corners = vertices[polygon]
        normal = sum(np.cross(a, b) for a, b in zip(corners, np.roll(corners, -1, axis=0), strict=True))
        assert normal @ (corners.mean(axis=0) - centre) > 0.0  # counter-clockwise seen from outside
        for a, b in zip(polygon, np.roll(polygon, -1), strict=True):
            sides[(a, b)] = sides.get((a, b), 0) + 1
    assert all(sides.get((b, a)) == 1 for a, b in sides) and set(sides.values()) == {1}  # closed, manifold
    front = [i for i, p in enumerate(polygons) if vertices[p].mean(axis=0)[1] < centre[1] - 0.01]
    assert {slots[i] for i in front} == {2}  # the iris looks forward (-y)


def test_weights_are_normalised_and_stay_on_their_side(skin: SkinMesh, fitted, layout: RigLayout) -> None:
    names, weights = _dense(skin)
    np.testing.assert_allclose(weights.sum(axis=1), 1.0, atol=1e-12)
    assert set(names) <= {b.name for b in layout.bones} | set(skin.twists)
    base_x = fitted.data.vertices[:, 0]
    for k, name in enumerate(names):
        side = side_of(name.removesuffix(".twist"))
        on = np.flatnonzero(weights[: len(base_x), k] > 0.0)
        if side == "l":
            assert (base_x[on] >= -MIDLINE).all(), name
        elif side == "r":
            assert (base_x[on] <= MIDLINE).all(), name
    eyes = np.arange(len(fitted.vertices), len(skin.vertices))
    assert len(eyes) > 0 and (weights[eyes, names.index("head")] == 1.0).all()


def test_twist_helpers_split_the_segments_mpfb_splits(skin: SkinMesh, fitted, layout: RigLayout) -> None:
    assert sorted(twist_bones(layout)) == sorted(f"{b}_{s}" for b in ("upper_arm", "forearm", "thigh") for s in "lr")
    assert skin.twists == {twist_name(b): b for b in twist_bones(layout)}
    assert twist_bones(RigLayout(load_body(preset="snake"))) == []
    names, weights = _dense(skin)
    data = fitted.data
    n = len(fitted.vertices)
    near = data.weights[:n, data.weight_bones.index("lowerarm01.L")]
    far = data.weights[:n, data.weight_bones.index("lowerarm02.L")]
    helper, bone = weights[:n, names.index("forearm_l.twist")], weights[:n, names.index("forearm_l")]
    both = helper + bone
    on = both > 0.01
    np.testing.assert_allclose(helper[on] / both[on], near[on] / np.maximum(near + far, 1e-12)[on], atol=1e-9)


def _sections(vertices: np.ndarray, faces: np.ndarray, start: np.ndarray, end: np.ndarray) -> np.ndarray:
    """Section areas (m^2) of the limb between two joints, at 10 places along it."""
    axis = end - start
    return np.array([section_area(vertices, faces, start + f * axis, axis, 0.07) for f in np.linspace(0.05, 0.95, 10)])


def _joint(model, theta: np.ndarray, name: str) -> np.ndarray:
    return model.forward(theta).position[model.joint_index(name)]


def test_twist_helpers_take_the_pinch_out_of_a_twisted_forearm(skin: SkinMesh, fitted, layout: RigLayout,
                                                               model) -> None:  # fmt: skip
    """At 80 degrees of pronation, one bone twisting the whole forearm pinches it at the elbow to about 71 % of its
    section; with the helpers no section of the forearm falls below 85 %."""
    n, faces = len(fitted.vertices), fitted.faces
    zero = model.zero_pose()
    rest = _sections(skin.vertices[:n], faces, _joint(model, zero, "elbow_r_flexion"),
                     _joint(model, zero, "wrist_r_flexion"))  # fmt: skip
    for degrees in (-80.0, 80.0):
        theta = zero.copy()
        theta[model.joint_index("forearm_r_pronation")] = np.radians(degrees)
        theta[model.joint_index("elbow_r_flexion")] = np.radians(20.0)
        ends = _joint(model, theta, "elbow_r_flexion"), _joint(model, theta, "wrist_r_flexion")
        split = _sections(deform(skin, layout, theta)[:n], faces, *ends) / rest
        whole = _sections(deform(_untwisted(skin), layout, theta)[:n], faces, *ends) / rest
        assert split.min() > 0.85 and whole.min() < 0.82 and split.min() > whole.min() + 0.05, (split, whole)


@pytest.mark.parametrize(
    ("joints", "least"),
    [
        (("shoulder_r_flexion", "elbow_r_flexion", "wrist_r_flexion"), 0.68),
        (("hip_r_flexion", "knee_r_flexion", "ankle_r_dorsiflexion"), 0.68),
    ],
)
def test_elbow_and_knee_keep_their_section_when_bent(skin: SkinMesh, fitted, layout: RigLayout, model, joints,
                                                     least: float) -> None:  # fmt: skip
    """The section through the joint on the plane halfway between the two segments keeps ``least`` of its straight
    area at 120 degrees of flexion (linear blend skinning loses some: 71 % measured for either)."""
    n, faces = len(fitted.vertices), fitted.faces

    def section(theta: np.ndarray, vertices: np.ndarray) -> float:
        a, j, b = (_joint(model, theta, name) for name in joints)
        normal = (j - a) / np.linalg.norm(j - a) + (b - j) / np.linalg.norm(b - j)
        return section_area(vertices[:n], faces, j, normal, 0.1)

    zero = model.zero_pose()
    bent = zero.copy()
    bent[model.joint_index(joints[1])] = np.radians(120.0)
    assert section(bent, deform(skin, layout, bent)) > least * section(zero, skin.vertices)


def test_deform_keeps_the_rest_pose_and_moves_rigid_parts_rigidly(skin: SkinMesh, layout: RigLayout, model) -> None:
    np.testing.assert_allclose(deform(skin, layout, model.zero_pose()), skin.vertices, atol=1e-12)
    theta = model.zero_pose()
    theta[model.joint_index("elbow_r_flexion")] = np.radians(90.0)
    moved = deform(skin, layout, theta)
    index, weight = skin.groups["hand_r"]
    rigid = index[weight == 1.0]
    before = np.linalg.norm(skin.vertices[rigid[:, None]] - skin.vertices[rigid[None, :]], axis=2)
    after = np.linalg.norm(moved[rigid[:, None]] - moved[rigid[None, :]], axis=2)
    np.testing.assert_allclose(after, before, atol=1e-12)
    assert np.linalg.norm(moved[rigid] - skin.vertices[rigid], axis=1).min() > 0.1


def test_capsule_mesh_covers_the_collision_capsules(model, layout: RigLayout) -> None:
    capsules = capsules_of(model)
    mesh = capsule_mesh(layout, capsules)
    zero = layout.zero
    start = np.einsum("kij,kj->ki", zero.rotation[capsules.link], capsules.start) + zero.position[capsules.link]
    end = np.einsum("kij,kj->ki", zero.rotation[capsules.link], capsules.end) + zero.position[capsules.link]
    per = len(mesh.vertices) // len(capsules)
    for k in range(len(capsules)):
        points = mesh.vertices[k * per : (k + 1) * per]
        axis = end[k] - start[k]
        t = np.clip((points - start[k]) @ axis / (axis @ axis), 0.0, 1.0)
        distance = np.linalg.norm(points - (start[k] + t[:, None] * axis), axis=1)
        np.testing.assert_allclose(distance, capsules.radius[k], rtol=1e-9)  # on the capsule's surface
        assert (mesh.vertex_bone[k * per : (k + 1) * per] == layout.bone_of_link[capsules.link[k]]).all()


def test_section_area_of_a_cylinder() -> None:
    sides, rings = 64, 5
    turn = np.linspace(0.0, 2.0 * np.pi, sides, endpoint=False)
    vertices = np.array([(0.05 * np.cos(a), 0.05 * np.sin(a), z) for z in np.linspace(0, 0.4, rings) for a in turn])
    faces = np.array([(r * sides + i, r * sides + (i + 1) % sides, (r + 1) * sides + (i + 1) % sides,
                       (r + 1) * sides + i) for r in range(rings - 1) for i in range(sides)])  # fmt: skip
    polygon = 0.5 * sides * 0.05**2 * np.sin(2.0 * np.pi / sides)  # the inscribed polygon
    assert section_area(vertices, faces, np.array([0.0, 0.0, 0.17]), np.array([0.0, 0.0, 1.0]), 0.2) == (
        pytest.approx(polygon, rel=1e-9)
    )
    tilted = section_area(vertices, faces, np.array([0.0, 0.0, 0.2]), np.array([0.0, 0.5, 1.0]), 0.2)
    assert tilted == pytest.approx(np.hypot(1.0, 0.5) * np.pi * 0.05**2, rel=0.01)  # an ellipse
    assert section_area(vertices, faces, np.array([0.0, 0.0, 0.17]), np.array([0.0, 0.0, 1.0]), 0.01) == 0.0


def test_smoothing_is_neighbour_averaging(fitted) -> None:
    """Each round every row moves halfway to its neighbours' mean (checked against a plain loop over the edges)."""
    faces = fitted.faces[:400]
    used = np.unique(faces)
    rng = np.random.default_rng(3)
    values = rng.random((int(used.max()) + 3, 4))  # a few rows beyond the faces' vertices: they only halve
    expected = values.copy()
    pairs = edges(faces)
    for _ in range(3):
        total, count = np.zeros_like(expected), np.zeros(len(expected))
        for a, b in pairs:
            total[a] += expected[b]
            count[a] += 1
        expected = 0.5 * expected + 0.5 * total / np.maximum(count, 1.0)[:, None]
    np.testing.assert_allclose(smooth(values, faces, 3), expected, atol=1e-12)


@pytest.mark.parametrize("preset", ["female_5", "male_95"])
def test_every_human_preset_gets_a_skin(preset: str) -> None:
    model = load_body(preset=preset)
    layout = RigLayout(model)
    fitted = fit_body(model)
    skin = skin_mesh(fitted, layout)
    names, weights = _dense(skin)
    np.testing.assert_allclose(weights.sum(axis=1), 1.0, atol=1e-12)
    assert set(names) == {b.name for b in layout.bones} - {"eyes"} | {twist_name(b) for b in twist_bones(layout)}
    assert len(skin.vertices) == len(fitted.vertices) + 2 * len(eyeball(np.zeros(3), 1.0)[0])
