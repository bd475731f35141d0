"""Joint loads of one result frame: 3D moments, their axis component, percent of strength, L4/L5 compression.

Moment at joint j (Delfs 2012, eq. 3.11), over everything acting on the links in the subtree of the link the
joint moves (the joint's own link included):

    M_j = sum_k (c_k - p_j) x m_k g  +  sum_contacts (q - p_j) x f + t  +  sum_loads (q - p_j) x f

with c_k the link centres of mass, q the contact point / load point and t a contact's free moment; a contact or a
load acts on the link of its TCP. ``axis_moment`` tau_j = a_j . M_j (for a prismatic joint a_j . F_j, N). The
muscles must produce -tau_j, so ``percent_strength`` = |tau_j| / s_j * 100 with s_j the joint's capacity in the
direction of -tau_j (the model's ``strength`` column 1 for positive, 0 for negative moments).

L4/L5 disc compression (an ESTIMATE, Chaffin's single-equivalent-muscle model, Chaffin, Andersson & Martin,
"Occupational Biomechanics", ch. 6): the extensor (or flexor) muscle force balances the sagittal moment at the
L4/L5 disc with a 5 cm moment arm, F_m = |M_flex| / 0.05 m, and acts along the disc axis; compression =
F_m + the subtree's external force component pressing along the disc axis. Intra-abdominal pressure, lateral
bending and twisting moments and co-contraction are ignored (they are reported, not used). Limits: 3400 N
(action limit) and 6400 N (maximum permissible limit) of the NIOSH Work Practices Guide (1981), as used by
3DSSPP-style low-back analysis (shared/reference/published_data.py).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..body.spatial import cross, length  # np.cross's arithmetic, without its overhead on small arrays
from ..io.result.frame import Frame

MUSCLE_MOMENT_ARM = 0.05  # m, single equivalent extensor muscle about L4/L5 (Chaffin et al., see above)
DISC_ACTION_LIMIT = 3400.0  # N, NIOSH 1981 action limit
DISC_MAXIMUM_LIMIT = 6400.0  # N, NIOSH 1981 maximum permissible limit
L4L5 = ("l4_rx", "l4_ry", "l4_rz")  # the joints at the L4/L5 disc (each vertebra's joints sit at its lower disc)


def subtree_sums(frame: Frame) -> tuple[np.ndarray, np.ndarray]:
    """(L, 3) force and (L, 3) moment about the world origin of everything acting on each link's subtree."""
    points = [frame.link_com]
    forces = [frame.link_mass[:, None] * frame.gravity[None, :]]
    on: list[int] = []
    free = np.zeros((len(frame.link_names), 3))
    for tcp, point, force, moment in frame.contacts:
        points.append(point[None, :])
        forces.append(force[None, :])
        on.append(frame.tcp_link[tcp])
        free[frame.tcp_link[tcp]] += moment
    for tcp, point, force in frame.loads:
        points.append(point[None, :])
        forces.append(force[None, :])
        on.append(frame.tcp_link[tcp])
    q, f = np.vstack(points), np.vstack(forces)
    acts = _acting(frame.below_weights, tuple(on))  # [j, k]: point force k acts inside the subtree of link j
    sub_force = acts @ f
    sub_moment = acts @ cross(q, f) + frame.below_weights @ free
    return sub_force, sub_moment


_ACTING: dict[tuple[int, ...], tuple[np.ndarray, np.ndarray]] = {}  # links of the point forces past the links' own


def _acting(weights: np.ndarray, on: tuple[int, ...]) -> np.ndarray:
    """``weights[:, links]`` for the links' own weights (every link) then forces on the links ``on``: the same
    columns every frame of a motion, so taken once per subtree matrix (read-only, shared)."""
    kept = _ACTING.get(on)
    if kept is not None and kept[0] is weights:  # the subtree matrix itself held here: its identity is not reused
        return kept[1]
    acts = weights[:, np.concatenate([np.arange(len(weights)), np.array(on, dtype=int)])]
    acts.setflags(write=False)
    if len(_ACTING) >= 16:
        _ACTING.clear()
    _ACTING[on] = (weights, acts)
    return acts


