"""The box obstacle kind: an oriented box, and capsules vs many boxes in one query (:mod:`solver.collision.boxes`)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np

from ... import kernels
from ...errors import ScenarioError
from ...kernels.clearance_boxes import boxes_near_rows
from ..boxes import box_edges, box_rows, box_rows_one
from ..distance import as_batch
from ..generate import box_mesh
from ..proximity import Proximity, near_only_many
from .base import POINT, ROTATION, VECTOR, Obstacle, Segments, ShapeGroup, frozen_array, label, placement

ROTATION_TOLERANCE = 1e-6


@dataclass(frozen=True, eq=False)
class Box(Obstacle):
    """An oriented box: ``center`` (3,) m, ``size`` (3,) full edge lengths m > 0 along the columns of
    ``rotation`` (3x3, a proper rotation: world = rotation @ local + center)."""

    center: np.ndarray
    size: np.ndarray
    rotation: np.ndarray = field(default_factory=lambda: np.eye(3))

    kind = "box"
    keys = {"center": POINT, "size": VECTOR, "rotation": ROTATION}
    description = "The mesh's bounds in the object's own axes"

    def __post_init__(self) -> None:
        self._check_common()
        object.__setattr__(self, "center", frozen_array(self, "center", self.center, (3,)))
        size = frozen_array(self, "size", self.size, (3,))
        if (size <= 0).any():
            raise ScenarioError(f"{label(self)}: size: expected 3 edge lengths > 0 (m), got {size.tolist()}")
        object.__setattr__(self, "size", size)
        rot = frozen_array(self, "rotation", self.rotation, (3, 3))
        if not np.allclose(rot.T @ rot, np.eye(3), atol=ROTATION_TOLERANCE) or np.linalg.det(rot) < 0:
            raise ScenarioError(f"{label(self)}: rotation: expected a proper rotation matrix, got {rot.tolist()}")
        object.__setattr__(self, "rotation", rot)
        object.__setattr__(self, "_stacked", box_set([self]))

    @property
    def half(self) -> np.ndarray:
        """Half edge lengths (3,), m."""
        return 0.5 * self.size

    def distance(self, p0, p1, radii, margin=np.inf, memory=None) -> Proximity:
        # only the capsules near the box: most of a scene's boxes are far from most parts
        return boxes_distance(*as_batch(p0, p1, radii), self._stacked, margin)[0]

    @classmethod
    def group(cls, shapes: list[Obstacle], names: tuple[str, ...]) -> ShapeGroup:
        return BoxGroup(shapes, names)

    def skeleton(self) -> Segments:
        return (*box_edges(self.center, self.rotation, self.half), np.zeros(12))

    def placed(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        vertices, faces = box_mesh(np.zeros(3), self.size)
        return vertices, faces, placement(self.rotation, self.center)

    @classmethod
    def from_bounds(cls, center, rotation, size, **common) -> Box:
        return cls(center, size, rotation, **common)


class BoxGroup(ShapeGroup):
    """A constraint's boxes, stacked once and answered by one query per evaluation."""

    def __init__(self, shapes: list[Box], names: tuple[str, ...]) -> None:
        super().__init__(shapes, names)
        self.stacked = box_set(self.shapes)
        center, _, _, extent = self.stacked
        self._bounds = (center - extent, center + extent)  # the boxes' world bounds (m), asked at every evaluation

    def distances(self, p0, p1, radii, margins) -> list[Proximity]:
        return boxes_distance(p0, p1, radii, self.stacked, margins)

    def flat_rows(self, p0, p1, radii, margins, far) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(distance (m k,) m, point (m k, 3) m, normal (m k, 3)) of capsules p0-p1 (k, 3) vs the m boxes, box by
        box, as :meth:`distances` gives them but ``far[i]`` (m) where box i's distance is not finite (by the kernels:
        one loop, no per-box arrays)."""
        got = _compiled_distances(p0, p1, radii, self.stacked, margins, np.asarray(far, dtype=float), True,
                                  self._bounds)  # fmt: skip
        return got.distance.reshape(-1), got.point.reshape(-1, 3), got.normal.reshape(-1, 3)


def box_distance(p0: np.ndarray, p1: np.ndarray, radii: np.ndarray, box: Box) -> Proximity:
    """Capsules (k rows) vs one oriented box, exact for every row."""
    return box_rows_one(p0, p1, radii, box.center, box.rotation, box.half)


class BoxSet(NamedTuple):
    """m boxes stacked for one query: ``center`` (m, 3) m, ``rotation`` (m, 3, 3), ``half`` sizes (m, 3) m and
    ``extent`` (m, 3) m, the half sizes of their world bounding boxes."""

    center: np.ndarray
    rotation: np.ndarray
    half: np.ndarray
    extent: np.ndarray


def box_set(boxes: list[Box]) -> BoxSet:
    """``boxes`` stacked once (a constraint asks about the same boxes at every evaluation)."""
    m = len(boxes)
    rotation = np.array([b.rotation for b in boxes]).reshape(m, 3, 3)
    half = np.array([b.half for b in boxes]).reshape(m, 3)
    center = np.array([b.center for b in boxes]).reshape(m, 3)
    return BoxSet(center, rotation, half, np.einsum("mij,mj->mi", np.abs(rotation), half))


def boxes_distance(p0: np.ndarray, p1: np.ndarray, radii: np.ndarray, boxes: BoxSet, margins) -> list[Proximity]:
    """Capsules (k rows) vs each of ``boxes``, one Proximity per box: exact for the capsules whose bounding box,
    grown by radius + the box's margin (``margins``, m, one per box), meets the box's, +inf beyond it (see
    :func:`~solver.collision.proximity.near_only_many`)."""
    center, rotation, half, extent = boxes
    margins = np.broadcast_to(np.asarray(margins, dtype=float), (len(center),))
    if kernels.active():
        got = _compiled_distances(p0, p1, radii, boxes, margins, np.full(len(center), np.inf), False)
        return [Proximity(*(field[i] for field in got)) for i in range(len(center))]

    def exact(box: np.ndarray, cap: np.ndarray) -> Proximity:
        return box_rows(p0[cap], p1[cap], radii[cap], center[box], rotation[box], half[box])

    return near_only_many(p0, p1, radii, margins, center - extent, center + extent, exact)


def _compiled_distances(p0, p1, radii, boxes: BoxSet, margins, far: np.ndarray, finite: bool,
                        bounds: tuple[np.ndarray, np.ndarray] | None = None) -> Proximity:  # fmt: skip
    """:func:`boxes_distance` by the kernels, as one Proximity of (m, k) fields (``far``, ``finite``: as
    :func:`~solver.kernels.clearance_boxes.boxes_near_rows`); rows whose axis meets or touches a box by
    :func:`box_rows`. ``bounds``: the boxes' (center - extent, center + extent), when the caller keeps them."""
    center, rotation, half, extent = boxes
    low, high = (center - extent, center + extent) if bounds is None else bounds
    # writable C arrays: one compiled version of the kernel (a read-only argument is another type to Numba)
    p0, p1, radii, margins = (x if x.flags.writeable else x.copy() for x in (
        np.ascontiguousarray(x, dtype=float) for x in (p0, p1, radii, margins)))  # fmt: skip
    m, k = len(center), len(p0)
    distance, t, rare = np.empty(m * k), np.empty(m * k), np.empty(m * k, dtype=np.int64)
    point, normal, closest = np.empty((m * k, 3)), np.empty((m * k, 3)), np.empty((m * k, 3))
    if boxes_near_rows(p0, p1, radii, margins, low, high, center, rotation, half, far, finite, distance, t, point,
                       normal, closest, rare):  # fmt: skip
        rows = np.flatnonzero(rare)
        box, cap = np.divmod(rows, k)
        got = box_rows(p0[cap], p1[cap], radii[cap], center[box], rotation[box], half[box])
        keep = got.distance <= margins[box]
        for mine, theirs in zip((distance, t, point, normal, closest), got, strict=True):
            mine[rows[keep]] = theirs[keep]
        if finite:
            distance[rows] = np.where(np.isfinite(distance[rows]), distance[rows], far[box])
    return Proximity(distance.reshape(m, k), t.reshape(m, k), point.reshape(m, k, 3), normal.reshape(m, k, 3),
                     closest.reshape(m, k, 3))  # fmt: skip
