"""The skinned human as the armature needs it: the fitted body's mesh, eyeballs, and skin weights per bone with the
limbs' twist split over helper bones. NumPy only (no bpy), so it is tested without Blender.

Twist: our upper arm, forearm and thigh bones each turn about their own length by one channel (shoulder and hip
rotation, forearm pronation: the Euler y channel, applied first). Skinned to one bone, the whole segment turns
with it, and the skin between it and its parent (which does not turn) pinches like a sweet wrapper. MPFB splits
these segments into two bones (``upperarm01/02``, ``lowerarm01/02``, ``upperleg01/02``): its proximal bone's share
of a vertex goes to a helper bone ``<bone>.twist``, a child of the bone at its rest frame that undoes half of the
twist (the add-on drives it), the distal share stays on the bone. The skin's turn then steps 0 - 1/2 - 1 from the
parent to the bone, so no blend spans more than half of the twist.

Eyes: spheres at the fitted eye centres (the mesh has sockets, no eyeballs), looking along -y, on the head bone;
the front cap and first ring are the iris (material 2), the rest the sclera (material 1), the skin is material 0.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .bones import LETTERS, RigLayout

TWIST_SUFFIX = ".twist"
TWIST_SHARE = 0.5  # of the bone's twist that its helper keeps
TWIST_CHANNEL = 1  # rotation_euler index of the twist (the bone's y axis, applied first)
TWISTS = {"upper_arm": "upperarm01", "forearm": "lowerarm01", "thigh": "upperleg01"}  # our bone -> MPFB proximal
SKIN, SCLERA, IRIS = 0, 1, 2  # material slots
EYE_RINGS, EYE_SIDES = 8, 16  # latitude rings and segments of an eyeball
EYE_CAP = 10.0  # deg from each pole where an n-gon closes the sphere
IRIS_RINGS = 1  # rings next to the front cap that are iris


@dataclass(frozen=True)
class SkinMesh:
    """Vertices (m, armature space, zero pose), polygons as a flat vertex list with each one's corner count and
    material slot, and the weights: ``groups[name] = (vertex indices, weights)``, every vertex's weights summing
    to 1; ``twists`` maps each helper bone to its bone."""

    vertices: np.ndarray  # (N, 3)
    corners: np.ndarray  # (L,) vertex index of every polygon corner
    sizes: np.ndarray  # (P,) corners per polygon
    materials: np.ndarray  # (P,) material slot
    groups: dict[str, tuple[np.ndarray, np.ndarray]]
    twists: dict[str, str]


def twist_name(bone: str) -> str:
    return bone + TWIST_SUFFIX


def twist_bones(layout: RigLayout) -> list[str]:
    """The layout's bones that get a twist helper: those of :data:`TWISTS` in an Euler mode whose y channel is a
    joint and applied first (no channel of theirs before it in the mode's order), so undoing part of it in a child
    leaves the swing alone."""
    out = []
    for bone in layout.bones:
        if bone.name.rpartition("_")[0] not in TWISTS or not bone.exact:
            continue
        used = {c.index for c in bone.channels if c.prop == "rotation_euler"}
        before = bone.rotation_mode[: bone.rotation_mode.index("Y")]
        if TWIST_CHANNEL in used and not any(LETTERS.index(a) in used for a in before):
            out.append(bone.name)
    return out


def split_twist(bone_names: tuple[str, ...], weights: np.ndarray, mpfb_bones: tuple[str, ...],
                mpfb_weights: np.ndarray, twisting: list[str]) -> tuple[list[str], np.ndarray, dict]:  # fmt: skip
    """(names, (N, B + h) weights, helper -> bone): the weight of each bone in ``twisting`` split between it and its
    helper by the MPFB proximal bone's share of the two MPFB bones of that segment (``mpfb_weights``: (N, M) over
    ``mpfb_bones``). Rows keep their sums."""
    names, columns, twists = list(bone_names), [weights], {}
    for ours, proximal in TWISTS.items():
        distal = proximal[:-1] + "2"
        for side, tag in (("l", "L"), ("r", "R")):
            bone = f"{ours}_{side}"
            if bone not in twisting or bone not in bone_names:
                continue
            near = mpfb_weights[:, mpfb_bones.index(f"{proximal}.{tag}")]
            far = mpfb_weights[:, mpfb_bones.index(f"{distal}.{tag}")]
            share = np.divide(near, near + far, out=np.zeros_like(near), where=near + far > 0.0)
            k = names.index(bone)
            moved = columns[0][:, k] * share
            columns[0][:, k] -= moved
            columns.append(moved[:, None])
            names.append(twist_name(bone))
            twists[twist_name(bone)] = bone
    return names, np.hstack(columns), twists


def eyeball(centre: np.ndarray, radius: float) -> tuple[np.ndarray, list[list[int]], list[int]]:
    """(vertices, polygons, material slots) of a sphere looking along -y: rings of quads between two n-gon caps,
    counter-clockwise seen from outside."""
    polar = np.deg2rad(np.linspace(180.0 - EYE_CAP, EYE_CAP, EYE_RINGS))  # from the front (-y) backwards
    turn = np.linspace(0.0, 2.0 * np.pi, EYE_SIDES, endpoint=False)
    ring = np.stack([np.cos(turn), np.zeros_like(turn), np.sin(turn)], axis=1)
    points = [centre + radius * (np.sin(p) * ring + np.array([0.0, np.cos(p), 0.0])) for p in polar]
    vertices = np.concatenate(points)
    polygons, slots = [], []
    polygons.append(list(range(EYE_SIDES)))  # front cap
    slots.append(IRIS)
    for r in range(EYE_RINGS - 1):
        a, b = r * EYE_SIDES, (r + 1) * EYE_SIDES
        for i in range(EYE_SIDES):
            j = (i + 1) % EYE_SIDES
            polygons.append([a + i, b + i, b + j, a + j])
            slots.append(IRIS if r < IRIS_RINGS else SCLERA)
    last = (EYE_RINGS - 1) * EYE_SIDES
    polygons.append([last + i for i in reversed(range(EYE_SIDES))])
    slots.append(SCLERA)
    return vertices, polygons, slots


def skin_mesh(body, layout: RigLayout) -> SkinMesh:
    """The mesh and weights of a ``solver.bodymesh.FittedBody`` for the armature of ``layout`` (eyeballs added,
    twist split over the helpers of :func:`twist_bones`)."""
    n = len(body.vertices)
    data = body.data
    names, weights, twists = split_twist(body.bone_names, body.weights.copy(), data.weight_bones, data.weights[:n],
                                         twist_bones(layout))  # fmt: skip
    vertices = [body.vertices]
    corners = [body.faces.ravel()]
    sizes = [np.full(len(body.faces), body.faces.shape[1])]
    materials = [np.full(len(body.faces), SKIN)]
    eye_vertices = []
    for centre in body.eye_centres:
        offset = n + sum(len(v) for v in eye_vertices)
        points, polygons, slots = eyeball(centre, body.eye_radius)
        eye_vertices.append(points)
        corners.append(np.array([i + offset for p in polygons for i in p]))
        sizes.append(np.array([len(p) for p in polygons]))
        materials.append(np.array(slots))
    vertices += eye_vertices
    groups = {}
    for k, name in enumerate(names):
        idx = np.flatnonzero(weights[:, k] > 0.0)
        if len(idx):
            groups[name] = (idx, weights[idx, k])
    eyes = np.arange(n, n + sum(len(v) for v in eye_vertices))
    head_idx, head_w = groups["head"]
    groups["head"] = (np.concatenate([head_idx, eyes]), np.concatenate([head_w, np.ones(len(eyes))]))
    return SkinMesh(
        vertices=np.concatenate(vertices), corners=np.concatenate(corners).astype(np.int32),
        sizes=np.concatenate(sizes).astype(np.int32), materials=np.concatenate(materials).astype(np.int32),
        groups=groups, twists=twists,
    )  # fmt: skip


def bone_transforms(layout: RigLayout, theta: np.ndarray, twists: dict[str, str]) -> dict[str, np.ndarray]:
    """Bone (and twist helper) -> 4x4 map from the rest pose to the pose of joint values ``theta`` (armature space),
    as Blender's Armature modifier applies them: pose matrix times inverse rest matrix."""
    pose = layout.bone_matrices(layout.model.forward(theta))
    _, euler = layout.channel_values(theta)
    index = {bone.name: b for b, bone in enumerate(layout.bones)}
    out = {bone.name: pose[b] @ np.linalg.inv(bone.matrix()) for b, bone in enumerate(layout.bones)}
    for helper, bone in twists.items():
        b = index[bone]
        angle = (TWIST_SHARE - 1.0) * euler[b, TWIST_CHANNEL]
        c, s = np.cos(angle), np.sin(angle)
        untwist = np.array([[c, 0.0, s, 0.0], [0.0, 1.0, 0.0, 0.0], [-s, 0.0, c, 0.0], [0.0, 0.0, 0.0, 1.0]])
        out[helper] = pose[b] @ untwist @ np.linalg.inv(layout.bones[b].matrix())
    return out


def deform(skin: SkinMesh, layout: RigLayout, theta: np.ndarray) -> np.ndarray:
    """(N, 3) m: the mesh in the pose ``theta`` by linear blend skinning (what the Armature modifier does, without
    volume preservation), for measuring the deformation without Blender."""
    maps = bone_transforms(layout, theta, skin.twists)
    points = np.hstack([skin.vertices, np.ones((len(skin.vertices), 1))])
    out = np.zeros((len(points), 3))
    for bone, (index, weight) in skin.groups.items():
        out[index] += weight[:, None] * (points[index] @ maps[bone].T)[:, :3]
    return out
