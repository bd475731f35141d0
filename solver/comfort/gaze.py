"""Gaze discomfort: the head turned away from the hands' working point beyond the share the eyes take.

In reaching and manipulation the eyes lead the hand and fixate its target until it is reached or the grasp is
made (Land & Hayhoe 2001; Johansson et al. 2001), and a gaze shift of more than a few degrees is shared between the
eyes and the head (Freedman & Sparks 1997, in monkeys; in people the eyes alone take shifts up to about 15-20 deg,
Stahl 1999, measured for horizontal shifts). The term models the head's share: psi is the angle between the head's
view axis (the eyes' view axis with the eye joints at rest: the eyes are free to take the rest within their range)
and the line from the eyes to the working point, the mean of the reach targets on the arms that hold a position (all
of x, y, z; not supports). Cost (max(cos a - cos psi, 0) / (cos a - cos(a + 15 deg)))^2: 0 while the eyes can take
the shift (psi <= a, ``EYES_TAKE``), 1 when the head is 15 deg beyond it. A body with no eyes TCP uses its ``head``
TCP's forward (-y) axis; no head, no such target, or a target on the eyes or head (a gaze the user set: the
operations' ``look``) makes the cost 0. Within the behaviour model (:func:`.standard.behaviour_on`): with
``trunk = 0`` its weight counts as 0. Fitted on the training subjects (docs/explanation/mocap-validation.md, "Gaze"),
no weight and share helped (the head's error grew): its default weight is 0, and ``a`` the least-bad fit, 40 deg.
"""

from __future__ import annotations

import numpy as np

from ..body.model import Model
from ..body.state import State
from .base import ComfortTerm
from .trunk_tilt import THORAX_JOINT

EYES_TAKE = np.radians(40.0)  # rad: the gaze shift the eyes take alone (no cost below; the least-bad fit)
REFERENCE_ANGLE = np.radians(15.0)  # rad: cost 1 this far beyond EYES_TAKE
POSITION = ("x", "y", "z")


def _head_frame(model: Model) -> tuple[int, np.ndarray, np.ndarray, set[str]]:
    """(head link, eye point (3,) m and view axis (3,) in that link's frame, the head's TCP names); link -1: none."""
    tcp = model.tcps.get("eyes") or model.tcps.get("head")
    if tcp is None:
        return -1, np.zeros(3), np.zeros(3), set()
    link = tcp.link
    while link >= 0 and model.joint_names[link].startswith("eyes_"):
        link = int(model.parent[link])  # the eye joints are left out: the eyes take the rest of the gaze
    if link < 0:
        return -1, np.zeros(3), np.zeros(3), set()
    zero = model.forward(model.zero_pose())
    rot, pos = zero.tcp_frame(tcp)
    r_link = zero.rotation[link]
    heads = {n for n, t in model.tcps.items() if model.descendant[link, t.link]}
    return link, r_link.T @ (pos - zero.position[link]), r_link.T @ -rot[:, 1], heads


class Gaze(ComfortTerm):
    """k max(cos a - v . u, 0)^2: v the head's view axis, u the unit line from the eyes to the working point, a the
    eyes' share; the curvature model is the exact diagonal of the Hessian, clipped at 0."""

    name = "gaze"
    description = "head turned away from the hands' working point (behaviour model)"

    def __init__(self, model: Model) -> None:
        self.model = model
        self.link, self.eye, self.view, self.heads = _head_frame(model)
        self.chain = np.flatnonzero(model.descendant[:, self.link]) if self.link >= 0 else np.zeros(0, int)
        self.free = float(np.cos(EYES_TAKE))  # cos of the angle the eyes take: no cost closer than that
        self.scale = 1.0 / (self.free - np.cos(EYES_TAKE + REFERENCE_ANGLE)) ** 2
        names = model.joint_names
        self.arms = model.descendant[names.index(THORAX_JOINT)] if THORAX_JOINT in names else None
        self.point: np.ndarray | None = None  # m, world: the working point, set by :meth:`with_targets`

    def with_targets(self, targets: list) -> Gaze:
        """This term aimed at the mean of ``targets``' positions held on the arms (None: no such target)."""
        points, model = [], self.model
        for t in targets:
            if not t.enabled or t.tcp not in model.tcps:
                continue
            if t.tcp in self.heads:
                points = []  # a gaze the user set wins
                break
            link = model.tcps[t.tcp].link
            on_arm = self.arms is None or (self.arms[link] and (self.link < 0 or not model.descendant[self.link, link]))
            if not t.support and t.operator is None and set(POSITION) <= set(t.lock) and on_arm:
                points.append(np.asarray(t.position, dtype=float))
        point = np.mean(points, axis=0) if points and self.link >= 0 else None
        if point is None and self.point is None:
            return self
        bound = object.__new__(Gaze)
        bound.__dict__.update(self.__dict__)
        bound.point = point
        return bound

    def geometry(self, state: State) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
        """(eye point e, view axis v, unit line u, distance r) in the world."""
        kin = state.kin
        r_link = kin.rotation[self.link]
        e = kin.position[self.link] + r_link @ self.eye
        d = self.point - e
        r = max(float(np.linalg.norm(d)), 1e-6)
        return e, r_link @ self.view, d / r, r

    def cost(self, state: State) -> float:
        if self.point is None:
            return 0.0
        _, v, u, _ = self.geometry(state)
        return float(self.scale * max(self.free - v @ u, 0.0) ** 2)

    def derivatives(self, state: State, weight: float) -> tuple[np.ndarray, np.ndarray]:
        grad, curv = np.zeros(state.n_x), np.zeros(state.n_x)
        if self.point is None:
            return grad, curv
        e, v, u, r = self.geometry(state)
        g = self.free - v @ u
        if g <= 0.0:
            return grad, curv
        kin, chain = state.kin, self.chain
        a = kin.axis[chain]
        slide = self.model.prismatic[chain][:, None]
        # turning joint j by t: v' = a x v, e' = a x (e - o); sliding: v' = 0, e' = a (second derivatives 0)
        v1 = np.where(slide, 0.0, np.cross(a, v))
        v2 = np.where(slide, 0.0, np.cross(a, v1))
        e1 = np.where(slide, a, np.cross(a, e - kin.position[chain]))
        e2 = np.where(slide, 0.0, np.cross(a, e1))
        d1, d2 = -e1, -e2  # d = point - e
        r1 = d1 @ u
        u1 = (d1 - u * r1[:, None]) / r
        r2 = np.einsum("ij,ij->i", u1, d1) + d2 @ u
        u2 = (d2 - 2.0 * u1 * r1[:, None] - u * r2[:, None]) / r
        f1 = v1 @ u + u1 @ v  # d(v . u)
        f2 = v2 @ u + 2.0 * np.einsum("ij,ij->i", v1, u1) + u2 @ v
        k = weight * self.scale  # cost k g^2, g = cos(eyes' share) - v . u
        grad[chain] = -2.0 * k * g * f1
        curv[chain] = np.maximum(2.0 * k * (f1 * f1 - g * f2), 0.0)
        return grad, curv
