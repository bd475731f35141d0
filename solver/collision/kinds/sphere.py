"""The sphere obstacle kind: a ball."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..closest import dot, perpendicular, point_segment, unit
from ..distance import as_batch
from ..generate import capsule_mesh
from ..proximity import Proximity
from .base import LENGTH, POINT, RINGS, SEGMENTS, Obstacle, Segments, frozen_array, placement, positive


@dataclass(frozen=True, eq=False)
class Sphere(Obstacle):
    """A ball: ``center`` (3,) m, ``radius`` m > 0."""

    center: np.ndarray
    radius: float

    kind = "sphere"
    keys = {"center": POINT, "radius": LENGTH}
    description = "A ball at the middle of the mesh's bounds, as wide as their largest dimension"
    smooth = True

    def __post_init__(self) -> None:
        self._check_common()
        object.__setattr__(self, "center", frozen_array(self, "center", self.center, (3,)))
        object.__setattr__(self, "radius", positive(self, "radius", self.radius))

    def distance(self, p0, p1, radii, margin=np.inf, memory=None) -> Proximity:
        return sphere_distance(p0, p1, radii, self)

    def skeleton(self) -> Segments:
        return self.center[None], self.center[None], np.array([self.radius])

    def placed(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        vertices, faces = capsule_mesh(np.zeros(3), np.zeros(3), self.radius, SEGMENTS, RINGS)
        return vertices, faces, placement(np.eye(3), self.center)

    @classmethod
    def from_bounds(cls, center, rotation, size, **common) -> Sphere:
        return cls(center, 0.5 * float(size.max()), **common)


def sphere_distance(p0: np.ndarray, p1: np.ndarray, radii: np.ndarray, sphere: Sphere) -> Proximity:
    """Capsules vs a sphere: the axis point nearest the center."""
    p0, p1, radii = as_batch(p0, p1, radii)
    t, w = point_segment(sphere.center, p0, p1)
    n = unit(w - sphere.center, perpendicular(p1 - p0))
    axis = np.sqrt(dot(w - sphere.center, w - sphere.center)) - sphere.radius
    return Proximity(axis - radii, t, w, n, sphere.center + sphere.radius * n)
