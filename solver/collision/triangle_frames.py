"""Closest points of segments and a mesh's triangles, from per-triangle frames made once.

The same answer as :func:`solver.collision.closest.segment_triangle` (the best of the two ends and the plane
crossing over the face, and the segment against the three edges), but a query near a mesh asks about tens of
pairs, where the time goes into the number of NumPy calls rather than into the pairs: each triangle keeps the
rows that map a point to its coordinates on the face and its height (one matrix product answers both ends), and
its corners, edges and squared edge lengths in one array (one gather).
"""

from __future__ import annotations

import numpy as np

from .closest import PARALLEL, TINY, clip01

# A triangle whose doubled area is below this fraction of its longest edge squared has collinear corners.
DEGENERATE_RATIO = 1e-10


def degenerate_faces(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Mask (F,) of triangles with a repeated corner or (nearly) collinear corners."""
    tri = vertices[faces]
    edges = tri[:, [1, 2, 0]] - tri
    longest = np.max(np.einsum("fij,fij->fi", edges, edges), axis=1)
    doubled_area = np.linalg.norm(np.cross(edges[:, 0], -edges[:, 2]), axis=1)
    repeated = (faces[:, 0] == faces[:, 1]) | (faces[:, 1] == faces[:, 2]) | (faces[:, 2] == faces[:, 0])
    return repeated | (doubled_area <= DEGENERATE_RATIO * longest) | (longest == 0)


class TriangleFrames:
    """Triangles a, b, c (F, 3) m, none degenerate (a :class:`~solver.collision.Mesh` rejects those)."""

    def __init__(self, a: np.ndarray, b: np.ndarray, c: np.ndarray) -> None:
        ab, ac = b - a, c - a
        normal = np.cross(ab, ac)
        d00, d01, d11 = (np.einsum("ij,ij->i", x, y) for x, y in ((ab, ab), (ab, ac), (ac, ac)))
        den = (d00 * d11 - d01 * d01)[:, None]
        # rows: the dual basis of ab, ac in the plane (p - a -> its face coordinates v, w) and the unit normal
        self.local = np.stack(
            [(d11[:, None] * ab - d01[:, None] * ac) / den, (d00[:, None] * ac - d01[:, None] * ab) / den,
             normal / np.linalg.norm(normal, axis=1)[:, None]], axis=1)  # fmt: skip
        corners = np.stack([a, b, c], axis=1)
        edges = np.stack([ab, c - b, -ac], axis=1)
        squared = np.einsum("fkj,fkj->fk", edges, edges)[..., None]
        self.packed = np.concatenate([corners, edges, squared], axis=2)  # (F, 3 edges, 7): start, direction, |d|^2

    def closest(self, p0: np.ndarray, p1: np.ndarray, tri: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """For segments p0-p1 (m, 3) m and triangles ``tri`` (m,): (t (m,) on the segment, its point (m, 3), the
        triangle's closest point (m, 3)). A segment piercing its triangle gets the piercing point twice."""
        m = len(p0)
        local, packed = self.local[tri], self.packed[tri]
        start, direction, squared = packed[..., 0:3], packed[..., 3:6], packed[..., 6]
        u = p1 - p0
        coords = local @ (np.stack([p0, p1], axis=2) - start[:, 0, :, None])  # (m, 3: v w h, 2 ends)
        h0, h1 = coords[:, 2, 0], coords[:, 2, 1]
        crosses = (h0 * h1 <= 0.0) & (h0 != h1)
        ts = np.zeros((m, 3))  # the three points tried over the face: end 0, the plane crossing, end 1
        ts[:, 1], ts[:, 2] = h0 / np.where(crosses, h0 - h1, 1.0) * crosses, 1.0
        at = coords[..., :1] + (coords[..., 1:] - coords[..., :1]) * ts[:, None, :]  # (m, v w h, 3 points)
        v, w, h = at[:, 0], at[:, 1], at[:, 2]
        over = (v >= 0.0) & (w >= 0.0) & (v + w <= 1.0)
        over[:, 1] &= crosses
        d2 = np.empty((m, 6))
        d2[:, :3] = np.where(over, h * h, np.inf)
        # the segment against each edge: minimise |r + s u - t d|^2 on [0, 1]^2 (segment_segment's rule)
        r = p0[:, None] - start
        uu = np.einsum("ij,ij->i", u, u)[:, None]
        ud = (direction @ u[:, :, None])[..., 0]
        ur = (r @ u[:, :, None])[..., 0]
        dr = np.einsum("mkj,mkj->mk", direction, r)
        safe_u, safe_d = np.maximum(uu, TINY), np.maximum(squared, TINY)
        denom = uu * squared - ud * ud
        s = clip01((ud * dr - ur * squared) / np.maximum(denom, 1e-300)) * (denom > PARALLEL * uu * squared)
        t = (ud * s + dr) / safe_d
        s = np.where(t < 0.0, clip01(-ur / safe_u), np.where(t > 1.0, clip01((ud - ur) / safe_u), s)) * (uu > TINY)
        t = clip01(t)
        gap = r + s[..., None] * u[:, None] - t[..., None] * direction
        d2[:, 3:] = np.einsum("mkj,mkj->mk", gap, gap)
        best = np.argmin(d2, axis=1)
        rows, edge = np.arange(m), np.maximum(best - 3, 0)
        face = best < 3
        param = np.where(face, ts[rows, np.minimum(best, 2)], s[rows, edge])
        point = p0 + param[:, None] * u
        on_face = point - h[rows, np.minimum(best, 2)][:, None] * local[:, 2]
        on_edge = start[rows, edge] + t[rows, edge][:, None] * direction[rows, edge]
        return param, point, np.where(face[:, None], on_face, on_edge)
