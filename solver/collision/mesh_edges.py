"""A mesh's edges, each once, with a uniform grid over their bounds: which edges come near a box (m).

The carried box measures a mesh's own edges against itself (:mod:`solver.constraints.carried_obstacles`): a mesh
corner poking into the middle of one of its faces touches none of its edges. Built once per mesh, kept with its
:class:`~solver.collision.mesh_index.MeshIndex` (:meth:`~solver.collision.mesh_index.MeshIndex.edges`).
"""

from __future__ import annotations

import numpy as np

from .grid import UniformGrid


class MeshEdges:
    """The unique edges of triangles ``faces`` (F, 3) over ``vertices`` (V, 3) m: ``start``, ``end`` (E, 3) m, and a
    grid over their bounding boxes."""

    def __init__(self, vertices: np.ndarray, faces: np.ndarray) -> None:
        pairs = np.sort(np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]]), axis=1)
        pairs = np.unique(pairs, axis=0)  # an edge shared by two faces once
        self.start, self.end = vertices[pairs[:, 0]], vertices[pairs[:, 1]]
        self.grid = UniformGrid(np.minimum(self.start, self.end), np.maximum(self.start, self.end))

    def __len__(self) -> int:
        return len(self.start)

    def meeting(self, low: np.ndarray, high: np.ndarray) -> np.ndarray:
        """Indices (ascending) of the edges whose bounding boxes meet the world box ``low``..``high`` (3,) m."""
        return np.sort(self.grid.overlapping(low[None], high[None])[1])
