"""A bounding-volume tree over triangles for nearest-triangle searches from many segments at once.

Triangles are put in k-d tree order by their centroids, so runs of neighbours in the order are compact in
space; 8 consecutive triangles form a leaf and 8 consecutive nodes a parent, up to a top level of at most TOP
nodes. Every node keeps its box. A search walks down level by level for all segments together, keeping a node
only while its lower bound (bounding sphere and box gap) does not exceed a cut-off per segment, so the work
follows the nodes near the answer.
"""

from __future__ import annotations

import numpy as np

from .closest import dot, point_segment

BRANCH = 8
TOP = 64


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
    """A level's arrays (lo, hi, center, radius) extended with far-away empty nodes to ``size`` entries."""
    extra = size - len(level[0])
    return tuple(np.concatenate([x, np.full((extra, *x.shape[1:]), FAR if x.ndim > 1 else 0.0)]) for x in level)


class TriangleTree:
    """The tree over triangles a, b, c (F, 3); ``order`` maps tree slots to triangle indices. Every level but the
    top is padded so that node i's children are exactly BRANCH * i + (0..BRANCH-1)."""

    def __init__(self, a: np.ndarray, b: np.ndarray, c: np.ndarray) -> None:
        self.order = kd_order((a + b + c) / 3.0)
        tri = np.stack([a, b, c], axis=1)[self.order]
        lo, hi = tri.min(axis=1), tri.max(axis=1)
        levels: list[tuple[np.ndarray, ...]] = []
        while len(lo) > TOP or not levels:
            starts = np.arange(0, len(lo), BRANCH)
            lo, hi = np.minimum.reduceat(lo, starts), np.maximum.reduceat(hi, starts)
            levels.append((lo, hi, 0.5 * (lo + hi), 0.5 * np.sqrt(dot(hi - lo, hi - lo))))
        levels.reverse()  # top first; the last level's children are triangle slots
        self.levels = [levels[0]] + [_pad(lv, BRANCH * len(up[0])) for up, lv in zip(levels, levels[1:], strict=False)]
        self.size = len(a)

    def _lower(self, depth: int, p0, p1, seg, node) -> tuple[np.ndarray, np.ndarray]:
        """Lower bounds (m) of the distance from segments to the nodes (bounding sphere and box gap), and the
        distances to the nodes' centers."""
        lo, hi, center, radius = self.levels[depth]
        _, near = point_segment(center[node], p0[seg], p1[seg])
        gap = near - center[node]
        box = np.maximum(np.maximum(lo[node] - np.maximum(p0, p1)[seg], np.minimum(p0, p1)[seg] - hi[node]), 0.0)
        to_center = np.sqrt(dot(gap, gap))
        return np.maximum(to_center - radius[node], np.sqrt(dot(box, box))), to_center

    def _leaves(self, seg: np.ndarray, node: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        slot = (node[:, None] * BRANCH + np.arange(BRANCH)).ravel()
        seg = np.repeat(seg, BRANCH)
        real = slot < self.size
        return seg[real], slot[real]

    def descend(self, p0: np.ndarray, p1: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Pairs (segment, triangle slot): the triangles of one promising leaf per segment, found by always taking
        the child whose center is nearest (a guess that gives a first upper bound, not a search)."""
        k = len(p0)
        top = len(self.levels[0][0])
        node = np.tile(np.arange(top), (k, 1))
        for depth in range(len(self.levels)):
            seg = np.repeat(np.arange(k), node.shape[1])
            to_center = self._lower(depth, p0, p1, seg, node.ravel())[1].reshape(node.shape)
            best = node[np.arange(k), np.argmin(to_center, axis=1)]
            node = best[:, None] * BRANCH + np.arange(BRANCH)
        return self._leaves(np.arange(k), best)

    def search(self, p0: np.ndarray, p1: np.ndarray, cut: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Pairs (segment, triangle slot), grouped by segment, under every node whose lower bound is at most
        ``cut`` (k,) m for that segment."""
        k = len(p0)
        top = len(self.levels[0][0])
        seg, node = np.repeat(np.arange(k), top), np.tile(np.arange(top), k)
        for depth in range(len(self.levels)):
            keep = self._lower(depth, p0, p1, seg, node)[0] <= cut[seg]
            seg, node = seg[keep], node[keep]
            if depth + 1 < len(self.levels):
                seg, node = np.repeat(seg, BRANCH), (node[:, None] * BRANCH + np.arange(BRANCH)).ravel()
        return self._leaves(seg, node)
