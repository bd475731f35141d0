"""A population of one sex: stature (m) and body mass (kg) bivariate normal, the extra measurements (m) linear in
them with correlated normal residuals (a multivariate normal in all, from :mod:`.ansur2`)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..body.humans.human import MASS_RANGE, SEXES, STATURE_RANGE
from ..body.humans.measurements import MEASUREMENTS
from ..errors import UsageError
from . import ansur2

MAX_DRAWS = 100  # rounds of redrawing the samples outside the bodies' valid ranges before giving up


@dataclass(frozen=True)
class Population:
    """One sex's distribution: ``mean`` (stature m, mass kg), their covariance ``cov``; each extra measurement
    ``extras[i]`` = ``regression[i] @ (1, stature, mass)`` + a residual of covariance ``residual_cov``."""

    sex: str
    mean: np.ndarray  # (2,) m, kg
    cov: np.ndarray  # (2, 2)
    extras: tuple[str, ...]
    regression: np.ndarray  # (k, 3): intercept m, m per m of stature, m per kg of mass
    residual_cov: np.ndarray  # (k, k) m^2
    source: str

    @property
    def sd(self) -> np.ndarray:
        """Standard deviations of stature (m) and mass (kg)."""
        return np.sqrt(np.diag(self.cov))

    @property
    def correlation(self) -> float:
        """Pearson correlation of stature and mass."""
        return float(self.cov[0, 1] / (self.sd[0] * self.sd[1]))

    def mahalanobis(self, points: np.ndarray) -> np.ndarray:
        """Mahalanobis distance of each (stature m, mass kg) row of ``points`` from the mean."""
        diff = np.atleast_2d(points) - self.mean
        return np.sqrt(np.einsum("ij,ij->i", diff @ np.linalg.inv(self.cov), diff))

    def measurements(self, stature: float, mass: float) -> dict[str, float]:
        """The extra measurements (m) expected for ``stature`` (m) and ``mass`` (kg): the regressions' means."""
        values = self.regression @ np.array([1.0, stature, mass])
        return {key: float(v) for key, v in zip(self.extras, values, strict=True)}

    def sample(self, n: int, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
        """``n`` random bodies: (stature m, mass kg) rows (n, 2) and their extra measurements (n, k), m.

        A draw outside the bodies' valid ranges (:mod:`solver.io.scenario.bodies`) is drawn again, so the distribution
        is
        truncated there (beyond 4 standard deviations: it does not happen in practice)."""
        size, extra = np.empty((n, 2)), np.empty((n, len(self.extras)))
        todo = np.arange(n)
        for _ in range(MAX_DRAWS):
            if todo.size == 0:
                return size, extra
            size[todo] = rng.multivariate_normal(self.mean, self.cov, size=todo.size, method="cholesky")
            noise = rng.multivariate_normal(np.zeros(len(self.extras)), self.residual_cov, todo.size, method="cholesky")
            design = np.column_stack([np.ones(todo.size), size[todo]])
            extra[todo] = design @ self.regression.T + noise
            todo = todo[~self.valid(size[todo], extra[todo])]
        raise UsageError(f"{self.sex}: cannot draw bodies within the valid ranges ({todo.size} left)")

    def valid(self, size: np.ndarray, extra: np.ndarray) -> np.ndarray:
        """Which rows lie within the ranges a body accepts (stature, mass, and each measurement's share of stature)."""
        ok = (size[:, 0] >= STATURE_RANGE[0]) & (size[:, 0] <= STATURE_RANGE[1])
        ok &= (size[:, 1] >= MASS_RANGE[0]) & (size[:, 1] <= MASS_RANGE[1])
        for i, key in enumerate(self.extras):
            lo, hi = MEASUREMENTS[key]
            share = extra[:, i] / size[:, 0]
            ok &= (share >= lo) & (share <= hi)
        return ok


def population(sex: str) -> Population:
    """The ANSUR II population of ``sex`` ("male" or "female"); a UsageError names any other."""
    if sex not in SEXES:
        raise UsageError(f"sex must be 'male' or 'female', got {sex!r}")
    stats = ansur2.STATS[sex]
    sd = np.array([stats["stature"][1], stats["mass"][1]])
    cov = np.outer(sd, sd) * np.array([[1.0, stats["r"]], [stats["r"], 1.0]])
    rows = [ansur2.REGRESSION[sex][key] for key in ansur2.EXTRAS]
    corr = np.eye(len(rows))
    for i, row in enumerate(ansur2.RESIDUAL_CORRELATION[sex], start=1):
        corr[i, :i] = corr[:i, i] = row
    res_sd = np.array([r[3] for r in rows])
    return Population(
        sex, np.array([stats["stature"][0], stats["mass"][0]]), cov, ansur2.EXTRAS,
        np.array([r[:3] for r in rows]), np.outer(res_sd, res_sd) * corr, ansur2.SOURCE,
    )  # fmt: skip


def coverage_radius(coverage: float) -> float:
    """Mahalanobis radius of the ellipse holding ``coverage`` (0-1) of a bivariate normal: the square root of the
    chi-square quantile with 2 degrees of freedom, which has the closed form -2 ln(1 - coverage)."""
    return math.sqrt(-2.0 * math.log1p(-coverage))
