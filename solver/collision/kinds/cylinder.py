"""The cylinder obstacle kind: a solid round cylinder with flat ends (a post, a pipe, a drum), its axis any way.

A point p's signed distance to the cylinder of axis a -> b (unit u, length L) and radius R, with s = (p - a) . u its
place along the axis and rho its distance from the axis line, is |(max(rho - R, 0), max(-s, s - L, 0))| outside and
max(rho - R, -s, s - L) (<= 0) inside; its gradient is the unit normal. Being the signed distance of a convex solid
it is convex along a capsule's axis p(t) = p0 + t (p1 - p0), so its least value over t in [0, 1] lies between the
neighbours of the least of evenly spaced samples: measured at GRID points, then again between those neighbours,
ROUNDS times (to 1e-14 of the axis): exact outside, where the distance is smooth. Inside it is the depth of the
deepest axis point, as a closed mesh's: it pushes a capsule out, but where two faces are equally deep (or the axis
crosses the cylinder's) it has a kink and the normal is the deeper face's.

A carried box is nearest a cylinder at one of the box's edges or at one of the cylinder's rims (a linear function is
least over a cylinder on a rim): the skeleton is each rim as a polygon of RIM segments around it, so the box's rows
against them keep it at most R (1 / cos(pi / RIM) - 1) (0.5 % of R) farther away than need be.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...errors import ScenarioError
from ..closest import dot, perpendicular, unit
from ..distance import as_batch
from ..generate import axis_frame
from ..proximity import Proximity, near_only
from .base import SEGMENTS, AlongSegment, Segments, label, placement

GRID = np.linspace(0.0, 1.0, 33)  # points of the axis measured at once, then around the least of them again
ROUNDS = 12  # each shrinks the interval 16-fold: 16^-12 < 1e-14
RIM = 32  # segments of the polygon around each rim (carried box rows)


@dataclass(frozen=True, eq=False)
class Cylinder(AlongSegment):
    """The disc of ``radius`` m > 0 swept from ``a`` to ``b`` (3,) m (the middles of its flat ends, a != b)."""

    kind = "cylinder"

    def __post_init__(self) -> None:
        super().__post_init__()
        if not np.linalg.norm(self.b - self.a) > 1e-9:
            raise ScenarioError(f"{label(self)}: b: expected an end apart from a (m), got {self.b.tolist()}")
        object.__setattr__(self, "length", float(np.linalg.norm(self.b - self.a)))  # m
        object.__setattr__(self, "axis", (self.b - self.a) / self.length)  # unit, from a to b
        # a disc across the unit axis reaches R sqrt(1 - u_i^2) along world axis i
        reach = self.radius * np.sqrt(np.maximum(1.0 - self.axis**2, 0.0))
        object.__setattr__(self, "_bounds", (np.minimum(self.a, self.b) - reach, np.maximum(self.a, self.b) + reach))

    def distance(self, p0, p1, radii, margin=np.inf, memory=None) -> Proximity:
        p0, p1, radii = as_batch(p0, p1, radii)
        low, high = self.bounds()
        return near_only(p0, p1, radii, margin, low, high, lambda rows: self._exact(p0[rows], p1[rows], radii[rows]))

    def _exact(self, p0: np.ndarray, p1: np.ndarray, radii: np.ndarray) -> Proximity:
        """Every row's least signed distance along its axis (module docstring)."""
        k, step = len(p0), p1 - p0
        lo, hi = np.zeros(k), np.ones(k)
        best_t, best = np.zeros(k), np.full(k, np.inf)
        for _ in range(ROUNDS):
            t = lo[:, None] + (hi - lo)[:, None] * GRID  # (k, GRID) from lo to hi
            value = self.signed((p0[:, None] + t[..., None] * step[:, None]).reshape(-1, 3), normals=False)[0]
            j = np.argmin(value.reshape(k, -1), axis=1)
            rows = np.arange(k)
            better = value.reshape(k, -1)[rows, j] < best
            best_t, best = np.where(better, t[rows, j], best_t), np.where(better, value.reshape(k, -1)[rows, j], best)
            # convex along the axis: the least lies between the best point's neighbours
            lo, hi = t[rows, np.maximum(j - 1, 0)], t[rows, np.minimum(j + 1, len(GRID) - 1)]
        point = p0 + best_t[:, None] * step
        d, normal = self.signed(point)
        return Proximity(d - radii, best_t, point, normal, point - d[:, None] * normal)

    def signed(self, points: np.ndarray, normals: bool = True) -> tuple[np.ndarray, np.ndarray | None]:
        """(signed distance (k,) m, unit normal (k, 3): the gradient, outward, or None without ``normals``) of
        ``points`` (k, 3) m."""
        u = self.axis
        rel = points - self.a
        s = rel @ u
        radial = rel - s[:, None] * u
        rho = np.sqrt(dot(radial, radial))
        side = rho - self.radius
        below, above = -s, s - self.length
        end = np.maximum(below, above)
        out_side, out_end = np.maximum(side, 0.0), np.maximum(end, 0.0)
        outside = np.hypot(out_side, out_end)
        signed = np.where(outside > 0, outside, np.maximum(side, end))
        if not normals:
            return signed, None
        away = unit(radial, perpendicular(u))
        along = np.where((above >= below)[:, None], u, -u)
        mixed = (out_side[:, None] * away + out_end[:, None] * along) / np.maximum(outside, 1e-300)[:, None]
        normal = np.where((outside > 0)[:, None], mixed, np.where((side >= end)[:, None], away, along))
        return signed, normal

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        return self._bounds

    def skeleton(self) -> Segments:
        frame = axis_frame(self.b - self.a)
        angle = np.linspace(0.0, 2.0 * np.pi, RIM + 1)
        ring = (self.radius / np.cos(np.pi / RIM)) * (np.cos(angle)[:, None] * frame[:, 0] + np.sin(angle)[:, None]
                                                        * frame[:, 1])  # fmt: skip
        starts = np.concatenate([self.a + ring[:-1], self.b + ring[:-1]])
        ends = np.concatenate([self.a + ring[1:], self.b + ring[1:]])
        return starts, ends, np.zeros(2 * RIM)

    def placed(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        half = 0.5 * float(np.linalg.norm(self.b - self.a))
        angle = 2.0 * np.pi * np.arange(SEGMENTS) / SEGMENTS  # a corner at angle 0: the bounds are the cylinder's
        ring = self.radius * np.column_stack([np.cos(angle), np.sin(angle), np.zeros(SEGMENTS)])
        vertices = np.vstack([ring - [0.0, 0.0, half], ring + [0.0, 0.0, half], [[0.0, 0.0, -half], [0.0, 0.0, half]]])
        j, k = np.arange(SEGMENTS), (np.arange(SEGMENTS) + 1) % SEGMENTS
        bottom, top = np.full(SEGMENTS, 2 * SEGMENTS), np.full(SEGMENTS, 2 * SEGMENTS + 1)
        faces = np.vstack([np.column_stack([j, k, SEGMENTS + k]), np.column_stack([j, SEGMENTS + k, SEGMENTS + j]),
                           np.column_stack([bottom, k, j]), np.column_stack([top, SEGMENTS + j, SEGMENTS + k])])
        return vertices, faces.astype(np.int64), placement(axis_frame(self.b - self.a), 0.5 * (self.a + self.b))

    @classmethod
    def from_bounds(cls, center, rotation, size, **common) -> Cylinder:
        half = 0.5 * float(size[2])
        return cls(center - half * rotation[:, 2], center + half * rotation[:, 2], 0.5 * float(size[:2].max()),
                   **common)  # fmt: skip
