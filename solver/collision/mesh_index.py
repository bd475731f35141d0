"""A triangle mesh prepared for queries: a tree of triangle bounds for nearest-triangle searches, inside/outside by
ray parity (a grid of the triangles seen from below), and the nearest surface point of any point.

Build one :class:`MeshIndex` per obstacle (about 20 ms per 10,000 triangles) and reuse it for every pose.
"""

from __future__ import annotations

import hashlib
from typing import Protocol

import numpy as np

from .closest import dot, point_segment, point_triangle, unit
from .grid import UniformGrid
from .mesh_edges import MeshEdges
from .tree import TIE, TriangleTree, group_argmin, group_min
from .triangle_frames import TriangleFrames


class Triangles(Protocol):
    """What an index is built from (a :class:`solver.collision.Mesh`): ``vertices`` (V, 3) m, ``faces`` (F, 3)."""

    vertices: np.ndarray
    faces: np.ndarray

    def is_closed(self) -> bool: ...

    def signed_volume(self) -> float: ...


class _Column:
    """Triangles seen from below (projected on x-y) for counting the crossings of an upward ray (+z).

    A point on a projected edge or corner is counted in exactly one triangle of a sheet, as if it were moved by
    an infinitesimal (1, eps) in x-y: edge functions are computed once per edge from its lower-numbered vertex
    (so the two faces sharing it agree to the last bit), and an edge owns the points on it if that move takes them
    inside. Triangles with zero projected area are skipped (that move never lands inside them).
    """

    def __init__(self, vertices: np.ndarray, faces: np.ndarray) -> None:
        tri = vertices[faces]
        area2 = np.cross(tri[:, 1, :2] - tri[:, 0, :2], tri[:, 2, :2] - tri[:, 0, :2])
        keep = np.flatnonzero(area2 != 0.0)
        faces, tri, orient = faces[keep], tri[keep], np.sign(area2[keep])
        first, second = faces, faces[:, [1, 2, 0]]
        low, high = np.minimum(first, second), np.maximum(first, second)
        self.origin = vertices[low][..., :2]  # (F, 3, 2)
        self.direction = vertices[high][..., :2] - self.origin
        self.sign = np.where(first < second, 1.0, -1.0) * orient[:, None]  # (F, 3)
        moved = self.direction * self.sign[..., None]  # edge direction with the triangle counter-clockwise
        self.owns = (moved[..., 1] < 0) | ((moved[..., 1] == 0) & (moved[..., 0] > 0))
        normal = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
        self.corner, self.normal = tri[:, 0], normal
        self.top = tri[:, :, 2].max(axis=1)
        self.grid = UniformGrid(tri[:, :, :2].min(axis=1), tri[:, :, :2].max(axis=1))

    def crossings(self, points: np.ndarray) -> np.ndarray:
        """Number of triangles (k,) the ray from each point straight up (+z) passes through."""
        query, item = self.grid.overlapping(points[:, :2], points[:, :2])
        above = self.top[item] > points[query, 2]
        query, item = query[above], item[above]
        p = points[query]
        rel = p[:, None, :2] - self.origin[item]
        d = self.direction[item]
        w = self.sign[item] * (d[..., 0] * rel[..., 1] - d[..., 1] * rel[..., 0])
        inside = np.all((w > 0) | ((w == 0) & self.owns[item]), axis=1)
        n, corner = self.normal[item], self.corner[item]
        height = corner[:, 2] - (n[:, 0] * (p[:, 0] - corner[:, 0]) + n[:, 1] * (p[:, 1] - corner[:, 1])) / n[:, 2]
        hit = inside & (height > p[:, 2])
        return np.bincount(query[hit], minlength=len(points))


