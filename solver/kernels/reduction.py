"""The live Jacobian's rows in the solver's scaled variables: through a linear reduction's basis and scaled, in one
loop (the kernel of :meth:`solver.problem.problem.Problem.live_jacobian`).

Row i of the output is (jac[i] @ basis) * row_scale[live[i]] * scale. The basis's columns have disjoint supports,
so each x column j adds to at most one variable, ``column[j]`` (-1: none), with the weight ``weight[j]``; the sums
run over the row's nonzeros in x order, as the NumPy path adds each column's rows. Without a reduction (empty
``column``) each x column is its own variable, weight 1: the scaling alone.
"""

from __future__ import annotations

import numpy as np

from . import kernel


@kernel
def reduce_and_scale(
    jac: np.ndarray,
    live: np.ndarray,
    row_scale: np.ndarray,
    scale: np.ndarray,
    column: np.ndarray,
    weight: np.ndarray,
    out: np.ndarray,
) -> None:
    """Fill ``out`` (k, n_var) from ``jac`` (k, n_x), the row scales of the ``live`` rows and the variables'
    ``scale`` (n_var,)."""
    identity = column.shape[0] == 0
    for i in range(jac.shape[0]):
        for c in range(out.shape[1]):
            out[i, c] = 0.0
        used = False
        for j in range(jac.shape[1]):
            value = jac[i, j]
            if value != 0.0:  # NaN counts, as in the NumPy path
                if identity:
                    out[i, j] = value
                elif column[j] >= 0:
                    out[i, column[j]] += value * weight[j]
                used = True
        if used:
            factor = row_scale[live[i]]
            for c in range(out.shape[1]):
                out[i, c] = out[i, c] * factor * scale[c]
