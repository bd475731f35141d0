"""Obstacle shapes in world coordinates (m): sphere, capsule, box, half-space and triangle mesh.

Every shape is a frozen value with a ``name`` and a ``clearance`` (m, >= 0: the distance the body keeps from it).
Construction validates the geometry and raises :class:`solver.errors.ScenarioError` with one line naming the
shape, the field and what was expected. Arrays are stored as read-only float64 (int64 for mesh faces).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import ScenarioError, shown

# A triangle whose doubled area is below this fraction of its longest edge squared has collinear corners.
DEGENERATE_RATIO = 1e-10
ROTATION_TOLERANCE = 1e-6


def _label(shape: object) -> str:
    name = getattr(shape, "name", "")
    return f"{type(shape).__name__.lower()} {name!r}" if name else type(shape).__name__.lower()


def _frozen_array(shape: object, key: str, value: object, dims: tuple[int, ...]) -> np.ndarray:
    """A read-only float64 copy of ``value`` with the given dimensions (-1 = any), all finite."""
    try:
        arr = np.array(value, dtype=float)
    except (TypeError, ValueError):
        raise ScenarioError(f"{_label(shape)}: {key}: expected numbers, got {shown(value)}") from None
    if arr.ndim != len(dims) or any(d != -1 and d != n for d, n in zip(dims, arr.shape, strict=True)):
        want = "x".join("N" if d == -1 else str(d) for d in dims)
        raise ScenarioError(f"{_label(shape)}: {key}: expected shape {want}, got {arr.shape}")
    if not np.isfinite(arr).all():
        if arr.ndim == 2:  # a mesh's vertices: the first bad one
            row = int(np.flatnonzero(~np.isfinite(arr).all(axis=1))[0])
            raise ScenarioError(f"{_label(shape)}: {key}[{row}]: expected finite numbers, got {arr[row].tolist()}")
        raise ScenarioError(f"{_label(shape)}: {key}: expected finite numbers, got {arr.tolist()}")
    arr.setflags(write=False)
    return arr


def _positive(shape: object, key: str, value: object, allow_zero: bool = False) -> float:
    try:
        x = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise ScenarioError(f"{_label(shape)}: {key}: expected a number, got {value!r}") from None
    if not np.isfinite(x) or x < 0 or (x == 0 and not allow_zero):
        want = ">= 0" if allow_zero else "> 0"
        raise ScenarioError(f"{_label(shape)}: {key}: expected a finite number {want} (m), got {value!r}")
    return x


@dataclass(frozen=True, eq=False)
class _Obstacle:
    name: str = field(default="", kw_only=True)
    clearance: float = field(default=0.0, kw_only=True)  # m

    def _check_common(self) -> None:
        if not isinstance(self.name, str):
            raise ScenarioError(f"{type(self).__name__.lower()}: name: expected a string, got {self.name!r}")
        object.__setattr__(self, "clearance", _positive(self, "clearance", self.clearance, allow_zero=True))


@dataclass(frozen=True, eq=False)
class Sphere(_Obstacle):
    """A ball: ``center`` (3,) m, ``radius`` m > 0."""

    center: np.ndarray
    radius: float

    def __post_init__(self) -> None:
        self._check_common()
        object.__setattr__(self, "center", _frozen_array(self, "center", self.center, (3,)))
        object.__setattr__(self, "radius", _positive(self, "radius", self.radius))


@dataclass(frozen=True, eq=False)
class Capsule(_Obstacle):
    """The segment ``a``-``b`` (3,) m swept by a ball of ``radius`` m > 0 (a == b gives a sphere)."""

    a: np.ndarray
    b: np.ndarray
    radius: float

    def __post_init__(self) -> None:
        self._check_common()
        object.__setattr__(self, "a", _frozen_array(self, "a", self.a, (3,)))
        object.__setattr__(self, "b", _frozen_array(self, "b", self.b, (3,)))
        object.__setattr__(self, "radius", _positive(self, "radius", self.radius))


@dataclass(frozen=True, eq=False)
class Box(_Obstacle):
    """An oriented box: ``center`` (3,) m, ``size`` (3,) full edge lengths m > 0 along the columns of
    ``rotation`` (3x3, a proper rotation: world = rotation @ local + center)."""

    center: np.ndarray
    size: np.ndarray
    rotation: np.ndarray = field(default_factory=lambda: np.eye(3))

    def __post_init__(self) -> None:
        self._check_common()
        object.__setattr__(self, "center", _frozen_array(self, "center", self.center, (3,)))
        size = _frozen_array(self, "size", self.size, (3,))
        if (size <= 0).any():
            raise ScenarioError(f"{_label(self)}: size: expected 3 edge lengths > 0 (m), got {size.tolist()}")
        object.__setattr__(self, "size", size)
        rot = _frozen_array(self, "rotation", self.rotation, (3, 3))
        if not np.allclose(rot.T @ rot, np.eye(3), atol=ROTATION_TOLERANCE) or np.linalg.det(rot) < 0:
            raise ScenarioError(f"{_label(self)}: rotation: expected a proper rotation matrix, got {rot.tolist()}")
        object.__setattr__(self, "rotation", rot)

    @property
    def half(self) -> np.ndarray:
        """Half edge lengths (3,), m."""
        return 0.5 * self.size


@dataclass(frozen=True, eq=False)
class HalfSpace(_Obstacle):
    """A plane through ``point`` whose solid side is against ``normal``: free space is (p - point) . n >= 0.
    The normal is stored unit length."""

    point: np.ndarray
    normal: np.ndarray

    def __post_init__(self) -> None:
        self._check_common()
        object.__setattr__(self, "point", _frozen_array(self, "point", self.point, (3,)))
        normal = np.array(_frozen_array(self, "normal", self.normal, (3,)))
        length = np.linalg.norm(normal)
        if length < 1e-12:
            raise ScenarioError(f"{_label(self)}: normal: expected a non-zero vector, got {normal.tolist()}")
        normal /= length
        normal.setflags(write=False)
        object.__setattr__(self, "normal", normal)


def degenerate_faces(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Mask (F,) of triangles with a repeated corner or (nearly) collinear corners."""
    tri = vertices[faces]
    edges = tri[:, [1, 2, 0]] - tri
    longest = np.max(np.einsum("fij,fij->fi", edges, edges), axis=1)
    doubled_area = np.linalg.norm(np.cross(edges[:, 0], -edges[:, 2]), axis=1)
    repeated = (faces[:, 0] == faces[:, 1]) | (faces[:, 1] == faces[:, 2]) | (faces[:, 2] == faces[:, 0])
    return repeated | (doubled_area <= DEGENERATE_RATIO * longest) | (longest == 0)


