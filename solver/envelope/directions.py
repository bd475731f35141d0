"""Directions from the shoulder: a geodesic sphere (a subdivided icosahedron), optionally cut to a hemisphere, with
its triangles, so that reach radii along the directions make a closed mesh.

A sphere of frequency ``f`` has 10 f^2 + 2 unit directions and 20 f^2 triangles (f = 3: 92, f = 4: 162). A
hemisphere keeps the directions within 90 degrees of its axis and closes the cut with a fan of triangles to the
centre (the shoulder), so its mesh is closed too. World frame: z up, the manikin faces -y, its left is +x.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import UsageError

HEMISPHERES = {
    "all": None,
    "front": (0.0, -1.0, 0.0),
    "back": (0.0, 1.0, 0.0),
    "upper": (0.0, 0.0, 1.0),
    "lower": (0.0, 0.0, -1.0),
    "left": (1.0, 0.0, 0.0),
    "right": (-1.0, 0.0, 0.0),
}
MAX_FREQUENCY = 12  # 1442 directions: far beyond what a reach envelope needs


@dataclass(frozen=True)
class DirectionSphere:
    """Unit ``directions`` (k, 3), ``faces`` (m, 3) indices into the directions, and, for a hemisphere, the index
    ``centre`` = k of an extra vertex at the origin that closes the mesh (None for the whole sphere)."""

    directions: np.ndarray
    faces: np.ndarray
    centre: int | None

    def vertices(self, radii: np.ndarray) -> np.ndarray:
        """Mesh vertices (k or k + 1, 3) m relative to the shoulder: each direction scaled by its radius (m), then
        the centre (the origin) for a hemisphere."""
        points = self.directions * np.asarray(radii, dtype=float)[:, None]
        return points if self.centre is None else np.vstack([points, np.zeros((1, 3))])

    def neighbours(self) -> list[set[int]]:
        """Per direction, the directions it shares a triangle edge with (the centre left out)."""
        out: list[set[int]] = [set() for _ in range(len(self.directions))]
        for face in self.faces:
            for a in face:
                if a != self.centre:
                    out[a].update(int(b) for b in face if b != a and b != self.centre)
        return out


def _icosahedron() -> tuple[np.ndarray, np.ndarray]:
    """12 unit vertices and 20 outward (counter-clockwise seen from outside) triangles."""
    g = (1.0 + 5.0**0.5) / 2.0
    v = np.array([[-1, g, 0], [1, g, 0], [-1, -g, 0], [1, -g, 0], [0, -1, g], [0, 1, g],
                  [0, -1, -g], [0, 1, -g], [g, 0, -1], [g, 0, 1], [-g, 0, -1], [-g, 0, 1]], float)  # fmt: skip
    f = np.array([[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11], [1, 5, 9], [5, 11, 4], [11, 10, 2],
                  [10, 7, 6], [7, 1, 8], [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8], [3, 8, 9], [4, 9, 5],
                  [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1]])  # fmt: skip
    return v / np.linalg.norm(v, axis=1, keepdims=True), f


def geodesic_sphere(frequency: int) -> tuple[np.ndarray, np.ndarray]:
    """(10 f^2 + 2 unit directions, 20 f^2 outward triangles): each icosahedron face cut into f^2 triangles."""
    ico, ico_faces = _icosahedron()
    n = frequency
    points, faces = [], []
    grid = [(i, j) for i in range(n + 1) for j in range(n + 1 - i)]
    local = {ij: k for k, ij in enumerate(grid)}
    for a, b, c in ico_faces:
        base = len(points) * len(grid)
        points.append([ico[a] + (ico[b] - ico[a]) * i / n + (ico[c] - ico[a]) * j / n for i, j in grid])
        for i, j in grid:
            if i + j < n:
                faces.append([base + local[i, j], base + local[i + 1, j], base + local[i, j + 1]])
            if i + j < n - 1:
                faces.append([base + local[i + 1, j], base + local[i + 1, j + 1], base + local[i, j + 1]])
    flat = np.concatenate(points)
    flat /= np.linalg.norm(flat, axis=1, keepdims=True)
    # the points on shared edges and corners appear once per face: merge them
    _, first, inverse = np.unique(np.round(flat, 9), axis=0, return_index=True, return_inverse=True)
    order = np.argsort(first)  # keep the directions in the order they were made
    rank = np.empty_like(order)
    rank[order] = np.arange(len(order))
    return flat[first[order]], rank[np.asarray(inverse).ravel()][np.array(faces)]


def direction_sphere(frequency: int, hemisphere: str = "all") -> DirectionSphere:
    """The directions of a geodesic sphere of ``frequency`` (1..12), cut to ``hemisphere`` (see HEMISPHERES)."""
    if not (isinstance(frequency, int) and 1 <= frequency <= MAX_FREQUENCY):
        raise UsageError(f"--frequency: expected a whole number 1..{MAX_FREQUENCY}, got {frequency!r}")
    if hemisphere not in HEMISPHERES:
        raise UsageError(f"--hemisphere: expected one of {', '.join(HEMISPHERES)}, got {hemisphere!r}")
    directions, faces = geodesic_sphere(frequency)
    axis = HEMISPHERES[hemisphere]
    if axis is None:
        return DirectionSphere(directions, faces, None)
    keep = directions @ np.asarray(axis) >= -1e-9
    faces = faces[keep[faces].all(axis=1)]
    new = np.cumsum(keep) - 1
    faces = new[faces]
    centre = int(keep.sum())
    return DirectionSphere(directions[keep], np.vstack([faces, _cap(faces, centre)]), centre)


def _cap(faces: np.ndarray, centre: int) -> np.ndarray:
    """Triangles from every boundary edge (an edge of one face only) to ``centre``, oriented like their face."""
    edges = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    key = np.sort(edges, axis=1)
    _, inverse, counts = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    boundary = edges[counts[np.asarray(inverse).ravel()] == 1]
    return np.column_stack([boundary[:, 1], boundary[:, 0], np.full(len(boundary), centre)]).astype(faces.dtype)
