"""The carried box keeps out of the obstacles and above the floor, as the body does (one-sided rows, m).

The box (:mod:`solver.collision.carried`) moves with the two TCPs that hold it, so a hand target that would set it down
inside
a table ends unmet, the box on the table top, like any target pulling a body part into something (priority 1).

Rows, per obstacle: against a half-space (the floor) one per box corner, g = n.(corner - point), exact and smooth
(the lowest point of a box is a corner); against any other obstacle one per box edge, g = the edge's (a segment of
radius 0) signed distance to it; and one per edge of the obstacle (its axis, for a capsule or a sphere) to the
carried box: two convex shapes are nearest at an edge of one of them, so the two sets of rows see every way they
meet. For a mesh those are its EDGE_ROWS edges nearest the box, nearest first, among its edges but the flat ones
(:mod:`solver.collision.mesh_edges`) whose bounds come within the margin of the box's (a mesh corner poking into
the middle of one of the box's faces touches none of the box's edges): the k-th smallest distance is continuous (to
1e-12 m at ties), and each row is exact for the edge it holds. The Jacobian of a row is n . (velocity of the box's
material point at its nearest point), n pointing away from the obstacle, through both TCPs
(:func:`solver.collision.carried.box_motion_terms`). Only obstacles whose bounds come within the margin of the box's
bounds
are measured.
"""

from __future__ import annotations

import numpy as np

from ..body.model import Model
from ..body.state import State
from ..collision import Box, Capsule, HalfSpace, Mesh, Obstacle, Proximity, Sphere, obstacle_distance
from ..collision.boxes import box_rows
from ..collision.carried import Carried, box_motion_terms, held_frame
from ..collision.mesh_index import MeshIndex, index_of
from ..constraints.clearance import ClearanceRows, Closeness

_CORNERS = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], dtype=float)
_NO_RADIUS = np.zeros(12)  # the box's edges are segments
# a mesh corner poking in brings its fan of edges (about 6 in a regular triangulation), all at its depth: 8 rows hold
# it and the next nearest edges; the rows are re-chosen at every evaluation
EDGE_ROWS = 8
_EDGES = np.array([(i, j) for i in range(8) for j in range(i + 1, 8) if np.abs(_CORNERS[i] - _CORNERS[j]).sum() == 2])


def box_corners(center: np.ndarray, rotation: np.ndarray, half: np.ndarray) -> np.ndarray:
    """The 8 corners ((8, 3) world m) of the box ``center``, ``rotation`` (axes as columns), ``half`` sizes."""
    return center + (_CORNERS * half) @ rotation.T


