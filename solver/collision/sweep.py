"""Swept motion of the body's capsules between two poses (continuous collision, pure NumPy).

Between two solved frames Blender plays joint values interpolated linearly (the baked keys are linear), so the
path is theta(s) = theta_a + s dtheta, s in [0, 1]. Along it every axis point p of capsule k moves at a speed
|dp/ds| <= L_k = sum_j |dtheta_j| w_kj: w_kj = 1 for a slide, and for a rotation a bound on the distance of any of
the capsule's axis points from joint j's pivot (the lengths of the links between them plus the farther capsule
end's offset; valid in every pose). Differentiating once more, |d2p/ds2| <= 3 W_k L_k with W_k = sum |dtheta_j| over
the rotations above the capsule, so the speed is also at most the longer end chord |p(1) - p(0)| + 1.5 W_k L_k
(tight for the small steps of a long motion, where W_k is small). The bound M_k is the smaller of the two; over a
piece of the way of length h (in s) it is the piece's chord + 1.5 h^2 W_k L_k, or h L_k.

Every axis point moving at most M_k |s - s'|, the capsule's signed distance D to a convex obstacle (the floor, a
box, a sphere, a capsule) changes by at most as much, so between two samples min D >= (D(s0) + D(s1) - M) / 2
(for a mesh the same holds wherever D >= 0). :meth:`SweptBody.check` certifies a pair from the two frames alone
when M_k <= D_a + D_b + 2 tol (no sub-sampling), else bisects the uncertain pieces, querying all of them at once
per round, until every piece is certified, a sample is deeper than ``tolerance`` (a crossing), or a piece's path
is at most 2 tol long. So a way reported clear has no point deeper than 2 tol, and a capsule that passes through
an obstacle of any thickness (its axis reaching the surface: depth >= radius > 2 tol) is always reported.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from typing import NamedTuple

import numpy as np

from ..model import Model
from .body import BodyCapsules, capsules_of
from .distance import obstacle_distance
from .mesh_index import MeshIndex, index_of
from .shapes import Mesh, Obstacle

TOLERANCE = 1e-3  # m: a sample this deep (or less) into an obstacle is not a crossing
FAR = 1e3  # m: stands in for an unbounded slide's travel in the path weights


@dataclass(frozen=True)
class Crossing:
    """Capsule ``part`` inside ``obstacle`` between the two poses: ``depth`` m (> tolerance) at the fraction ``s``
    of the way (the deepest sample found)."""

    part: str
    obstacle: str
    s: float
    depth: float


class Pose(NamedTuple):
    """Joint values ``theta`` (n,) and the capsules' world end points ``p0``, ``p1`` (k, 3) m there."""

    theta: np.ndarray
    p0: np.ndarray
    p1: np.ndarray


class SweepReport(NamedTuple):
    """What :meth:`SweptBody.check` found on the way to pose ``b`` (None if not computed): the ``crossings``, the
    number of in-between ``samples`` (capsule-obstacle queries; 0 when the two ends alone certify the way) and of
    in-between ``poses`` (forward kinematics)."""

    b: Pose | None
    crossings: list[Crossing]
    samples: int
    poses: int


def path_weights(model: Model, capsules: BodyCapsules) -> np.ndarray:
    """(k, n) w_kj: the speed of capsule k's axis points per unit speed of joint j (m/rad, 1 for a slide, 0 when j
    does not move the capsule); see the module docstring."""
    out = np.zeros((len(capsules), model.n))
    offset = np.linalg.norm(model.origin_position, axis=1)
    travel = np.where(model.prismatic, np.minimum(np.maximum(np.abs(model.lower), np.abs(model.upper)), FAR), 0.0)
    for k, link in enumerate(capsules.link):
        reach = max(float(np.linalg.norm(capsules.start[k])), float(np.linalg.norm(capsules.end[k])))
        j = int(link)
        while j >= 0:
            out[k, j] = 1.0 if model.prismatic[j] else reach
            reach += offset[j] + travel[j]  # the pivot of j's parent is this far farther (at most)
            j = int(model.parent[j])
    return out