@dataclass(frozen=True, eq=False)
class Mesh(_Obstacle):
    """Triangles: ``vertices`` (V, 3) m and ``faces`` (F, 3) vertex indices, counter-clockwise seen from outside
    for a closed mesh. Validated: finite, indices in range, no degenerate triangle, at least one face."""

    vertices: np.ndarray
    faces: np.ndarray

    def __post_init__(self) -> None:
        self._check_common()
        vertices = _frozen_array(self, "vertices", self.vertices, (-1, 3))
        try:
            raw = np.asarray(self.faces)
            faces = raw.astype(np.int64)
        except (TypeError, ValueError):
            raise ScenarioError(f"{_label(self)}: faces: expected integer vertex indices") from None
        if faces.ndim != 2 or faces.shape[1] != 3 or len(faces) == 0:
            raise ScenarioError(f"{_label(self)}: faces: expected shape Nx3 with N >= 1, got {faces.shape}")
        if raw.dtype.kind == "f" and not np.array_equal(faces, raw):
            raise ScenarioError(f"{_label(self)}: faces: expected integer vertex indices, got fractions")
        bad = np.flatnonzero(((faces < 0) | (faces >= len(vertices))).any(axis=1))
        if bad.size:
            raise ScenarioError(
                f"{_label(self)}: faces[{bad[0]}]: vertex index out of range 0..{len(vertices) - 1}: "
                f"{faces[bad[0]].tolist()}"
            )
        flat = np.flatnonzero(degenerate_faces(vertices, faces))
        if flat.size:
            raise ScenarioError(
                f"{_label(self)}: faces[{flat[0]}]: degenerate triangle (zero area), {flat.size} such face(s)"
            )
        faces.setflags(write=False)
        object.__setattr__(self, "vertices", vertices)
        object.__setattr__(self, "faces", faces)

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


Obstacle = Sphere | Capsule | Box | HalfSpace | Mesh
