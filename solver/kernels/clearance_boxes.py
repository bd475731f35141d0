"""Capsules vs several boxes and vs the carried box, the bounds test and the rows in one loop (the kernels of
:func:`solver.collision.kinds.box.boxes_distance` and
:meth:`solver.constraints.carried_clearance.CarriedClearance._distances`).

Units: m. Each measured row is :func:`~solver.kernels.clearance_box.box_row_apart`'s; a row whose axis meets or only
touches its box is marked in ``rare`` and left to the caller (which asks :func:`solver.collision.boxes.box_rows`), as
NumPy's per-call cost on a few rows of many small arrays is what these loops save.
"""

from __future__ import annotations

import numpy as np

from . import kernel
from .clearance_box import box_row_apart


@kernel
def boxes_near_rows(
    p0: np.ndarray,
    p1: np.ndarray,
    radii: np.ndarray,
    margins: np.ndarray,
    lo: np.ndarray,
    hi: np.ndarray,
    center: np.ndarray,
    rotation: np.ndarray,
    half: np.ndarray,
    far: np.ndarray,
    finite: bool,
    distance: np.ndarray,
    t_out: np.ndarray,
    point: np.ndarray,
    normal: np.ndarray,
    closest: np.ndarray,
    rare: np.ndarray,
) -> int:
    """Capsules p0-p1 (k, 3) of ``radii`` (k,) vs m boxes (``center`` (m, 3), ``rotation`` (m, 3, 3), ``half``
    (m, 3)), row i k + c for box i and capsule c (``distance``, ``t_out`` (m k,), ``point``, ``normal``, ``closest``
    (m k, 3)): measured where the capsule's bounds grown by radius + ``margins[i]`` meet the box's bounds ``lo[i]``,
    ``hi[i]``, kept where the distance is <= ``margins[i]``; elsewhere distance ``far[i]``, t 0, point and closest
    p0, normal 0 (as :func:`solver.collision.proximity.near_only_many`); with ``finite``, a kept distance that is not
    finite is ``far[i]`` too. Rows whose axis meets or touches the box: ``rare`` 1 or 2 (else 0), their fields the
    defaults. Returns how many."""
    k, count, work = p0.shape[0], 0, np.empty(26)
    for i in range(lo.shape[0]):
        for c in range(k):
            o = i * k + c
            reach = radii[c] + margins[i]
            near = True
            for j in range(3):
                top, bottom = max(p0[c, j], p1[c, j]), min(p0[c, j], p1[c, j])
                if not (top + reach >= lo[i, j] and bottom - reach <= hi[i, j]):
                    near = False
            rare[o] = 0
            if near:
                rare[o] = box_row_apart(p0, p1, radii, c, center, i, rotation, i, half, i, distance, t_out, point,
                                        normal, closest, o, work)  # fmt: skip
                count += rare[o] != 0
                if rare[o] == 0 and distance[o] <= margins[i]:
                    if finite and not np.isfinite(distance[o]):
                        distance[o] = far[i]
                    continue
            distance[o], t_out[o] = far[i], 0.0
            for j in range(3):
                point[o, j], closest[o, j], normal[o, j] = p0[c, j], p0[c, j], 0.0
    return count


@kernel
def carried_capsule_rows(
    p0: np.ndarray,
    p1: np.ndarray,
    radii: np.ndarray,
    center: np.ndarray,
    rotation: np.ndarray,
    half: np.ndarray,
    margin: float,
    distance: np.ndarray,
    t_out: np.ndarray,
    point: np.ndarray,
    normal: np.ndarray,
    closest: np.ndarray,
    rare: np.ndarray,
) -> int:
    """Capsules p0-p1 (k, 3) of ``radii`` vs the one box ``center`` (1, 3), ``rotation`` (1, 3, 3), ``half`` (1, 3):
    measured where the capsule's box-frame bounds grown by radius + ``margin`` meet the box; elsewhere distance
    margin + 1, point p0, normal 0. Rows whose axis meets or touches the box: ``rare`` 1 or 2 (else 0), their fields
    unset. Returns how many."""
    count, work, a, b = 0, np.empty(26), np.empty(3), np.empty(3)
    for c in range(p0.shape[0]):
        for j in range(3):  # box coordinates: (p - center) @ rotation, as the NumPy path's bounds test
            a[j] = (p0[c, 0] - center[0, 0]) * rotation[0, 0, j] + (p0[c, 1] - center[0, 1]) * rotation[0, 1, j]
            a[j] += (p0[c, 2] - center[0, 2]) * rotation[0, 2, j]
            b[j] = (p1[c, 0] - center[0, 0]) * rotation[0, 0, j] + (p1[c, 1] - center[0, 1]) * rotation[0, 1, j]
            b[j] += (p1[c, 2] - center[0, 2]) * rotation[0, 2, j]
        reach = radii[c] + margin
        near = True
        for j in range(3):
            if not (min(a[j], b[j]) - reach <= half[0, j] and max(a[j], b[j]) + reach >= -half[0, j]):
                near = False
        rare[c] = 0
        if near:
            rare[c] = box_row_apart(p0, p1, radii, c, center, 0, rotation, 0, half, 0, distance, t_out, point,
                                    normal, closest, c, work)  # fmt: skip
            count += rare[c] != 0
            continue
        distance[c], t_out[c] = margin + 1.0, 0.0
        for j in range(3):
            point[c, j], closest[c, j], normal[c, j] = p0[c, j], p0[c, j], 0.0
    return count
