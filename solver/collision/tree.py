"""A bounding-volume tree over triangles for nearest-triangle searches from many segments at once.

Triangles are put in k-d tree order by their centroids, so runs of neighbours in the order are compact in
space; 8 consecutive triangles form a leaf and 8 consecutive nodes a parent, up to a top level of at most TOP
nodes. Every node keeps its box and one surface point under it. A search walks down level by level for all
segments together, keeping a node only while its lower bound (bounding sphere and box gap) does not exceed the
best upper bound so far (the distance to a node's surface point, or the reach), so the work follows the nodes
near the answer.
"""

from __future__ import annotations

import numpy as np

from .closest import distances_to_segments, dot

BRANCH = 8
TOP = 64
TIE = 1e-12  # m: distances closer than this to the best found count as ties (a search may drop either)


def kd_order(points: np.ndarray) -> np.ndarray:
    """A permutation of points (N, 3) in which every aligned run of BRANCH^m points (m >= 1) is a cell of a k-d
    tree: ranges of a virtual power-of-two length are split in half, level by level, along their longest extent."""
    n = len(points)
    size = BRANCH
    while size < n:
        size *= 2
    order = np.arange(n)
    span = size
    while span > BRANCH:
        cell = np.arange(n) // span
        starts = np.flatnonzero(np.r_[True, cell[1:] != cell[:-1]])
        p = points[order]
        extent = np.maximum.reduceat(p, starts) - np.minimum.reduceat(p, starts)
        axis = np.repeat(np.argmax(extent, axis=1), np.diff(np.r_[starts, n]))
        order = order[np.lexsort((p[np.arange(n), axis], cell))]
        span //= 2
    return order


def group_argmin(group: np.ndarray, values: np.ndarray, size: int) -> np.ndarray:
    """For values grouped by ``group`` (non-decreasing ints in 0..size-1): the index of each group's smallest value
    (the first on ties), -1 for groups without values."""
    best = np.full(size, -1, dtype=np.int64)
    if group.size == 0:
        return best
    starts = np.flatnonzero(np.r_[True, group[1:] != group[:-1]])
    lengths = np.diff(np.r_[starts, group.size])
    lowest = np.repeat(np.minimum.reduceat(values, starts), lengths)
    index = np.where(values == lowest, np.arange(group.size), group.size)
    best[group[starts]] = np.minimum.reduceat(index, starts)
    return best


def group_min(group: np.ndarray, values: np.ndarray, out: np.ndarray) -> None:
    """out[g] = min(out[g], smallest value of group g) for values grouped by ``group`` (non-decreasing)."""
    if group.size:
        starts = np.flatnonzero(np.r_[True, group[1:] != group[:-1]])
        g = group[starts]
        out[g] = np.minimum(out[g], np.minimum.reduceat(values, starts))


FAR = 1e30  # m: where padding nodes sit (finite, so that no arithmetic on them makes NaN)


def _pad(level: tuple[np.ndarray, ...], size: int) -> tuple[np.ndarray, ...]:
    """A level's arrays (lo, hi, center, radius, point) extended with far-away empty nodes to ``size`` entries."""
    extra = size - len(level[0])
    return tuple(np.concatenate([x, np.full((extra, *x.shape[1:]), FAR if x.ndim > 1 else 0.0)]) for x in level)


