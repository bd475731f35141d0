"""A uniform grid over axis-aligned boxes (2-D or 3-D) answering "which items' boxes overlap this box" in batch.

Items (e.g. triangles) are binned into every cell their box touches; the cell lists are stored flat (CSR). A
query box visits its cells; a pair (query, item) is reported once, in the lowest cell both touch, so no sort or
de-duplication is needed, and pairs come out grouped by query in query order.
"""

from __future__ import annotations

import numpy as np

MAX_CELLS = 1 << 18


def _box_cells(lo: np.ndarray, hi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Every integer cell (owner, cell coordinates (M, D)) of the inclusive cell ranges lo..hi (K, D)."""
    span = hi - lo + 1
    count = np.prod(span, axis=1)
    owner = np.repeat(np.arange(len(lo)), count)
    rest = np.arange(owner.size) - np.repeat(np.cumsum(count) - count, count)
    coords = np.empty((owner.size, lo.shape[1]), dtype=np.int64)
    for d in reversed(range(lo.shape[1])):
        s = span[owner, d]
        coords[:, d] = lo[owner, d] + rest % s
        rest = rest // s
    return owner, coords


class UniformGrid:
    """Boxes ``lo``..``hi`` (N, D) binned in cubic cells of edge ``cell`` (default: the median box extent, made
    coarser until at most MAX_CELLS cells cover all boxes)."""

    def __init__(self, lo: np.ndarray, hi: np.ndarray, cell: float | None = None) -> None:
        lo, hi = np.asarray(lo, dtype=float), np.asarray(hi, dtype=float)
        self.lo, self.hi = lo, hi
        self.origin = lo.min(axis=0)
        extent = np.maximum(hi.max(axis=0) - self.origin, 0.0)
        if cell is None:
            cell = float(np.median(np.max(hi - lo, axis=1)))
        cell = max(cell, float(extent.max()) * 1e-6, 1e-9)
        while np.prod(np.floor(extent / cell) + 1) > MAX_CELLS:
            cell *= 1.25
        self.cell = cell
        self.dims = (np.floor(extent / cell) + 1).astype(np.int64)
        self.item_lo = self._cell_of(lo)
        owner, coords = _box_cells(self.item_lo, self._cell_of(hi))
        ids = self._flat(coords)
        order = np.argsort(ids, kind="stable")
        self.items = owner[order]
        self.starts = np.searchsorted(ids[order], np.arange(int(np.prod(self.dims)) + 1))

    def _cell_of(self, x: np.ndarray) -> np.ndarray:
        return np.clip(np.floor((x - self.origin) / self.cell), 0, self.dims - 1).astype(np.int64)

    def _flat(self, coords: np.ndarray) -> np.ndarray:
        flat = coords[:, 0]
        for d in range(1, coords.shape[1]):
            flat = flat * self.dims[d] + coords[:, d]
        return flat

    def overlapping(self, lo: np.ndarray, hi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Pairs (query index, item index) whose boxes overlap, for query boxes ``lo``..``hi`` (K, D); grouped by
        query, each pair once."""
        lo, hi = np.atleast_2d(lo), np.atleast_2d(hi)
        top = self.origin + self.dims * self.cell
        inside = np.flatnonzero(np.all((hi >= self.origin) & (lo <= top), axis=1))
        q_lo = self._cell_of(np.maximum(lo[inside], self.origin))  # clipped first: boxes may be infinite
        owner, coords = _box_cells(q_lo, self._cell_of(np.minimum(hi[inside], top)))
        cells = self._flat(coords)
        first, last = self.starts[cells], self.starts[cells + 1]
        count = last - first
        query = np.repeat(inside[owner], count)
        slot = np.repeat(first - np.cumsum(count) + count, count) + np.arange(query.size)
        item = self.items[slot]
        # report a pair only in the lowest cell both boxes touch
        here = np.repeat(coords, count, axis=0)
        lowest = np.maximum(np.repeat(q_lo[owner], count, axis=0), self.item_lo[item])
        keep = np.all(here == lowest, axis=1)
        keep &= np.all((self.lo[item] <= hi[query]) & (self.hi[item] >= lo[query]), axis=1)
        return query[keep], item[keep]
