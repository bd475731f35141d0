"""Skin weights for our armature: the MPFB default rig's weights carried over through a bone map, normalised.

Our bones are the armature's (``blender_manikin.rigging.bones``): one per joint group, named after the group's
last link, e.g. ``upper_arm_l``, ``index_l_middle``, ``t7``. The map (MPFB -> ours, ``{s}`` = l / r):

=====================================  =============================================================
MPFB                                   ours
=====================================  =============================================================
root, pelvis.L/.R                      pelvis
spine05..spine01, neck01..03, breast   the axial chain pelvis, l5 .. t1, c7 .. c2, head, shared by
                                       height (below)
clavicle, shoulder01                   clavicle_{s}, scapula_{s}
upperarm01/02, lowerarm01/02           upper_arm_{s}, forearm_{s}
wrist, metacarpal1..4                  hand_{s}
finger1-1/2/3                          thumb_{s}_metacarpal / _proximal / _distal
finger2..5-1/2/3                       index / middle / ring / little _{s}_proximal / _middle / _distal
upperleg01/02, lowerleg01/02           thigh_{s}, shank_{s}
foot, toe*                             foot_{s}, toes_{s}
head, jaw, eyes, face, tongue          head (the ``eyes`` bone gets none: the mesh has no eyeballs)
=====================================  =============================================================

MPFB has 5 spine and 3 neck bones, we have 24 vertebrae: a vertex's weight on MPFB's trunk bones goes to our
axial chain by its height in our zero pose, split linearly between the two bones whose mid-heights enclose it.
"""

from __future__ import annotations

import numpy as np

from ..body.model import Model
from ..errors import ModelError
from .landmarks import FINGERS

AXIAL = ("spine05", "spine04", "spine03", "spine02", "spine01", "neck01", "neck02", "neck03", "breast")
PHALANX = ("proximal", "middle", "distal")
THUMB = ("metacarpal", "proximal", "distal")
MIDLINE = 0.001  # m: vertices this close to x = 0 are on both sides (the sternum follows both clavicles)
VERTEBRAE = ("l5", "l4", "l3", "l2", "l1", *(f"t{k}" for k in range(12, 0, -1)), *(f"c{k}" for k in range(7, 1, -1)))


def our_bone(mpfb: str) -> str | None:
    """Our bone for an MPFB default-rig bone, or None for the trunk bones shared along the axial chain."""
    base, _, side = mpfb.partition(".")
    s = side.lower()
    if base in AXIAL:
        return None
    if base in ("root", "pelvis"):
        return "pelvis"
    named = {"clavicle": "clavicle", "shoulder01": "scapula", "upperarm01": "upper_arm", "upperarm02": "upper_arm",
             "lowerarm01": "forearm", "lowerarm02": "forearm", "wrist": "hand", "upperleg01": "thigh",
             "upperleg02": "thigh", "lowerleg01": "shank", "lowerleg02": "shank", "foot": "foot"}  # fmt: skip
    if base in named:
        return f"{named[base]}_{s}"
    if base.startswith("metacarpal"):
        return f"hand_{s}"
    if base.startswith("finger"):
        k, n = (int(t) for t in base[len("finger") :].split("-"))
        if k == 1:
            return f"thumb_{s}_{THUMB[n - 1]}"
        finger = next(f for f, v in FINGERS.items() if v == k)
        return f"{finger}_{s}_{PHALANX[n - 1]}"
    if base.startswith("toe"):
        return f"toes_{s}"
    return "head"


def axial_chain(model: Model) -> tuple[list[str], np.ndarray]:
    """Our trunk bones from the pelvis up (pelvis, l5 .. c2, head) and the height (m) of each one's lower joint."""
    zero = model.forward(model.zero_pose())
    hips = [zero.position[model.joint_index(f"hip_{s}_flexion")][2] for s in ("l", "r")]
    names, heights = ["pelvis"], [0.5 * (hips[0] + hips[1])]
    for bone, joint in [(v, f"{v}_rx") for v in VERTEBRAE] + [("head", "c1_rx")]:
        if joint not in model.joint_names:
            raise ModelError(f"body mesh: model '{model.name}' has no joint '{joint}' (only human bodies get a mesh)")
        names.append(bone)
        heights.append(zero.position[model.joint_index(joint)][2])
    return names, np.array(heights)


def axial_shares(z: np.ndarray, heights: np.ndarray) -> np.ndarray:
    """(n, k) shares of the axial chain's k bones for points at heights ``z`` (m): linear between the bones'
    mid-heights, all to the end bone beyond them; every row sums to 1."""
    spans = np.diff(heights)
    middles = np.concatenate([heights[:-1] + 0.5 * spans, [heights[-1] + 0.5 * spans[-1]]])
    return np.column_stack([np.interp(z, middles, np.eye(len(heights))[k]) for k in range(len(heights))])


def side_of(bone: str) -> str | None:
    """``l``, ``r`` or None (midline) from our bone name's tokens."""
    tokens = bone.split("_")
    return "l" if "l" in tokens else "r" if "r" in tokens else None


def transfer(model: Model, mpfb_bones: tuple[str, ...], weights: np.ndarray, vertices: np.ndarray,
             base_x: np.ndarray) -> tuple:  # fmt: skip
    """(our bone names, (N, B) weights, weight removed) for ``vertices`` (N, 3, our zero pose) skinned by ``weights``
    (N, M) over ``mpfb_bones``. Rows are normalised. A vertex's side is its x sign on the base mesh (``base_x``, m;
    within :data:`MIDLINE` of 0 it is on both): a bone of the other side keeps no weight, and the largest share so
    removed from a vertex is returned (0 for the shipped data). (The fit may move a vertex across x = 0: the inner
    thighs of a body whose knees are closer than MPFB's touch and overlap a little.)"""
    chain, heights = axial_chain(model)
    mapped = [our_bone(b) for b in mpfb_bones]
    names = list(chain) + sorted({b for b in mapped if b is not None} - set(chain))
    missing = [b for b in names if b not in model.link_names]
    if missing:
        raise ModelError(f"body mesh: model '{model.name}' has no bone '{missing[0]}' (only human bodies get a mesh)")
    out = np.zeros((len(vertices), len(names)))
    axial = np.zeros(len(vertices))
    for column, bone in enumerate(mapped):
        if bone is None:
            axial += weights[:, column]
        else:
            out[:, names.index(bone)] += weights[:, column]
    out[:, : len(chain)] += axial[:, None] * axial_shares(vertices[:, 2], heights)
    before = out.sum(axis=1)
    for k, bone in enumerate(names):
        other = {"l": base_x < -MIDLINE, "r": base_x > MIDLINE}.get(side_of(bone) or "")
        if other is not None:
            out[other, k] = 0.0
    total = out.sum(axis=1, keepdims=True)
    if np.any(total <= 0.0):
        raise ModelError(f"body mesh: {int(np.sum(total <= 0.0))} vertices left without a bone by the weight map")
    removed = float(np.max((before - total[:, 0]) / np.maximum(before, 1e-12)))
    return names, out / total, removed
