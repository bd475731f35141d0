"""Clearance: the body's capsules keep at least each obstacle's clearance from it (one-sided rows, m).

Rows: for a half-space (the floor; any kind with ``end_rows``) one per capsule end, g = n.(end - point) - radius,
exact and smooth (a capsule's lowest point is one of its ends, and a capsule lying flat needs both to stay down); for
any other obstacle one per capsule, g = the signed surface distance of the obstacle's own
:meth:`~solver.collision.kinds.base.Obstacle.distance` (obstacles of one kind asked together: a scene's boxes in one
query). The Jacobian of a row is
n . (velocity of the witness point on the capsule's axis), the point carried by the capsule's link (the distance's
gradient with respect to that point is the unit normal n; the envelope theorem drops the witness's own motion).
Rows farther than ``margin`` are met and cost nothing; every row ranks with supports and balance (priority 1).
"""

from __future__ import annotations

from abc import abstractmethod
from typing import NamedTuple

import numpy as np

from .. import kernels
from ..body.model import Model
from ..body.state import State
from ..collision import HalfSpace, Obstacle
from ..collision.body import BodyCapsules, capsules_of
from ..kernels.clearance import clearance_jacobian, least_bound, plane_rows
from .base import MET_FACTOR
from .inequality import Inequality
from .per_model import fresh, per_model

TOLERANCE = 1e-3  # m: a row this far inside its clearance still counts as met
WATCH = 0.01  # m: a met row this close to its clearance gives the step its Jacobian (held if the step goes past)
HOLD = 0.5e-3  # m: the watch band of the body's own pairs (an arm hangs against the trunk: docs/TUNING.md)
SAFE = 1e-9  # m: what a movement bound keeps in hand against rounding
MET = TOLERANCE * MET_FACTOR  # m: how far below its clearance a met row may be (Constraint.met_rows's bound)
FLOOR = HalfSpace([0.0, 0.0, 0.0], [0.0, 0.0, 1.0], name="floor")  # z = 0, the free side up


class Closeness(NamedTuple):
    """One body part near something: ``part`` (a capsule's link, with ".start"/".end" for a half-space row),
    ``other`` (an obstacle's name or another body part), the surface-to-surface ``distance`` (m, negative when they
    overlap), the ``clearance`` it must keep (m) and the nearest surface points ``point`` on the part and
    ``other_point`` on the other (world, m)."""

    part: str
    other: str
    distance: float
    clearance: float
    point: np.ndarray
    other_point: np.ndarray

    @property
    def pair(self) -> str:
        """ "part vs other", e.g. "hand_r vs floor"."""
        return f"{self.part} vs {self.other}"

    def to_dict(self) -> dict:
        """The result JSON's entry: pair, part, other, distance, clearance (m), point, other_point (m); a -0.0 (a
        touching pair's exact zero) written as 0.0."""
        return dict(pair=self.pair, part=self.part, other=self.other, distance=self.distance + 0.0,
                    clearance=self.clearance + 0.0, point=[float(v) + 0.0 for v in self.point],
                    other_point=[float(v) + 0.0 for v in self.other_point])  # fmt: skip


def floor_clearance(model: Model, targets: list, n_x: int) -> Clearance:
    """Every capsule above the floor z = 0, but those of links that a target holds on its plane: a support, or a
    sole whose height the target locks (its rows would repeat the target's)."""
    held = set()
    for t in targets:
        tcp = model.tcp(t.tcp)
        if t.support or (tcp.sole is not None and t.operator is None and "z" in t.lock):
            held.add(tcp.link)
    capsules = capsules_of(model)
    exclude = tuple(name for name, link in zip(capsules.names, capsules.link, strict=True) if link in held)
    template = per_model(model, ("floor", exclude, n_x),
                         lambda: Clearance(model, capsules, [FLOOR], n_x, exclude=exclude, name="floor"))  # fmt: skip
    return fresh(template)  # its last query its own


