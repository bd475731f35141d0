"""Where the moving thing may be: the hand (a ball) or a carried box, and its room to the obstacles (m).

The planner works in the workspace of one point: the hand's centre, or the carried box's centre with the box's
orientation a function of that point (:meth:`CarriedBox.rotation_at`), so a way is a polyline of points. The room at a
point is, per obstacle, the signed distance of the hand ball (the rounded box) to it less the obstacle's clearance
and the planning margin (room for the forearm behind the hand, or around the box): >= 0 is free. Distances come from
the project's own code: each obstacle kind's capsule distance, and for the box its 12 edges against the obstacle and
the obstacle's skeleton against the box, as the carried box's clearance rows do
(:mod:`solver.constraints.carried_obstacles`).

The room changes at most as fast as the thing's points move, so a straight piece a-b is free when the room at both
ends sums to at least how far any point moves between them (the lower bound (r_a + r_b - M) / 2 of the room on
the way, as :mod:`solver.collision.sweep`); :meth:`Space.free` bisects until every piece is certified or a sample
has no room.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..body.spatial import matrix_to_quat, quat_to_matrix, slerp
from ..collision import Box, Obstacle
from ..collision.boxes import _CORNERS, box_rows, edges_of_corners

HAND_RADIUS = 0.05  # m: a hand closed round a grasp, as a ball
MARGIN = 0.05  # m: room kept beyond an obstacle's own clearance, for the forearm behind the hand or around the box
LOOK = 0.5  # m: distances beyond this count as this far (a lower bound; the queries stop there)
FINEST = 1e-3  # m: a piece whose points move less than this is not split further


@dataclass(frozen=True)
class CarriedBox:
    """What the hands carry: a box of ``size`` (3,) m along the columns of ``rotation`` (3x3, at the start), turned to
    ``goal_rotation`` at the goal (None: kept as at the start)."""

    size: np.ndarray
    rotation: np.ndarray = field(default_factory=lambda: np.eye(3))
    goal_rotation: np.ndarray | None = None
    name: str = "carried box"

    @property
    def half(self) -> np.ndarray:
        """Half edge lengths (3,), m."""
        return 0.5 * np.asarray(self.size, dtype=float)

    def turn(self) -> float:
        """The angle (rad) from the start's orientation to the goal's."""
        if self.goal_rotation is None:
            return 0.0
        cos = (np.trace(np.asarray(self.rotation).T @ self.goal_rotation) - 1.0) / 2.0
        return float(np.arccos(np.clip(cos, -1.0, 1.0)))

    def rotation_at(self, share: float) -> np.ndarray:
        """The orientation ``share`` (0..1) of the way from the start's to the goal's (slerp)."""
        if self.goal_rotation is None:
            return np.asarray(self.rotation, dtype=float)
        q = slerp(matrix_to_quat(np.asarray(self.rotation, dtype=float)), matrix_to_quat(self.goal_rotation), share)
        return quat_to_matrix(q)


class Space:
    """The room (m) of the hand (``carried`` None) or of ``carried`` to ``obstacles``, on the way from ``start`` to
    ``goal`` (3,) m: the box turns with the share s(p) = |p - start| / (|p - start| + |p - goal|), 0 at the start, 1
    at the goal, so a point alone says where the box is."""

    def __init__(self, start: np.ndarray, goal: np.ndarray, carried: CarriedBox | None, obstacles: list[Obstacle],
                 margin: float = MARGIN) -> None:  # fmt: skip
        self.start, self.goal = np.asarray(start, dtype=float), np.asarray(goal, dtype=float)
        self.carried, self.obstacles, self.margin = carried, list(obstacles), margin
        self.names = [ob.name or f"obstacle {i + 1}" for i, ob in enumerate(self.obstacles)]
        self.clearance = np.array([ob.clearance for ob in self.obstacles], dtype=float)
        self.queries = 0  # points whose room was measured
        if carried is not None:
            self.half = carried.half
            self.turn = carried.turn()
            self.spread = float(np.linalg.norm(self.half))  # the box's points are this far from its centre at most
        self._box_columns = [o for o, ob in enumerate(self.obstacles) if isinstance(ob, Box)]
        self._boxes = Box.group([self.obstacles[o] for o in self._box_columns], ()) if self._box_columns else None
        self._others = [o for o, ob in enumerate(self.obstacles) if not isinstance(ob, Box)]
        self._ends = [o for o, ob in enumerate(self.obstacles) if ob.end_rows]
        parts = [(o, ob.skeleton()) for o, ob in enumerate(self.obstacles) if not ob.end_rows]
        self._meshes = [o for o, sk in parts if sk is None and self.obstacles[o].nearest_edges > 0]
        parts = [(o, sk) for o, sk in parts if sk is not None]
        self._skeleton = None  # every obstacle's skeleton stacked: starts, ends, radii, the obstacle of each row
        if parts:
            self._skeleton = tuple(np.concatenate(x) for x in zip(*[(*sk, np.full(len(sk[2]), o)) for o, sk in parts],
                                                                   strict=True))  # fmt: skip

    def share(self, points: np.ndarray) -> np.ndarray:
        """s(p) (k,) for ``points`` (k, 3): how far the box has turned from the start's orientation to the goal's."""
        a = np.linalg.norm(points - self.start, axis=1)
        b = np.linalg.norm(points - self.goal, axis=1)
        return a / np.maximum(a + b, 1e-12)

    def rotations(self, points: np.ndarray) -> np.ndarray:
        """The carried box's orientation (k, 3, 3) at ``points`` (k, 3) m."""
        if self.carried is None:
            return np.broadcast_to(np.eye(3), (len(points), 3, 3)).copy()
        return np.array([self.carried.rotation_at(float(s)) for s in self.share(points)]).reshape(-1, 3, 3)

    def motion(self, a: np.ndarray, b: np.ndarray) -> np.ndarray:
        """How far (m) any point of the hand ball or the box moves at most on the straight pieces a-b ((k, 3) each)."""
        out = np.linalg.norm(b - a, axis=1)
        if self.carried is not None and self.turn > 0:
            out = out + np.abs(self.share(b) - self.share(a)) * self.turn * self.spread
        return out

    def distances(self, points: np.ndarray) -> np.ndarray:
        """(k, m) signed distance (m) of the hand ball or the box at each of ``points`` (k, 3) to each obstacle, at
        most :data:`LOOK`."""
        points = np.atleast_2d(np.asarray(points, dtype=float))
        self.queries += len(points)
        k = len(points)
        if self.carried is None:
            return self._capsules(points, points, np.full(k, HAND_RADIUS))
        rotations = self.rotations(points)
        corners = self.half * _CORNERS @ rotations.transpose(0, 2, 1) + points[:, None]  # (k, 8, 3)
        a, b = edges_of_corners(corners.transpose(1, 0, 2))  # (12, k, 3) each
        a, b = a.transpose(1, 0, 2).reshape(-1, 3), b.transpose(1, 0, 2).reshape(-1, 3)
        out = self._capsules(a, b, np.zeros(len(a))).reshape(k, 12, -1).min(axis=1)
        for o in self._ends:  # a half-space: the box is nearest it at a corner
            flat = corners.reshape(-1, 3)
            got = self.obstacles[o].distance(flat, flat, np.zeros(len(flat)), LOOK).distance
            out[:, o] = np.minimum(np.where(np.isfinite(got), got, LOOK).reshape(k, 8).min(axis=1), LOOK)
        if self._skeleton is not None:  # every fixed skeleton against every box in one query
            s0, s1, radii, owner = self._skeleton
            n = len(radii)
            back = box_rows(np.tile(s0, (k, 1)), np.tile(s1, (k, 1)), np.tile(radii, k), np.repeat(points, n, axis=0),
                            np.repeat(rotations, n, axis=0), np.broadcast_to(self.half, (k * n, 3))).distance
            back = back.reshape(k, n)
            for o in np.unique(owner):
                out[:, o] = np.minimum(out[:, o], back[:, owner == o].min(axis=1))
        for o in self._meshes:  # a mesh: its edges nearest each box
            for i in range(k):
                near = self.obstacles[o].edges_near_box(points[i], rotations[i], self.half, LOOK)
                if near is not None:
                    s0, s1, radii = near
                    n = len(radii)
                    got = box_rows(s0, s1, radii, np.broadcast_to(points[i], (n, 3)),
                                   np.broadcast_to(rotations[i], (n, 3, 3)), np.broadcast_to(self.half, (n, 3)))
                    out[i, o] = min(out[i, o], float(got.distance.min(initial=LOOK)))
        return out

    def _capsules(self, p0: np.ndarray, p1: np.ndarray, radii: np.ndarray) -> np.ndarray:
        """(rows, m) distances (m, at most LOOK) of capsules p0-p1 of ``radii`` to each obstacle; the boxes in one
        query."""
        out = np.full((len(p0), len(self.obstacles)), LOOK)
        if self._boxes is not None:
            for o, got in zip(self._box_columns, self._boxes.distances(p0, p1, radii, np.full(len(self._box_columns),
                                                                                              LOOK)), strict=True):
                out[:, o] = got.distance
        for o in self._others:
            out[:, o] = self.obstacles[o].distance(p0, p1, radii, LOOK).distance
        return np.minimum(np.where(np.isfinite(out), out, LOOK), LOOK)

    def room(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(room (k,) m, the obstacle with the least room (k,) index) at ``points``: the distance less the obstacle's
        clearance and the margin (and, for the hand alone, nothing else); +LOOK with no obstacles."""
        points = np.atleast_2d(np.asarray(points, dtype=float))
        if not self.obstacles:
            return np.full(len(points), LOOK), np.zeros(len(points), dtype=int)
        surplus = self.distances(points) - self.clearance - self.margin
        which = np.argmin(surplus, axis=1)
        return surplus[np.arange(len(points)), which], which

    def free(self, a: np.ndarray, b: np.ndarray, allowance: float = 0.0) -> tuple[bool, int]:
        """Is the straight piece a-b (3,) m free (room + ``allowance`` >= 0 all along)? (free, the obstacle that
        blocks it, -1 if free). Bisects the uncertain pieces, all of a round measured together."""
        ends = np.array([a, b], dtype=float)
        room, which = self.room(ends)
        room = room + allowance
        if room.min() < 0:
            return False, int(which[np.argmin(room)])
        s0, s1, r0, r1 = np.zeros(1), np.ones(1), room[:1], room[1:]
        u = ends[1] - ends[0]
        while s0.size:
            moved = self.motion(ends[0] + s0[:, None] * u, ends[0] + s1[:, None] * u)
            more = (r0 + r1 < moved) & (moved > FINEST)
            s0, s1, r0, r1 = s0[more], s1[more], r0[more], r1[more]
            if not s0.size:
                break
            mid = 0.5 * (s0 + s1)
            rm, wm = self.room(ends[0] + mid[:, None] * u)
            rm = rm + allowance
            if rm.min() < 0:
                return False, int(wm[np.argmin(rm)])
            s0, s1 = np.concatenate([s0, mid]), np.concatenate([mid, s1])
            r0, r1 = np.concatenate([r0, rm]), np.concatenate([rm, r1])
        return True, -1

    def away(self, point: np.ndarray) -> np.ndarray:
        """A unit direction (3,) out of the obstacles nearest ``point`` (m): the sum of the finite-difference
        gradients of the room to each obstacle within the margin, or up when they cancel."""
        base = self.distances(point[None])[0]
        near = base - self.clearance < self.margin + 1e-9
        h = 1e-4
        grad = np.zeros(3)
        for axis in range(3):
            step = np.zeros(3)
            step[axis] = h
            grad[axis] = ((self.distances((point + step)[None])[0] - base)[near]).sum() / h
        size = float(np.linalg.norm(grad))
        return grad / size if size > 1e-6 else np.array([0.0, 0.0, 1.0])
