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


@kernel
def comfort_model(
    grad: np.ndarray,
    curv: np.ndarray,
    rows: np.ndarray,
    weight: np.ndarray,
    starts: np.ndarray,
    scale: np.ndarray,
    grad_f: np.ndarray,
    curv_f: np.ndarray,
) -> None:
    """Fill ``grad_f`` = -(grad @ basis) * scale and ``curv_f`` = (curv @ basis**2) * scale**2 (n_var,) from the
    comfort's dh/dx and curvature (n_x,), the basis's nonzeros by column (x ``rows``, their ``weight``, each column's
    first entry ``starts``; every column has one). Each column's products are summed as NumPy's ``add.reduceat``
    sums them (the first, then the rest pairwise in eight lanes), so the numbers are the NumPy path's to the bit."""
    count, total = starts.shape[0], rows.shape[0]
    lanes = np.empty(8)
    for part in range(2):
        values = grad if part == 0 else curv
        for c in range(count):
            begin = starts[c]
            end = starts[c + 1] if c + 1 < count else total
            w = weight[begin] if part == 0 else weight[begin] * weight[begin]
            first = values[rows[begin]] * w
            rest = 0.0
            m = end - begin - 1
            if m < 8:
                for k in range(begin + 1, end):
                    w = weight[k] if part == 0 else weight[k] * weight[k]
                    rest += values[rows[k]] * w
            else:
                for lane in range(8):
                    k = begin + 1 + lane
                    w = weight[k] if part == 0 else weight[k] * weight[k]
                    lanes[lane] = values[rows[k]] * w
                i = 8
                while i < m - (m % 8):
                    for lane in range(8):
                        k = begin + 1 + i + lane
                        w = weight[k] if part == 0 else weight[k] * weight[k]
                        lanes[lane] += values[rows[k]] * w
                    i += 8
                rest = ((lanes[0] + lanes[1]) + (lanes[2] + lanes[3])) + ((lanes[4] + lanes[5]) + (lanes[6] + lanes[7]))
                while i < m:
                    k = begin + 1 + i
                    w = weight[k] if part == 0 else weight[k] * weight[k]
                    rest += values[rows[k]] * w
                    i += 1
            total_c = first + rest
            if part == 0:
                grad_f[c] = -total_c * scale[c]
            else:
                curv_f[c] = total_c * (scale[c] * scale[c])
