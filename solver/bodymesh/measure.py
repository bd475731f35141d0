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
    """(E, 2) directed vertex pairs along the quads' sides, both directions."""
    sides = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 3]], faces[:, [3, 0]]])
    return np.unique(np.concatenate([sides, sides[:, ::-1]]), axis=0)


def smooth(values: np.ndarray, faces: np.ndarray, iterations: int) -> np.ndarray:
    """Each round, every vertex's row of ``values`` (N, k) moves halfway to its neighbours' mean."""
    pairs = edges(faces)
    count = np.bincount(pairs[:, 0], minlength=len(values)).astype(float)[:, None]
    out = np.array(values, dtype=float)
    for _ in range(iterations):
        mean = np.zeros_like(out)
        np.add.at(mean, pairs[:, 0], out[pairs[:, 1]])
        out = 0.5 * out + 0.5 * mean / np.maximum(count, 1.0)
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
