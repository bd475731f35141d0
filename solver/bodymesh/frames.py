"""Small geometry for the body fit: orthonormal frames from two directions, and the affine map taking one
scaled frame onto another. Plain NumPy; lengths in m, affines as (3x3 linear part, translation m)."""

from __future__ import annotations

import numpy as np

Affine = tuple[np.ndarray, np.ndarray]  # (A 3x3, t (3,)): p -> A @ p + t
_TINY = 1e-12


def unit(v: np.ndarray) -> np.ndarray:
    n = float(np.linalg.norm(v))
    return v / n if n > _TINY else v * 0.0


def frame(along: np.ndarray, toward: np.ndarray) -> np.ndarray:
    """Columns e1 = along, e2 = ``toward`` made orthogonal to it, e3 = e1 x e2 (right-handed, orthonormal).
    If ``toward`` is parallel to ``along``, a basis axis stands in for it."""
    e1 = unit(np.asarray(along, dtype=float))
    e2 = np.asarray(toward, dtype=float) - e1 * float(e1 @ toward)
    if np.linalg.norm(e2) < 1e-6:
        axis = np.eye(3)[int(np.argmin(np.abs(e1)))]
        e2 = axis - e1 * float(e1 @ axis)
    e2 = unit(e2)
    return np.column_stack([e1, e2, np.cross(e1, e2)])


def rotation_about(axis: np.ndarray, angle: float) -> np.ndarray:
    """Rotation matrix of ``angle`` rad about unit ``axis`` (Rodrigues)."""
    k = unit(axis)
    skew = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    return np.eye(3) + np.sin(angle) * skew + (1.0 - np.cos(angle)) * skew @ skew


def signed_angle(a: np.ndarray, b: np.ndarray, axis: np.ndarray) -> float:
    """Angle (rad) turning ``a`` onto ``b`` about ``axis``, both seen in the plane normal to it."""
    k = unit(axis)
    a, b = a - k * (k @ a), b - k * (k @ b)
    return float(np.arctan2(k @ np.cross(a, b), a @ b))


def frame_map(source: np.ndarray, target: np.ndarray, scales: np.ndarray, at: np.ndarray, to: np.ndarray) -> Affine:
    """The affine taking point ``at`` to ``to`` and source frame axis k (scaled by ``scales[k]``) onto target
    frame axis k: A = T diag(scales) S^T, t = to - A at."""
    linear = target @ np.diag(scales) @ source.T
    return linear, np.asarray(to, dtype=float) - linear @ at


def apply(affine: Affine, points: np.ndarray) -> np.ndarray:
    linear, shift = affine
    return points @ linear.T + shift
