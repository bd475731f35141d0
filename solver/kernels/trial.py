"""A trial point's scaled error and its largest row in one loop (the kernel of
:meth:`solver.problem.problem.Problem.scaled_error_and_worst`, which :class:`solver.iteration.trial.Evaluator` calls
for every trial point).

Units: rows in tolerances, times their weight; ``worst`` takes the weights out again (<= 1: every row met).
"""

from __future__ import annotations

import numpy as np

from . import kernel


@kernel
def scale_rows(err: np.ndarray, weight: np.ndarray, tolerance: np.ndarray, unweight: np.ndarray) -> float:
    """Scale ``err`` in place to ``err * weight / tolerance`` and return the largest ``|err| * unweight`` (0 without
    rows; NaN when a row is NaN), as ``np.max(np.abs(err) * unweight, initial=0.0)`` of NumPy's scaled error."""
    worst = 0.0
    undefined = False
    for i in range(err.shape[0]):
        value = err[i] * weight[i] / tolerance[i]
        err[i] = value
        share = abs(value) * unweight[i]
        if share != share:
            undefined = True
        elif share > worst:
            worst = share
    return np.nan if undefined else worst
