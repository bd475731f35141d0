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


@kernel
def step_point(
    x: np.ndarray,
    alpha: float,
    direction: np.ndarray,
    task: np.ndarray,
    scale: np.ndarray,
    lower: np.ndarray,
    upper: np.ndarray,
    out: np.ndarray,
) -> None:
    """Fill ``out`` with the trial point ``np.clip(x + alpha * direction * scale, lower, upper)`` (empty ``task``) or,
    with ``task`` given, ``np.clip(x + (task + alpha * direction) * scale, lower, upper)``: NumPy's operations in its
    order, and np.clip's choices (a NaN stays, a bound is taken when not strictly inside it)."""
    whole = task.shape[0] == 0
    for i in range(x.shape[0]):
        if whole:
            value = x[i] + alpha * direction[i] * scale[i]
        else:
            value = x[i] + (task[i] + alpha * direction[i]) * scale[i]
        if value == value:  # np.clip: min(max(value, lower), upper), a NaN kept
            value = value if value > lower[i] else lower[i]
            if value == value:
                value = value if value < upper[i] else upper[i]
        out[i] = value


@kernel
def linear_phi(beta: np.ndarray, offset: np.ndarray, column: np.ndarray, weight: np.ndarray, out: np.ndarray) -> None:
    """Fill ``out`` (n_x,) with x = offset + basis @ beta of a linear reduction, its basis by x row (the ``column`` of
    each row's one nonzero, -1 for none; its ``weight``), as ``Reduction.phi`` sums it (a row without one adds 0.0)."""
    for i in range(out.shape[0]):
        c = column[i]
        out[i] = offset[i] + (weight[i] * beta[c] if c >= 0 else 0.0)
