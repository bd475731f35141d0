"""RRT-Connect (Kuffner & LaValle 2000) over the points of a :class:`~solver.planning.space.Space`, and the way it
finds shortened (random shortcuts, then the farthest visible point greedily) and smoothed (corner cutting where the
cut is free). Deterministic for a given random generator: no clock decides anything.
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass, field

import numpy as np

from .space import Space

STEP = 0.10  # m: the longest edge a tree grows by at once
SAMPLES = 1500  # samples at most before the search gives up
AROUND = 0.8  # m: the samples come from the bounds of the start and goal grown by this much
SHORTCUTS = 40  # random shortcut tries
SMOOTHING = 2  # corner-cutting rounds


@dataclass
class Search:
    """What a search found: the ``way`` (k, 3) m (None if none), the ``samples`` drawn, and how often each obstacle
    (index) stopped a tree growing, by tree (0: the start's, 1: the goal's), and each tree's size."""

    way: np.ndarray | None
    samples: int
    hits: tuple[Counter, Counter] = field(default_factory=lambda: (Counter(), Counter()))
    sizes: tuple[int, int] = (1, 1)


class Tree:
    """Points (grown in a preallocated array) and each one's parent index."""

    def __init__(self, root: np.ndarray, capacity: int) -> None:
        self.points = np.empty((capacity, 3))
        self.parent = np.full(capacity, -1)
        self.points[0], self.size = root, 1

    def nearest(self, q: np.ndarray) -> int:
        d = self.points[: self.size] - q
        return int(np.argmin(np.einsum("ij,ij->i", d, d)))

    def add(self, point: np.ndarray, parent: int) -> int:
        self.points[self.size], self.parent[self.size] = point, parent
        self.size += 1
        return self.size - 1

    def branch(self, i: int) -> list[np.ndarray]:
        """The points from the root to ``i``."""
        out = []
        while i >= 0:
            out.append(self.points[i])
            i = int(self.parent[i])
        return out[::-1]


def _extend(space: Space, tree: Tree, q: np.ndarray, hits: Counter) -> tuple[str, int]:
    """Grow ``tree`` one step towards ``q``: ("reached" | "advanced" | "trapped", the new point's index)."""
    near = tree.nearest(q)
    p = tree.points[near]
    gap = q - p
    length = float(np.linalg.norm(gap))
    target = q if length <= STEP else p + gap * (STEP / length)
    if length < 1e-9:
        return "reached", near
    ok, blocker = space.free(p, target)
    if not ok:
        hits[blocker] += 1
        return "trapped", -1
    return ("reached" if length <= STEP else "advanced"), tree.add(target, near)


def connect(space: Space, start: np.ndarray, goal: np.ndarray, rng: np.random.Generator,
            samples: int = SAMPLES) -> Search:  # fmt: skip
    """RRT-Connect from ``start`` to ``goal`` (3,) m, both free: grow one tree towards a random point, the other
    straight towards that tree's new point until it is reached or stopped, then swap."""
    low = np.minimum(start, goal) - AROUND
    high = np.maximum(start, goal) + AROUND
    low[2] = max(low[2], 0.0)  # the floor is the lowest a way goes (an obstacle says so too, when given)
    trees = [Tree(start, samples * 2 + 2), Tree(goal, samples * 2 + 2)]
    hits: tuple[Counter, Counter] = (Counter(), Counter())
    a = 0
    for n in range(1, samples + 1):
        grow, other = trees[a], trees[1 - a]
        status, new = _extend(space, grow, rng.uniform(low, high), hits[a])
        if status != "trapped":
            q = grow.points[new]
            while True:
                status, last = _extend(space, other, q, hits[1 - a])
                if status != "advanced":
                    break
            if status == "reached":
                first, second = (grow, other) if a == 0 else (other, grow)
                ends = (new, last) if a == 0 else (last, new)
                way = first.branch(ends[0]) + second.branch(ends[1])[::-1][1:]
                return Search(np.array(way), n, hits, (trees[0].size, trees[1].size))
        a = 1 - a
    return Search(None, samples, hits, (trees[0].size, trees[1].size))


def shorten(space: Space, way: np.ndarray, rng: np.random.Generator, tries: int = SHORTCUTS) -> np.ndarray:
    """``way`` with random shortcuts taken (two points i < j joined straight where that is free), then each point
    joined to the farthest later one it sees."""
    points = [np.asarray(p) for p in way]
    for _ in range(tries):
        if len(points) <= 2:
            break
        i, j = sorted(rng.choice(len(points), size=2, replace=False))
        if j - i > 1 and space.free(points[i], points[j])[0]:
            points = points[: i + 1] + points[j:]
    out, i = [points[0]], 0
    while i < len(points) - 1:
        j = len(points) - 1
        while j > i + 1 and not space.free(points[i], points[j])[0]:
            j -= 1
        out.append(points[j])
        i = j
    return np.array(out)


def smooth(space: Space, way: np.ndarray, rounds: int = SMOOTHING) -> np.ndarray:
    """Corner cutting (Chaikin): each inner corner replaced by the points a quarter of the way along its two
    pieces, where the cut between them is free; the ends stay."""
    for _ in range(rounds):
        if len(way) <= 2:
            break
        out = [way[0]]
        for i in range(1, len(way) - 1):
            before, corner, after = way[i - 1], way[i], way[i + 1]
            a, b = corner + 0.25 * (before - corner), corner + 0.25 * (after - corner)
            if space.free(a, b)[0]:
                out += [a, b]
            else:
                out.append(corner)
        out.append(way[-1])
        way = np.array(out)
    return way
