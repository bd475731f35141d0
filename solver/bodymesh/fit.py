"""Fit a shaped MPFB body onto our skeleton: one affine map per body segment, blended by the MPFB skin weights.

Each MPFB default-rig bone follows one segment's affine (``segment_of``); a point moves to
``sum_b w_b (A_b p + t_b)`` (linear-blend skinning from the shaped rest pose to ours). The affines:

- limbs, spine, neck, fingers: a *two-point* map: the segment's MPFB end joints onto ours (rotation taking one
  direction onto the other, scaled along it to our length), turned about the segment so that a reference direction
  matches: the elbow's hinge axis for the arm (the base mesh's elbows are bent; ours straight, hinge along -x),
  left-right (+x) for the spine, legs and clavicles, the hand's index-to-little line for the fingers. Across the
  segment the scale is 1: girth comes from the macro targets, lengths from our joints. The forearm also turns
  about its axis so the hand's palm faces where ours does: 1/4 of that turn in the proximal half (``lowerarm01``),
  3/4 in the distal half, all of it in the hand;
- pelvis: no turn; moved so the hips' midpoint lands on ours, scaled vertically to our L5/S1 height above it and
  across so the mesh's hip breadth is our body's (``hip_breadth``). MPFB's hip joints sit further out in the
  hips than ours (x_hip = 1/4 of the hip breadth); matching them instead would make a man's hips narrow, moving
  the thighs in would push their inner sides across the midline. Each thigh runs from where the pelvis puts its
  hip joint to our knee: the hip joint is off along x only, the axis of hip flexion, so flexing the hip bends
  the mesh where ours bends;
- head (and face, eyes, jaw, tongue): no turn, uniform scale by the stature ratio, top of the head at our stature,
  front-back placed halfway between matching C1 and matching the eyes;
- hand (wrist, metacarpals, thumb): wrist -> index and little MCPs: along and across scaled to our hand, the
  thumb kept in MPFB's natural pose (ours lies in the finger plane, so the mesh's thumb would fold into the index);
- foot (and toes): ankle on ours, soles on the floor (vertical scale = ankle heights' ratio), length scaled to our
  sole's length, facing -y.

For the fit the weights are smoothed over the mesh (``measure.smooth``): the base pose's arms are raised 40 degrees
and its elbows bent, and MPFB's posing weights, blended sharply, would leave a ridge on the shoulders.
Units: m. The result: the fitted points (mesh vertices and anchors) in our zero pose.
"""

from __future__ import annotations

import numpy as np

from .data import BodyData
from .frames import Affine, apply, frame, frame_map, rotation_about, signed_angle
from .landmarks import FINGERS, SIDES

X, Z = np.array([1.0, 0.0, 0.0]), np.array([0.0, 0.0, 1.0])
HINGE = np.array([-1.0, 0.0, 0.0])  # upper arm x forearm when our elbow flexes (the forearm swings forward, -y)
FOREARM_TWIST = {"lowerarm01": 0.25, "lowerarm02": 0.75}
SPINE_BONES = {"spine05": ("pelvis_centre", "l5"), "spine04": ("l5", "l3"), "spine03": ("l3", "l1"),
               "spine02": ("l1", "t7"), "spine01": ("t7", "c7")}  # fmt: skip


def two_point(src: tuple[np.ndarray, np.ndarray, np.ndarray], dst: tuple[np.ndarray, np.ndarray, np.ndarray],
              across: float = 1.0) -> Affine:  # fmt: skip
    """(head, tail, reference direction) of MPFB onto ours: head onto head, along scaled to our length."""
    (h0, t0, r0), (h1, t1, r1) = src, dst
    scale = np.linalg.norm(t1 - h1) / max(np.linalg.norm(t0 - h0), 1e-9)
    return frame_map(frame(t0 - h0, r0), frame(t1 - h1, r1), np.array([scale, across, across]), h0, h1)


def twisted(affine: Affine, pivot: np.ndarray, axis: np.ndarray, angle: float) -> Affine:
    """``affine`` followed by a turn of ``angle`` rad about the line through ``pivot`` along ``axis``."""
    turn = rotation_about(axis, angle)
    linear, shift = affine
    return turn @ linear, turn @ (shift - pivot) + pivot