def joint_moments(frame: Frame) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(n, 3) moment about each joint (N*m, world), (n,) axis component and (n, 3) subtree force (N)."""
    sub_force, sub_moment = subtree_sums(frame)
    f = sub_force[frame.joint_link]
    m = sub_moment[frame.joint_link] - cross(frame.joint_position, f)
    tau = np.einsum("ni,ni->n", frame.joint_axis, m)
    tau = np.where(frame.prismatic, np.einsum("ni,ni->n", frame.joint_axis, f), tau)
    return m, tau, f


def percent_of_strength(tau: np.ndarray, strength: np.ndarray) -> np.ndarray:
    """|tau| / capacity in the direction of the muscle moment -tau, in percent; NaN where the capacity is unknown
    or unlimited."""
    capacity = np.where(tau < 0.0, strength[:, 1], strength[:, 0])
    ok = np.isfinite(capacity) & (capacity > 0)
    return np.where(ok, np.abs(tau) / np.where(ok, capacity, 1.0) * 100.0, np.nan)


def disc_compression(flexion_moment: float, axial_force: float) -> float:
    """Chaffin single-muscle L4/L5 compression (N): |M| / 0.05 m + the external force along the disc (N, >0
    pressing). An estimate; see the module docstring."""
    return abs(flexion_moment) / MUSCLE_MOMENT_ARM + axial_force


def l4_l5(frame: Frame, moments: np.ndarray, sub_force: np.ndarray) -> dict:
    """L4/L5 moment (world, and flexion / lateral / twist parts) and the disc-compression estimate."""
    if not frame.has(*L4L5):
        return dict(moment=None, compression=None, reason="the body has no L4/L5 joints (l4_rx, l4_ry, l4_rz)")
    i_rx, i_ry, i_rz = (frame.index[n] for n in L4L5)
    m = moments[i_rx]
    flexion = float(frame.joint_axis[i_rx] @ m)  # > 0: the loads bend the trunk forward
    lateral = float(frame.joint_axis[i_ry] @ m)
    twist = float(frame.joint_axis[i_rz] @ m)
    disc_axis = frame.joint_axis[i_rz]  # the L4 vertebra's long axis (its rz joint turns about it)
    axial = float(-(sub_force[i_rx] @ disc_axis))  # weight of everything above, pressing down the disc axis
    compression = disc_compression(flexion, axial)
    level = "green" if compression < DISC_ACTION_LIMIT else "yellow" if compression <= DISC_MAXIMUM_LIMIT else "red"
    return dict(
        moment=[float(v) for v in m],
        flexion_moment=flexion,
        lateral_moment=lateral,
        twist_moment=twist,
        axial_force=axial,
        muscle_force=abs(flexion) / MUSCLE_MOMENT_ARM,
        compression=compression,
        level=level,
        limits=dict(action=DISC_ACTION_LIMIT, maximum=DISC_MAXIMUM_LIMIT),
        model="estimate: single equivalent muscle, 5 cm moment arm (Chaffin et al.); limits NIOSH 1981",
    )


def hand_load_kg(frame: Frame) -> float:
    """Mass (kg) of the loads hanging on hand/knuckle TCPs: their downward force / g."""
    g = length(np.asarray(frame.gravity, dtype=float)) or 9.81
    down = frame.gravity / g
    total = sum(float(f @ down) for tcp, _, f in frame.loads if tcp.startswith(("hand_", "knuckles_")))
    return max(total, 0.0) / g


def _num(v: float) -> float | None:
    return float(v) if math.isfinite(v) else None


@dataclass
class JointLoads:
    """A frame's joint loads as arrays, in the frame's joint order: moment (n, 3) about each joint (N*m, world),
    axis_moment (n,) and percent (n,) of strength (NaN where unknown); ``l4_l5`` as :func:`l4_l5` has it."""

    names: list[str]
    moment: np.ndarray
    axis_moment: np.ndarray
    percent: np.ndarray
    l4_l5: dict

    def as_dict(self) -> dict:
        """Per joint {moment, axis_moment, percent_strength} plus ``l4_l5``: plain floats, null where not finite
        (JSON-safe as they are, but ``l4_l5``)."""
        out: dict = {}
        rows, axis, share = self.moment.tolist(), self.axis_moment.tolist(), self.percent.tolist()
        if not (np.isfinite(self.moment).all() and np.isfinite(self.axis_moment).all()):
            rows, axis = [[_num(v) for v in row] for row in rows], [_num(v) for v in axis]
        for i, name in enumerate(self.names):
            out[name] = dict(moment=rows[i], axis_moment=axis[i], percent_strength=_num(share[i]))
        out["l4_l5"] = self.l4_l5
        return out


def load_arrays(frame: Frame, strength: np.ndarray) -> JointLoads:
    """The joint loads of ``frame`` with the joint capacities ``strength`` ((n, 2), as :func:`percent_of_strength`)."""
    moments, tau, sub_force = joint_moments(frame)
    return JointLoads(
        frame.joint_names, moments, tau, percent_of_strength(tau, strength), l4_l5(frame, moments, sub_force)
    )


def joint_loads(frame: Frame, strength: np.ndarray) -> tuple[dict, np.ndarray, np.ndarray]:
    """Per joint {moment, axis_moment, percent_strength} plus ``l4_l5``; also returns (tau, percent) arrays. The
    per-joint values are plain floats, null where not finite (JSON-safe as they are)."""
    loads = load_arrays(frame, strength)
    return loads.as_dict(), loads.axis_moment, loads.percent
