"""Arrays -> the plain values JSON and TOML writers take: lists of floats, quaternions, null for unlimited."""

from __future__ import annotations

import math

import numpy as np

from ..body.spatial import matrix_to_quat


def floats(v: np.ndarray) -> list[float]:
    """A vector as a list of Python floats."""
    return np.asarray(v, dtype=float).tolist()


def quaternion(rotation: np.ndarray) -> list[float]:
    """The quaternion [w, x, y, z] (w >= 0) of a rotation matrix."""
    return floats(matrix_to_quat(np.asarray(rotation, dtype=float)))


def finite_or_none(v: float) -> float | None:
    """A limit as written: the number, or None (JSON null) when unlimited."""
    return float(v) if math.isfinite(v) else None
