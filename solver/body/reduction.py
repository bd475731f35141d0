"""Variable reduction x = phi(beta) (thesis ch. 4): fewer solver variables, the same model.

Linear groups (thesis 4.1.1): each spine region's rx, ry and rz joints follow one bend variable each,
shared over the region's vertebrae in proportion to their ranges (so ``beta`` is the region's total bend,
rad), and one grasp variable per hand (0 = open, 1 = closed) drives every finger flexion joint to that
fraction of its range; finger spreading stays at zero. The nonlinear group (thesis 4.1.2): the Högfors
shoulder rhythm, two variables per shoulder (rad) driving its nine joints (:mod:`.shoulder_rhythm`).
Everything else maps one to one. So x = offset + B beta + s(beta), s the shoulder part, and the solver sees
J dphi/dbeta; bounds on beta keep every driven joint inside its range (the shoulder clips at its ranges).
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from ..errors import ManikinError
from .model import Model
from .shoulder_rhythm import LOWER, UPPER, ShoulderRhythm, build_rhythm

GROUPS = ("lumbar", "thoracic", "cervical", "grasp", "shoulder")
# What `reduction = true` means: every group except the shoulder rhythm, which is opt-in by name because its
# 2-variable shoulders (elevation <= 60 deg, no free humeral rotation) lose much reach (docs/BENCHMARKS.md).
DEFAULT_GROUPS = ("lumbar", "thoracic", "cervical", "grasp")
_REGION = {"lumbar": r"l[1-5]", "thoracic": r"t(1[0-2]|[1-9])", "cervical": r"c[1-7]"}
_FINGER_FLEXION = re.compile(r"(thumb|index|middle|ring|little)_([lr])_(mcp_flexion|pip|dip|mcp|ip|cmc_flexion)$")
_FINGER_OTHER = re.compile(r"(thumb|index|middle|ring|little)_([lr])_")


@dataclass(frozen=True, eq=False)
class Reduction:
    """x = offset + basis @ beta, the shoulder rows then set by the rhythm, over x = [joints, forces]."""

    names: tuple[str, ...]  # one per beta
    basis: np.ndarray  # (n_x, n_beta) linear part; zero in the shoulder rows and columns
    offset: np.ndarray  # (n_x,)
    lower: np.ndarray  # (n_beta,)
    upper: np.ndarray
    scale: np.ndarray  # scaled-variable unit per beta
    is_joint: np.ndarray  # (n_beta,) bool
    fit: np.ndarray  # (n_beta, n_x) least-squares inverse of basis
    basis_sq: np.ndarray  # basis * basis, for the comfort curvature
    slope: np.ndarray  # (n_x, n_beta) largest |d x / d beta| over the bounds (= |basis| for linear columns)
    shoulder: ShoulderRhythm | None = None
    shoulder_vars: np.ndarray | None = None  # (n_sides, 2) beta indices of (alpha_h, beta_h) per side

    @property
    def n(self) -> int:
        return len(self.names)

    @property
    def linear(self) -> bool:
        """True when dphi/dbeta is the constant ``basis``."""
        return self.shoulder is None

    @cached_property
    def _supports(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, bool]:
        """The nonzeros of ``basis`` by column: (x rows, their columns, weights, each column's first entry,
        whether every column has one). Columns have disjoint supports, so each x row has at most one entry."""
        rows, cols = np.nonzero(self.basis)
        order = np.argsort(cols, kind="stable")
        rows, cols = rows[order], cols[order]
        starts = np.searchsorted(cols, np.arange(self.n))
        complete = bool(np.all(np.diff(np.append(starts, len(cols))) > 0))
        return rows, cols, self.basis[rows, cols], starts, complete

    @cached_property
    def kernel_supports(self) -> tuple[np.ndarray, np.ndarray]:
        """``basis`` by x row for the compiled kernels: (the column of each row's one nonzero, -1 where none; its
        weight), contiguous int64 and float64 (n_x,)."""
        rows, cols, weight, _, _ = self._supports
        column, value = np.full(self.basis.shape[0], -1, dtype=np.int64), np.zeros(self.basis.shape[0])
        column[rows], value[rows] = cols, weight
        return column, value

    def times_basis(self, a: np.ndarray, squared: bool = False) -> np.ndarray:
        """``a @ basis`` (``a @ basis**2`` when ``squared``) for a (..., n_x) array, summing each column's own
        rows instead of a dense product (most columns are a single joint)."""
        rows, _, weight, starts, complete = self._supports
        if not complete:
            return a @ (self.basis_sq if squared else self.basis)
        return np.add.reduceat(a[..., rows] * (weight * weight if squared else weight), starts, axis=-1)

    def basis_times(self, beta: np.ndarray) -> np.ndarray:
        """``basis @ beta`` (n_x,) by scattering each column's weights (every x row has at most one)."""
        rows, cols, weight, _, _ = self._supports
        out = np.zeros(self.basis.shape[0])
        out[rows] = weight * beta[cols]
        return out

    def phi(self, beta: np.ndarray) -> np.ndarray:
        """Full x for variables beta."""
        x = self.offset + self.basis_times(beta)
        if self.shoulder is not None:
            x[self.shoulder.joints] = self.shoulder.values(beta[self.shoulder_vars])
        return x

    def jacobian(self, beta: np.ndarray) -> np.ndarray:
        """dphi/dbeta (n_x, n_beta) at beta."""
        if self.shoulder is None:
            return self.basis
        _, d = self.shoulder.values_and_jacobian(beta[self.shoulder_vars])
        jac = self.basis.copy()
        jac[self.shoulder.joints[:, :, None], self.shoulder_vars[:, None, :]] = d
        return jac

    def from_x(self, x: np.ndarray) -> np.ndarray:
        """The beta whose phi is closest to x (least squares; the shoulder by a fit), for warm starts."""
        beta = self.fit @ (x - self.offset)
        if self.shoulder is not None:
            beta[self.shoulder_vars] = self.shoulder.fit(x[self.shoulder.joints])
        return beta


