"""Sums over subtrees and over ancestors in a tree of links, in O(n) by prefix sums in depth-first order.

In depth-first preorder every subtree is one contiguous run [start, end), so its sum is the difference of two
prefix sums; a link's ancestors are the links whose run contains its position: those entered up to it minus
those whose run closed before it. This replaces products with dense (n, n) descendant matrices (O(n^2) per
column, and 200 kB each to keep in cache) in statics and comfort. Values are summed in any units.
"""

from __future__ import annotations

import numpy as np


class TreeSums:
    """Subtree and ancestor sums for the tree given by ``parent`` (parent[i] < 0 for a root)."""

    def __init__(self, parent: np.ndarray) -> None:
        parent = np.asarray(parent, dtype=int)
        n = len(parent)
        children: list[list[int]] = [[] for _ in range(n)]
        for k in range(n):
            if parent[k] >= 0:
                children[int(parent[k])].append(k)
        order: list[int] = []
        end = np.zeros(n, dtype=int)
        for root in (k for k in range(n) if parent[k] < 0):
            stack = [(root, False)]
            while stack:
                k, closing = stack.pop()
                if closing:
                    end[k] = len(order)
                    continue
                order.append(k)
                stack.append((k, True))
                stack.extend((c, False) for c in reversed(children[k]))
        self.order = np.array(order, dtype=int)  # links in preorder
        self.start = np.empty(n, dtype=int)
        self.start[self.order] = np.arange(n)  # position of each link in the preorder
        self.end = end  # one past the last position of its subtree
        self.by_end = np.argsort(end, kind="stable")  # links in the order their runs close
        self.closed_before = np.searchsorted(end[self.by_end], self.start, side="right")  # runs closed by then
        self.after = self.start + 1  # prefix length that includes the link itself

    def subtree(self, values: np.ndarray) -> np.ndarray:
        """(n, k): per link, the sum of ``values`` (n, k) over its subtree, itself included."""
        prefix = np.zeros((len(values) + 1,) + values.shape[1:])
        np.cumsum(values.take(self.order, axis=0), axis=0, out=prefix[1:])
        return prefix.take(self.end, axis=0) - prefix.take(self.start, axis=0)

    def ancestors(self, values: np.ndarray) -> np.ndarray:
        """(n, k): per link, the sum of ``values`` (n, k) over its ancestors, itself included."""
        entered = np.zeros((len(values) + 1,) + values.shape[1:])
        np.cumsum(values.take(self.order, axis=0), axis=0, out=entered[1:])
        closed = np.zeros_like(entered)
        np.cumsum(values.take(self.by_end, axis=0), axis=0, out=closed[1:])
        return entered.take(self.after, axis=0) - closed.take(self.closed_before, axis=0)


def descendants(parent: np.ndarray) -> np.ndarray:
    """(n, n) bool: [j, k] when link k is in the subtree of link j, itself included (parent[i] < 0 for a root).

    Each walk up stops after n steps, so a cycle of parents (a malformed file) cannot loop forever."""
    n = len(parent)
    below = np.zeros((n, n), dtype=bool)
    for k in range(n):
        j, steps = k, 0
        while j >= 0 and steps <= n:
            below[j, k] = True
            j, steps = int(parent[j]), steps + 1
    return below
