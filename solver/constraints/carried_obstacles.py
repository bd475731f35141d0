"""The carried box keeps out of the obstacles and above the floor, as the body does (one-sided rows, m).

The box (:mod:`solver.collision.carried`) moves with the two TCPs that hold it, so a hand target that would set it down
inside a table ends unmet, the box on the table top, like any target pulling a body part into something (priority 1).

Rows, per obstacle: against a half-space (the floor; any kind with ``end_rows``) one per box corner, g = the corner's
distance n.(corner - point), exact and smooth (the lowest point of a box is a corner); against any other obstacle one
per box edge, g = the edge's (a segment of radius 0) signed distance to it; and one per segment of the obstacle's
skeleton (a box's edges, a capsule's axis, a sphere's centre: :meth:`~solver.collision.kinds.base.Obstacle.skeleton`)
to the carried box: two convex shapes are nearest at an edge of one of them, so the two sets of rows see every way
they meet. A mesh has no fixed skeleton: its rows are its ``nearest_edges`` edges nearest the box, nearest first,
among its edges but the flat ones (:mod:`solver.collision.mesh_edges`) whose bounds come within the margin of the
box's (a mesh corner poking into the middle of one of the box's faces touches none of the box's edges): the k-th
smallest distance is continuous (to 1e-12 m at ties), and each row is exact for the edge it holds. The Jacobian of a
row is n . (velocity of the box's material point at its nearest point), n pointing away from the obstacle, through
both TCPs (:func:`solver.collision.carried.box_motion_terms`). Only obstacles whose bounds come within the margin of
the box's bounds (a half-space: whose distance to a corner does) are measured.
"""

from __future__ import annotations

import numpy as np

from .. import kernels
from ..body.model import Model
from ..body.state import State
from ..collision import HalfSpace, Obstacle, Proximity
from ..collision.boxes import box_corners, box_edges, box_rows_one, edges_of_corners
from ..collision.carried import Carried, box_motion_jacobian, box_motion_terms, held_frame
from ..constraints.clearance import ClearanceRows, Closeness

__all__ = ["CarriedObstacles", "box_corners", "box_edges"]

SURE = 1e-9  # m: what the float test of "near nothing" keeps in hand against rounding
_NO_RADIUS = np.zeros(12)  # the box's edges are segments
_CORNER_RADIUS = np.zeros(8)


