"""The swept check's certificate from lower bounds in one loop (the kernel of
:meth:`solver.collision.sweep.SweptBody.any_uncertain`: a long motion's frames mostly end there, nothing near).

Units: m. The same sums in the same order as ``SweptBody.uncertain(d_p - relative(first), d_p - relative(second),
way)``: a pair's motion is its capsule's, plus its partner's for a self pair.
"""

from __future__ import annotations

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
