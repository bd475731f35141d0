"""Corresponding points of the two skeletons: our model's joint centres (zero pose) and the MPFB default rig's
joints on a shaped mesh. The bone map of the fit and of the weight transfer rests on this table.

Each landmark is named after our joint (its name without the motion: ``elbow_l`` for ``elbow_l_flexion``) and
defined on the MPFB side by a joint cube of the base mesh (its centre is an anchor point):

========================  ========================  =========================================================
ours                      MPFB                      note
========================  ========================  =========================================================
l5 (L5/S1), l3, l1        joint-spine-4, -3, -2     MPFB's lumbar joints, matched to the vertebra at the same
t7, c7, c1                joint-spine-1, joint-     fraction of the way from the hips to the head joint (checked
                          neck, joint-head          on the female and male shapes)
clavicle_{s} (SC joint)   joint-{s}-clavicle
scapula_{s} (AC joint)    joint-{s}-scapula
shoulder_{s}, elbow_{s}   joint-{s}-shoulder,
wrist_{s}                 -elbow, -hand
{finger}_{s}_mcp/pip/dip  joint-{s}-finger-k-1/2/3  k = 2 index, 3 middle, 4 ring, 5 little
thumb_{s}_cmc/mcp/ip      joint-{s}-finger-1-1/2/3
hip_{s}, knee_{s},        joint-{s}-upper-leg,
ankle_{s}                 -knee, -ankle
toes_{s} (MTP line)       mean of joint-{s}-toe-
                          1-1 .. 5-1
eyes                      mean of joint-l-eye,
                          joint-r-eye
========================  ========================  =========================================================

Side tags: ours ``l``/``r``, MPFB ``l``/``r`` in cube names and ``L``/``R`` in bone names; left is +x in both.
"""

from __future__ import annotations

import numpy as np

from ..body.humans.anthropometry import HIP_JOINT_SHARE
from ..body.model import Model
from ..errors import ModelError
from .data import BodyData

SIDES = ("l", "r")
FINGERS = {"index": 2, "middle": 3, "ring": 4, "little": 5}
SPINE = {"l5": "joint-spine-4", "l3": "joint-spine-3", "l1": "joint-spine-2", "t7": "joint-spine-1",
         "c7": "joint-neck", "c1": "joint-head"}  # fmt: skip
LIMBS = {"clavicle": "clavicle", "scapula": "scapula", "shoulder": "shoulder", "elbow": "elbow", "wrist": "hand",
         "hip": "upper-leg", "knee": "knee", "ankle": "ankle"}  # fmt: skip
OUR_JOINT = {"clavicle": "rx", "scapula": "tilt", "shoulder": "flexion", "elbow": "flexion", "wrist": "flexion",
             "hip": "flexion", "knee": "flexion", "ankle": "dorsiflexion", "toes": "flexion"}  # fmt: skip
PHALANGES = ("mcp", "pip", "dip")
THUMB = ("cmc", "mcp", "ip")
OUR_FINGER_JOINT = {"mcp": "mcp_flexion", "pip": "pip", "dip": "dip"}
OUR_THUMB_JOINT = {"cmc": "cmc_flexion", "mcp": "mcp", "ip": "ip"}


def mpfb_definitions() -> dict[str, list[str]]:
    """Landmark -> the MPFB anchors (joint cubes) whose mean defines it."""
    out = {ours: [cube] for ours, cube in SPINE.items()}
    out["eyes"] = ["joint-l-eye", "joint-r-eye"]
    for s in SIDES:
        for ours, cube in LIMBS.items():
            out[f"{ours}_{s}"] = [f"joint-{s}-{cube}"]
        out[f"toes_{s}"] = [f"joint-{s}-toe-{k}-1" for k in range(1, 6)]
        for finger, k in FINGERS.items():
            for n, joint in enumerate(PHALANGES, start=1):
                out[f"{finger}_{s}_{joint}"] = [f"joint-{s}-finger-{k}-{n}"]
        for n, joint in enumerate(THUMB, start=1):
            out[f"thumb_{s}_{joint}"] = [f"joint-{s}-finger-1-{n}"]
    return out


def our_joint_names() -> dict[str, str]:
    """Landmark -> the name of our model's joint at that point."""
    out = {ours: f"{ours}_rx" for ours in SPINE}
    out["eyes"] = "eyes_yaw"
    for s in SIDES:
        for ours in (*LIMBS, "toes"):
            out[f"{ours}_{s}"] = f"{ours}_{s}_{OUR_JOINT[ours]}"
        for finger in FINGERS:
            for joint in PHALANGES:
                out[f"{finger}_{s}_{joint}"] = f"{finger}_{s}_{OUR_FINGER_JOINT[joint]}"
        for joint in THUMB:
            out[f"thumb_{s}_{joint}"] = f"thumb_{s}_{OUR_THUMB_JOINT[joint]}"
    return out


def mpfb_landmarks(data: BodyData, points: np.ndarray) -> dict[str, np.ndarray]:
    """Landmark -> position (m) on ``points`` (the mesh's points, shaped or fitted)."""
    return {k: points[[data.anchor(a) for a in cubes]].mean(axis=0) for k, cubes in mpfb_definitions().items()}


def our_landmarks(model: Model) -> dict[str, np.ndarray]:
    """Landmark -> our joint centre (m, world, zero pose); also ``stature`` (top of the head, m), the foot's
    ``heel_{s}``/``toe_end_{s}`` (the sole's back and front edge on the floor) and ``hip_breadth`` (m, the body's
    breadth at the hips, from the hip joints' spacing as the body builder places them)."""
    zero = model.forward(model.zero_pose())
    out = {}
    for key, joint in our_joint_names().items():
        if joint not in model.joint_names:
            raise ModelError(f"body mesh: model '{model.name}' has no joint '{joint}' (only human bodies get a mesh)")
        out[key] = zero.position[model.joint_index(joint)].copy()
    out["hip_breadth"] = abs(out["hip_l"][0] - out["hip_r"][0]) / HIP_JOINT_SHARE
    top = out["c1"].copy()
    top[2] = float(model.info.get("stature", 0.0)) or _guess_top(out)
    out["stature"] = top
    for s in SIDES:
        rotation, centre = zero.tcp_frame(model.tcp(f"foot_{s}"))
        sole = model.tcp(f"foot_{s}").sole
        if sole is None:
            raise ModelError(f"body mesh: model '{model.name}' has no sole polygon on TCP 'foot_{s}'")
        ys = sole[:, 1]
        out[f"heel_{s}"] = centre + rotation @ np.array([0.0, ys.max(), 0.0])
        out[f"toe_end_{s}"] = centre + rotation @ np.array([0.0, ys.min(), 0.0])
    return out


def _guess_top(ours: dict[str, np.ndarray]) -> float:
    """Top of the head when a model states no stature: as far above the eyes as the eyes are above C1."""
    return float(ours["eyes"][2] + (ours["eyes"][2] - ours["c1"][2]))
