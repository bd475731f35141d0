"""Generated triangle meshes (m): a subdivided closed box, a closed capsule (a sphere when its ends meet) and an
open height-field patch, for presets, tests, benchmarks and the obstacles Blender recreates from a scenario."""

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


def axis_frame(direction) -> np.ndarray:
    """A proper rotation (3x3) whose third column is ``direction`` made unit length (the identity for a zero one)."""
    d = np.asarray(direction, dtype=float)
    length = np.linalg.norm(d)
    if length < 1e-12:
        return np.eye(3)
    z = d / length
    x = np.cross((0.0, 1.0, 0.0) if abs(z[1]) < 0.9 else (1.0, 0.0, 0.0), z)
    x /= np.linalg.norm(x)
    return np.column_stack([x, np.cross(z, x), z])


def capsule_mesh(a, b, radius: float, segments: int = 16, rings: int = 4) -> tuple[np.ndarray, np.ndarray]:
    """A closed capsule around the segment ``a``-``b`` (3,) m of ``radius`` m, counter-clockwise seen from outside:
    ``segments`` around, ``rings`` latitudes per half sphere (a == b gives a UV sphere). Its corners lie on the
    surface: poles on the axis, a vertex at local angle 0 on each ring (so its bounding box is the capsule's)."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    half = 0.5 * float(np.linalg.norm(b - a))
    phi = np.linspace(0.0, 0.5 * np.pi, rings + 1)[1:]  # from the pole down to the equator
    bottom = phi[::-1] if half > 0 else phi[-2::-1]  # a sphere has one equator, not two on top of each other
    levels = [(half + radius * np.cos(p), radius * np.sin(p)) for p in phi]
    levels += [(-half - radius * np.cos(p), radius * np.sin(p)) for p in bottom]
    theta = np.linspace(0.0, 2.0 * np.pi, segments, endpoint=False)
    circles = [np.column_stack([rho * np.cos(theta), rho * np.sin(theta), np.full(segments, z)]) for z, rho in levels]
    vertices = np.vstack([[0.0, 0.0, half + radius], *circles, [0.0, 0.0, -half - radius]])
    j = np.arange(segments)
    k = (j + 1) % segments
    faces = [np.column_stack([np.zeros(segments, int), 1 + j, 1 + k])]
    for i in range(len(levels) - 1):
        top, low = 1 + i * segments, 1 + (i + 1) * segments
        faces += [np.column_stack([top + j, low + j, low + k]), np.column_stack([top + j, low + k, top + k])]
    last, pole = 1 + (len(levels) - 1) * segments, len(vertices) - 1
    faces.append(np.column_stack([np.full(segments, pole), last + k, last + j]))
    return vertices @ axis_frame(b - a).T + 0.5 * (a + b), np.vstack(faces).astype(np.int64)
