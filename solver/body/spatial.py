"""Rotations and rigid motions: skew, SO(3) exp/log and the inverse left Jacobian, quaternions.

Conventions: rotation matrices act on column vectors; quaternions are (w, x, y, z); angles in rad.
"""

from __future__ import annotations

import math

import numpy as np

_SMALL = 1e-8


def skew(v: np.ndarray) -> np.ndarray:
    """Cross-product matrix [v]x of a 3-vector (or a stack of them, shape (..., 3) -> (..., 3, 3))."""
    v = np.asarray(v, dtype=float)
    if v.shape == (3,):
        x, y, z = v.tolist()
        return np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])
    out = np.zeros(v.shape[:-1] + (3, 3))
    out[..., 0, 1] = -v[..., 2]
    out[..., 0, 2] = v[..., 1]
    out[..., 1, 0] = v[..., 2]
    out[..., 1, 2] = -v[..., 0]
    out[..., 2, 0] = -v[..., 1]
    out[..., 2, 1] = v[..., 0]
    return out


def exp_so3(w: np.ndarray) -> np.ndarray:
    """Rotation matrix of the rotation vector w (axis * angle, rad)."""
    w = np.asarray(w, dtype=float)
    angle = float(np.linalg.norm(w))
    k = skew(w)
    if angle < _SMALL:
        return np.eye(3) + k + 0.5 * k @ k
    return np.eye(3) + (np.sin(angle) / angle) * k + ((1.0 - np.cos(angle)) / angle**2) * k @ k


def log_so3(r: np.ndarray) -> np.ndarray:
    """Rotation vector (axis * angle, angle in [0, pi]) of the rotation matrix r."""
    (r00, r01, r02), (r10, r11, r12), (r20, r21, r22) = np.asarray(r, dtype=float).tolist()
    cos_angle = min(1.0, max(-1.0, (r00 + r11 + r22 - 1.0) * 0.5))
    angle = math.acos(cos_angle)
    vee = (r21 - r12, r02 - r20, r10 - r01)
    if angle < 1e-6:
        return np.array(vee) * 0.5
    if math.pi - angle > 1e-4:
        k = angle / (2.0 * math.sin(angle))
        return np.array(vee) * k
    # Near pi the antisymmetric part vanishes: take the axis from the symmetric part.
    r = np.asarray(r, dtype=float)
    sym = 0.5 * (r + r.T) - cos_angle * np.eye(3)
    col = int(np.argmax(np.diag(sym)))
    axis = sym[:, col] / np.sqrt(max(sym[col, col], _SMALL))
    if axis @ np.array(vee) < 0.0:
        axis = -axis
    return axis / np.linalg.norm(axis) * angle


def left_jacobian_inverse_so3(w: np.ndarray) -> np.ndarray:
    """Inverse left Jacobian of SO(3): d log(exp([d] ) exp(w)) / d d at d = 0.

    If r = log(R) and R is perturbed on the left, R' = exp([d]) R, then dr = J_l^-1(r) d exactly to first
    order. Used for the exact Jacobian of the rotation error (not only the small-error identity).
    """
    x, y, z = np.asarray(w, dtype=float).tolist()
    angle2 = x * x + y * y + z * z
    angle = math.sqrt(angle2)
    if angle < 1e-5:
        coef = 1.0 / 12.0
    else:
        half = 0.5 * angle
        coef = (1.0 - half * math.cos(half) / math.sin(half)) / angle2
    # I - K/2 + coef K^2 with K = [w]x and K^2 = w w^T - |w|^2 I
    d = 1.0 - coef * angle2
    return np.array(
        [
            [d + coef * x * x, 0.5 * z + coef * x * y, -0.5 * y + coef * x * z],
            [-0.5 * z + coef * x * y, d + coef * y * y, 0.5 * x + coef * y * z],
            [0.5 * y + coef * x * z, -0.5 * x + coef * y * z, d + coef * z * z],
        ]
    )


