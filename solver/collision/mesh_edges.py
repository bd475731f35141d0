"""A mesh's edges that may be nearest a box, each once, with a tree over their bounds (m).

The carried box measures a mesh's own edges against itself (:mod:`solver.constraints.carried_obstacles`): a mesh
corner poking into the middle of one of its faces touches none of its edges. An edge between two coplanar
triangles (a flat one, inside a planar region of the mesh) is left out: a box apart from such a region is nearest it
at one of its own edges or at the region's rim (the non-flat edges around it), never nearer a flat edge than those;
and a box that meets the region either has one of its own edges through it or a rim edge inside it. So a flat face
of many triangles costs no rows; and a straight run of edges (a subdivided rim) is one segment, so that a box
resting on a rim is held by one row, not by the nearest few of its pieces. Built once per mesh, kept with its
:class:`~solver.collision.mesh_index.MeshIndex` (:meth:`~solver.collision.mesh_index.MeshIndex.edges`).
"""

from __future__ import annotations

import numpy as np

from .closest import cross, dot
from .tree import TIE, TriangleTree

FLAT = 1e-9  # sine of the bend (rad) below which an edge between two triangles counts as flat


def _box_bounds(mid: np.ndarray, half_edge: np.ndarray, half: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Lower and upper bounds (k,) m of the signed distances (negative: minus the penetration depth) of segments
    mid +- half_edge (k, 3), in box coordinates, to the box |x_i| <= half_i.

    Lower: the gap between the segment's bounds and the box, or where they overlap, minus the least overlap along a
    face axis (the depth is the least over the separating axes, these among them). Upper: the nearer end's signed
    distance (a segment is no farther than its ends, and pushing it out moves each end out)."""
    overlap = half + np.abs(half_edge) - np.abs(mid)  # per axis: of the segment's bounds with the box's (< 0: a gap)
    least = _least(overlap)
    gap = np.maximum(-overlap, 0.0)
    lower = np.where(least >= 0.0, -least, np.sqrt(dot(gap, gap)))
    upper = None
    for end in (mid - half_edge, mid + half_edge):
        beyond = np.abs(end) - half
        out = np.maximum(beyond, 0.0)
        signed = np.sqrt(dot(out, out)) - np.maximum(-_most(beyond), 0.0)
        upper = signed if upper is None else np.minimum(upper, signed)
    return lower, upper


def _least(x: np.ndarray) -> np.ndarray:
    """Row minima of (k, 3) (column by column: NumPy's reduction along a short last axis is several times slower)."""
    return np.minimum(np.minimum(x[:, 0], x[:, 1]), x[:, 2])


def _most(x: np.ndarray) -> np.ndarray:
    """Row maxima of (k, 3), as :func:`_least`."""
    return np.maximum(np.maximum(x[:, 0], x[:, 1]), x[:, 2])


def _sharp_edges(vertices: np.ndarray, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The edges (first, second vertex indices (E,)) of triangles ``faces``, each once, but the flat ones: two
    triangles on them whose far corners lie in one plane on either side (within FLAT)."""
    first, second, third = (np.concatenate([faces[:, i], faces[:, (i + 1) % 3], faces[:, (i + 2) % 3]])
                            for i in range(3))  # fmt: skip
    n = np.int64(len(vertices))
    key = np.minimum(first, second) * n + np.maximum(first, second)
    order = np.argsort(key, kind="stable")
    _, at, count = np.unique(key[order], return_index=True, return_counts=True)
    keep = np.ones(len(at), dtype=bool)
    two = np.flatnonzero(count == 2)
    i, j = order[at[two]], order[at[two] + 1]
    a, along = vertices[first[i]], vertices[second[i]] - vertices[first[i]]
    p, q = vertices[third[i]] - a, vertices[third[j]] - a
    up = cross(along, p)
    height = np.abs(dot(up, q)) / np.maximum(np.sqrt(dot(up, up) * dot(q, q)), 1e-300)
    keep[two] = (height > FLAT) | (dot(up, cross(along, q)) >= 0.0)
    edge = order[at[keep]]
    return first[edge], second[edge]


def _joined(vertices: np.ndarray, u: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Edges u-v (vertex indices) with every straight run joined into one (a subdivided rim is one segment: the
    same points, so the same distance): a vertex on exactly two edges that go on in one line (within FLAT) is
    passed through. Returns the runs' end vertices."""
    count = len(u)
    ends = np.concatenate([u, v])
    edge = np.tile(np.arange(count), 2)
    order = np.argsort(ends, kind="stable")
    degree = np.bincount(ends, minlength=len(vertices))
    start = np.concatenate([[0], np.cumsum(degree)])
    middle = np.flatnonzero(degree == 2)
    e1, e2 = edge[order[start[middle]]], edge[order[start[middle] + 1]]
    d1 = vertices[np.where(u[e1] == middle, v[e1], u[e1])] - vertices[middle]
    d2 = vertices[np.where(u[e2] == middle, v[e2], u[e2])] - vertices[middle]
    across = cross(d1, d2)
    straight = (np.sqrt(dot(across, across)) <= FLAT * np.sqrt(dot(d1, d1) * dot(d2, d2))) & (dot(d1, d2) < 0.0)
    e1, e2 = e1[straight], e2[straight]
    if not e1.size:
        return u, v
    label = np.arange(count)  # each run takes its least edge number (labels spread along the run until settled)
    while True:
        low = np.minimum(label[e1], label[e2])
        spread = label.copy()
        np.minimum.at(spread, e1, low)
        np.minimum.at(spread, e2, low)
        spread = spread[spread]
        if np.array_equal(spread, label):
            break
        label = spread
    # a run's ends are the vertices met once among its edges' ends (the passed-through ones twice)
    key, seen = np.unique(np.tile(label, 2) * np.int64(len(vertices)) + ends, return_counts=True)
    tips = key[seen == 1]  # sorted by run: two per run
    return tips[0::2] % len(vertices), tips[1::2] % len(vertices)


class MeshEdges:
    """The edges of triangles ``faces`` (F, 3) over ``vertices`` (V, 3) m, each once, but the flat ones, straight
    runs joined: ``start``, ``end`` (E, 3) m, and a tree over their bounding boxes."""

    def __init__(self, vertices: np.ndarray, faces: np.ndarray) -> None:
        u, v = _joined(vertices, *_sharp_edges(vertices, faces))
        self.start, self.end = vertices[u], vertices[v]
        self.mid, self.half_edge = (self.start + self.end) / 2.0, (self.end - self.start) / 2.0
        low, high = np.minimum(self.start, self.end), np.maximum(self.start, self.end)
        self._low, self._high = tuple(np.ascontiguousarray(low.T)), tuple(np.ascontiguousarray(high.T))  # per axis
        # a tree of the edges as triangles of no area (its search walks only the nodes near the box; a uniform grid
        # suits edges of one length, not a mesh's long rims and small rounded corners together)
        self.tree = TriangleTree(self.start, self.end, self.end) if len(u) else None

    def __len__(self) -> int:
        return len(self.start)

    def meeting(self, low: np.ndarray, high: np.ndarray) -> np.ndarray:
        """Indices (ascending) of the edges whose bounding boxes meet the world box ``low``..``high`` (3,) m."""
        if self.tree is None:
            return np.zeros(0, dtype=np.int64)
        edge = self.tree.order[self.tree.meeting(low, high)]
        meet = (self._low[0][edge] <= high[0]) & (self._high[0][edge] >= low[0])
        for d in (1, 2):
            meet &= (self._low[d][edge] <= high[d]) & (self._high[d][edge] >= low[d])
        return np.sort(edge[meet])

    def near_box(self, centre: np.ndarray, rotation: np.ndarray, half: np.ndarray, reach: float,
                 count: int) -> np.ndarray:  # fmt: skip
        """Indices (ascending) of edges among which are the ``count`` nearest the box ``centre`` (m), ``rotation``
        (axes as columns), ``half`` sizes (m), of those whose bounds meet the box's world bounds grown by ``reach``
        (m): every such edge whose lower bound is below the count-th least upper bound by more than TIE, and the
        count edges of least upper bounds (so the j-th least distance among them is within TIE of the true one,
        and a flat of many edges at one distance costs ``count`` exact queries, not one per edge)."""
        grown = np.abs(rotation) @ half + reach
        near = self.meeting(centre - grown, centre + grown)
        if len(near) <= count:
            return near
        lower, upper = _box_bounds((self.mid[near] - centre) @ rotation, self.half_edge[near] @ rotation, half)
        best = np.argpartition(upper, count - 1)[:count]
        keep = lower < upper[best].max() - TIE
        keep[best] = True
        return near[keep]
