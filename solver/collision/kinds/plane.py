"""The plane obstacle kind: a half-space (a floor, a wall), solid on one side of a plane."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ... import kernels
from ...errors import ScenarioError
from ...kernels.clearance import plane_distance
from ..distance import as_batch
from ..generate import axis_frame
from ..proximity import Proximity
from .base import POINT, VECTOR, Obstacle, frozen_array, label, placement

PLANE_SIZE = 4.0  # m: the edge of the square that shows a plane (a half-space has no edges)


@dataclass(frozen=True, eq=False)
class HalfSpace(Obstacle):
    """A plane through ``point`` whose solid side is against ``normal``: free space is (p - point) . n >= 0.
    The normal is stored unit length."""

    point: np.ndarray
    normal: np.ndarray

    kind = "plane"
    keys = {"point": POINT, "normal": VECTOR}
    description = "A half-space through the middle of the bounds, solid below the object's local z"
    end_rows = True  # a capsule's (a box's) lowest point is one of its ends (corners)
    unbounded = True  # its object is a PLANE_SIZE square

    def __post_init__(self) -> None:
        self._check_common()
        object.__setattr__(self, "point", frozen_array(self, "point", self.point, (3,)))
        normal = np.array(frozen_array(self, "normal", self.normal, (3,)))
        length = np.linalg.norm(normal)
        if length < 1e-12:
            raise ScenarioError(f"{label(self)}: normal: expected a non-zero vector, got {normal.tolist()}")
        normal /= length
        normal.setflags(write=False)
        object.__setattr__(self, "normal", normal)

    def distance(self, p0, p1, radii, margin=np.inf, memory=None) -> Proximity:
        return halfspace_distance(p0, p1, radii, self)

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """Unbounded, but along an axis the normal points along (a floor: below its height)."""
        low, high = np.full(3, -np.inf), np.full(3, np.inf)
        axis = np.flatnonzero(self.normal)
        if len(axis) == 1:
            i = int(axis[0])
            (high if self.normal[i] > 0 else low)[i] = self.point[i]
        return low, high

    def placed(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        corners = 0.5 * PLANE_SIZE * np.array([[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [1.0, 1.0, 0.0], [-1.0, 1.0, 0.0]])
        faces = np.array([[0, 1, 2], [0, 2, 3]], dtype=np.int64)  # counter-clockwise seen from the free side
        return corners, faces, placement(axis_frame(self.normal), self.point)

    @classmethod
    def from_bounds(cls, center, rotation, size, **common) -> HalfSpace:
        return cls(center, rotation[:, 2], **common)


def halfspace_distance(p0: np.ndarray, p1: np.ndarray, radii: np.ndarray, plane: HalfSpace) -> Proximity:
    """Capsules vs a half-space: the lower end along the normal (p0 on a tie). Rows of points (p1 is p0: a capsule's
    ends, a box's corners) are measured once."""
    same = p1 is p0
    if kernels.active():  # one loop: the NumPy code below is ~15 calls on a few rows (a box's 8 corners)
        p0 = np.ascontiguousarray(np.atleast_2d(p0), dtype=float)
        p1 = p0 if same else np.ascontiguousarray(np.atleast_2d(p1), dtype=float)
        k = len(p0)
        out = Proximity(np.empty(k), np.empty(k), np.empty((k, 3)), np.empty((k, 3)), np.empty((k, 3)))
        plane_distance(p0, p1, np.atleast_1d(np.asarray(radii, dtype=float)), plane.point, plane.normal, *out)
        return out
    p0, p1, radii = as_batch(p0, p1, radii)
    h0 = (p0 - plane.point) @ plane.normal
    h1 = h0 if same else (p1 - plane.point) @ plane.normal
    lower = h1 < h0
    w = np.where(lower[:, None], p1, p0)
    h = np.where(lower, h1, h0)
    n = np.broadcast_to(plane.normal, p0.shape).copy()
    return Proximity(h - radii, lower.astype(float), w, n, w - h[:, None] * n)
