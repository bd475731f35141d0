"""The one interface every obstacle kind implements, and what all kinds share: a name, a clearance, checked geometry.

An obstacle kind is one module in this folder holding one frozen shape class, a subclass of :class:`Obstacle`,
and one line in ``kinds/__init__.py`` that registers it under the name a scenario's ``kind = "..."`` gives. The
rest of the solver asks the shape (or the registry), never its type: the clearance rows ask for its
:meth:`~Obstacle.distance`, the carried box for its :meth:`~Obstacle.bounds` and :meth:`~Obstacle.skeleton`, the
scenario files for its :attr:`~Obstacle.keys`, Blender for :meth:`~Obstacle.placed` and
:meth:`~Obstacle.from_bounds`.

Units: m, world coordinates. Construction checks the geometry and raises :class:`solver.errors.ScenarioError` with
one line naming the shape, the field and what was expected; arrays are stored as read-only float64.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from dataclasses import dataclass, field
from pathlib import Path
from typing import ClassVar

import numpy as np

from ...errors import ScenarioError, shown
from ..mesh_distance import mesh_distance
from ..mesh_index import MeshIndex, NearMemory
from ..proximity import Proximity

# What a scenario key holds (Obstacle.keys); solver/io/scenario/obstacles.py reads and writes each of these.
POINT = "point"  # 3 numbers, m
VECTOR = "vector"  # 3 numbers (sizes, a direction)
LENGTH = "length"  # a number > 0, m
ROTATION = "rotation"  # a 3x3 rotation matrix, a quaternion [w, x, y, z] in the file; optional (identity)
POINTS = "points"  # a list of [x, y, z], m
INDICES = "indices"  # a list of [i, j, k] (0-based)

SEGMENTS = 24  # around a round shape as it is shown (a sphere, a capsule)
RINGS = 6  # latitudes per half sphere

Segments = tuple[np.ndarray, np.ndarray, np.ndarray]  # starts (k, 3) m, ends (k, 3) m, radii (k,) m


def label(shape: object) -> str:
    """How an error names a shape: its type and name, e.g. "box 'shelf'"."""
    name = getattr(shape, "name", "")
    return f"{type(shape).__name__.lower()} {name!r}" if name else type(shape).__name__.lower()


def frozen_array(shape: object, key: str, value: object, dims: tuple[int, ...]) -> np.ndarray:
    """A read-only float64 copy of ``value`` with the given dimensions (-1 = any), all finite."""
    try:
        arr = np.array(value, dtype=float)
    except (TypeError, ValueError, OverflowError):  # OverflowError: an int too large for a float
        raise ScenarioError(f"{label(shape)}: {key}: expected numbers, got {shown(value)}") from None
    if arr.ndim != len(dims) or any(d != -1 and d != n for d, n in zip(dims, arr.shape, strict=True)):
        want = "x".join("N" if d == -1 else str(d) for d in dims)
        raise ScenarioError(f"{label(shape)}: {key}: expected shape {want}, got {arr.shape}")
    if not np.isfinite(arr).all():
        if arr.ndim == 2:  # a mesh's vertices: the first bad one
            row = int(np.flatnonzero(~np.isfinite(arr).all(axis=1))[0])
            raise ScenarioError(f"{label(shape)}: {key}[{row}]: expected finite numbers, got {arr[row].tolist()}")
        raise ScenarioError(f"{label(shape)}: {key}: expected finite numbers, got {arr.tolist()}")
    arr.setflags(write=False)
    return arr


def positive(shape: object, key: str, value: object, allow_zero: bool = False) -> float:
    """``value`` as a finite float > 0 (>= 0 with ``allow_zero``), m."""
    try:
        x = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError, OverflowError):
        raise ScenarioError(f"{label(shape)}: {key}: expected a number, got {value!r}") from None
    if not np.isfinite(x) or x < 0 or (x == 0 and not allow_zero):
        want = ">= 0" if allow_zero else "> 0"
        raise ScenarioError(f"{label(shape)}: {key}: expected a finite number {want} (m), got {value!r}")
    return x


def placement(rotation: np.ndarray, position: np.ndarray) -> np.ndarray:
    """The 4x4 matrix of an object at ``position`` (m) turned by ``rotation``."""
    matrix = np.eye(4)
    matrix[:3, :3], matrix[:3, 3] = rotation, position
    return matrix


@dataclass(frozen=True, eq=False)
class Obstacle(ABC):
    """A solid (or a surface) the body keeps ``clearance`` (m, >= 0) from; ``name`` names it in reports.

    A kind sets the class attributes below and implements the abstract methods; the others have defaults that fit
    a convex shape of fixed size."""

    name: str = field(default="", kw_only=True)
    clearance: float = field(default=0.0, kw_only=True)  # m

    kind: ClassVar[str]  # the scenario's ``kind = "..."``, the registry's key (Blender's shape: its upper case)
    keys: ClassVar[dict[str, str]]  # scenario keys (= constructor arguments, in order) -> what each holds (POINT...)
    description: ClassVar[str]  # one line for a user: what Blender makes of an object's bounds (:meth:`from_bounds`)
    files: ClassVar[bool] = False  # also read from ``file = "..."`` beside the scenario (:meth:`from_file`)
    # its distance to a capsule (a box) is the least over the capsule's two ends (the box's eight corners), each
    # exact and smooth (a plane): the clearance rows are one per end (per corner) instead of one per capsule (edge)
    end_rows: ClassVar[bool] = False
    nearest_edges: ClassVar[int] = 0  # no fixed skeleton: this many of its edges nearest a carried box are rows
    smooth: ClassVar[bool] = False  # shown smooth-shaded (a round shape)
    unbounded: ClassVar[bool] = False  # endless (a half-space): the object that shows it is a piece of it only

    def _check_common(self) -> None:
        if not isinstance(self.name, str):
            raise ScenarioError(f"{type(self).__name__.lower()}: name: expected a string, got {self.name!r}")
        object.__setattr__(self, "clearance", positive(self, "clearance", self.clearance, allow_zero=True))

    @abstractmethod
    def distance(self, p0: np.ndarray, p1: np.ndarray, radii: np.ndarray, margin: float = np.inf,
                 memory: NearMemory | None = None) -> Proximity:  # fmt: skip
        """Capsules p0-p1 (k, 3) m of ``radii`` (k,) m vs this shape (see :mod:`solver.collision.distance` for the
        conventions). Rows farther than ``margin`` (m) may come back +inf; ``memory`` (from :meth:`memory`) lets a
        query near the last one of the same capsules start from there. The clearance is not subtracted."""

    def memory(self, names: tuple[str, ...]) -> NearMemory | None:
        """What queries by the capsules ``names`` keep between calls (None: nothing)."""
        return None

    @classmethod
    def group(cls, shapes: list[Obstacle], names: tuple[str, ...]) -> ShapeGroup:
        """``shapes`` (all of this kind) asked about together by the capsules ``names`` at every evaluation."""
        return ShapeGroup(shapes, names)

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """The world bounding box (low, high (3,) m); +-inf where the shape is unbounded. By default that of its
        :meth:`skeleton`."""
        a, b, r = self.skeleton()
        return np.minimum(a, b).min(axis=0) - r.max(), np.maximum(a, b).max(axis=0) + r.max()

    def skeleton(self) -> Segments | None:
        """The segments, each with a radius, that the shape is swept from (a box: its 12 edges of radius 0): a carried
        box is nearest a convex shape at one of the box's edges or one of these. None: no fixed set (a mesh:
        :meth:`edges_near_box`; a plane: :attr:`end_rows`)."""
        return None

    def edges_near_box(self, centre: np.ndarray, rotation: np.ndarray, half: np.ndarray,
                       reach: float) -> Segments | None:  # fmt: skip
        """For a kind with :attr:`nearest_edges`: its edges that may be among that many nearest the box ``centre``
        (m), ``rotation`` (axes as columns), ``half`` sizes (m), within ``reach`` (m); None if none."""
        return None

    @abstractmethod
    def placed(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(vertices (V, 3) in the object's own axes, triangles (F, 3), the object's matrix (4x4)) that show the shape
        and that :meth:`from_bounds` reads back as it (a mesh: its own vertices and faces, the identity)."""

    @classmethod
    def from_bounds(cls, center: np.ndarray, rotation: np.ndarray, size: np.ndarray, **common) -> Obstacle:
        """The shape of an object whose mesh bounds have the middle ``center`` (3,) m, the edges ``size`` (3,) m along
        the columns of ``rotation`` (a proper rotation). ``common``: name, clearance."""
        raise ValueError(f"a {cls.kind} is not made from bounds")

    @classmethod
    def from_file(cls, path: Path, **common) -> Obstacle:
        """The shape in the file ``path`` (for a kind with :attr:`files`)."""
        raise ValueError(f"a {cls.kind} is not read from a file")


