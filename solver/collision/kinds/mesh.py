"""The mesh obstacle kind: triangles (a closed mesh is a solid, an open one a surface), from a scenario's numbers or
a mesh file, queried through its index (:mod:`solver.collision.mesh_index`, :mod:`solver.collision.mesh_distance`).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...errors import ScenarioError
from ..mesh_distance import mesh_distance
from ..mesh_files import mesh_arrays
from ..mesh_index import MeshIndex, NearMemory, index_of
from ..proximity import Proximity
from ..triangle_frames import degenerate_faces
from .base import INDICES, POINTS, Obstacle, Segments, frozen_array, label


@dataclass(frozen=True, eq=False)
class Mesh(Obstacle):
    """Triangles: ``vertices`` (V, 3) m and ``faces`` (F, 3) vertex indices, counter-clockwise seen from outside
    for a closed mesh. Validated: finite, indices in range, no degenerate triangle, at least one face."""

    vertices: np.ndarray
    faces: np.ndarray

    kind = "mesh"
    keys = {"vertices": POINTS, "faces": INDICES}
    description = "The mesh itself (any shape; a closed mesh is solid)"
    files = True
    # a mesh corner poking into a carried box brings its fan of edges (about 6 in a regular triangulation), all at its
    # depth: 8 rows hold it and the next nearest edges; the rows are re-chosen at every evaluation
    nearest_edges = 8

    def __post_init__(self) -> None:
        self._check_common()
        vertices = frozen_array(self, "vertices", self.vertices, (-1, 3))
        try:
            raw = np.asarray(self.faces)
            faces = raw.astype(np.int64)
        except (TypeError, ValueError):
            raise ScenarioError(f"{label(self)}: faces: expected integer vertex indices") from None
        if faces.ndim != 2 or faces.shape[1] != 3 or len(faces) == 0:
            raise ScenarioError(f"{label(self)}: faces: expected shape Nx3 with N >= 1, got {faces.shape}")
        if raw.dtype.kind == "f" and not np.array_equal(faces, raw):
            raise ScenarioError(f"{label(self)}: faces: expected integer vertex indices, got fractions")
        bad = np.flatnonzero(((faces < 0) | (faces >= len(vertices))).any(axis=1))
        if bad.size:
            raise ScenarioError(
                f"{label(self)}: faces[{bad[0]}]: vertex index out of range 0..{len(vertices) - 1}: "
                f"{faces[bad[0]].tolist()}"
            )
        flat = np.flatnonzero(degenerate_faces(vertices, faces))
        if flat.size:
            raise ScenarioError(
                f"{label(self)}: faces[{flat[0]}]: degenerate triangle (zero area), {flat.size} such face(s)"
            )
        faces.setflags(write=False)
        object.__setattr__(self, "vertices", vertices)
        object.__setattr__(self, "faces", faces)
        object.__setattr__(self, "_index", None)

    def __getstate__(self) -> dict:
        return {**self.__dict__, "_index": None}  # a copy sent to another process indexes itself there

    def is_closed(self) -> bool:
        """True when every edge is shared by exactly two faces that traverse it in opposite directions (a
        consistently oriented, watertight surface)."""
        f = self.faces
        n = np.int64(len(self.vertices))
        directed = np.concatenate([f[:, 0] * n + f[:, 1], f[:, 1] * n + f[:, 2], f[:, 2] * n + f[:, 0]])
        reverse = np.concatenate([f[:, 1] * n + f[:, 0], f[:, 2] * n + f[:, 1], f[:, 0] * n + f[:, 2]])
        unique = np.unique(directed)
        if len(unique) != len(directed):
            return False  # an edge traversed twice in the same direction (or shared by > 2 faces)
        return bool(np.isin(reverse, unique, assume_unique=False).all())

    def signed_volume(self) -> float:
        """Enclosed volume, m^3: positive when the faces are counter-clockwise seen from outside (closed meshes)."""
        tri = self.vertices[self.faces] - self.vertices.mean(axis=0)
        return float(np.einsum("fi,fi->", tri[:, 0], np.cross(tri[:, 1], tri[:, 2])) / 6.0)

    def index(self) -> MeshIndex:
        """The mesh's query index, built on first use (shared by every mesh of the same triangles)."""
        if self._index is None:
            object.__setattr__(self, "_index", index_of(self))
        return self._index

    def distance(self, p0, p1, radii, margin=np.inf, memory=None) -> Proximity:
        return mesh_distance(p0, p1, radii, self.index(), margin, memory)

    def memory(self, names: tuple[str, ...]) -> NearMemory:
        return self.index().memory(names)

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        return self.vertices.min(axis=0), self.vertices.max(axis=0)

    def edges_near_box(self, centre, rotation, half, reach) -> Segments | None:
        edges = self.index().edges()
        near = edges.near_box(centre, rotation, half, reach, self.nearest_edges)
        return (edges.start[near], edges.end[near], np.zeros(len(near))) if near.size else None

    def placed(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        return np.array(self.vertices), np.array(self.faces), np.eye(4)

    @classmethod
    def from_file(cls, path: Path, **common) -> Mesh:
        return read_mesh(path, **common)


def read_mesh(path: str | Path, name: str = "", clearance: float = 0.0) -> Mesh:
    """A validated :class:`Mesh` from an .obj, .stl or .ply file (m)."""
    path = Path(path)
    vertices, faces = mesh_arrays(path)
    try:
        return Mesh(vertices, faces, name=name or path.stem, clearance=clearance)
    except ScenarioError as exc:
        raise ScenarioError(f"{path}: {exc}") from None
