"""The swept check's certificate from lower bounds in one loop (the kernel of
:meth:`solver.collision.sweep.SweptBody.any_uncertain`: a long motion's frames mostly end there, nothing near).

Units: m. The same sums in the same order as ``SweptBody.uncertain(d_p - relative(first), d_p - relative(second),
way)``: a pair's motion is its capsule's, plus its partner's for a self pair.
"""

from __future__ import annotations

import math

import numpy as np

from . import kernel


@kernel
def any_uncertain(pairs: np.ndarray, partner: np.ndarray, d_p: np.ndarray, first: np.ndarray, second: np.ndarray,
                  way: np.ndarray, tolerance: float) -> bool:  # fmt: skip
    """Whether some entry of ``pairs`` (k, c) is not certified: (d_p - r(first)) + (d_p - r(second)) - r(way) <
    -2 ``tolerance``, r(m) the motion (k,) m of the entry's capsule plus its ``partner``'s (>= 0: a self pair)."""
    limit = -2.0 * tolerance
    for k in range(pairs.shape[0]):
        for col in range(pairs.shape[1]):
            if not pairs[k, col]:
                continue
            o = partner[k, col]
            r0 = first[k] if o < 0 else first[k] + first[o]
            r1 = second[k] if o < 0 else second[k] + second[o]
            r2 = way[k] if o < 0 else way[k] + way[o]
            if (d_p[k, col] - r0) + (d_p[k, col] - r1) - r2 < limit:
                return True
    return False


@kernel
def way_bound(theta_a: np.ndarray, theta_b: np.ndarray, a0: np.ndarray, a1: np.ndarray, b0: np.ndarray,
              b1: np.ndarray, weights: np.ndarray, turns: np.ndarray, out: np.ndarray) -> None:  # fmt: skip
    """Fill ``out`` (k,) m: min(L, chord + 1.5 W L) per capsule on the way from joint values ``theta_a`` to
    ``theta_b`` (n,), L = sum |dtheta_j| ``weights[k, j]``, W = sum |dtheta_j| ``turns[k, j]``, the chord the longer
    move of the capsule's ends ``a0``, ``a1`` -> ``b0``, ``b1`` (k, 3) m (NaN passed on, as np.minimum does)."""
    for k in range(out.shape[0]):
        length, turn = 0.0, 0.0
        for j in range(theta_a.shape[0]):
            step = abs(theta_b[j] - theta_a[j])
            length += step * weights[k, j]
            turn += step * turns[k, j]
        c0, c1 = 0.0, 0.0
        for i in range(3):
            c0 += (b0[k, i] - a0[k, i]) * (b0[k, i] - a0[k, i])
            c1 += (b1[k, i] - a1[k, i]) * (b1[k, i] - a1[k, i])
        chord = np.nan if c0 != c0 or c1 != c1 else math.sqrt(c0 if c0 >= c1 else c1)
        other = chord + 1.5 * turn * length
        out[k] = np.nan if length != length or other != other else (length if length < other else other)
