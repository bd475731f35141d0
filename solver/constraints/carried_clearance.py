"""Carried clearance: the body stays out of a box carried between two TCPs (``[carried]``,
:mod:`solver.collision.carried`).

One row per body capsule but those on the two holding TCPs' links (the hands that hold the box: where they sit on
it is the grip, which their targets decide; a hand touching its side is meant), g = the capsule's signed surface
distance to the box where the two TCPs put it in this pose (m), g >= :data:`solver.collision.carried.CLEARANCE` (0: the
body
may touch the box, as a box carried against the belly does, but not enter it).

The box moves with the hands, so a row's Jacobian has two parts: n . (velocity of the witness on the capsule's
axis) - n . (velocity of the box's material point at the closest point q), the second from the two TCPs'
velocities through the box frame (:func:`solver.collision.carried.box_motion_terms`). Like the body's own pairs, the
witnesses' sliding drops out (the envelope theorem, for overlapping pairs too: the two points differ along n).
Rows rank with supports and balance (priority 1), as every clearance row does.
"""

from __future__ import annotations

import numpy as np

from .. import kernels
from ..body.model import Model
from ..body.state import State
from ..collision.body import BodyCapsules
from ..collision.boxes import box_rows, box_rows_one
from ..collision.carried import CLEARANCE, Carried, box_motion_jacobian, box_motion_terms, held_frame
from ..kernels.clearance_boxes import carried_capsule_rows
from .clearance import ClearanceRows


class CarriedClearance(ClearanceRows):
    """``model``'s capsules (``capsules``) outside ``carried``, but the capsules on the links of its two TCPs."""

    name = "carried"

    def __init__(self, model: Model, capsules: BodyCapsules, carried: Carried, n_x: int, margin: float = 0.05) -> None:
        self.model, self.n_x, self.margin, self.carried = model, n_x, margin, carried
        self.tcps = tuple(model.tcp(name) for name in carried.tcps)
        keep = ~np.isin(capsules.link, [tcp.link for tcp in self.tcps])
        self.excluded = tuple(n for n, k in zip(capsules.names, keep, strict=True) if not k)
        self.capsules = BodyCapsules(tuple(n for n, k in zip(capsules.names, keep, strict=True) if k),
                                     capsules.link[keep], capsules.start[keep], capsules.end[keep],
                                     capsules.radius[keep])  # fmt: skip
        names = self.capsules.names
        self._parts = list(names)
        self._others = [carried.name] * len(names)
        self._pairs = [f"{name} vs {carried.name}" for name in names]
        self.floor = np.full(len(names), CLEARANCE)
        self._half = np.asarray(carried.size, dtype=float) / 2.0
        self._index = np.arange(len(names))

    def frame(self, state: State) -> tuple[np.ndarray, np.ndarray]:
        """(centre (3,) m, rotation (3, 3)) of the box at ``state``."""
        return held_frame(state, self.tcps)[1:]

    def _distances(self, state: State) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        caps, half = self.capsules, self._half
        k = len(caps)
        p0, p1 = caps.world(state.kin)
        centre, rotation = self.frame(state)
        if kernels.active():
            return self._compiled_distances(p0, p1, centre, rotation)
        # only capsules whose box-frame bounds, grown by radius + margin, meet the box are measured; the rest are
        # met by more than the margin and get margin + 1 m and a zero normal (no Jacobian), as obstacles' rows do
        a, b = (p0 - centre) @ rotation, (p1 - centre) @ rotation
        reach = (caps.radius + self.margin)[:, None]
        near = np.flatnonzero(np.all((np.minimum(a, b) - reach <= half) & (np.maximum(a, b) + reach >= -half), axis=1))
        distance, point, normal = np.full(k, self.margin + 1.0), p0.copy(), np.zeros((k, 3))
        if near.size:
            m = len(near)
            got = box_rows(p0[near], p1[near], caps.radius[near], np.broadcast_to(centre, (m, 3)),
                           np.broadcast_to(rotation, (m, 3, 3)), np.broadcast_to(half, (m, 3)))  # fmt: skip
            distance[near], point[near], normal[near] = got.distance, got.point, got.normal
        return distance, point, normal, np.arange(k)

    def _compiled_distances(self, p0: np.ndarray, p1: np.ndarray, centre: np.ndarray,
                            rotation: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:  # fmt: skip
        """:meth:`_distances` by the kernels: the bounds test and the rows apart in one loop, a row whose axis meets
        or touches the box by :func:`box_rows`."""
        caps, k = self.capsules, len(self.capsules)
        distance, t, rare = np.empty(k), np.empty(k), np.empty(k, dtype=np.int64)
        point, normal, closest = np.empty((k, 3)), np.empty((k, 3)), np.empty((k, 3))
        box = (centre.reshape(1, 3), np.ascontiguousarray(rotation).reshape(1, 3, 3), self._half.reshape(1, 3))
        if carried_capsule_rows(p0, p1, caps.radius, *box, self.margin, distance, t, point, normal, closest, rare):
            rows = np.flatnonzero(rare)
            got = box_rows_one(p0[rows], p1[rows], caps.radius[rows], centre, rotation, self._half)
            distance[rows], point[rows], normal[rows] = got.distance, got.point, got.normal
        return distance, point, normal, self._index

    def _jacobian_of(self, state: State, rows: np.ndarray) -> np.ndarray:
        if not rows.size:
            return np.zeros((0, self.n_x))
        distance, points, normals, capsule = self._evaluate(state)
        normal, k = normals[rows], len(rows)
        on_box = points[rows] - (distance[rows] + self.capsules.radius[capsule[rows]])[:, None] * normal
        if kernels.active():  # the three terms per joint in one loop
            own = (points[rows], normal, self._row_link(capsule)[rows])
            return box_motion_jacobian(state, self.tcps, on_box, -normal, self.n_x, own)
        # one call for the three points: the witness on the capsule, and each TCP moving the box's point
        links, where, along = box_motion_terms(state, self.tcps, on_box, -normal)
        links = np.concatenate([self.capsules.link[capsule[rows]], links])
        where, along = np.concatenate([points[rows], where]), np.concatenate([normal, along])
        mask = self.model.descendant[:, links].T.astype(float)
        moved = state.kin.jacobian_rows(where, along, np.zeros_like(along), mask)
        out = np.zeros((k, self.n_x))
        out[:, : self.model.n] = moved[:k] + moved[k : 2 * k] + moved[2 * k :]
        return out