def _nearest_to_centers(points: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """Of each run of BRANCH points (N, 3), the one nearest the center of its box lo..hi (one row per run)."""
    pad = (-len(points)) % BRANCH
    runs = np.concatenate([points, np.full((pad, 3), FAR)]).reshape(-1, BRANCH, 3)
    gap = runs - 0.5 * (lo + hi)[:, None]
    return runs[np.arange(len(runs)), np.argmin(dot(gap, gap), axis=1)]


class TriangleTree:
    """The tree over triangles a, b, c (F, 3); ``order`` maps tree slots to triangle indices. Every level but the
    top is padded so that node i's children are exactly BRANCH * i + (0..BRANCH-1). A level is (lo, hi, center,
    radius, surface point): the box, its bounding sphere and the centroid of one triangle under the node."""

    def __init__(self, a: np.ndarray, b: np.ndarray, c: np.ndarray) -> None:
        self.order = kd_order((a + b + c) / 3.0)
        tri = np.stack([a, b, c], axis=1)[self.order]
        lo, hi, point = tri.min(axis=1), tri.max(axis=1), tri.mean(axis=1)
        levels: list[tuple[np.ndarray, ...]] = []
        while len(lo) > TOP or not levels:
            starts = np.arange(0, len(lo), BRANCH)
            lo, hi = np.minimum.reduceat(lo, starts), np.maximum.reduceat(hi, starts)
            point = _nearest_to_centers(point, lo, hi)
            levels.append((lo, hi, 0.5 * (lo + hi), 0.5 * np.sqrt(dot(hi - lo, hi - lo)), point))
        levels.reverse()  # top first; the last level's children are triangle slots
        levels = [levels[0]] + [_pad(lv, BRANCH * len(up[0])) for up, lv in zip(levels, levels[1:], strict=False)]
        # one row per node (lo, hi, center, point, radius): a search gathers a node's data in one indexing
        self.levels = [np.column_stack([lo, hi, center, point, radius]) for lo, hi, center, radius, point in levels]
        self.size = len(a)

    def _bounds(self, depth: int, p0, p1, seg, node) -> tuple[np.ndarray, np.ndarray]:
        """Lower bounds (m) of the distance from segments to the nodes (bounding sphere and box gap), and upper
        bounds (the distance to the node's surface point)."""
        row = self.levels[depth][node]
        a, b = p0[seg], p1[seg]
        to_center, to_point = distances_to_segments((row[:, 6:9], row[:, 9:12]), a, b)
        box = np.maximum(np.maximum(row[:, 0:3] - np.maximum(a, b), np.minimum(a, b) - row[:, 3:6]), 0.0)
        return np.maximum(to_center - row[:, 12], np.sqrt(dot(box, box))), to_point

    def _leaves(self, seg: np.ndarray, node: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        slot = (node[:, None] * BRANCH + np.arange(BRANCH)).ravel()
        seg = np.repeat(seg, BRANCH)
        real = slot < self.size
        return seg[real], slot[real]

    def meeting(self, low: np.ndarray, high: np.ndarray) -> np.ndarray:
        """Triangle slots under every lowest node whose box meets the box ``low``..``high`` (3,) m: among them every
        triangle whose own box meets it."""
        node = np.arange(len(self.levels[0]))
        for level in self.levels:
            row = level[node]
            meet = (row[:, 0] <= high[0]) & (row[:, 3] >= low[0])  # axis by axis: padding nodes (FAR) never meet
            for d in (1, 2):
                meet &= (row[:, d] <= high[d]) & (row[:, 3 + d] >= low[d])
            node = node[meet]
            node = (node[:, None] * BRANCH + np.arange(BRANCH)).ravel()  # the children: nodes, or at last slots
        return node[node < self.size]

    def search(
        self, p0: np.ndarray, p1: np.ndarray, upper: np.ndarray, slack: float = 0.0
    ) -> tuple[np.ndarray, np.ndarray]:
        """Pairs (segment, triangle slot), grouped by segment, under every node whose lower bound is at most
        ``upper`` (k,) + ``slack`` m for that segment; ``upper`` is lowered in place to the distance of the nearest
        node surface point seen (its triangle is then among the pairs, so the nearest triangle within the cut-off
        stays)."""
        k = len(p0)
        top = len(self.levels[0])
        seg, node = np.repeat(np.arange(k), top), np.tile(np.arange(top), k)
        for depth in range(len(self.levels)):
            lower, to_point = self._bounds(depth, p0, p1, seg, node)
            group_min(seg, to_point, upper)
            keep = lower <= upper[seg] + slack
            seg, node = seg[keep], node[keep]
            if depth + 1 < len(self.levels):
                seg, node = np.repeat(seg, BRANCH), (node[:, None] * BRANCH + np.arange(BRANCH)).ravel()
        return self._leaves(seg, node)
