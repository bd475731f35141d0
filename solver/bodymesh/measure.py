"""Measurements of a body mesh: stature, enclosed volume and the mass it stands for, and the mesh's neighbour
lists (for smoothing). Units: m, m^3, kg."""

from __future__ import annotations

import numpy as np

BODY_DENSITY = 1000.0  # kg/m^3: with air in the lungs a body is about as dense as water (as the capsule body)


def stature(vertices: np.ndarray) -> float:
    """Height of the mesh from its lowest to its highest vertex (m)."""
    return float(vertices[:, 2].max() - vertices[:, 2].min())


def volume(vertices: np.ndarray, faces: np.ndarray) -> float:
    """Enclosed volume (m^3) of a closed mesh of quads, counter-clockwise seen from outside (divergence theorem
    over the quads split into triangles)."""
    tri = np.concatenate([faces[:, [0, 1, 2]], faces[:, [0, 2, 3]]])
    origin = vertices.mean(axis=0)
    a, b, c = (vertices[tri[:, k]] - origin for k in range(3))
    return float(np.einsum("ij,ij->", a, np.cross(b, c)) / 6.0)


def mass(vertices: np.ndarray, faces: np.ndarray) -> float:
    """The mass (kg) a body of this mesh's volume has at :data:`BODY_DENSITY`."""
    return BODY_DENSITY * volume(vertices, faces)


def edges(faces: np.ndarray) -> np.ndarray:
    """(E, 2) directed vertex pairs along the quads' sides, both directions, sorted (by first, then second)."""
    sides = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 3]], faces[:, [3, 0]]]).astype(np.int64)
    both = np.concatenate([sides, sides[:, ::-1]])
    span = int(both.max()) + 1
    keys = np.unique(both[:, 0] * span + both[:, 1])  # one integer per pair: a 1-D unique, much faster than rows
    return np.stack([keys // span, keys % span], axis=1)


def smooth(values: np.ndarray, faces: np.ndarray, iterations: int) -> np.ndarray:
    """Each round, every vertex's row of ``values`` (N, k) moves halfway to its neighbours' mean."""
    pairs = edges(faces)
    n = len(values)
    count = np.bincount(pairs[:, 0], minlength=n)
    # A neighbour table padded with a zero row (index n): one gather per neighbour slot is much faster than
    # scattering every edge (np.add.at) on a mesh of at most a few neighbours per vertex. Pairs are sorted by
    # their first vertex, so each vertex's neighbours are one run.
    slot = np.arange(len(pairs)) - np.searchsorted(pairs[:, 0], pairs[:, 0])
    table = np.full((n, int(count.max(initial=0))), n)
    table[pairs[:, 0], slot] = pairs[:, 1]
    out = np.array(values, dtype=float)
    scale = 0.5 / np.maximum(count, 1)[:, None]
    for _ in range(iterations):
        padded = np.concatenate([out, np.zeros((1,) + out.shape[1:])])
        total = np.zeros_like(out)
        for column in table.T:
            total += padded[column]
        out = 0.5 * out + scale * total
    return out


def winding_numbers(vertices: np.ndarray, faces: np.ndarray, points: np.ndarray) -> np.ndarray:
    """(P,) generalised winding number of each point about the closed quad mesh: 1 inside, 0 outside (the sum of
    the solid angles its triangles subtend, over 4 pi; van Oosterom and Strackee's formula)."""
    tri = np.concatenate([faces[:, [0, 1, 2]], faces[:, [0, 2, 3]]])
    out = np.empty(len(points))
    for i, p in enumerate(np.asarray(points, dtype=float)):
        a, b, c = (vertices[tri[:, k]] - p for k in range(3))
        la, lb, lc = (np.linalg.norm(v, axis=1) for v in (a, b, c))
        det = np.einsum("ij,ij->i", a, np.cross(b, c))
        dots = np.einsum("ij,ij->i", a, b) * lc + np.einsum("ij,ij->i", b, c) * la + np.einsum("ij,ij->i", c, a) * lb
        out[i] = 2.0 * np.arctan2(det, la * lb * lc + dots).sum() / (4.0 * np.pi)
    return out


def section_area(vertices: np.ndarray, faces: np.ndarray, point: np.ndarray, normal: np.ndarray,
                 reach: float) -> float:  # fmt: skip
    """Area (m^2) of the mesh's cross-section by the plane through ``point`` normal to ``normal``, taking only the
    edge crossings within ``reach`` (m) of ``point`` (one limb's section, not the trunk beside it). The crossings are
    joined in order of their angle about their centroid: exact for a star-shaped section (a limb's)."""
    normal = np.asarray(normal, dtype=float) / np.linalg.norm(normal)
    pairs = edges(faces)
    pairs = pairs[pairs[:, 0] < pairs[:, 1]]
    side = (vertices - point) @ normal
    a, b = side[pairs[:, 0]], side[pairs[:, 1]]
    cross = pairs[(a < 0.0) != (b < 0.0)]
    t = side[cross[:, 0]] / (side[cross[:, 0]] - side[cross[:, 1]])
    hits = vertices[cross[:, 0]] + t[:, None] * (vertices[cross[:, 1]] - vertices[cross[:, 0]])
    hits = hits[np.linalg.norm(hits - point, axis=1) < reach]
    if len(hits) < 3:
        return 0.0
    u = np.cross(normal, [1.0, 0.0, 0.0] if abs(normal[0]) < 0.9 else [0.0, 1.0, 0.0])
    u /= np.linalg.norm(u)
    v = np.cross(normal, u)
    flat = np.column_stack([(hits - hits.mean(axis=0)) @ u, (hits - hits.mean(axis=0)) @ v])
    flat = flat[np.argsort(np.arctan2(flat[:, 1], flat[:, 0]))]
    x, y = flat[:, 0], flat[:, 1]
    return float(0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1))))