class CarriedObstacles(ClearanceRows):
    """``carried`` (held by TCPs of ``model``) at each of ``obstacles``' clearance (the floor among them, if kept)."""

    name = "carried_obstacles"

    def __init__(self, model: Model, carried: Carried, obstacles: list[Obstacle], n_x: int,
                 margin: float = 0.05) -> None:  # fmt: skip
        self.model, self.n_x, self.margin, self.carried = model, n_x, margin, carried
        self.tcps = tuple(model.tcp(name) for name in carried.tcps)
        self.obstacles = list(obstacles)
        self.half = np.asarray(carried.size, dtype=float) / 2.0  # m
        self._reach = [margin + max(ob.clearance, 0.0) for ob in self.obstacles]
        self._corners = [i for i, ob in enumerate(self.obstacles) if ob.end_rows]  # measured at the box's corners
        self._skeletons = [None if ob.end_rows else ob.skeleton() for ob in self.obstacles]
        # an obstacle measured at the corners is never met by the bounds test (NaN): its corners are measured
        bounds = [(np.full(3, np.nan),) * 2 if ob.end_rows else ob.bounds() for ob in self.obstacles]
        grow = np.array(self._reach).reshape(-1, 1)
        self._low = np.array([low for low, _ in bounds]).reshape(-1, 3) - grow
        self._high = np.array([high for _, high in bounds]).reshape(-1, 3) + grow
        back = [ob.nearest_edges if s is None else len(s[2]) for ob, s in zip(self.obstacles, self._skeletons,
                                                                               strict=True)]  # fmt: skip
        counts = [8 if ob.end_rows else 12 + k for ob, k in zip(self.obstacles, back, strict=True)]
        self._parts = [carried.name] * sum(counts)
        self._others = [ob.name for ob, k in zip(self.obstacles, counts, strict=True) for _ in range(k)]
        self._pairs = [f"{carried.name} vs {other}" for other in self._others]
        self.floor = np.concatenate([np.full(k, ob.clearance) for ob, k in zip(self.obstacles, counts, strict=True)])
        self._starts = np.cumsum([0, *counts[:-1]]).astype(int)
        rows = len(self.floor)
        # gaps' test of "near nothing" in Python floats (most poses of a motion; 3-vectors cost NumPy more than their
        # sums): each bounded obstacle's grown bounds, each half-space's (point, normal, reach); None if another kind
        # is measured at the corners (then the arrays decide)
        boxes = [(*low, *high) for i, (low, high) in enumerate(zip(self._low.tolist(), self._high.tolist(),
                                                                   strict=True)) if i not in self._corners]  # fmt: skip
        planes = [(ob.point.tolist(), ob.normal.tolist(), self._reach[i]) for i, ob in enumerate(self.obstacles)
                  if i in self._corners and isinstance(ob, HalfSpace)]  # fmt: skip
        self._sure = (boxes, planes) if len(planes) == len(self._corners) else None
        self._far = (np.full(rows, margin + 1.0), np.zeros((rows, 3)), np.zeros((rows, 3)), np.zeros((rows, 3)))
        for array in self._far:
            array.flags.writeable = False

    def _distances(self, state: State) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        return self.gaps(*held_frame(state, self.tcps)[1:])

    def gaps(self, centre: np.ndarray, rotation: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """With the box at ``centre`` (m), ``rotation``: (distance (rows,) m, the box's nearest point (rows, 3), unit
        normal away from the obstacle (rows, 3), the obstacle's nearest point (rows, 3)); rows not measured (farther
        than the margin): margin + 1 m, zero normal."""
        if self._near_nothing(centre, rotation):
            return self._far
        half = self.half
        extent = np.abs(rotation) @ half
        near = np.flatnonzero(np.all((centre - extent <= self._high) & (centre + extent >= self._low), axis=1))
        corners = box_corners(centre, rotation, half)
        at_corners = {}
        for i in self._corners:  # near when a corner is within reach: the box's nearest point is one of them
            got = self.obstacles[i].distance(corners, corners, _CORNER_RADIUS)
            if got.distance.min() <= self._reach[i]:
                at_corners[i] = got
        if not near.size and not at_corners:
            return self._far
        distance, on_box, normal, on_other = (array.copy() for array in self._far)
        for i, got in at_corners.items():
            part = slice(self._starts[i], self._starts[i] + 8)
            distance[part], on_box[part], normal[part] = got.distance, got.point, got.normal
            on_other[part] = got.closest
        a, b = edges_of_corners(corners)
        for i in near:
            ob, at, reach = self.obstacles[i], self._starts[i], self._reach[i]
            got = ob.distance(a, b, _NO_RADIUS, reach)
            part = slice(at, at + 12)
            distance[part] = np.where(np.isfinite(got.distance), got.distance, reach + 1.0)
            on_box[part], normal[part], on_other[part] = got.point, got.normal, got.closest
            back = self._reverse_rows(i, centre, rotation, reach)
            if back is not None:
                got, radii = back
                part = slice(at + 12, at + 12 + len(radii))
                distance[part], on_box[part], normal[part] = got.distance, got.closest, -got.normal
                on_other[part] = got.point - radii[:, None] * got.normal
        return distance, on_box, normal, on_other

    def _near_nothing(self, centre: np.ndarray, rotation: np.ndarray) -> bool:
        """True when the box at ``centre`` (m), ``rotation`` is surely farther than :data:`SURE` (m) beyond every
        obstacle's bounds test and every half-space's corner test of :meth:`gaps` (which would then measure nothing):
        the same sums in floats, the order of rounding aside. False when not sure (NaN too)."""
        if self._sure is None:
            return False
        boxes, planes = self._sure
        (r00, r01, r02), (r10, r11, r12), (r20, r21, r22) = rotation.tolist()
        hx, hy, hz = self.half.tolist()
        cx, cy, cz = centre.tolist()
        ex = abs(r00) * hx + abs(r01) * hy + abs(r02) * hz  # the box's half extent along x, y, z
        ey = abs(r10) * hx + abs(r11) * hy + abs(r12) * hz
        ez = abs(r20) * hx + abs(r21) * hy + abs(r22) * hz
        for lx, ly, lz, ux, uy, uz in boxes:  # apart along some axis: not near (NaN: not apart, not sure)
            if not (cx - ex > ux + SURE or cx + ex < lx - SURE or cy - ey > uy + SURE or cy + ey < ly - SURE
                    or cz - ez > uz + SURE or cz + ez < lz - SURE):  # fmt: skip
                return False
        for (px, py, pz), (nx, ny, nz), reach in planes:  # the lowest corner along n: centre's height less the extent
            height = (cx - px) * nx + (cy - py) * ny + (cz - pz) * nz
            lowest = height - (abs(r00 * nx + r10 * ny + r20 * nz) * hx + abs(r01 * nx + r11 * ny + r21 * nz) * hy
                               + abs(r02 * nx + r12 * ny + r22 * nz) * hz)  # fmt: skip
            if not lowest > reach + SURE:
                return False
        return True

    def _reverse_rows(self, i: int, centre: np.ndarray, rotation: np.ndarray,
                      reach: float) -> tuple[Proximity, np.ndarray] | None:  # fmt: skip
        """Obstacle ``i``'s skeleton (its edges, axis, centre) against the box at ``centre`` (m), ``rotation``: (their
        Proximity, radii (k,) m); for a kind without a fixed skeleton (a mesh), its edges nearest the box, nearest
        first, at most ``nearest_edges`` of those whose bounds come within ``reach`` (m) of the box's; None if none."""
        ob, skeleton = self.obstacles[i], self._skeletons[i]
        ranked = skeleton is None and ob.nearest_edges > 0
        if ranked:
            skeleton = ob.edges_near_box(centre, rotation, self.half, reach)
        if skeleton is None:
            return None
        s0, s1, radii = skeleton
        got = box_rows_one(s0, s1, radii, centre, rotation, self.half)
        if ranked:  # the nearest first: row j holds the j-th smallest distance (continuous)
            keep = np.argsort(got.distance, kind="stable")[: ob.nearest_edges]
            got, radii = Proximity(*(field[keep] for field in got)), radii[keep]
        return got, radii

    def near_way(self, a: tuple[np.ndarray, np.ndarray], b: tuple[np.ndarray, np.ndarray], moved: float) -> bool:
        """Might the box come within the margin of an obstacle on its way from placement ``a`` to ``b`` ((centre m,
        rotation) each), no point of it leaving the two placements' bounds by more than ``moved`` (m)?"""
        ends = [(centre, np.abs(rotation) @ self.half) for centre, rotation in (a, b)]
        low = np.minimum(*(c - e for c, e in ends)) - moved
        high = np.maximum(*(c + e for c, e in ends)) + moved
        if np.any(np.all((low <= self._high) & (high >= self._low), axis=1)):
            return True
        if not self._corners:
            return False
        # the corners of the way's bounds: the bounds are nearest a half-space at one of them
        corners = np.array([(x, y, z) for x in (low[0], high[0]) for y in (low[1], high[1]) for z in (low[2], high[2])])
        return any(self.obstacles[i].distance(corners, corners, _CORNER_RADIUS).distance.min() <= self._reach[i]
                   for i in self._corners)  # fmt: skip

    def inside(self, centre: np.ndarray, rotation: np.ndarray, tolerance: float) -> list[str]:
        """The obstacles the box at ``centre`` (m), ``rotation`` is inside of, by more than ``tolerance`` (m)."""
        distance = self.gaps(centre, rotation)[0]
        return sorted({self._others[i] for i in np.flatnonzero(distance < self.floor - tolerance)})

    def _jacobian_of(self, state: State, rows: np.ndarray) -> np.ndarray:
        out = np.zeros((len(rows), self.n_x))
        if not rows.size:
            return out
        _, on_box, normal, _ = self._evaluate(state)
        if kernels.active():  # the two TCPs' terms per joint in one loop
            return box_motion_jacobian(state, self.tcps, on_box[rows], normal[rows], self.n_x)
        links, where, along = box_motion_terms(state, self.tcps, on_box[rows], normal[rows])
        mask = self.model.descendant[:, links].T.astype(float)
        moved = state.kin.jacobian_rows(where, along, np.zeros_like(along), mask)
        k = len(rows)
        out[:, : self.model.n] = moved[:k] + moved[k:]
        return out

    def closest(self, state: State) -> list[Closeness]:
        """The nearest row to each obstacle within the margin of its clearance, nearest first (part: the box; point:
        on the box)."""
        distance, on_box, _, on_other = self._evaluate(state)
        near = (distance - self.floor < self.margin).nonzero()[0].tolist()
        out, seen = [], set()
        for i in sorted(near, key=distance.item):  # a stable sort, as argsort(kind="stable")
            if self._others[i] not in seen:
                seen.add(self._others[i])
                out.append(Closeness(self._parts[i], self._others[i], distance.item(i), self.floor.item(i), on_box[i],
                                     on_other[i]))  # fmt: skip
        return out
