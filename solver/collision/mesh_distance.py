"""Capsules vs a triangle mesh: exact distance outside, a measured depth inside a closed mesh.

Outside (and for any capsule that does not touch the surface and is not enclosed): the exact closest points of
the axis segment and the candidate triangles of the tree within ``radius + margin``; capsules with nothing within
the margin get +inf. A closed mesh also has an inside: a capsule whose axis touches the surface or lies inside
(ray parity) gets the signed distance at the deepest of SAMPLES evenly spaced axis points, -(distance to the
surface), with the normal towards that nearest surface point (the way out); if no sample is inside, the touching
point with distance 0 and the outward face normal. An open mesh has no inside: a surface, not a solid; an axis
that crosses it has distance -radius and the normal of the crossed face turned to the side holding more of the
segment.
"""

from __future__ import annotations

import numpy as np

from .closest import dot, unit
from .mesh_index import MeshIndex, NearMemory
from .proximity import Proximity, near_only
from .tree import group_argmin

SAMPLES = 9  # axis points where the depth inside a closed mesh is measured (t = 0, 1/8, ..., 1)
TOUCH = 1e-12  # m: an axis this close to the surface touches it (its normal is then the face's)


def _closest_triangles(p0, p1, reach, index: MeshIndex, memory: NearMemory | None, ids) -> tuple[np.ndarray, ...]:
    """Per segment: the nearest triangle within reach (-1 if none), the distance (inf if none), t and the points."""
    k = len(p0)
    which, dist, t, x, y = np.full(k, -1), np.full(k, np.inf), np.zeros(k), p0.copy(), p0.copy()
    seg, tri = index.candidates(p0, p1, reach, memory, ids)
    if seg.size:
        tt, xx, yy = index.frames.closest(p0[seg], p1[seg], tri)
        d = np.sqrt(dot(xx - yy, xx - yy))
        best = group_argmin(seg, d, k)
        rows = np.flatnonzero(best >= 0)
        pick = best[rows]
        which[rows], dist[rows], t[rows], x[rows], y[rows] = tri[pick], d[pick], tt[pick], xx[pick], yy[pick]
    return which, dist, t, x, y


def _depth_inside(p0, p1, rows, index: MeshIndex):
    """For segments ``rows``: the deepest inside sample (t, point, nearest surface point, depth > 0), or depth 0
    where no sample is inside."""
    ts = np.linspace(0.0, 1.0, SAMPLES)
    pts = p0[rows, None] + ts[None, :, None] * (p1 - p0)[rows, None]
    flat = pts.reshape(-1, 3)
    depth = np.zeros(len(flat))
    near = flat.copy()
    inside = np.flatnonzero(index.contains(flat))
    depth[inside], near[inside], _ = index.nearest(flat[inside])
    depth, near = depth.reshape(-1, SAMPLES), near.reshape(-1, SAMPLES, 3)
    k = np.argmax(depth, axis=1)
    m = np.arange(len(rows))
    return ts[k], pts[m, k], near[m, k], depth[m, k]


def _signed(p0, p1, radii, margin: float, index: MeshIndex, memory: NearMemory | None = None, ids=None) -> Proximity:
    """mesh_distance for capsules near the mesh's box (``ids``: their numbers in ``memory``)."""
    k = len(p0)
    which, axis, t, w, near = _closest_triangles(p0, p1, radii + margin, index, memory, ids)
    found = np.flatnonzero(which >= 0)
    face = np.zeros((k, 3))
    face[found] = index.normals[which[found]]
    if not index.closed:  # a crossed sheet pushes towards the side with more of the segment
        side = np.sign(dot(face[found], 0.5 * (p0[found] + p1[found]) - near[found]))
        face[found] *= np.where(side < 0, -1.0, 1.0)[:, None]
    normal = np.zeros((k, 3))
    normal[found] = np.where((axis[found] > TOUCH)[:, None], unit(w[found] - near[found], face[found]), face[found])
    if index.closed:
        touching = np.zeros(k, dtype=bool)
        touching[found] = axis[found] <= TOUCH
        enclosed = ~touching & index.contains(w)
        rows = np.flatnonzero(touching | enclosed)
        if rows.size:
            ts, pts, surface, depth = _depth_inside(p0, p1, rows, index)
            deep = depth > 0
            r = rows[deep]
            axis[rows] = np.where(deep, -depth, 0.0)
            t[r], w[r], near[r] = ts[deep], pts[deep], surface[deep]
            normal[r] = unit(surface[deep] - pts[deep], normal[r])
            normal[rows[~deep]] = face[rows[~deep]]  # touching only: the outward face normal
    return Proximity(axis - radii, t, w, normal, near)


def mesh_distance(
    p0: np.ndarray, p1: np.ndarray, radii: np.ndarray, index: MeshIndex, margin: float, memory: NearMemory | None = None
) -> Proximity:
    """Capsules p0-p1 (k, 3) m with ``radii`` (k,) m vs an indexed mesh; see the module docstring. Capsules
    farther than ``margin`` (m) get distance +inf, t = 0, point = closest = p0 and a zero normal. ``memory``: the
    same capsules' last query of this mesh (:class:`~solver.collision.mesh_index.NearMemory`), to start from."""
    p0, p1 = np.atleast_2d(np.asarray(p0, dtype=float)), np.atleast_2d(np.asarray(p1, dtype=float))
    k = len(p0)
    radii = np.broadcast_to(np.asarray(radii, dtype=float), (k,))
    return near_only(p0, p1, radii, margin, index.lo, index.hi,
                     lambda rows: _signed(p0[rows], p1[rows], radii[rows], margin, index, memory, rows))  # fmt: skip