class MeshIndex:
    """A mesh (:class:`Triangles`) with a tree over its triangles, unit face normals (outward for a closed mesh,
    whatever its winding) and, for a closed mesh, an inside test."""

    def __init__(self, mesh: Triangles) -> None:
        self.mesh = mesh
        tri = mesh.vertices[mesh.faces]
        self.a, self.b, self.c = (np.ascontiguousarray(tri[:, i]) for i in range(3))
        self.centroid = tri.mean(axis=1)
        self.bound = np.sqrt(np.max(np.sum((tri - self.centroid[:, None]) ** 2, axis=2), axis=1))
        self.tree = TriangleTree(self.a, self.b, self.c)
        self.frames = TriangleFrames(self.a, self.b, self.c)
        self.lo, self.hi = mesh.vertices.min(axis=0), mesh.vertices.max(axis=0)
        self.closed = mesh.is_closed()
        outward = -1.0 if self.closed and mesh.signed_volume() < 0 else 1.0
        raw = np.cross(self.b - self.a, self.c - self.a) * outward
        self.normals = unit(raw, np.array([0.0, 0.0, 1.0]))
        offset = dot(self.normals, self.a)
        # one row per triangle for the bounds: centroid, unit normal, plane offset, bounding radius, corner a and
        # the dual basis of its edges in the plane (p - a -> face coordinates v, w; the frames' rows)
        dual = self.frames.local
        self._rows = np.column_stack([self.centroid, self.normals, offset, self.bound, self.a, dual[:, 0], dual[:, 1]])
        self._column = _Column(mesh.vertices, mesh.faces) if self.closed else None
        self._memories: dict[tuple[str, ...], NearMemory] = {}
        self._edges: MeshEdges | None = None

    def edges(self) -> MeshEdges:
        """The mesh's edges that may be nearest a box, with a tree over them, built on first use and kept here."""
        if self._edges is None:
            self._edges = MeshEdges(self.mesh.vertices, self.mesh.faces)
        return self._edges

    def memory(self, capsules: tuple[str, ...]) -> NearMemory:
        """The :class:`NearMemory` of queries by these capsules (named in order), kept with the index: every problem
        with this mesh and these capsules (a motion's frames, Live's re-solves) starts from where the last left."""
        found = self._memories.get(capsules)
        if found is None:
            found = self._memories[capsules] = NearMemory(len(capsules))
        return found

    def __len__(self) -> int:
        return len(self.a)

    def _bounds(self, p0: np.ndarray, p1: np.ndarray, tri: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Lower and upper bounds (m) of the distances between segments p0-p1 and triangles ``tri`` (pairs).

        Lower: the bounding sphere, and the plane when both ends are on one side. Upper: the distance from the
        segment point nearest the centroid to the centroid, or to the plane if its projection falls inside."""
        row = self._rows[tri]
        c, n, offset, bound = row[:, 0:3], row[:, 3:6], row[:, 6], row[:, 7]
        _, near = point_segment(c, p0, p1)
        upper = np.sqrt(dot(near - c, near - c))
        h0, h1, h = dot(n, p0) - offset, dot(n, p1) - offset, dot(n, near) - offset
        lower = np.maximum(upper - bound, np.where(h0 * h1 > 0, np.minimum(np.abs(h0), np.abs(h1)), 0.0))
        ap = near - row[:, 8:11]  # the dual basis lies in the plane: no need to project onto it first
        v, w = dot(ap, row[:, 11:14]), dot(ap, row[:, 14:17])
        over = (v >= 0) & (w >= 0) & (v + w <= 1)
        return lower, np.where(over, np.minimum(upper, np.abs(h)), upper)

    def candidates(
        self, p0: np.ndarray, p1: np.ndarray, reach: np.ndarray, memory: NearMemory | None = None, ids=None
    ) -> tuple[np.ndarray, np.ndarray]:
        """Pairs (segment index, triangle index), grouped by segment, among which is each segment's nearest
        triangle if one lies within ``reach`` (k,) m: the tree's leaves within reach, minus the triangles whose
        lower bound is not below the segment's best upper bound by more than TIE (ties may be dropped: the
        answer is then another triangle at most TIE farther). With a ``memory`` (segments named by ``ids``), a
        segment near where it was last asked about takes its leaves from there instead of the tree."""
        if memory is None:
            seg, tri = self._near(p0, p1, reach, 0.0)
        else:
            seg, tri = memory.near(self, p0, p1, reach, ids)
        lower, upper = self._bounds(p0[seg], p1[seg], tri)
        best = reach.astype(float).copy()
        group_min(seg, upper, best)
        cut = best[seg]
        keep = (lower < cut - TIE) | (upper <= cut)
        return seg[keep], tri[keep]

    def _near(self, p0: np.ndarray, p1: np.ndarray, reach: np.ndarray, slack: float) -> tuple[np.ndarray, np.ndarray]:
        """Pairs (segment, triangle), grouped by segment: every triangle whose lower bound is within ``slack`` m of
        the segment's best upper bound (at most its reach)."""
        best = reach.astype(float).copy()
        seg, slot = self.tree.search(p0, p1, best, slack)
        if not slack:
            return seg, self.tree.order[slot]
        tri = self.tree.order[slot]
        lower, upper = self._bounds(p0[seg], p1[seg], tri)
        group_min(seg, upper, best)
        keep = lower <= best[seg] + slack
        return seg[keep], tri[keep]

    def contains(self, points: np.ndarray) -> np.ndarray:
        """True (k,) for points strictly inside a closed mesh (odd crossings of an upward ray); all False for an
        open mesh. Points on the surface may go either way."""
        points = np.atleast_2d(np.asarray(points, dtype=float))
        inside = np.zeros(len(points), dtype=bool)
        if self._column is None:
            return inside
        box = np.flatnonzero(np.all((points >= self.lo) & (points <= self.hi), axis=1))
        if box.size:
            inside[box] = self._column.crossings(points[box]) % 2 == 1
        return inside

    def nearest(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The nearest surface point of every point (k, 3): (distance (k,) m, point (k, 3), triangle (k,))."""
        points = np.atleast_2d(np.asarray(points, dtype=float))
        k = len(points)
        seg, tri = self.candidates(points, points, np.full(k, np.inf))
        y = point_triangle(points[seg], self.a[tri], self.b[tri], self.c[tri])
        d = np.sqrt(dot(y - points[seg], y - points[seg]))
        best = group_argmin(seg, d, k)  # every point has a candidate: the search keeps the best leaf
        return d[best], y[best], tri[best]


class NearMemory:
    """The triangles near each capsule of a query (by its number, 0..capsules-1) when it was last asked about:
    those within SLACK of its nearest. Asked again within SLACK / 2 of there (each end moved less), the capsule's
    nearest triangle is among them, so the tree need not be walked: a pose re-solved a little farther on (the
    iterations of a solve, the next frame, Live) moves the capsules near a mesh by millimetres.

    Exact: a triangle T nearest the moved segment has d_old(T) <= d_new(T) + e <= d_new(B) + e <= d_old(B) + 2 e for
    B the old nearest and e the largest end move (the segment's points move at most e), so T was kept."""

    SLACK = 0.06  # m: a re-solve as a target is dragged starts 1-2 cm from the last walk (docs/TUNING.md)

    def __init__(self, capsules: int) -> None:
        self.ends = np.full((capsules, 6), np.nan)  # p0, p1 when last asked (m)
        self.reach = np.zeros(capsules)  # the reach then (m)
        self.kept: list[np.ndarray] = [np.zeros(0, dtype=np.int64)] * capsules

    def near(self, index: MeshIndex, p0, p1, reach, ids) -> tuple[np.ndarray, np.ndarray]:
        """(segment, triangle) pairs for ``index.candidates``: remembered or searched (and then remembered)."""
        ids = np.asarray(ids)
        moved = np.abs(np.concatenate([p0, p1], axis=1) - self.ends[ids])
        ok = (
            np.sqrt(np.maximum(dot(moved[:, :3], moved[:, :3]), dot(moved[:, 3:], moved[:, 3:]))) <= 0.5 * self.SLACK
        ) & (reach <= self.reach[ids])  # fmt: skip  (NaN: never asked, not ok)
        fresh = np.flatnonzero(~ok)
        if fresh.size:
            seg, tri = index._near(p0[fresh], p1[fresh], reach[fresh], self.SLACK)
            starts = np.searchsorted(seg, np.arange(len(fresh) + 1))
            for j, row in enumerate(fresh):
                self.kept[ids[row]] = tri[starts[j] : starts[j + 1]]
            self.ends[ids[fresh]] = np.concatenate([p0[fresh], p1[fresh]], axis=1)
            self.reach[ids[fresh]] = reach[fresh]
        tris = [self.kept[i] for i in ids]
        seg = np.repeat(np.arange(len(ids)), [len(t) for t in tris])
        return seg, np.concatenate(tris) if tris else np.zeros(0, dtype=np.int64)


_INDEXES: dict[bytes, MeshIndex] = {}  # by content: the same mesh read again (each baked frame) is indexed once
_KEPT = 8


def index_of(mesh: Triangles) -> MeshIndex:
    """The :class:`MeshIndex` of ``mesh``, built once per content (its vertices, faces; the last few kept)."""
    digest = hashlib.blake2b(digest_size=16)
    digest.update(mesh.vertices.tobytes())
    digest.update(mesh.faces.tobytes())
    key = digest.digest()
    index = _INDEXES.get(key)
    if index is None:
        if len(_INDEXES) >= _KEPT:
            _INDEXES.pop(next(iter(_INDEXES)))
        index = _INDEXES[key] = MeshIndex(mesh)
    return index