def quat_to_matrix(q: np.ndarray) -> np.ndarray:
    """Rotation matrix of a quaternion (w, x, y, z); the quaternion is normalised first."""
    q = np.asarray(q, dtype=float)
    norm = length(q)  # np.linalg.norm's number
    if not math.isfinite(norm) or norm < _SMALL:
        raise ValueError("a rotation quaternion must be finite and non-zero")
    w, x, y, z = (q / norm).tolist()  # Python floats: the same IEEE arithmetic, no numpy scalar per product
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


def matrix_to_quat(r: np.ndarray) -> np.ndarray:
    """Quaternion (w, x, y, z) with w >= 0 of a rotation matrix."""
    r = np.asarray(r, dtype=float).tolist()  # Python floats: the same IEEE arithmetic, no array per number
    trace = r[0][0] + r[1][1] + r[2][2]
    if trace > 0.0:
        s = 2.0 * math.sqrt(trace + 1.0)
        q = np.array([0.25 * s, (r[2][1] - r[1][2]) / s, (r[0][2] - r[2][0]) / s, (r[1][0] - r[0][1]) / s])
    else:
        diagonal = [r[0][0], r[1][1], r[2][2]]
        i = diagonal.index(max(diagonal))  # the first of equal ones, as np.argmax
        j, k = (i + 1) % 3, (i + 2) % 3
        s = 2.0 * math.sqrt(max(1.0 + r[i][i] - r[j][j] - r[k][k], _SMALL))
        q = np.zeros(4)
        q[0] = (r[k][j] - r[j][k]) / s
        q[1 + i] = 0.25 * s
        q[1 + j] = (r[j][i] + r[i][j]) / s
        q[1 + k] = (r[k][i] + r[i][k]) / s
    q /= np.linalg.norm(q)
    return q if q[0] >= 0.0 else -q


_NEXT = np.array([1, 2, 0])  # component i+1 (mod 3) of a 3-vector
_AFTER_NEXT = np.array([2, 0, 1])  # component i+2 (mod 3)


def length(v: np.ndarray) -> float:
    """``np.linalg.norm`` of a float vector: the square root of its dot product with itself, as ``norm`` computes it
    (the same number), without ``norm``'s overhead on a 3-vector."""
    return math.sqrt(v.dot(v))


def cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Row-wise cross product of (..., 3) arrays (broadcasting); much cheaper than np.cross for small stacks.

    Component i is a[i+1] b[i+2] - a[i+2] b[i+1] (indices mod 3), all three at once.
    """
    return a.take(_NEXT, axis=-1) * b.take(_AFTER_NEXT, axis=-1) - a.take(_AFTER_NEXT, axis=-1) * b.take(_NEXT, axis=-1)


def slerp(q0: np.ndarray, q1: np.ndarray, t: float) -> np.ndarray:
    """Spherical linear interpolation of unit quaternions (w, x, y, z), t in [0, 1], along the short arc."""
    return Arc(q0, q1).at(t)


class Arc:
    """The short arc from quaternion ``q0`` to ``q1`` (w, x, y, z; normalised here), for :func:`slerp` at many t:
    what does not depend on t (the ends, their angle and its sine) is computed once."""

    def __init__(self, q0: np.ndarray, q1: np.ndarray) -> None:
        q0 = np.asarray(q0, dtype=float) / np.linalg.norm(q0)
        q1 = np.asarray(q1, dtype=float) / np.linalg.norm(q1)
        dot = float(q0 @ q1)
        if dot < 0.0:
            q1, dot = -q1, -dot
        self.q0, self.q1 = q0, q1
        self.near = dot > 0.9995  # nearly the same: a normalised linear blend
        self.delta = q1 - q0
        # the same ends: at(t) is q0 + t * 0 normalised, the same bits for every t >= 0 (t * +-0.0 is +-0.0)
        self.still = self.near and not self.delta.any()
        self.angle = 0.0 if self.near else np.arccos(dot)  # (a dot a rounding above 1 has no arccos)
        self.sin = np.sin(self.angle)

    def at(self, t: float) -> np.ndarray:
        """The unit quaternion ``t`` (0..1) of the way from ``q0`` to ``q1``."""
        if self.near:
            q = self.q0 + t * self.delta
            return q / length(q)
        angle = self.angle
        return (np.sin((1.0 - t) * angle) * self.q0 + np.sin(t * angle) * self.q1) / self.sin
