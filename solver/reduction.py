"""Variable reduction x = phi(beta) (thesis ch. 4): fewer solver variables, the same model.

Linear groups (thesis 4.1.1): each spine region's rx, ry and rz joints follow one bend variable each,
shared over the region's vertebrae in proportion to their ranges (so ``beta`` is the region's total bend,
rad), and one grasp variable per hand (0 = open, 1 = closed) drives every finger flexion joint to that
fraction of its range; finger spreading stays at zero. Everything else maps one to one. With
x = x0 + B beta the solver sees J B, and bounds on beta keep every driven joint inside its range.
The nonlinear shoulder rhythm (thesis 4.1.2) is not implemented yet.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

import numpy as np

from .errors import ManikinError
from .model import Model

GROUPS = ("lumbar", "thoracic", "cervical", "grasp")
_REGION = {"lumbar": r"l[1-5]", "thoracic": r"t(1[0-2]|[1-9])", "cervical": r"c[1-7]"}
_FINGER_FLEXION = re.compile(r"(thumb|index|middle|ring|little)_([lr])_(mcp_flexion|pip|dip|mcp|ip|cmc_flexion)$")
_FINGER_OTHER = re.compile(r"(thumb|index|middle|ring|little)_([lr])_")


@dataclass(frozen=True, eq=False)
class LinearReduction:
    """x = offset + basis @ beta over the full variable vector x = [joints, forces]."""

    names: tuple[str, ...]  # one per beta
    basis: np.ndarray  # (n_x, n_beta)
    offset: np.ndarray  # (n_x,)
    lower: np.ndarray  # (n_beta,)
    upper: np.ndarray
    scale: np.ndarray  # scaled-variable unit per beta
    is_joint: np.ndarray  # (n_beta,) bool
    fit: np.ndarray  # (n_beta, n_x) least-squares inverse of basis

    @property
    def n(self) -> int:
        return len(self.names)

    def phi(self, beta: np.ndarray) -> np.ndarray:
        return self.offset + self.basis @ beta

    def from_x(self, x: np.ndarray) -> np.ndarray:
        """The beta whose phi is closest to x (least squares), for warm starts."""
        return self.fit @ (x - self.offset)


def build_reduction(
    model: Model, groups: tuple[str, ...], x_lower: np.ndarray, x_upper: np.ndarray, x_scale: np.ndarray
) -> LinearReduction | None:
    """The linear map for the chosen ``groups`` (names from GROUPS); None when no joint is grouped."""
    unknown = [g for g in groups if g not in GROUPS]
    if unknown:
        raise ManikinError(f"unknown reduction group {unknown[0]!r}; expected some of {list(GROUPS)}")
    n_x, n = len(x_lower), model.n
    columns: list[tuple[str, dict[int, float], bool]] = []  # (name, {x index: weight}, is_joint)
    grouped: set[int] = set()
    for region in ("lumbar", "thoracic", "cervical"):
        if region not in groups:
            continue
        for axis in ("rx", "ry", "rz"):
            members = [i for i, j in enumerate(model.joint_names) if re.fullmatch(_REGION[region] + "_" + axis, j)]
            if members:
                span = np.array([model.upper[i] - model.lower[i] for i in members])
                weights = span / span.sum()
                columns.append((f"{region}_{axis}", dict(zip(members, weights, strict=True)), True))
                grouped.update(members)
    if "grasp" in groups:
        for side in ("l", "r"):
            flex = [i for i, j in enumerate(model.joint_names) if (m := _FINGER_FLEXION.match(j)) and m[2] == side]
            other = [i for i, j in enumerate(model.joint_names) if (m := _FINGER_OTHER.match(j)) and m[2] == side]
            if flex:
                columns.append((f"grasp_{side}", {i: float(model.upper[i]) for i in flex}, True))
                grouped.update(other)
    if not columns:
        return None
    for i in range(n_x):
        if i not in grouped:
            columns.append((model.joint_names[i] if i < n else f"force_{i - n}", {i: 1.0}, i < n))
    columns.sort(key=lambda c: min(c[1]))  # keep the model's order (exterior joints first)
    basis = np.zeros((n_x, len(columns)))
    for k, (_, weights, _) in enumerate(columns):
        for i, w in weights.items():
            basis[i, k] = w
    offset = np.zeros(n_x)
    for i in grouped:
        if not basis[i].any():
            offset[i] = float(np.clip(0.0, x_lower[i], x_upper[i]))  # held (finger spreading)
    lower, upper = np.full(len(columns), -np.inf), np.full(len(columns), np.inf)
    for k in range(len(columns)):
        rows = np.nonzero(basis[:, k])[0]
        w = basis[rows, k]
        lo = np.where(w > 0, (x_lower[rows] - offset[rows]) / w, (x_upper[rows] - offset[rows]) / w)
        hi = np.where(w > 0, (x_upper[rows] - offset[rows]) / w, (x_lower[rows] - offset[rows]) / w)
        lower[k], upper[k] = lo.max(), hi.min()
    names = tuple(c[0] for c in columns)
    is_joint = np.array([c[2] for c in columns])
    single = np.array([len(c[1]) == 1 for c in columns])
    idx = np.array([min(c[1]) for c in columns])
    half = 0.5 * (upper - lower)
    scale = np.where(single, x_scale[idx], np.where(np.isfinite(half), np.clip(half, 0.02, 1.0), 1.0))
    fit = (basis / np.maximum((basis * basis).sum(axis=0), 1e-300)).T  # columns have disjoint supports
    return LinearReduction(names, basis, offset, lower, upper, scale, is_joint, fit)