def build_reduction(
    model: Model, groups: tuple[str, ...], x_lower: np.ndarray, x_upper: np.ndarray, x_scale: np.ndarray
) -> Reduction | None:
    """The map for the chosen ``groups`` (names from GROUPS); None when no joint is grouped."""
    unknown = [g for g in groups if g not in GROUPS]
    if unknown:
        raise ManikinError(f"unknown reduction group {unknown[0]!r}; expected some of {list(GROUPS)}")
    n_x, n = len(x_lower), model.n
    # (name, {x index: weight}, is_joint, sort key); the shoulder's columns have no linear weights
    columns: list[tuple[str, dict[int, float], bool, int]] = []
    grouped: set[int] = set()
    for region in ("lumbar", "thoracic", "cervical"):
        if region not in groups:
            continue
        for axis in ("rx", "ry", "rz"):
            members = [i for i, j in enumerate(model.joint_names) if re.fullmatch(_REGION[region] + "_" + axis, j)]
            if members:
                span = np.array([model.upper[i] - model.lower[i] for i in members])
                weights = span / span.sum()
                columns.append((f"{region}_{axis}", dict(zip(members, weights, strict=True)), True, min(members)))
                grouped.update(members)
    if "grasp" in groups:
        for side in ("l", "r"):
            flex = [i for i, j in enumerate(model.joint_names) if (m := _FINGER_FLEXION.match(j)) and m[2] == side]
            other = [i for i, j in enumerate(model.joint_names) if (m := _FINGER_OTHER.match(j)) and m[2] == side]
            if flex:
                columns.append((f"grasp_{side}", {i: float(model.upper[i]) for i in flex}, True, min(flex)))
                grouped.update(other)
    rhythm = build_rhythm(model) if "shoulder" in groups else None
    if rhythm is not None:
        for s, joints in zip(rhythm.sides, rhythm.joints, strict=True):
            key = int(joints.min())
            columns += [(f"shoulder_{s}_alpha_h", {}, True, key), (f"shoulder_{s}_beta_h", {}, True, key)]
            grouped.update(int(i) for i in joints)
    if not columns:
        return None
    for i in range(n_x):
        if i not in grouped:
            columns.append((model.joint_names[i] if i < n else f"force_{i - n}", {i: 1.0}, i < n, i))
    columns.sort(key=lambda c: c[3])  # keep the model's order (exterior joints first); stable within a shoulder
    basis = np.zeros((n_x, len(columns)))
    for k, (_, weights, _, _) in enumerate(columns):
        for i, w in weights.items():
            basis[i, k] = w
    offset = np.zeros(n_x)
    for i in grouped:
        if not basis[i].any():
            offset[i] = float(np.clip(0.0, x_lower[i], x_upper[i]))  # held (finger spreading); shoulder: unused
    names = tuple(c[0] for c in columns)
    lower, upper = np.full(len(columns), -np.inf), np.full(len(columns), np.inf)
    for k in range(len(columns)):
        rows = np.nonzero(basis[:, k])[0]
        if len(rows) == 0:
            continue  # a shoulder variable: set below
        w = basis[rows, k]
        lo = np.where(w > 0, (x_lower[rows] - offset[rows]) / w, (x_upper[rows] - offset[rows]) / w)
        hi = np.where(w > 0, (x_upper[rows] - offset[rows]) / w, (x_lower[rows] - offset[rows]) / w)
        lower[k], upper[k] = lo.max(), hi.min()
    slope = np.abs(basis)
    shoulder_vars = None
    if rhythm is not None:
        pairs = [[f"shoulder_{s}_alpha_h", f"shoulder_{s}_beta_h"] for s in rhythm.sides]
        shoulder_vars = np.array([[names.index(v) for v in pair] for pair in pairs])
        lower[shoulder_vars], upper[shoulder_vars] = LOWER, UPPER
        slope[rhythm.joints[:, :, None], shoulder_vars[:, None, :]] = rhythm.slope
    is_joint = np.array([c[2] for c in columns])
    single = np.array([len(c[1]) == 1 for c in columns])
    idx = np.array([c[3] for c in columns])
    half = 0.5 * (upper - lower)
    scale = np.where(single, x_scale[idx], np.where(np.isfinite(half), np.clip(half, 0.02, 1.0), 1.0))
    fit = (basis / np.maximum((basis * basis).sum(axis=0), 1e-300)).T  # columns have disjoint supports
    return Reduction(
        names, basis, offset, lower, upper, scale, is_joint, fit, basis * basis, slope, rhythm, shoulder_vars
    )
