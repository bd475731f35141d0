"""The capsule obstacle kind: a segment swept by a ball (a pole, a rail, a pipe with round ends)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..closest import dot
from ..distance import as_batch, closest_on_axes
from ..generate import axis_frame, capsule_mesh
from ..proximity import Proximity
from .base import RINGS, SEGMENTS, AlongSegment, Segments, placement


@dataclass(frozen=True, eq=False)
class Capsule(AlongSegment):
    """The segment ``a``-``b`` (3,) m swept by a ball of ``radius`` m > 0 (a == b gives a sphere)."""

    kind = "capsule"

    def distance(self, p0, p1, radii, margin=np.inf, memory=None) -> Proximity:
        return capsule_distance(p0, p1, radii, self)

    def skeleton(self) -> Segments:
        return self.a[None], self.b[None], np.array([self.radius])

    def placed(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        half = 0.5 * float(np.linalg.norm(self.b - self.a))
        vertices, faces = capsule_mesh((0.0, 0.0, -half), (0.0, 0.0, half), self.radius, SEGMENTS, RINGS)
        return vertices, faces, placement(axis_frame(self.b - self.a), 0.5 * (self.a + self.b))

    @classmethod
    def from_bounds(cls, center, rotation, size, **common) -> Capsule:
        radius = 0.5 * float(size[:2].max())
        half = max(0.5 * float(size[2]) - radius, 0.0)
        return cls(center - half * rotation[:, 2], center + half * rotation[:, 2], radius, **common)


def capsule_distance(p0: np.ndarray, p1: np.ndarray, radii: np.ndarray, capsule: Capsule) -> Proximity:
    """Capsules vs a capsule obstacle: closest points of the two axes (parallel axes included)."""
    p0, p1, radii = as_batch(p0, p1, radii)
    q0, q1 = np.broadcast_to(capsule.a, p0.shape), np.broadcast_to(capsule.b, p0.shape)
    s, w, _, q, n = closest_on_axes(p0, p1, q0, q1)
    axis = np.sqrt(dot(w - q, w - q)) - capsule.radius
    return Proximity(axis - radii, s, w, n, q + capsule.radius * n)