class ClearanceRows(Inequality):
    """Rows g = the surface distance between one of the body's capsules and something else (m), g >= floor: what
    the floor's, the obstacles' and the body's own clearances share. A subclass fills the per-row names and
    :meth:`_evaluate`."""

    name = "clearance"  # an instance's own: "floor", "obstacles", "self_collision" (its residual's key)
    capsules: BodyCapsules
    margin: float  # m: rows closer than this to their floor are reported as near (closest)
    watch: float = WATCH  # m: met rows closer than this to their floor give the step their Jacobian
    _parts: list[str]  # per row, the body part: "hand_r", or "shank_r.end" for a half-space row
    _others: list[str]  # per row, what it keeps clear of: an obstacle or another body part
    _pairs: list[str]  # per row, "part vs other" without the capsule end
    _last: tuple[bytes, tuple] | None = None  # the joint values last measured and what they gave
    # rows whose distance is exact at any range and costly to measure (the body's own pairs) are bounded from how far
    # their capsules moved since the last exact query: per row its capsule and the other's (None: it stands still)
    _bounded = False
    _row_capsule: np.ndarray | None = None
    _row_other: np.ndarray | None = None
    _source: BodyCapsules | None = None  # the capsules whose world ends a state shares (the body's own)
    _subset: np.ndarray | None = None  # which of ``_source`` are ``capsules`` (None: all)
    _whole = False  # ``_subset`` is every capsule of ``_source`` (their ends are the source's, not indexed again)
    _reference: tuple | None = None  # ((start, end) world ends (k, 3), distance - floor per row): last exact query

    @property
    def rows(self) -> int:
        return len(self.floor)

    def tolerance(self) -> np.ndarray:
        return np.full(self.rows, TOLERANCE)

    def _evaluate(self, state: State) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """(distance (rows,) m, witness points on the part's axis (rows, 3), unit normals towards the part
        (rows, 3), the part's capsule of each row), once per state; and once per joint values while they are the
        last asked about (the next frame of a motion starts where the last one ended: the rows are shared, the
        state is new)."""
        cached = state.cache.get(self)
        if cached is None:
            key = state.theta.tobytes()
            last = self._last
            if last is not None and last[0] == key:
                cached = last[1]
            else:
                cached = self._distances(state)
                self._last = (key, cached)
            state.cache[self] = cached
            if self._bounded:
                self._reference = (self._ends(state), cached[0] - self.floor)
        return cached

    def _ends(self, state: State) -> tuple[np.ndarray, np.ndarray]:
        """World ends (m) of ``capsules`` at ``state``, computed once per state for all clearances of the same body
        capsules (the floor's and the body's own)."""
        ends = self._source_ends(state)
        return ends if self._subset is None or self._whole else (ends[0][self._subset], ends[1][self._subset])

    def _source_ends(self, state: State) -> tuple[np.ndarray, np.ndarray]:
        """World ends (m) of every capsule of ``_source`` (else ``capsules``) at ``state``, once per state."""
        source = self._source if self._source is not None else self.capsules
        key = ("capsule ends", id(source))
        found = state.cache.get(key)
        if found is None or found[0] is not source:  # the source kept with them: its id is not another's
            found = state.cache[key] = (source, source.world(state.kin))
        return found[1]

    def _clear_by(self, state: State, band: float) -> bool:
        """True when no row can be within ``band`` (m) of its floor at ``state``, known without a query from how its
        capsules' ends moved since the last exact query (:meth:`_least_bound`, docs/TUNING.md). False whenever not
        sure (the state measured already, no reference, NaN)."""
        if self._reference is None or self in state.cache:
            return False
        key = (self, "bound")
        least = state.cache.get(key)
        if least is None:
            least = state.cache[key] = self._least_bound(state)
        return bool(least > band + SAFE)

    def _least_bound(self, state: State) -> float:
        """The least distance - floor any row can have at ``state`` (m; NaN if unknown): the last exact query's, less
        the most the gap between the row's two capsules can have changed since. A point at s on a capsule moved by
        the blend (1 - s) d0 + s d1 of its ends' moves, so the change of a gap, (blend on one) - (blend on the other),
        is affine in the two parameters and largest in norm at a pair of ends: 4 differences per pair (a part and
        the trunk moving together change nothing), 2 ends against a still obstacle."""
        (start, end), slack = self._reference
        p0, p1 = self._ends(state)
        if kernels.active():
            paired = self._row_other is not None
            other = self._row_other if paired else self._row_capsule
            return float(least_bound(p0, p1, start, end, slack, self._row_capsule, other, paired))
        moved = np.stack([p0 - start, p1 - end], axis=1)  # (capsules, 2 ends, 3)
        mine = moved[self._row_capsule]
        if self._row_other is None:
            change = np.einsum("rej,rej->re", mine, mine)
        else:
            rel = mine[:, :, None, :] - moved[self._row_other][:, None, :, :]  # (rows, 2, 2, 3)
            change = np.einsum("rabj,rabj->rab", rel, rel).reshape(len(mine), 4)
        return float(np.min(slack - np.sqrt(change.max(axis=1)), initial=np.inf))

    def error(self, state: State) -> np.ndarray:
        if self._bounded and self._clear_by(state, 0.0):  # only a bounded row has a reference to be clear by
            return np.zeros(self.rows)
        return np.minimum(self.gap(state), 0.0)  # Inequality.error

    @abstractmethod
    def _distances(self, state: State) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """What :meth:`_evaluate` caches, computed."""

    def value(self, state: State) -> np.ndarray:
        return self._evaluate(state)[0]

    def value_jacobian(self, state: State) -> np.ndarray:
        return self._jacobian_of(state, np.arange(self.rows))

    def jacobian(self, state: State) -> np.ndarray:
        """d error / dx on the rows inside their clearance or within ``watch`` of it (their error is zero: the step
        stops them at the surface when it would go past it, so a comfort step slides a part along a surface instead
        of into it); the others are met, their rows zero."""
        rows, jac = self.jacobian_rows(state)
        out = np.zeros((self.rows, self.n_x))
        out[rows] = jac
        return out

    def jacobian_rows(self, state: State) -> tuple[np.ndarray, np.ndarray]:
        if self._clear_by(state, self.watch):
            return np.zeros(0, dtype=np.intp), np.zeros((0, self.n_x))
        rows = np.flatnonzero(self.gap(state) < self.watch)
        return rows, self._jacobian_of(state, rows)

    @abstractmethod
    def _jacobian_of(self, state: State, rows: np.ndarray) -> np.ndarray:
        """(len(rows), n_x): d g / dx of ``rows``."""

    def _part_rows(self, state: State, rows: np.ndarray) -> np.ndarray:
        """(len(rows), n) n . (velocity of the witness point on the part's capsule) per joint."""
        _, points, normals, capsule = self._evaluate(state)
        mask = self.model.descendant[:, self.capsules.link[capsule[rows]]].T.astype(float)  # joints moving each
        normal = normals[rows]
        return state.kin.jacobian_rows(points[rows], normal, np.zeros_like(normal), mask)

    def _row_link(self, capsule: np.ndarray) -> np.ndarray:
        """Per row, the link of its part's capsule (int64), kept while the rows' capsules are ``capsule``."""
        kept = getattr(self, "_links_of", None)
        if kept is None or kept[0] is not capsule:
            kept = self._links_of = (capsule, np.ascontiguousarray(self.capsules.link[capsule], dtype=np.int64))
        return kept[1]

    def _no_other(self, rows: int) -> np.ndarray:
        """-1 per row: rows with no second moving part, for the Jacobian kernel."""
        kept = getattr(self, "_none", None)
        if kept is None or len(kept) != rows:
            kept = self._none = np.full(rows, -1, dtype=np.int64)
        return kept

    def met_rows(self, state: State) -> np.ndarray:
        """Per row: at most :data:`TOLERANCE` below its clearance (NaN unmet); |min(g - floor, 0)| <= MET is
        g - floor >= -MET, without the error's two steps."""
        if self._clear_by(state, 0.0):
            return np.ones(self.rows, dtype=bool)
        return self.gap(state) >= -MET

    def _lowest(self, state: State) -> float:
        """min(0, least g - floor) (m): the largest shortfall below a clearance, negated; NaN if a row is NaN; 0 when
        the rows are known clear without a query. The error's least row, without the error."""
        key = (self, "lowest")  # asked twice for a report (unmet, residuals)
        lowest = state.cache.get(key)
        if lowest is None:
            gap = None if self._clear_by(state, 0.0) else self.gap(state)
            lowest = state.cache[key] = 0.0 if gap is None else float(np.minimum.reduce(gap, initial=0.0))
        return lowest

    def residuals(self, state: State) -> dict[str, float]:
        """The largest shortfall below the clearance (0 when met), m."""
        return {f"{self.name}.shortfall": abs(self._lowest(state))}

    def unmet(self, state: State) -> list[str]:
        """One name per body part and what it keeps clear of, below the clearance, e.g. "hand_r vs floor"."""
        if self._lowest(state) >= -MET:  # every row met (the usual answer): no per-row test
            return []
        met = self.met_rows(state)
        return sorted({self._pairs[i] for i in np.flatnonzero(~met)})

    def closest(self, state: State) -> list[Closeness]:
        """The rows within the margin of their clearance, nearest first (a few rows: Python floats per row, the same
        products and differences as arrays would give)."""
        if self._clear_by(state, self.margin):
            return []
        near = (self.gap(state) < self.margin).nonzero()[0].tolist()  # the gap: distance - floor, kept per state
        if not near:
            return []
        distance, points, normals, capsule = self._evaluate(state)
        out, radius, floor, make = [], self.capsules.radius, self.floor, Closeness._make
        for i in sorted(near, key=distance.item):  # a stable sort, as argsort(kind="stable")
            d, r = distance.item(i), radius.item(capsule.item(i))
            (px, py, pz), (nx, ny, nz) = points[i].tolist(), normals[i].tolist()
            sx, sy, sz = px - r * nx, py - r * ny, pz - r * nz  # the part's surface point
            other = np.array((sx - d * nx, sy - d * ny, sz - d * nz))
            out.append(make((self._parts[i], self._others[i], d, floor.item(i), np.array((sx, sy, sz)), other)))
        return out