def _hand(mp: dict, us: dict, s: str) -> tuple[Affine, float]:
    """Wrist onto ours, index and little MCPs' midpoint and line scaled onto ours; also the thickness scale."""
    frames, lengths = [], []
    for side in (mp, us):
        wrist, index, little = side[f"wrist_{s}"], side[f"index_{s}_mcp"], side[f"little_{s}_mcp"]
        frames.append(frame(0.5 * (index + little) - wrist, little - index))
        lengths.append((np.linalg.norm(0.5 * (index + little) - wrist), np.linalg.norm(little - index)))
    along, across = lengths[1][0] / lengths[0][0], lengths[1][1] / lengths[0][1]
    thickness = float(np.sqrt(along * across))
    scales = np.array([along, across, thickness])
    return frame_map(frames[0], frames[1], scales, mp[f"wrist_{s}"], us[f"wrist_{s}"]), thickness


def _foot(mp: dict, us: dict, s: str, sole: float, foot_length: float) -> Affine:
    """Ankle onto ours; forward = the horizontal way to the toes; soles onto the floor."""
    forward = (mp[f"toes_{s}"] - mp[f"ankle_{s}"]) * np.array([1.0, 1.0, 0.0])
    ours = us[f"toe_end_{s}"] - us[f"heel_{s}"]
    vertical = us[f"ankle_{s}"][2] / max(mp[f"ankle_{s}"][2] - sole, 1e-9)
    length = np.linalg.norm(ours) / max(foot_length, 1e-9)
    source, target = frame(forward, Z), frame(ours * np.array([1.0, 1.0, 0.0]), Z)
    return frame_map(source, target, np.array([length, vertical, length]), mp[f"ankle_{s}"], us[f"ankle_{s}"])


def _arm(mp: dict, us: dict, s: str, out: dict[str, Affine]) -> None:
    gh, elbow, wrist = (mp[f"{k}_{s}"] for k in ("shoulder", "elbow", "wrist"))
    hinge = np.cross(elbow - gh, wrist - elbow)
    ours = [us[f"{k}_{s}"] for k in ("shoulder", "elbow", "wrist")]
    out[f"upper_arm_{s}"] = two_point((gh, elbow, hinge), (ours[0], ours[1], HINGE))
    forearm = two_point((elbow, wrist, hinge), (ours[1], ours[2], HINGE))
    hand, thickness = _hand(mp, us, s)
    out[f"hand_{s}"] = hand
    # how far the hand's across line (index -> little) turns about the forearm beyond the forearm's own map
    across_mp = mp[f"little_{s}_mcp"] - mp[f"index_{s}_mcp"]
    angle = signed_angle(forearm[0] @ across_mp, hand[0] @ across_mp, ours[2] - ours[1])
    for bone, share in FOREARM_TWIST.items():
        out[f"{bone}_{s}"] = twisted(forearm, ours[1], ours[2] - ours[1], share * angle)
    out[f"clavicle_{s}"] = two_point((mp[f"clavicle_{s}"], mp[f"scapula_{s}"], Z), (us[f"clavicle_{s}"],
                                     us[f"scapula_{s}"], Z))  # fmt: skip
    out[f"scapula_{s}"] = two_point((mp[f"scapula_{s}"], gh, Z), (us[f"scapula_{s}"], ours[0], Z))
    across = hand[0] @ across_mp
    for finger in FINGERS:
        joints = [f"{finger}_{s}_{j}" for j in ("mcp", "pip", "dip")]
        for k in range(2):
            src = (mp[joints[k]], mp[joints[k + 1]], across_mp)
            dst = (us[joints[k]], us[joints[k + 1]], across)
            out[f"{finger}_{s}_{k + 1}"] = two_point(src, dst, thickness)
        out[f"{finger}_{s}_3"] = out[f"{finger}_{s}_2"]  # the distal phalanx as the middle one (no tip joint)


