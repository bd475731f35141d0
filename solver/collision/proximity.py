"""What a distance query returns: per capsule (or per pair of capsules) the distance, witnesses and normal."""

from __future__ import annotations

from collections.abc import Callable
from typing import NamedTuple

import numpy as np


class Proximity(NamedTuple):
    """Per capsule (k rows): ``distance`` (k,) m surface to surface (negative = penetration, +inf = nothing within
    the margin), ``t`` (k,) the witness parameter on the axis, ``point`` (k, 3) the witness p0 + t (p1 - p0),
    ``normal`` (k, 3) unit from the obstacle to the capsule (zero where the distance is +inf) and ``closest``
    (k, 3) the obstacle's surface point paired with the witness (= point - (distance + radius) * normal)."""

    distance: np.ndarray
    t: np.ndarray
    point: np.ndarray
    normal: np.ndarray
    closest: np.ndarray


class PairProximity(NamedTuple):
    """Per pair (i, j) of capsules: ``distance`` (m) surface to surface, witnesses ``point`` = p0[i] + t (p1[i] -
    p0[i]) and ``point_other`` = p0[j] + t_other (p1[j] - p0[j]) on the two axes, and ``normal`` unit from j to i:
    dd/dpoint = normal, dd/dpoint_other = -normal."""

    distance: np.ndarray
    t: np.ndarray
    point: np.ndarray
    t_other: np.ndarray
    point_other: np.ndarray
    normal: np.ndarray


def near_only(p0: np.ndarray, p1: np.ndarray, radii: np.ndarray, margin: float, lo: np.ndarray, hi: np.ndarray,
              exact: Callable[[np.ndarray], Proximity]) -> Proximity:  # fmt: skip
    """Capsules p0-p1 (k, 3) m with ``radii`` (k,) vs an obstacle inside the world box ``lo``..``hi`` (m): ``exact``
    (rows -> their Proximity) only for the capsules whose bounding box, grown by radius + ``margin``, meets it; the
    rest, and rows farther than ``margin``, get distance +inf, t = 0, point = closest = p0 and a zero normal."""
    one = near_only_many(p0, p1, radii, np.array([margin]), lo[None], hi[None], lambda _, rows: exact(rows))
    return one[0]


PairQuery = Callable[[np.ndarray, np.ndarray], Proximity]  # (obstacle, capsule) index rows -> each pair's Proximity


def near_only_many(p0: np.ndarray, p1: np.ndarray, radii: np.ndarray, margins: np.ndarray, lo: np.ndarray,
                   hi: np.ndarray, exact: PairQuery) -> list[Proximity]:  # fmt: skip
    """:func:`near_only` for m obstacles at once (``margins`` (m,), bounding boxes ``lo``, ``hi`` (m, 3)): ``exact``
    takes (obstacle, capsule) index rows and answers each pair; one Proximity (k rows) per obstacle."""
    k, m = len(p0), len(margins)
    reach = radii[None, :, None] + margins[:, None, None]  # (m, k, 1)
    near = np.all((np.maximum(p0, p1)[None] + reach >= lo[:, None]) & (np.minimum(p0, p1)[None] - reach <= hi[:, None]),
                  axis=2)  # fmt: skip
    which, capsule = np.nonzero(near)
    point = np.broadcast_to(p0, (m, k, 3)).copy()
    out = Proximity(np.full((m, k), np.inf), np.zeros((m, k)), point, np.zeros((m, k, 3)), point.copy())
    if which.size:
        got = exact(which, capsule)
        keep = got.distance <= margins[which]
        for mine, theirs in zip(out, got, strict=True):
            mine[which[keep], capsule[keep]] = theirs[keep]
    return [Proximity(*(field[i] for field in out)) for i in range(m)]
