"""The one call the operations generator makes: a collision-free way from a start point to a goal point for the hand
or a carried box, or one line naming what blocks it.

Order of work: the ends are checked (inside an obstacle: blocked, naming it); an end that touches something (a grasp
on a box on a pallet, a box set onto a shelf) first leaves it straight along the way out of the obstacles near it
until it has the margin's room; the straight way is taken when it is free (no extra points); else RRT-Connect,
shortened and smoothed (:mod:`solver.planning.rrt`).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..collision import Obstacle
from .rrt import SAMPLES, connect, shorten, smooth
from .space import MARGIN, CarriedBox, Space

TOUCH = 0.005  # m: an end may be this far inside an obstacle (resting on it, gripping it) and count as touching
OUT_STEP = 0.01  # m: an end that touches something leaves it in steps of this much
OUT_MOST = 0.30  # m: ... at most this far


@dataclass
class Way:
    """A way for the hand (or the carried box's centre): ``points`` (k, 3) m from the start to the goal (empty when
    blocked), ``rotations`` (k, 3, 3) the carried box's orientation at each (identity without one), ``blocked`` one
    line naming what blocks it ("" when found), and what the search took (``samples`` drawn, ``queries``: points
    measured)."""

    points: np.ndarray
    rotations: np.ndarray
    blocked: str = ""
    samples: int = 0
    queries: int = 0
    notes: list[str] = field(default_factory=list)

    @property
    def found(self) -> bool:
        return not self.blocked


def _point(p: np.ndarray) -> str:
    return "(" + ", ".join(f"{v:.2f}" for v in p) + ") m"


def _blocked(space: Space, why: str, samples: int = 0) -> Way:
    return Way(np.zeros((0, 3)), np.zeros((0, 3, 3)), why, samples, space.queries)


def _leave(space: Space, end: np.ndarray) -> tuple[np.ndarray | None, int]:
    """(the first point straight out of the obstacles near ``end`` with the margin's room, or None; the obstacle
    in the way when none)."""
    direction = space.away(end)
    last = -1
    for i in range(1, int(round(OUT_MOST / OUT_STEP)) + 1):
        point = end + i * OUT_STEP * direction
        ok, blocker = space.free(end, point, allowance=space.margin + TOUCH)
        if not ok:
            return None, blocker
        room, last = space.room(point[None])
        if room[0] >= 0:
            return point, -1
        last = int(last[0])
    return None, last


def find_way(start, goal, carried: CarriedBox | None, obstacles: list[Obstacle], seed: int = 0,
             margin: float = MARGIN, samples: int = SAMPLES) -> Way:  # fmt: skip
    """A way from ``start`` to ``goal`` ((3,) m: the hand's centre, or the carried box's centre) for the hand ball
    (``carried`` None) or ``carried``, ``margin`` m clear of ``obstacles`` (beyond each one's clearance) except
    where an end touches one; deterministic for a ``seed``. See :class:`Way`; ``blocked`` is one line, e.g.
    "blocked by bench: the goal (0.40, 0.60, 0.90) m is inside it"."""
    start, goal = np.asarray(start, dtype=float), np.asarray(goal, dtype=float)
    space = Space(start, goal, carried, obstacles, margin)
    what = "the hand" if carried is None else f"the {carried.name}"
    ends = {"start": start, "goal": goal}
    room, which = space.room(np.array([start, goal]))
    for (name, point), r, w in zip(ends.items(), room, which, strict=True):
        if r + margin + TOUCH < 0:
            return _blocked(space, f"blocked by {space.names[w]}: {what}'s {name} {_point(point)} is inside it")
    notes, out = [], {}
    for (name, point), r in zip(ends.items(), room, strict=True):
        if r >= 0:
            out[name] = point
            continue
        left, blocker = _leave(space, point)
        if left is None:
            return _blocked(space, f"blocked by {space.names[blocker]}: {what} cannot leave its {name} "
                                   f"{_point(point)}")  # fmt: skip
        out[name] = left
        touched = space.names[which[0 if name == "start" else 1]]
        notes.append(f"{what} leaves its {name} straight to {_point(left)} (it touches {touched})")
    head = [start] if out["start"] is not start else []
    tail = [goal] if out["goal"] is not goal else []
    rng = np.random.default_rng(seed)
    if space.free(out["start"], out["goal"])[0]:
        middle = np.array([out["start"], out["goal"]])
        found = 0
    else:
        search = connect(space, out["start"], out["goal"], rng, samples)
        if search.way is None:
            return _blocked(space, _enclosed(space, what, search), search.samples)
        middle = smooth(space, shorten(space, search.way, rng))
        found = search.samples
    points = np.array([*head, *middle, *tail])
    return Way(points, space.rotations(points), "", found, space.queries, notes)


def _enclosed(space: Space, what: str, search) -> str:
    """One line for a search that found no way: the obstacles that stopped the smaller tree (the one shut in) most."""
    tree = int(np.argmin(search.sizes))
    hits = search.hits[tree] or search.hits[1 - tree]
    names = [space.names[o] for o, _ in hits.most_common(2)] or ["the obstacles around it"]
    end = ("start", space.start) if tree == 0 else ("goal", space.goal)
    return (f"blocked by {' and '.join(names)}: no way found for {what} in {search.samples} samples (its {end[0]} "
            f"{_point(end[1])} is shut in)")
