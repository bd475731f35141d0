"""Small dense linear algebra as loops, for kernels that call them: Cholesky factors and their solves, the inverse of
a lower triangle, Gaussian elimination, a copy into a larger array.

The matrices are small (a step's ~24 rows, a quasi-Newton memory's ~12 columns), where a loop costs less than a call
into LAPACK or BLAS; the numbers are LAPACK's to rounding (the order of the sums differs).
"""

from __future__ import annotations

import math

import numpy as np

from . import kernel


@kernel
def cholesky(a: np.ndarray, shift: float, out: np.ndarray) -> bool:
    """Fill ``out`` (m, m) with the lower factor L, L L^T = ``a`` + ``shift`` I (``a`` symmetric; its lower triangle is
    read); False, as LAPACK's dpotrf says info > 0, when a pivot is not positive (or NaN)."""
    m = a.shape[0]
    for j in range(m):
        pivot = a[j, j] + shift
        for p in range(j):
            pivot -= out[j, p] * out[j, p]
        if not pivot > 0.0:
            return False
        diagonal = math.sqrt(pivot)
        out[j, j] = diagonal
        for i in range(j):
            out[i, j] = 0.0
        for i in range(j + 1, m):
            value = a[i, j]
            for p in range(j):
                value -= out[i, p] * out[j, p]
            out[i, j] = value / diagonal
    return True


@kernel
def cholesky_solve(low: np.ndarray, rhs: np.ndarray, out: np.ndarray) -> None:
    """``out`` = (L L^T)^-1 ``rhs`` for the lower factor ``low`` (``out`` may be ``rhs``)."""
    m = low.shape[0]
    for i in range(m):  # L w = rhs
        value = rhs[i]
        for p in range(i):
            value -= low[i, p] * out[p]
        out[i] = value / low[i, i]
    for i in range(m - 1, -1, -1):  # L^T out = w
        value = out[i]
        for p in range(i + 1, m):
            value -= low[p, i] * out[p]
        out[i] = value / low[i, i]


@kernel
def lower_inverse(low: np.ndarray, out: np.ndarray) -> None:
    """``out`` = L^-1 (lower triangular, zeros above) for the lower triangle ``low``."""
    m = low.shape[0]
    for j in range(m):
        for i in range(j):
            out[i, j] = 0.0
        out[j, j] = 1.0 / low[j, j]
        for i in range(j + 1, m):
            value = 0.0
            for p in range(j, i):
                value -= low[i, p] * out[p, j]
            out[i, j] = value / low[i, i]


@kernel
def gauss_solve(a: np.ndarray, rhs: np.ndarray, work: np.ndarray, out: np.ndarray) -> bool:
    """``out`` = ``a``^-1 ``rhs`` by Gaussian elimination with partial pivoting (as LAPACK's dgesv), ``work`` (m, m)
    a scratch copy; False, as dgesv says info > 0, when a pivot is exactly zero."""
    m = a.shape[0]
    for i in range(m):
        out[i] = rhs[i]
        for j in range(m):
            work[i, j] = a[i, j]
    for j in range(m):
        best, row = abs(work[j, j]), j
        for i in range(j + 1, m):
            if abs(work[i, j]) > best:
                best, row = abs(work[i, j]), i
        if work[row, j] == 0.0:
            return False
        if row != j:
            for p in range(m):
                work[j, p], work[row, p] = work[row, p], work[j, p]
            out[j], out[row] = out[row], out[j]
        for i in range(j + 1, m):
            factor = work[i, j] / work[j, j]
            for p in range(j + 1, m):
                work[i, p] -= factor * work[j, p]
            out[i] -= factor * out[j]
    for i in range(m - 1, -1, -1):
        value = out[i]
        for p in range(i + 1, m):
            value -= work[i, p] * out[p]
        out[i] = value / work[i, i]
    return True


@kernel
def copy_into(source: np.ndarray, target: np.ndarray) -> None:
    """``target``[:m, :k] = ``source`` (m, k), as a loop: Numba compiles a slice assignment for seconds."""
    m, k = source.shape
    for i in range(m):
        for j in range(k):
            target[i, j] = source[i, j]
