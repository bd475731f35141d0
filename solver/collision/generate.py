"""Generated triangle meshes (m): a subdivided closed box and an open height-field patch, for presets, tests and
benchmarks."""

from __future__ import annotations

import numpy as np


def box_mesh(center, size, divisions: int = 1, rotation=None) -> tuple[np.ndarray, np.ndarray]:
    """A closed box of full edge lengths ``size`` (3,) m around ``center`` (3,), each face split into
    ``divisions`` x ``divisions`` squares of two triangles, counter-clockwise seen from outside:
    (vertices (V, 3), faces (12 divisions^2, 3))."""
    n = int(divisions)
    half = 0.5 * np.asarray(size, dtype=float)
    steps = np.linspace(-1.0, 1.0, n + 1)
    keys: dict[tuple[int, int, int], int] = {}
    vertices: list[np.ndarray] = []
    faces: list[list[int]] = []

    def vertex(grid: tuple[int, int, int]) -> int:
        if grid not in keys:  # shared by the faces that meet at an edge or corner
            keys[grid] = len(vertices)
            vertices.append(np.array([steps[g] for g in grid]) * half)
        return keys[grid]

    for axis in range(3):
        u, v = (axis + 1) % 3, (axis + 2) % 3
        for side in (0, n):
            for i in range(n):
                for j in range(n):
                    quad = []
                    for di, dj in ((0, 0), (1, 0), (1, 1), (0, 1)):
                        grid = [0, 0, 0]
                        grid[axis], grid[u], grid[v] = side, i + di, j + dj
                        quad.append(vertex(tuple(grid)))
                    if side == 0:  # the -axis face looks the other way
                        quad.reverse()
                    faces += [[quad[0], quad[1], quad[2]], [quad[0], quad[2], quad[3]]]
    rot = np.eye(3) if rotation is None else np.asarray(rotation, dtype=float)
    return np.array(vertices) @ rot.T + np.asarray(center, dtype=float), np.array(faces, dtype=np.int64)


def height_field(corner, size, divisions: tuple[int, int], height) -> tuple[np.ndarray, np.ndarray]:
    """An open surface z = corner_z + height(x, y) over the rectangle ``corner`` + [0, size_x] x [0, size_y] m,
    ``divisions`` (nx, ny) squares of two triangles facing up; ``height`` maps arrays x, y (m) to z offsets (m)."""
    nx, ny = divisions
    x, y = np.meshgrid(np.linspace(0.0, size[0], nx + 1), np.linspace(0.0, size[1], ny + 1), indexing="ij")
    z = np.asarray(height(x, y), dtype=float)
    vertices = np.stack([x + corner[0], y + corner[1], z + corner[2]], axis=-1).reshape(-1, 3)
    index = np.arange((nx + 1) * (ny + 1)).reshape(nx + 1, ny + 1)
    a, b, c, d = index[:-1, :-1], index[1:, :-1], index[1:, 1:], index[:-1, 1:]
    faces = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3), np.stack([a, c, d], -1).reshape(-1, 3)])
    return vertices, faces
