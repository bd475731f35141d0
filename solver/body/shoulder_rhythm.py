"""The Högfors et al. (1991) shoulder rhythm (thesis 4.1.2): two variables drive the nine joints of a shoulder.

Per shoulder, ``alpha_h`` in [-10, 90] deg and ``beta_h`` in [-90, -30] deg (the thesis's ranges; our variables
are in rad) give the orientations of clavicle (c), scapula (s) and humerus (h) in a thorax frame by the
thesis's formulas (degrees); rest is alpha_h = 0, beta_h = -90 deg. Each orientation is
R(alpha, beta, gamma) = Rz(alpha) Ry(-beta) Rx(gamma) (column vectors) in a thorax frame with x lateral (to the
side of that shoulder), y anterior, z up; the humerus's long axis is its local x, so alpha_h is the plane of
elevation (0 = coronal, 90 deg = sagittal) and beta_h the elevation (-90 deg = hanging, -30 deg = lifted 60 deg).

This frame and product order are OUR reading (the original paper was not available). The thesis writes
Rx(gamma) Ry(-beta) Rz(alpha), which is this product written with coordinate-transformation (passive)
matrices; read literally (active) it is gimbal-locked at rest and alpha_h does not lift the arm. Evidence:

- searching all signed-axis thorax frames, this is the only one in which rest hangs the arm (R_h e_x =
  (0, 0, -1)), (0, -30) deg abducts it 60 deg in the coronal plane and (90, -30) deg flexes it 60 deg forward;
- at beta_h = -90 deg the product is gimbal-locked and depends on gamma_h - alpha_h only, and the formula
  gives gamma_h = -45 + alpha_h there: the arm's rest orientation is the same for every alpha_h, by design;
- the clavicle at rest points lateral, 20 deg back and 9 deg up, and with elevation it elevates and retracts
  while the scapula rotates upward and tilts posteriorly, as shoulders do. The other order that passes the
  arm checks with alpha_h as sagittal lift (Ry(-beta) Rz(alpha) Rx(gamma)) turns the scapula 49 deg
  downward at 60 deg abduction and puts the girdle joints far outside their ranges.

tests/test_reduction.py checks these directions through the model's forward kinematics, both sides.
One oddity stays: with the arm hanging (beta_h = -90 deg) the scapula still follows alpha_h, through gamma_h
in beta_s (about 30 deg at alpha_h = 90 deg), while the glenohumeral joints keep the arm still.

Our joints take the rotations relative to rest, which do not depend on the bones' unknown local axes: with
D_k = R_k R_k(rest)^T the clavicle's three joints make D_c, the scapula's D_c^T D_s, the shoulder's D_s^T D_h,
all conjugated into our world by P = diag(lateral, -1, 1) (the manikin faces -y; lateral is -1 on the right,
+1 on the left, a reflection that gives the left side the mirror image of the right), and decomposed into each
body's X, Y, Z joint sequence (signs from the model's axes). The Jacobian is analytic: the angular velocity of
each relative rotation mapped through the inverse Euler-rate matrix.

Joint ranges: over much of the box's upper part (beta_h > ~-65 deg for alpha_h near 90 deg, the top edge
everywhere) the rhythm asks for more scapular tilt and upward rotation, and then more glenohumeral adduction,
than our (estimated) ranges allow. Shrinking the box would lose most of the elevation, so each body's joints
are clipped to their ranges and the next body's joints are computed from where the clipped body really is:
the humerus keeps its rhythm orientation unless its own joints clip. phi stays continuous and inside the
ranges; a clipped joint's derivative is zero.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import ModelError
from .model import Model

DEG = np.pi / 180.0
LOWER = np.array([-10.0, -90.0]) * DEG  # (alpha_h, beta_h), rad
UPPER = np.array([90.0, -30.0]) * DEG
REST = np.array([0.0, -90.0]) * DEG
JOINTS = tuple(
    f"{bone}_{{s}}_{motion}"
    for bone, motions in (
        ("clavicle", ("rx", "elevation", "protraction")),
        ("scapula", ("tilt", "upward_rotation", "protraction")),
        ("shoulder", ("flexion", "abduction", "rotation")),
    )
    for motion in motions
)
SIDES = {"r": -1.0, "l": 1.0}  # side tag: world x sign of lateral (the manikin's left is +x)


def bone_angles_deg(a: float, b: float, derivatives: bool) -> tuple[list, list]:
    """The thesis's formulas for one shoulder at (alpha_h, beta_h) deg: per bone c, s, h the angles (alpha,
    beta, gamma) deg and (with ``derivatives``) their derivatives w.r.t. alpha_h and beta_h (deg/deg = rad/rad)."""
    e = b + 90.0
    th = 0.5 * e * (1.0 + a / 90.0) * DEG
    k = 135.0 - a / 1.1
    sin_th = math.sin(th)
    gh = -45.0 + a * (1.0 - e / 360.0) + k * sin_th
    u = 0.75 * e * DEG
    c, s = math.cos(u), math.sin(u)
    w = (a + 10.0) * s * DEG
    f = 1.0 - gh / 270.0
    angles = [
        (-50.0 + 30.0 * c, 24.0 * (1.0 - c) * (0.5 + a / 90.0) + 9.0, 15.0 * (1.0 - c) + 3.0),
        (200.0 + 20.0 * c, -140.0 + 94.0 * c * f, 82.0 + 8.0 * math.cos(w)),
        (a, b, gh),
    ]
    if not derivatives:
        return angles, []
    cos_th = math.cos(th)
    gh_a = (1.0 - e / 360.0) - sin_th / 1.1 + k * cos_th * 0.5 * e / 90.0 * DEG
    gh_b = -a / 360.0 + k * cos_th * 0.5 * (1.0 + a / 90.0) * DEG
    c_b, s_b = -s * 0.75 * DEG, c * 0.75 * DEG
    sin_w = math.sin(w) * DEG
    d_a = [(0.0, 24.0 * (1.0 - c) / 90.0, 0.0), (0.0, -94.0 * c * gh_a / 270.0, -8.0 * sin_w * s), (1.0, 0.0, gh_a)]
    d_b = [
        (30.0 * c_b, -24.0 * c_b * (0.5 + a / 90.0), -15.0 * c_b),
        (20.0 * c_b, 94.0 * (c_b * f - c * gh_b / 270.0), -8.0 * sin_w * (a + 10.0) * s_b),
        (0.0, 1.0, gh_b),
    ]
    return angles, [d_a, d_b]


# Rotations are row-major 9-tuples, vectors 3-tuples: two shoulders make arrays too small for NumPy to pay.
Mat = tuple[float, ...]
Vec = tuple[float, float, float]


def _mul(a: Mat, b: Mat) -> Mat:
    """a b."""
    a0, a1, a2, a3, a4, a5, a6, a7, a8 = a
    b0, b1, b2, b3, b4, b5, b6, b7, b8 = b
    return (a0 * b0 + a1 * b3 + a2 * b6, a0 * b1 + a1 * b4 + a2 * b7, a0 * b2 + a1 * b5 + a2 * b8,
            a3 * b0 + a4 * b3 + a5 * b6, a3 * b1 + a4 * b4 + a5 * b7, a3 * b2 + a4 * b5 + a5 * b8,
            a6 * b0 + a7 * b3 + a8 * b6, a6 * b1 + a7 * b4 + a8 * b7, a6 * b2 + a7 * b5 + a8 * b8)  # fmt: skip


def _t(a: Mat) -> Mat:
    """a^T."""
    return (a[0], a[3], a[6], a[1], a[4], a[7], a[2], a[5], a[8])


def _mv(a: Mat, v: Vec) -> Vec:
    """a v."""
    return (a[0] * v[0] + a[1] * v[1] + a[2] * v[2], a[3] * v[0] + a[4] * v[1] + a[5] * v[2],
            a[6] * v[0] + a[7] * v[1] + a[8] * v[2])  # fmt: skip


def _bone(al: float, be: float, ga: float) -> tuple[Mat, Mat]:
    """R = Rz(al) Ry(-be) Rx(ga) (rad) and E (columns e_z, -Rz e_y, Rz Ry e_x): spatial omega = E d(al, be, ga)."""
    ca, sa, cb, sb, cg, sg = math.cos(al), math.sin(al), math.cos(be), math.sin(be), math.cos(ga), math.sin(ga)
    r = (ca * cb, -sa * cg - ca * sb * sg, sa * sg - ca * sb * cg,
         sa * cb, ca * cg - sa * sb * sg, -ca * sg - sa * sb * cg,
         sb, cb * sg, cb * cg)  # fmt: skip
    return r, (0.0, sa, ca * cb, 0.0, -ca, sa * cb, 1.0, 0.0, sb)


def _rxyz(a: float, b: float, c: float) -> tuple[Mat, Mat]:
    """R = Rx(a) Ry(b) Rz(c) (rad) and E (columns e_x, Rx e_y, Rx Ry e_z): spatial omega = E d(a, b, c)."""
    ca, sa, cb, sb, cc, sc = math.cos(a), math.sin(a), math.cos(b), math.sin(b), math.cos(c), math.sin(c)
    r = (cb * cc, -cb * sc, sb,
         sa * sb * cc + ca * sc, ca * cc - sa * sb * sc, -sa * cb,
         sa * sc - ca * sb * cc, ca * sb * sc + sa * cc, ca * cb)  # fmt: skip
    return r, (1.0, 0.0, sb, 0.0, ca, -sa * cb, 0.0, sa, ca * cb)


def _euler_xyz(r: Mat) -> Vec:
    """(a, b, c) with r = Rx(a) Ry(b) Rz(c); |b| stays far below 90 deg for the rhythm."""
    return math.atan2(-r[5], r[8]), math.asin(min(1.0, max(-1.0, r[2]))), math.atan2(-r[1], r[0])


def _euler_rates(e: Vec, w: Vec) -> Vec:
    """d(a, b, c) for a spatial angular velocity w of Rx(a) Ry(b) Rz(c): E^-1 w."""
    ca, sa = math.cos(e[0]), math.sin(e[0])
    c_dot = (ca * w[2] - sa * w[1]) / math.cos(e[1])
    return w[0] - math.sin(e[1]) * c_dot, ca * w[1] + sa * w[2], c_dot


def _side(a: float, b: float, lower: list, upper: list, derivatives: bool) -> tuple[list, list]:
    """One shoulder at (alpha_h, beta_h) rad: thorax-frame Euler angles (9, rad) of its joints, clipped to
    [lower, upper], and (with ``derivatives``) their derivatives [d/d alpha_h, d/d beta_h] (2 x 9).

    Each bone's rotation from rest is D_k = R_k R_k(rest)^T; down the chain a body's joint rotation is
    parent^T D_k with the parent where its clipped joints really put it, with angular velocities alike.
    """
    angles, d_angles = bone_angles_deg(a / DEG, b / DEG, derivatives)
    euler: list[float] = []
    rates: list[list[float]] = [[], []] if derivatives else []
    parent, parent_w = None, [(0.0, 0.0, 0.0)] * len(rates)  # None: the thorax
    for k in range(3):
        r, rate = _bone(angles[k][0] * DEG, angles[k][1] * DEG, angles[k][2] * DEG)
        target = _mul(r, _REST_T[k])
        omega = [_mv(rate, d[k]) for d in d_angles]  # spatial angular velocity of the bone, per variable
        if parent is None:
            rel, rel_w = target, omega
        else:
            pt = _t(parent)
            rel = _mul(pt, target)
            rel_w = [_mv(pt, (w[0] - p[0], w[1] - p[1], w[2] - p[2])) for w, p in zip(omega, parent_w, strict=True)]
        e = _euler_xyz(rel)
        lo, hi = lower[3 * k : 3 * k + 3], upper[3 * k : 3 * k + 3]
        clipped = (min(max(e[0], lo[0]), hi[0]), min(max(e[1], lo[1]), hi[1]), min(max(e[2], lo[2]), hi[2]))
        inside = (e[0] == clipped[0], e[1] == clipped[1], e[2] == clipped[2])
        d = [tuple(x if ok else 0.0 for x, ok in zip(_euler_rates(e, w), inside, strict=True)) for w in rel_w]
        euler += clipped
        for j, dj in enumerate(d):
            rates[j] += dj
        if k == 2:
            break
        if all(inside):  # the body is where the rhythm puts it
            parent, parent_w = target, omega
            continue
        local, local_rate = _rxyz(*clipped)
        local_w = [_mv(local_rate, dj) for dj in d]
        if parent is None:
            parent, parent_w = local, local_w
        else:
            parent_w = [(p[0] + q[0], p[1] + q[1], p[2] + q[2]) for p, q in
                        zip(parent_w, [_mv(parent, lw) for lw in local_w], strict=True)]  # fmt: skip
            parent = _mul(parent, local)
    return euler, rates


_REST_T = [_t(_bone(*(x * DEG for x in row))[0]) for row in bone_angles_deg(0.0, -90.0, False)[0]]
_FREE = (np.full(9, -np.inf), np.full(9, np.inf))


def rhythm_angles(
    ab: np.ndarray, bounds: tuple[np.ndarray, np.ndarray] = _FREE, derivatives: bool = True
) -> tuple[np.ndarray, np.ndarray | None]:
    """Euler angles (m, 9) rad, X, Y, Z for the clavicle, scapula and shoulder joints in the thorax frame, for
    variables ab (m, 2) rad; with ``derivatives`` also d angles / d ab (m, 9, 2).

    Each body's angles are clipped to ``bounds`` (lower, upper, each broadcastable to (m, 9)); the bodies below
    a clipped one take up the difference, so the humerus keeps its rhythm orientation while it can.
    """
    ab = np.atleast_2d(ab)
    lower = np.broadcast_to(bounds[0], (len(ab), 9)).tolist()
    upper = np.broadcast_to(bounds[1], (len(ab), 9)).tolist()
    rows = [_side(a, b, lo, hi, derivatives) for (a, b), lo, hi in zip(ab.tolist(), lower, upper, strict=True)]
    euler = np.array([r[0] for r in rows])
    return euler, np.array([r[1] for r in rows]).transpose(0, 2, 1) if derivatives else None


@dataclass(frozen=True, eq=False)
class ShoulderRhythm:
    """The rhythm on a model's shoulders: per side, (alpha_h, beta_h) rad -> 9 joint values (rad), clipped."""

    sides: tuple[str, ...]
    joints: np.ndarray  # (n_sides, 9) joint indices
    sign: np.ndarray  # (n_sides, 9): joint value = sign * thorax-frame Euler angle
    lower: np.ndarray  # (n_sides, 9) joint ranges, rad
    upper: np.ndarray
    bounds: tuple[np.ndarray, np.ndarray]  # the ranges as bounds on the thorax-frame Euler angles
    table: tuple[np.ndarray, np.ndarray]  # grid (k, 2) rad and its joint values (n_sides, k, 9), for fits
    slope: np.ndarray  # (n_sides, 9, 2) largest |d joint / d variable| over the grid

    def values(self, ab: np.ndarray) -> np.ndarray:
        """Joint values (n_sides, 9) rad for variables ab (n_sides, 2) rad."""
        return self.sign * rhythm_angles(ab, self.bounds, derivatives=False)[0]

    def values_and_jacobian(self, ab: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Joint values (n_sides, 9) and d values / d ab (n_sides, 9, 2), zero where a joint is clipped."""
        angles, d_angles = rhythm_angles(ab, self.bounds)
        return self.sign * angles, self.sign[..., None] * d_angles

    def fit(self, q: np.ndarray, iterations: int = 12) -> np.ndarray:
        """Variables (n_sides, 2) rad, in the box, whose joint values are closest to q (n_sides, 9) rad.

        Weighted by each joint's range; the nearest grid point, then projected Gauss-Newton steps.
        """
        grid, table = self.table
        w = 1.0 / np.maximum(self.upper - self.lower, 1e-3)
        q = np.clip(q, self.lower, self.upper)
        ab = grid[np.argmin((((table - q[:, None, :]) * w[:, None, :]) ** 2).sum(axis=-1), axis=1)]
        for _ in range(iterations):
            val, jac = self.values_and_jacobian(ab)
            jw = jac * w[..., None]
            rw = (q - val) * w
            step = np.stack([np.linalg.lstsq(jw[i], rw[i], rcond=1e-10)[0] for i in range(len(ab))])
            ab = np.clip(ab + step, LOWER, UPPER)
            if np.abs(step).max() < 1e-12:
                break
        return ab


def build_rhythm(model: Model) -> ShoulderRhythm | None:
    """The rhythm for the shoulders ``model`` has (None for none); ModelError when a shoulder's joints do not
    have the human model's layout (X, Y, Z axis sequences up to sign, identity origin rotations)."""
    sides, joints, signs = [], [], []
    for s, lateral in SIDES.items():
        names = [j.format(s=s) for j in JOINTS]
        present = [n in model.joint_names for n in names]
        if not any(present):
            continue
        if not all(present):
            raise ModelError(f"shoulder rhythm needs all nine joints {', '.join(names)}")
        idx = np.array([model.joint_index(n) for n in names])
        axes = model.axis[idx]
        expected = np.tile(np.eye(3), (3, 1))
        sign = np.sign((axes * expected).sum(axis=1))
        if not np.allclose(axes, sign[:, None] * expected) or not np.allclose(model.origin_rotation[idx], np.eye(3)):
            raise ModelError(f"shoulder rhythm needs X, Y, Z joint axes and plain origins on side {s!r}")
        p = np.array([lateral, -1.0, 1.0])  # Högfors thorax (lateral, anterior, up) -> our world, diagonal
        sides.append(s)
        joints.append(idx)
        signs.append(sign * np.prod(p) * np.tile(p, 3))  # P R_u(t) P^T = R_{det(P) P u}(t)
    if not sides:
        return None
    joints_a, sign_a = np.array(joints), np.array(signs)
    lower, upper = model.lower[joints_a], model.upper[joints_a]
    bounds = (np.minimum(sign_a * lower, sign_a * upper), np.maximum(sign_a * lower, sign_a * upper))
    g_a, g_b = np.meshgrid(np.linspace(LOWER[0], UPPER[0], 21), np.linspace(LOWER[1], UPPER[1], 13))
    grid = np.stack([g_a.ravel(), g_b.ravel()], axis=1)
    table, slope = [], []
    for i in range(len(sides)):
        angles, d_angles = rhythm_angles(grid, (bounds[0][i], bounds[1][i]))
        table.append(sign_a[i] * angles)
        slope.append(np.abs(d_angles).max(axis=0))
    return ShoulderRhythm(tuple(sides), joints_a, sign_a, lower, upper, bounds, (grid, np.array(table)),
                          np.array(slope))  # fmt: skip