def box_edges(center: np.ndarray, rotation: np.ndarray, half: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The 12 edges (starts, ends: (12, 3) world m) of the box ``center``, ``rotation`` (axes as columns), ``half``."""
    corners = box_corners(center, rotation, half)
    return corners[_EDGES[:, 0]], corners[_EDGES[:, 1]]


def _segments(obstacle: Obstacle) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
    """(starts, ends (k, 3) m, radii (k,) m) that ``obstacle`` is swept from, for the reverse rows; None for a mesh
    (its edges near the box, chosen at each evaluation) or a half-space."""
    if isinstance(obstacle, Box):
        return (*box_edges(obstacle.center, obstacle.rotation, obstacle.half), np.zeros(12))
    if isinstance(obstacle, Capsule):
        return obstacle.a[None], obstacle.b[None], np.array([obstacle.radius])
    if isinstance(obstacle, Sphere):
        return obstacle.center[None], obstacle.center[None], np.array([obstacle.radius])
    return None


def _bounds(obstacle: Obstacle) -> tuple[np.ndarray, np.ndarray]:
    """World bounding box (low, high, m) of ``obstacle``; NaN for a half-space."""
    if isinstance(obstacle, Mesh):
        return obstacle.vertices.min(axis=0), obstacle.vertices.max(axis=0)
    if isinstance(obstacle, HalfSpace):  # not a box: never met by the bounds test (NaN), measured on its own
        return np.full(3, np.nan), np.full(3, np.nan)
    a, b, r = _segments(obstacle)
    return np.minimum(a, b).min(axis=0) - r.max(), np.maximum(a, b).max(axis=0) + r.max()


class CarriedObstacles(ClearanceRows):
    """``carried`` (held by TCPs of ``model``) at each of ``obstacles``' clearance (the floor among them, if kept)."""

    name = "carried_obstacles"

    def __init__(self, model: Model, carried: Carried, obstacles: list[Obstacle], n_x: int,
                 margin: float = 0.05) -> None:  # fmt: skip
        self.model, self.n_x, self.margin, self.carried = model, n_x, margin, carried
        self.tcps = tuple(model.tcp(name) for name in carried.tcps)
        self.obstacles = list(obstacles)
        self.half = np.asarray(carried.size, dtype=float) / 2.0  # m
        self._queries = [index_of(ob) if isinstance(ob, Mesh) else ob for ob in self.obstacles]
        # a box's query is one exact call on the 12 edges (its bounds were tested already): its arrays, made once
        self._box_args = {
            i: (
                np.broadcast_to(ob.center, (12, 3)),
                np.broadcast_to(ob.rotation, (12, 3, 3)),
                np.broadcast_to(ob.half, (12, 3)),
            )
            for i, ob in enumerate(obstacles)
            if isinstance(ob, Box)
        }
        self._reverse = [_segments(ob) for ob in self.obstacles]
        self._edges = {i: query.edges() for i, query in enumerate(self._queries) if isinstance(query, MeshIndex)}
        bounds = [_bounds(ob) for ob in self.obstacles]
        grow = np.array([[margin + max(ob.clearance, 0.0)] for ob in self.obstacles]).reshape(-1, 1)
        self._low = np.array([low for low, _ in bounds]).reshape(-1, 3) - grow
        self._high = np.array([high for _, high in bounds]).reshape(-1, 3) + grow
        back = [EDGE_ROWS if i in self._edges else 0 if r is None else len(r[2]) for i, r in enumerate(self._reverse)]
        counts = [8 if isinstance(ob, HalfSpace) else 12 + k for ob, k in zip(self.obstacles, back, strict=True)]
        self._parts = [carried.name] * sum(counts)
        self._others = [ob.name for ob, k in zip(self.obstacles, counts, strict=True) for _ in range(k)]
        self._pairs = [f"{carried.name} vs {other}" for other in self._others]
        self.floor = np.concatenate([np.full(k, ob.clearance) for ob, k in zip(self.obstacles, counts, strict=True)])
        self._starts = np.cumsum([0, *counts[:-1]]).astype(int)
        self._planes = [i for i, ob in enumerate(self.obstacles) if isinstance(ob, HalfSpace)]
        rows = len(self.floor)
        self._far = (np.full(rows, margin + 1.0), np.zeros((rows, 3)), np.zeros((rows, 3)), np.zeros((rows, 3)))
        for array in self._far:
            array.flags.writeable = False

    def _distances(self, state: State) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        return self.gaps(*held_frame(state, self.tcps)[1:])

    def gaps(self, centre: np.ndarray, rotation: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """With the box at ``centre`` (m), ``rotation``: (distance (rows,) m, the box's nearest point (rows, 3), unit
        normal away from the obstacle (rows, 3), the obstacle's nearest point (rows, 3)); rows not measured (farther
        than the margin): margin + 1 m, zero normal."""
        half = self.half
        extent = np.abs(rotation) @ half
        near = np.flatnonzero(np.all((centre - extent <= self._high) & (centre + extent >= self._low), axis=1))
        planes = [
            i
            for i in self._planes
            if (centre - self.obstacles[i].point) @ self.obstacles[i].normal
            - np.abs(rotation.T @ self.obstacles[i].normal) @ half
            <= self.margin + self.obstacles[i].clearance
        ]
        if not near.size and not planes:
            return self._far
        distance, on_box, normal, on_other = (array.copy() for array in self._far)
        corners = box_corners(centre, rotation, half)
        a, b = corners[_EDGES[:, 0]], corners[_EDGES[:, 1]]
        for i in planes:
            ob, part = self.obstacles[i], slice(self._starts[i], self._starts[i] + 8)
            height = (corners - ob.point) @ ob.normal
            distance[part], on_box[part], normal[part] = height, corners, ob.normal
            on_other[part] = corners - height[:, None] * ob.normal
        for i in near:
            ob, at = self.obstacles[i], self._starts[i]
            reach = self.margin + max(ob.clearance, 0.0)
            if i in self._box_args:
                got = box_rows(a, b, _NO_RADIUS, *self._box_args[i])
            else:
                got = obstacle_distance(a, b, _NO_RADIUS, self._queries[i], reach)
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

    def _reverse_rows(self, i: int, centre: np.ndarray, rotation: np.ndarray,
                      reach: float) -> tuple[Proximity, np.ndarray] | None:  # fmt: skip
        """Obstacle ``i``'s own edges (axis, centre) against the box at ``centre`` (m), ``rotation``: (their Proximity,
        radii (k,) m); a mesh's nearest first, at most EDGE_ROWS of its edges whose bounds come within ``reach`` (m) of
        the box's; None if none."""
        if i in self._edges:
            edges = self._edges[i]
            near = edges.near_box(centre, rotation, self.half, reach, EDGE_ROWS)
            if not near.size:
                return None
            s0, s1, radii = edges.start[near], edges.end[near], np.zeros(len(near))
        elif self._reverse[i] is not None:
            s0, s1, radii = self._reverse[i]
        else:
            return None
        k = len(radii)
        got = box_rows(s0, s1, radii, np.broadcast_to(centre, (k, 3)), np.broadcast_to(rotation, (k, 3, 3)),
                       np.broadcast_to(self.half, (k, 3)))  # fmt: skip
        if i in self._edges:  # the nearest first: row j holds the j-th smallest distance (continuous)
            keep = np.argsort(got.distance, kind="stable")[:EDGE_ROWS]
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
        planes = (self.obstacles[i] for i in self._planes)  # the bounds' lowest corner along each plane's normal
        return any(float((np.where(ob.normal > 0, low, high) - ob.point) @ ob.normal) <= self.margin + ob.clearance
                   for ob in planes)  # fmt: skip

    def inside(self, centre: np.ndarray, rotation: np.ndarray, tolerance: float) -> list[str]:
        """The obstacles the box at ``centre`` (m), ``rotation`` is inside of, by more than ``tolerance`` (m)."""
        distance = self.gaps(centre, rotation)[0]
        return sorted({self._others[i] for i in np.flatnonzero(distance < self.floor - tolerance)})

    def _jacobian_of(self, state: State, rows: np.ndarray) -> np.ndarray:
        out = np.zeros((len(rows), self.n_x))
        if not rows.size:
            return out
        _, on_box, normal, _ = self._evaluate(state)
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
        near = np.flatnonzero(distance - self.floor < self.margin)
        out, seen = [], set()
        for i in near[np.argsort(distance[near], kind="stable")]:
            if self._others[i] not in seen:
                seen.add(self._others[i])
                out.append(Closeness(self._parts[i], self._others[i], float(distance[i]), float(self.floor[i]),
                                     on_box[i], on_other[i]))  # fmt: skip
        return out
