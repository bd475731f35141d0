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
(for a mesh the same holds wherever D >= 0). Two of the body's own capsules i, j (self-collision pairs) move
relative to each other at most M_i + M_j, and their distance less its least allowed one takes the place of D.
:meth:`SweptBody.check` certifies a pair from the two frames alone
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

from .. import kernels
from ..body.model import Model
from ..kernels.sweep import any_uncertain, way_bound
from .body import BodyCapsules, capsules_of
from .distance import capsule_pairs
from .kinds import Box, Obstacle
from .kinds.box import box_set, boxes_distance
from .self_pairs import SelfPairs

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
    """The capsules of ``model`` (:func:`capsules_of`) against ``obstacles`` and, given ``own``, each other;
    ``pairs`` (k, m) bool says which capsule-obstacle pairs are checked (e.g. a support's foot is not checked
    against the floor it stands on). Distances are (k, m + p) arrays: a column per obstacle, then one per pair of
    ``own`` (filled in the row of its first capsule: its distance less its least)."""

    def __init__(self, model: Model, obstacles: list[Obstacle], pairs: np.ndarray, tolerance: float = TOLERANCE,
                 own: SelfPairs | None = None):  # fmt: skip
        self.model, self.capsules = model, capsules_of(model)
        self.obstacles = list(obstacles)
        k, m = len(self.capsules), len(self.obstacles)
        self.own = own if own is not None and len(own) else None
        p = 0 if self.own is None else len(self.own)
        self.pairs = np.zeros((k, m + p), dtype=bool)
        self.pairs[:, :m] = np.asarray(pairs, dtype=bool).reshape(k, m)
        self.partner = np.full((k, m + p), -1)  # the other capsule of a self pair's entry (-1: an obstacle's)
        if self.own is not None:
            self.pairs[self.own.first, m + np.arange(p)] = True
            self.partner[self.own.first, m + np.arange(p)] = self.own.second
        boxes = [o for o, ob in enumerate(self.obstacles) if type(ob) is Box]  # asked together in distances()
        self._boxes, self._others = np.array(boxes, dtype=int), [o for o in range(m) if o not in boxes]
        self._box_set = box_set([self.obstacles[o] for o in boxes])
        self._partner_or_none = np.where(self.partner >= 0, self.partner, k)  # k: the appended 0 of relative()
        self.weights = path_weights_of(model)
        self.turns = ((self.weights > 0) & ~model.prismatic).astype(float)  # (k, n) the rotations above capsule k
        self._stacked = np.concatenate([self.weights, self.turns]).T  # (n, 2k)
        self.tolerance = tolerance

    @property
    def queries(self) -> list[Obstacle]:
        """What each obstacle column's distances are asked of: the obstacles themselves (each answers its own)."""
        return self.obstacles

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
        if kernels.active():  # a loop per way: no (q, 2, k, 3) stack of the ends' moves
            out = np.empty((len(ways), k))
            for i, (a, b) in enumerate(ways):
                way_bound(a.theta, b.theta, a.p0, a.p1, b.p0, b.p1, self.weights, self.turns, out[i])
            return out
        both = np.abs(np.array([b.theta - a.theta for a, b in ways])) @ self._stacked
        ends = np.array([(b.p0 - a.p0, b.p1 - a.p1) for a, b in ways])  # (q, 2, k, 3)
        chord = np.sqrt(np.einsum("qekx,qekx->qek", ends, ends).max(axis=1))
        return self._bound(both[:, :k], both[:, k:], chord)

    @staticmethod
    def _bound(length: np.ndarray, turn: np.ndarray, chord: np.ndarray) -> np.ndarray:
        """min(L, chord + 1.5 W L) from the path bound L, the summed turns W (rad) and the end chord (m)."""
        return np.minimum(length, chord + 1.5 * turn * length)

    def distances(self, pose: Pose, margin: float) -> np.ndarray:
        """(k, m + p) signed distances (m) at ``pose``; a mesh row farther than ``margin`` gets ``margin`` (a lower
        bound; the mesh search stops there); entries of no pair are +inf."""
        m = len(self.obstacles)
        out = np.full(self.pairs.shape, np.inf)
        if self._boxes.size:  # the boxes in one query (each row is what the box's own distance gives)
            got = boxes_distance(pose.p0, pose.p1, self.capsules.radius, self._box_set, margin)
            box_rows = np.array([g.distance for g in got]).T
            out[:, self._boxes] = np.where(np.isinf(box_rows), margin, box_rows)
        for o in self._others:
            got = self.obstacles[o].distance(pose.p0, pose.p1, self.capsules.radius, margin).distance
            out[:, o] = np.where(np.isinf(got), margin, got)
        if self.own is not None:
            own = self.own
            got = capsule_pairs(pose.p0, pose.p1, self.capsules.radius, own.first, own.second).distance
            out[own.first, m + np.arange(len(own))] = got - own.least
        return out

    def relative(self, motion: np.ndarray) -> np.ndarray:
        """(k, m + p): how far each entry's distance can change when capsule k moves at most ``motion`` (k,) m: its
        own motion, plus its partner's for a self pair."""
        # the partner's motion gathered from the motions with a 0 appended (index k: no partner); adding 0 is exact
        return motion[:, None] + np.append(motion, 0.0)[self._partner_or_none]

    def uncertain(self, d_a: np.ndarray, d_b: np.ndarray, motion: np.ndarray) -> np.ndarray:
        """(k, m + p) pairs that two end distances (m, lower bounds will do) and the bound ``motion`` (k,) do not
        certify: some point of the way might be deeper than the tolerance."""
        return self.pairs & (d_a + d_b - self.relative(motion) < -2.0 * self.tolerance)

    def any_uncertain(self, d_p: np.ndarray, first: np.ndarray, second: np.ndarray, way: np.ndarray) -> bool:
        """Whether :meth:`uncertain` leaves any pair of the way whose ends' distances are at least ``d_p`` (k, m + p)
        m less the motions ``first`` and ``second`` (k,) m, the way's own bound being ``way`` (k,) m (by the kernels:
        one loop that stops at the first)."""
        if kernels.active():
            return bool(any_uncertain(self.pairs, self.partner, np.ascontiguousarray(d_p, dtype=float),
                                      *(np.ascontiguousarray(m, dtype=float) for m in (first, second, way)),
                                      self.tolerance))  # fmt: skip
        return bool(self.uncertain(d_p - self.relative(first), d_p - self.relative(second), way).any())

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
        length, turn = self.weights @ step, self.turns @ step
        partner = self.partner[kk, oo]
        poses = {0.0: a, 1.0: b}
        pair, s0, s1 = np.arange(len(kk)), np.zeros(len(kk)), np.ones(len(kk))
        deepest, at = np.full(len(kk), -tol), np.zeros(len(kk))  # the most negative sample per pair and its s
        samples = 0
        while pair.size:
            motion = self._piece_motion(poses, s0, s1, kk[pair], length, turn)
            own = partner[pair] >= 0
            if own.any():  # a self pair: the two capsules' motions add up
                motion[own] += self._piece_motion(poses, s0[own], s1[own], partner[pair][own], length, turn)
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
        crossings = [Crossing(self.capsules.names[kk[i]], self._other_name(oo[i]), float(at[i]), float(-deepest[i]))
                     for i in np.flatnonzero(deepest < -tol)]  # fmt: skip
        return SweepReport(b, crossings, samples, len(poses) - 2)

    def _piece_motion(self, poses: dict, s0, s1, capsule, length, turn) -> np.ndarray:
        """The bound (m) on capsule[i]'s motion over the piece s0[i]..s1[i] of the way (``length``, ``turn``: the
        whole way's path bound and summed turns per capsule)."""
        h = s1 - s0
        chord = np.array([_chord(poses[u], poses[v], k) for u, v, k in zip(s0, s1, capsule, strict=True)])
        return self._bound(h * length[capsule], h * turn[capsule], chord.reshape(-1))

    def _other_name(self, column: int) -> str:
        """What a column of the distances is: an obstacle's name, or the other body part of a self pair."""
        m = len(self.obstacles)
        if column >= m:
            return self.capsules.names[int(self.own.second[column - m])]
        return self.obstacles[column].name or f"obstacle {column + 1}"

    def _at(self, poses: dict, s: np.ndarray, capsule: np.ndarray, column: np.ndarray, margin: float) -> np.ndarray:
        """Distance (m) of capsule[i] to what column[i] names at fraction s[i], one query per obstacle."""
        out = np.empty(len(s))
        ends = [poses[float(v)] for v in s]
        p0 = np.array([e.p0[k] for e, k in zip(ends, capsule, strict=True)]).reshape(-1, 3)
        p1 = np.array([e.p1[k] for e, k in zip(ends, capsule, strict=True)]).reshape(-1, 3)
        m = len(self.obstacles)
        for o in np.unique(column[column < m]):
            rows = np.flatnonzero(column == o)
            got = self.obstacles[o].distance(p0[rows], p1[rows], self.capsules.radius[capsule[rows]], margin)
            out[rows] = np.where(np.isinf(got.distance), margin, got.distance)
        rows = np.flatnonzero(column >= m)
        if rows.size:  # self pairs: the partner's axis at the same fraction, as a one-pair batch per row
            pair = column[rows] - m
            other = self.own.second[pair]
            q0 = np.array([ends[r].p0[j] for r, j in zip(rows, other, strict=True)]).reshape(-1, 3)
            q1 = np.array([ends[r].p1[j] for r, j in zip(rows, other, strict=True)]).reshape(-1, 3)
            n = len(rows)
            both0, both1 = np.concatenate([p0[rows], q0]), np.concatenate([p1[rows], q1])
            radii = np.concatenate([self.capsules.radius[capsule[rows]], self.capsules.radius[other]])
            got = capsule_pairs(both0, both1, radii, np.arange(n), n + np.arange(n))
            out[rows] = got.distance - self.own.least[pair]
        return out


def _chord(a: Pose, b: Pose, k: int | slice = slice(None)) -> np.ndarray:
    """The longer of the straight moves of capsule k's two ends from ``a`` to ``b`` (m; (k,) for all)."""
    return np.maximum(np.linalg.norm(b.p0[k] - a.p0[k], axis=-1), np.linalg.norm(b.p1[k] - a.p1[k], axis=-1))