def _trunk(mp: dict, us: dict, data_top: float, out: dict[str, Affine]) -> None:
    hips_mp = 0.5 * (mp["hip_l"] + mp["hip_r"])
    hips_us = 0.5 * (us["hip_l"] + us["hip_r"])
    vertical = (us["l5"][2] - hips_us[2]) / max(mp["l5"][2] - hips_mp[2], 1e-9)
    lateral = us["hip_breadth"] / max(mp["hip_breadth"], 1e-9)  # the mesh's hips as broad as our body's
    scales = np.array([lateral, 1.0, vertical])
    out["pelvis"] = pelvis = frame_map(np.eye(3), np.eye(3), scales, hips_mp, hips_us)
    scale = us["stature"][2] / max(data_top - mp["floor"], 1e-9)  # our soles are on z = 0
    head_y = 0.5 * ((us["c1"][1] - scale * mp["c1"][1]) + (us["eyes"][1] - scale * mp["eyes"][1]))
    shift = np.array([0.0, head_y, us["stature"][2] - scale * data_top])
    out["head"] = head = (scale * np.eye(3), shift)
    ends = {"pelvis_centre": (mp["pelvis_centre"], apply(pelvis, mp["pelvis_centre"][None])[0])}
    for bone, (a, b) in SPINE_BONES.items():
        src = ends[a][0] if a in ends else mp[a]
        dst = ends[a][1] if a in ends else us[a]
        out[bone] = two_point((src, mp[b], X), (dst, us[b], X))
    out["neck"] = two_point((mp["c7"], mp["c1"], X), (us["c7"], apply(head, mp["c1"][None])[0], X))


def segment_affines(mp: dict, us: dict, top: float, foot_length: dict[str, float]) -> dict[str, Affine]:
    """Segment key -> affine, from MPFB landmarks ``mp`` (plus ``pelvis_centre``, ``floor``: the shaped mesh's
    lowest z, and ``hip_breadth``), ours ``us`` (:func:`~.landmarks.our_landmarks`), the shaped mesh's ``top`` z and
    the MPFB feet's lengths (m)."""
    out: dict[str, Affine] = {}
    _trunk(mp, us, top, out)
    for s in SIDES:
        _arm(mp, us, s, out)
        hip = apply(out["pelvis"], mp[f"hip_{s}"][None])[0]  # where the pelvis puts the hip: no gap, no overlap
        out[f"thigh_{s}"] = two_point((mp[f"hip_{s}"], mp[f"knee_{s}"], X), (hip, us[f"knee_{s}"], X))
        out[f"shank_{s}"] = two_point((mp[f"knee_{s}"], mp[f"ankle_{s}"], X), (us[f"knee_{s}"], us[f"ankle_{s}"], X))
        out[f"foot_{s}"] = _foot(mp, us, s, mp["floor"], foot_length[s])
    return out


def segment_of(bone: str) -> str:
    """The segment key whose affine an MPFB default-rig bone follows (see the module docstring)."""
    base, _, side = bone.partition(".")
    s = side.lower()
    if base in SPINE_BONES:
        return base
    if base in ("root",) or base == "pelvis":
        return "pelvis"
    if base in ("neck01", "neck02", "neck03"):
        return "neck"
    if base == "breast":
        return "spine02"
    named = {"clavicle": "clavicle", "shoulder01": "scapula", "upperarm01": "upper_arm", "upperarm02": "upper_arm",
             "wrist": "hand", "upperleg01": "thigh", "upperleg02": "thigh", "lowerleg01": "shank",
             "lowerleg02": "shank", "foot": "foot"}  # fmt: skip
    if base in named:
        return f"{named[base]}_{s}"
    if base in FOREARM_TWIST:
        return f"{base}_{s}"
    if base.startswith("metacarpal") or base.startswith("finger1-"):
        return f"hand_{s}"
    if base.startswith("finger"):
        k, n = base[len("finger") :].split("-")
        return f"{dict((v, f) for f, v in FINGERS.items())[int(k)]}_{s}_{n}"
    if base.startswith("toe"):
        return f"foot_{s}"
    return "head"  # face, eyes, jaw, tongue: everything parented under the head


def segment_weights(data: BodyData) -> tuple[list[str], np.ndarray]:
    """Segment keys and (N + A, K) weights: each point's MPFB weights summed per segment."""
    segments = [segment_of(b) for b in data.weight_bones]
    keys = sorted(set(segments))
    summed = np.zeros((len(data.weights), len(keys)))
    for column, key in enumerate(segments):
        summed[:, keys.index(key)] += data.weights[:, column]
    return keys, summed


def blend(points: np.ndarray, keys: list[str], weights: np.ndarray, affines: dict[str, Affine]) -> np.ndarray:
    """Linear-blend skinning of ``points`` (P, 3): sum over segments of weight * affine(point)."""
    out = np.zeros_like(points)
    for k, key in enumerate(keys):
        used = weights[:, k] > 0.0
        out[used] += weights[used, k, None] * apply(affines[key], points[used])
    return out