@lru_cache(maxsize=8)
def path_weights_of(model: Model) -> np.ndarray:
    """:func:`path_weights` of the model's body capsules, built once per model."""
    return path_weights(model, capsules_of(model))


class SweptBody:
    """The capsules of ``model`` (:func:`capsules_of`) against ``obstacles``; ``pairs`` (k, m) bool says which
    capsule-obstacle pairs are checked (e.g. a support's foot is not checked against the floor it stands on)."""

    def __init__(self, model: Model, obstacles: list[Obstacle], pairs: np.ndarray, tolerance: float = TOLERANCE):
        self.model, self.capsules = model, capsules_of(model)
        self.obstacles = list(obstacles)
        self.queries: list[Obstacle | MeshIndex] = [index_of(o) if isinstance(o, Mesh) else o for o in obstacles]
        self.pairs = np.asarray(pairs, dtype=bool).reshape(len(self.capsules), len(self.obstacles))
        self.weights = path_weights_of(model)
        self.turns = ((self.weights > 0) & ~model.prismatic).astype(float)  # (k, n) the rotations above capsule k
        self._stacked = np.concatenate([self.weights, self.turns]).T  # (n, 2k)
        self.tolerance = tolerance

    def pose(self, theta: np.ndarray) -> Pose:
        """The :class:`Pose` at joint values ``theta`` (one forward kinematics)."""
        theta = np.array(theta, dtype=float)
        return Pose(theta, *self.capsules.world(self.model.forward(theta)))

    def length(self, theta_a: np.ndarray, theta_b: np.ndarray) -> np.ndarray:
        """L_k (k,) (or (q, k) for (q, n) joint values): the path bound alone (m), from the joint values (no forward
        kinematics); >= :meth:`bound`."""
        return np.abs(np.asarray(theta_b, dtype=float) - theta_a) @ self.weights.T

    def bound(self, a: Pose, b: Pose) -> np.ndarray:
        """M_k (k,): the largest speed (m per unit s) of any axis point of each capsule on the way from ``a`` to
        ``b``, so also its path length and how far its distance to anything can change (module docstring)."""
        return self.bounds([(a, b)])[0]

    def bounds(self, ways: list[tuple[Pose, Pose]]) -> np.ndarray:
        """(q, k): :meth:`bound` of each of q ways (a, b), in one product."""
        k = len(self.capsules)
        both = np.abs(np.array([b.theta - a.theta for a, b in ways])) @ self._stacked
        ends = np.array([(b.p0 - a.p0, b.p1 - a.p1) for a, b in ways])  # (q, 2, k, 3)
        chord = np.sqrt(np.einsum("qekx,qekx->qek", ends, ends).max(axis=1))
        return self._bound(both[:, :k], both[:, k:], chord)

    @staticmethod
    def _bound(length: np.ndarray, turn: np.ndarray, chord: np.ndarray) -> np.ndarray:
        """min(L, chord + 1.5 W L) from the path bound L, the summed turns W (rad) and the end chord (m)."""
        return np.minimum(length, chord + 1.5 * turn * length)

    def distances(self, pose: Pose, margin: float) -> np.ndarray:
        """(k, m) signed distances (m) at ``pose``; a mesh row farther than ``margin`` gets ``margin`` (a lower
        bound; the mesh search stops there)."""
        out = np.empty((len(pose.p0), len(self.obstacles)))
        for o, query in enumerate(self.queries):
            out[:, o] = obstacle_distance(pose.p0, pose.p1, self.capsules.radius, query, margin).distance
        return np.where(np.isinf(out), margin, out)

    def uncertain(self, d_a: np.ndarray, d_b: np.ndarray, motion: np.ndarray) -> np.ndarray:
        """(k, m) pairs that two end distances (m, lower bounds will do) and the bound ``motion`` (k,) do not
        certify: some point of the way might be deeper than the tolerance."""
        return self.pairs & (d_a + d_b - motion[:, None] < -2.0 * self.tolerance)

    def check(self, a: Pose, b: Pose, d_a: np.ndarray, d_b: np.ndarray, margin: float) -> SweepReport:
        """Crossings on the way from ``a`` to ``b``, given the exact (k, m) :meth:`distances` at both ends (queried
        with ``margin`` >= the largest :meth:`bound` + 2 tol). Pairs already inside at either end are left to the
        frames' own clearance rows."""
        tol = self.tolerance
        kk, oo = np.nonzero(self.uncertain(d_a, d_b, self.bound(a, b)) & (d_a >= -tol) & (d_b >= -tol))
        if kk.size == 0:
            return SweepReport(b, [], 0, 0)
        return self._bisect(a, b, kk, oo, d_a[kk, oo], d_b[kk, oo], margin)

    def _bisect(self, a: Pose, b: Pose, kk, oo, d0, d1, margin: float) -> SweepReport:
        """Bisect every pair's uncertain pieces (see the module docstring); all pairs and pieces of a round are
        queried together, one forward kinematics per distinct fraction s."""
        tol = self.tolerance
        step = np.abs(b.theta - a.theta)
        length, turn = (self.weights @ step)[kk], (self.turns @ step)[kk]
        poses = {0.0: a, 1.0: b}
        pair, s0, s1 = np.arange(len(kk)), np.zeros(len(kk)), np.ones(len(kk))
        deepest, at = np.full(len(kk), -tol), np.zeros(len(kk))  # the most negative sample per pair and its s
        samples = 0
        while pair.size:
            h = s1 - s0
            chord = np.array([_chord(poses[u], poses[v], k) for u, v, k in zip(s0, s1, kk[pair], strict=True)])
            motion = self._bound(h * length[pair], h * turn[pair], chord.reshape(-1))
            more = ((d0 + d1 - motion) < -2.0 * tol) & (motion > 2.0 * tol) & (deepest[pair] >= -tol)
            pair, s0, s1, d0, d1 = pair[more], s0[more], s1[more], d0[more], d1[more]
            if not pair.size:
                break
            mid = 0.5 * (s0 + s1)
            for s in np.unique(mid):
                if float(s) not in poses:
                    poses[float(s)] = self.pose(a.theta + s * (b.theta - a.theta))
            dm = self._at(poses, mid, kk[pair], oo[pair], margin)
            samples += len(pair)
            np.minimum.at(deepest, pair, dm)
            hit = dm == deepest[pair]
            at[pair[hit]] = mid[hit]
            pair = np.concatenate([pair, pair])
            s0, s1 = np.concatenate([s0, mid]), np.concatenate([mid, s1])
            d0, d1 = np.concatenate([d0, dm]), np.concatenate([dm, d1])
        names = self.capsules.names
        crossings = [Crossing(names[kk[i]], self.obstacles[oo[i]].name or f"obstacle {oo[i] + 1}", float(at[i]),
                              float(-deepest[i])) for i in np.flatnonzero(deepest < -tol)]  # fmt: skip
        return SweepReport(b, crossings, samples, len(poses) - 2)

    def _at(self, poses: dict, s: np.ndarray, capsule: np.ndarray, obstacle: np.ndarray, margin: float) -> np.ndarray:
        """Distance (m) of capsule[i] to obstacle[i] at fraction s[i], one query per obstacle."""
        out = np.empty(len(s))
        p0 = np.array([poses[float(v)].p0[k] for v, k in zip(s, capsule, strict=True)]).reshape(-1, 3)
        p1 = np.array([poses[float(v)].p1[k] for v, k in zip(s, capsule, strict=True)]).reshape(-1, 3)
        for o in np.unique(obstacle):
            rows = np.flatnonzero(obstacle == o)
            got = obstacle_distance(p0[rows], p1[rows], self.capsules.radius[capsule[rows]], self.queries[o], margin)
            out[rows] = np.where(np.isinf(got.distance), margin, got.distance)
        return out


def _chord(a: Pose, b: Pose, k: int | slice = slice(None)) -> np.ndarray:
    """The longer of the straight moves of capsule k's two ends from ``a`` to ``b`` (m; (k,) for all)."""
    return np.maximum(np.linalg.norm(b.p0[k] - a.p0[k], axis=-1), np.linalg.norm(b.p1[k] - a.p1[k], axis=-1))