class Clearance(ClearanceRows):
    """Capsules ``capsules`` of ``model`` against ``obstacles``, but those named in ``exclude``: a support's capsule,
    held on its plane by its own target (its rows would repeat the target's and make the step's rows dependent)."""

    def __init__(
        self,
        model: Model,
        capsules: BodyCapsules,
        obstacles: list[Obstacle],
        n_x: int,
        margin: float = 0.05,
        exclude: tuple[str, ...] = (),
        name: str = "obstacles",
    ) -> None:
        self.name = name
        keep = np.array([name not in exclude for name in capsules.names], dtype=bool)
        source = capsules
        capsules = BodyCapsules(tuple(n for n, k in zip(capsules.names, keep, strict=True) if k), capsules.link[keep],
                                capsules.start[keep], capsules.end[keep], capsules.radius[keep])  # fmt: skip
        self._source, self._subset, self._whole = source, np.flatnonzero(keep), bool(keep.all())
        self.model, self.capsules, self.n_x, self.margin = model, capsules, n_x, margin
        self.obstacles = list(obstacles)
        # nothing nearer than its reach (m) is left out of an obstacle's query
        self._reach = [margin + max(ob.clearance, 0.0) for ob in self.obstacles]
        ends = tuple(f"{name}.{end}" for end in ("start", "end") for name in capsules.names)
        by_kind: dict[type[Obstacle], list[int]] = {}
        for i, ob in enumerate(self.obstacles):
            by_kind.setdefault(type(ob), []).append(i)
        # (a row per capsule end?, the kind's obstacles' indices, their reaches, their group): a kind's obstacles are
        # asked together at every evaluation
        self._groups = [(kind.end_rows, rows, np.array([self._reach[i] for i in rows]),
                         kind.group([self.obstacles[i] for i in rows], ends if kind.end_rows else capsules.names))
                        for kind, rows in by_kind.items()]  # fmt: skip
        k = len(capsules)
        self._parts, self._others, self._pairs = [], [], []
        floors = []
        for ob in self.obstacles:
            for end in ("start", "end") if ob.end_rows else ("",):
                self._parts += [f"{name}{'.' + end if end else ''}" for name in capsules.names]
                self._others += [ob.name] * k
                self._pairs += [f"{name} vs {ob.name}" for name in capsules.names]
                floors.append(np.full(k, ob.clearance))
        self.floor = np.concatenate(floors) if floors else np.zeros(0)
        # every obstacle of one kind (boxes), in order, with a row per capsule: its group's flat rows, by the kernels
        # (group, far value per obstacle, capsule per row)
        self._flat = None
        if len(self._groups) == 1 and not self._groups[0][0] and hasattr(self._groups[0][3], "flat_rows"):
            self._flat = (self._groups[0][3], self._groups[0][2] + 1.0, np.tile(np.arange(k), len(self.obstacles)))
        self._plane = None  # one half-space (the floor): measured inline, as halfspace_distance does, in 3 calls
        if len(self.obstacles) == 1 and isinstance(self.obstacles[0], HalfSpace):
            self._plane = self.obstacles[0]
            self._row_capsule = np.tile(np.arange(k), 2)
            self._plane_radius = np.concatenate([capsules.radius, capsules.radius])
            # shared by every state (nothing writes to it; a read-only array would compile the Jacobian kernel twice)
            self._plane_normal = np.tile(self._plane.normal, (2 * k, 1))

    def _distances(self, state: State) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        caps = self.capsules
        if not self.obstacles:
            return np.zeros(0), np.zeros((0, 3)), np.zeros((0, 3)), np.zeros(0, dtype=int)
        if self._plane is not None and kernels.active():  # the rows below, in one loop over the ends
            p0, p1 = self._source_ends(state)
            h, ends = np.empty(len(self._plane_radius)), np.empty((len(self._plane_radius), 3))
            plane_rows(p0, p1, self._subset, self._plane.point, self._plane.normal, self._plane_radius,
                       self._reach[0] + 1.0, h, ends)  # fmt: skip
            return h, ends, self._plane_normal, self._row_capsule
        p0, p1 = self._ends(state)
        if self._flat is not None and kernels.active():  # one kind answering every obstacle's rows in one array
            distance, point, normal = self._flat[0].flat_rows(p0, p1, caps.radius, self._groups[0][2], self._flat[1])
            return distance, point, normal, self._flat[2]
        if self._plane is not None:  # a row per capsule end, starts first; the end is its own witness
            ends = np.concatenate([p0, p1])
            h = (ends - self._plane.point) @ self._plane.normal - self._plane_radius
            return np.where(np.isfinite(h), h, self._reach[0] + 1.0), ends, self._plane_normal, self._row_capsule
        index = np.arange(len(caps))
        got = [None] * len(self.obstacles)
        for end_rows, rows, reach, group in self._groups:
            if end_rows:  # a row per capsule end: the ends as capsules of no length, starts first
                ends = np.concatenate([p0, p1])
                answers = group.distances(ends, ends, np.concatenate([caps.radius, caps.radius]), reach)
            else:
                answers = group.distances(p0, p1, caps.radius, reach)
            for i, answer in zip(rows, answers, strict=True):
                got[i] = answer
        parts = []
        for reach, ob, answer in zip(self._reach, self.obstacles, got, strict=True):
            distance = np.where(np.isfinite(answer.distance), answer.distance, reach + 1.0)
            parts.append((distance, answer.point, answer.normal, np.tile(index, 2) if ob.end_rows else index))
        return tuple(np.concatenate([p[i] for p in parts]) for i in range(4))

    def _jacobian_of(self, state: State, rows: np.ndarray) -> np.ndarray:
        out = np.zeros((len(rows), self.n_x))
        if rows.size and kernels.active():
            _, points, normals, capsule = self._evaluate(state)
            link = self._row_link(capsule)
            clearance_jacobian(points, normals, link, points, self._no_other(len(link)), np.asarray(rows, np.int64),
                               self.model.descendant, state.kin.twist, out)  # fmt: skip
        elif rows.size:
            out[:, : self.model.n] = self._part_rows(state, rows)
        return out
