"""Body angles measured on the manikin of a result frame (degrees), the inputs of RULA, REBA, OWAS and the worksheet.

How each angle is measured (world positions of joints and TCPs from the result; joint names of
:mod:`solver.body.humans.human`; every vertebra's joints sit at its lower disc):

* Feet frame: origin between the sole centres, ``forward`` the mean heading of the feet, ``left`` = z x forward.
* Trunk axis u: from the lumbosacral joint (``l5_rx``, L5/S1) to the C7/T1 joint (``c7_rx``).
  ``trunk_flexion`` = atan2(u . forward, u . z) (+ forward, - extension); ``trunk_side_bend`` = asin(u . left);
  ``trunk_twist`` = angle about u from the hip line (``hip_r``->``hip_l`` joints) to the thorax line
  (sternoclavicular joints ``clavicle_r_rx``->``clavicle_l_rx``), both projected normal to u.
* Thorax frame: up_t = u, left_t = the thorax line made normal to u, forward_t = left_t x up_t.
* Head: ``head`` TCP rotation (identity in the zero pose, so its z is the head's up h and its x the head's left).
  ``head_tilt`` = atan2(h . forward, h . z) (to the vertical); ``neck_flexion`` = atan2(h . forward_t, h . up_t)
  (to the trunk); ``neck_side_bend`` = asin(h . left_t); ``neck_twist`` = angle about up_t from left_t to the
  head's left axis.
* Upper arm a: glenohumeral joint (``shoulder_<s>_flexion``) -> elbow (``elbow_<s>_flexion``).
  ``upper_arm_elevation`` = angle between a and -up_t; ``upper_arm_flexion`` = atan2(a . forward_t, -a . up_t)
  (sagittal, + forward); ``upper_arm_abduction`` = atan2(a . outward, -a . up_t), outward = -left_t on the right.
* ``elbow_flexion`` = angle between a and the forearm (elbow -> ``wrist_<s>_flexion`` joint): 0 = straight.
* ``wrist_flexion``, ``wrist_deviation``, ``forearm_rotation``, ``shoulder_elevation`` (clavicle elevation) and
  ``knee_flexion`` are the joint values of ``wrist_<s>_flexion``, ``wrist_<s>_deviation``,
  ``forearm_<s>_pronation``, ``clavicle_<s>_elevation``, ``knee_<s>_flexion``;
  ``forearm_rotation_share`` = the pronation value as a share of its range on its side (0 mid, 1 at the limit).
* ``hand_lateral`` = wrist offset from the sternum midline along left_t, outward positive (m);
  ``hand_above_shoulder`` = the palm centre (``hand_<s>`` TCP) at or above the glenohumeral joint.
* ``weight_share_<s>``: vertical contact force on that side's feet TCPs / total vertical contact force.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from ..body.spatial import cross, length  # np.cross's arithmetic, without its overhead on small arrays
from ..io.result.frame import Frame
from .manikin import feet_frame

SIDES = ("l", "r")
_REQUIRED = ("l5_rx", "c7_rx", "clavicle_l_rx", "clavicle_r_rx", "hip_l_flexion", "hip_r_flexion") + tuple(
    f"{j}_{s}_{m}"
    for s in SIDES
    for j, m in (
        ("shoulder", "flexion"), ("elbow", "flexion"), ("wrist", "flexion"), ("wrist", "deviation"),
        ("forearm", "pronation"), ("clavicle", "elevation"), ("knee", "flexion"),
    )
)  # fmt: skip
_TCPS = ("head", "hand_l", "hand_r", "foot_l", "foot_r")
_Z = np.array([0.0, 0.0, 1.0])
_Z.setflags(write=False)  # shared by every frame


def _unit(v: np.ndarray) -> np.ndarray:
    n = length(v)
    return v / n if n > 1e-12 else v


def _clip(x: float) -> float:
    """``np.clip(x, -1.0, 1.0)`` of a number (NaN stays NaN), without its overhead."""
    return min(max(float(x), -1.0), 1.0)


def _deg(x: float) -> float:
    return math.degrees(x)


def _signed_angle(a: np.ndarray, b: np.ndarray, axis: np.ndarray) -> float:
    """Angle (deg) from a to b about ``axis`` after projecting both normal to it."""
    a = _unit(a - (a @ axis) * axis)
    b = _unit(b - (b @ axis) * axis)
    return _deg(math.atan2(float(cross(a, b) @ axis), float(a @ b)))


def missing_for_posture(frame: Frame) -> str | None:
    """Why this frame has no human posture, or None."""
    joints = [n for n in _REQUIRED if n not in frame.index]
    tcps = [n for n in _TCPS if n not in frame.tcp_position]
    if joints or tcps:
        what = ", ".join(joints[:3] + tcps[:3])
        return f"not a human body: no {what}{' ...' if len(joints) + len(tcps) > 3 else ''}"
    return None


def measure(frame: Frame, feet: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None) -> dict:
    """The body angles of one frame (degrees unless noted); ``{"reason": ...}`` if the body is not human. ``feet``:
    the frame's :func:`.manikin.feet_frame` if the caller has it."""
    reason = missing_for_posture(frame)
    if reason:
        return {"reason": reason}
    z = _Z
    _, forward, left = feet if feet is not None else feet_frame(frame.tcp_position, frame.tcp_rotation)
    u = _unit(frame.pos("c7_rx") - frame.pos("l5_rx"))
    thorax_line = frame.pos("clavicle_l_rx") - frame.pos("clavicle_r_rx")
    hip_line = frame.pos("hip_l_flexion") - frame.pos("hip_r_flexion")
    left_t = _unit(thorax_line - (thorax_line @ u) * u)
    fwd_t = cross(left_t, u)
    head = frame.tcp_rotation["head"]
    h = head[:, 2]
    out: dict = dict(
        trunk_flexion=_deg(math.atan2(u @ forward, u @ z)),
        trunk_side_bend=_deg(math.asin(_clip(u @ left))),
        trunk_twist=_signed_angle(hip_line, thorax_line, u),
        head_tilt=_deg(math.atan2(h @ forward, h @ z)),
        neck_flexion=_deg(math.atan2(h @ fwd_t, h @ u)),
        neck_side_bend=_deg(math.asin(_clip(h @ left_t))),
        neck_twist=_signed_angle(left_t, head[:, 0], u),
    )
    sternum = 0.5 * (frame.pos("clavicle_l_rx") + frame.pos("clavicle_r_rx"))
    vertical = {"l": 0.0, "r": 0.0}
    for tcp, _, force, _ in frame.contacts:
        side = tcp.rsplit("_", 1)[-1]
        if side in vertical:
            vertical[side] += max(float(force @ z), 0.0)
    total = vertical["l"] + vertical["r"]
    for s in SIDES:
        outward = left_t if s == "l" else -left_t
        gh, elbow, wrist = (
            frame.pos(f"shoulder_{s}_flexion"),
            frame.pos(f"elbow_{s}_flexion"),
            frame.pos(f"wrist_{s}_flexion"),
        )
        a, fa = _unit(elbow - gh), _unit(wrist - elbow)
        i_pro = frame.index[f"forearm_{s}_pronation"]
        lo, hi = frame.joint_range[i_pro]
        pro = frame.joint_value[i_pro]
        limit = hi if pro >= 0 else lo
        share = abs(pro / limit) if math.isfinite(limit) and limit != 0 else 0.0
        out[s] = dict(
            upper_arm_elevation=_deg(math.acos(_clip(-(a @ u)))),
            upper_arm_flexion=_deg(math.atan2(a @ fwd_t, -(a @ u))),
            upper_arm_abduction=_deg(math.atan2(a @ outward, -(a @ u))),
            shoulder_elevation=_deg(frame.value(f"clavicle_{s}_elevation")),
            elbow_flexion=_deg(math.acos(_clip(a @ fa))),
            wrist_flexion=_deg(frame.value(f"wrist_{s}_flexion")),
            wrist_deviation=_deg(frame.value(f"wrist_{s}_deviation")),
            forearm_rotation=_deg(pro),
            forearm_rotation_share=float(share),
            hand_lateral=float((wrist - sternum) @ outward),
            shoulder_width_half=float((gh - sternum) @ outward),
            hand_above_shoulder=bool(frame.tcp_position[f"hand_{s}"][2] >= gh[2]),
            knee_flexion=_deg(frame.value(f"knee_{s}_flexion")),
            weight_share=vertical[s] / total if total > 0 else None,
        )
    out["supported_feet"] = sum(1 for s in SIDES if vertical[s] > 0)
    return out


def digits(key: str) -> int:
    """The decimals :func:`rounded` keeps of a posture value: 3 for shares and metres, 1 for angles."""
    return 3 if key.endswith(("share", "lateral", "half")) else 1


def rounded(posture: dict, finish: Callable[[Any], Any] | None = None) -> dict:
    """A copy with angles rounded to 0.1 degree and shares/metres to 3 decimals, for the report; ``finish`` (the
    report's JSON-safe ``clean``) applied to each value in the same walk."""
    out = {}
    for k, v in posture.items():
        if isinstance(v, dict):
            v = rounded(v, finish)
        elif isinstance(v, float):
            v = round(v, digits(k))
        out[k] = v if finish is None or type(v) is dict else finish(v)
    return out
