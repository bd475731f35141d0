"""A way as per-frame points: positions at given shares of its arc length (the timing law, e.g. a minimum-jerk
profile s(t) = 10 t^3 - 15 t^4 + 6 t^5 (Flash & Hogan 1985), is the caller's: the operations generator's)."""

from __future__ import annotations

import numpy as np


def arc_lengths(points: np.ndarray) -> np.ndarray:
    """(k,) the distance along the polyline ``points`` (k, 3) m from its first point to each, m."""
    points = np.asarray(points, dtype=float)
    return np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(points, axis=0), axis=1))])


def at_shares(points: np.ndarray, shares) -> np.ndarray:
    """The points (q, 3) m at ``shares`` (q,) of the arc length of the polyline ``points`` (k, 3) m (0: its first
    point, 1: its last; clipped to 0..1), linearly along the piece each falls on. A way of length 0 (one point, or
    all the same) gives its first point everywhere."""
    points = np.asarray(points, dtype=float)
    s = np.clip(np.asarray(shares, dtype=float), 0.0, 1.0)
    along = arc_lengths(points)
    total = along[-1]
    if total <= 0.0:
        return np.repeat(points[:1], len(s), axis=0)
    return np.stack([np.interp(s * total, along, points[:, i]) for i in range(3)], axis=1)