class ShapeGroup:
    """Obstacles of one kind that a constraint asks about at every evaluation, each with its memory of the capsules
    ``names``; a kind that answers many shapes in one query (boxes) returns its own group."""

    def __init__(self, shapes: list[Obstacle], names: tuple[str, ...]) -> None:
        self.shapes = list(shapes)
        self.memories = [shape.memory(names) for shape in self.shapes]

    def distances(self, p0: np.ndarray, p1: np.ndarray, radii: np.ndarray, margins: np.ndarray) -> list[Proximity]:
        """One :meth:`Obstacle.distance` per shape, the i-th with ``margins[i]`` (m)."""
        return [shape.distance(p0, p1, radii, margin, memory)
                for shape, margin, memory in zip(self.shapes, margins, self.memories, strict=True)]  # fmt: skip


def obstacle_distance(p0: np.ndarray, p1: np.ndarray, radii: np.ndarray, obstacle: Obstacle | MeshIndex,
                      margin: float = np.inf, memory: NearMemory | None = None) -> Proximity:  # fmt: skip
    """Capsules vs any obstacle: its :meth:`Obstacle.distance`, or a prepared mesh's (a :class:`MeshIndex`)."""
    if isinstance(obstacle, MeshIndex):
        return mesh_distance(p0, p1, radii, obstacle, margin, memory)
    if not isinstance(obstacle, Obstacle):
        raise TypeError(f"not an obstacle: {type(obstacle).__name__}")
    return obstacle.distance(p0, p1, radii, margin, memory)


@dataclass(frozen=True, eq=False)
class AlongSegment(Obstacle):
    """A kind along the segment ``a``-``b`` (3,) m with a ``radius`` m > 0 (capsule, cylinder): the fields, their
    scenario keys and checks, and what Blender makes of an object's bounds (along its local z)."""

    a: np.ndarray
    b: np.ndarray
    radius: float

    keys = {"a": POINT, "b": POINT, "radius": LENGTH}
    description = "Along the object's local z: as long as the bounds, as wide as their largest x/y"
    smooth = True

    def __post_init__(self) -> None:
        self._check_common()
        object.__setattr__(self, "a", frozen_array(self, "a", self.a, (3,)))
        object.__setattr__(self, "b", frozen_array(self, "b", self.b, (3,)))
        object.__setattr__(self, "radius", positive(self, "radius", self.radius))
