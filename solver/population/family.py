"""Manikin families: boundary manikins on a coverage ellipse of (stature, mass), the mean manikin, random samples.

The boundary follows the IPS IMMA recipe (Brolin, Högberg, Hanson): stature and mass are standardised, their
principal components (for two variables always the "size" axis (1, 1) and the "build" axis (1, -1)) scaled by
the square roots of their eigenvalues, and ``points`` manikins placed at equal angles on the circle of radius
``sqrt(chi2_2(coverage))`` there, starting on the size axis (taller and heavier): with 8 points the principal
axes and the diagonals between them. Each lies on the ellipse that holds ``coverage`` of the population. Every
member's extra measurements are the regression means for its stature and mass (boundary and mean) or drawn
with their residuals (samples).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..body.humans.human import SEXES
from ..errors import UsageError, is_number
from .model import Population, coverage_radius, population

COVERAGE_RANGE = (0.01, 0.9999)  # beyond 0.9999 the ellipse leaves the adult range (5 standard deviations)
MAX_POINTS = 360
MAX_SAMPLES = 100_000
ROLES = ("boundary", "mean", "sample")


@dataclass(frozen=True)
class Member:
    """One manikin of a family: ``name``, ``sex``, ``role`` (one of :data:`ROLES`), ``stature`` (m), ``mass``
    (kg), ``measurements`` (the extra ones, m), ``angle`` (deg on the standardised circle, boundary only)."""

    name: str
    sex: str
    role: str
    stature: float
    mass: float
    measurements: dict[str, float] = field(default_factory=dict)
    angle: float | None = None


def check_family_args(coverage: float, points: int, samples: int, seed: int) -> None:
    """A UsageError line for the first argument out of its range."""
    lo, hi = COVERAGE_RANGE
    if not (is_number(coverage) and lo <= coverage <= hi):
        raise UsageError(f"--coverage must be a share in [{lo}, {hi}] (e.g. 0.95), got {coverage!r}")
    if not (points == 0 or 3 <= points <= MAX_POINTS):
        raise UsageError(f"--points must be 0 (no boundary) or in [3, {MAX_POINTS}], got {points}")
    if not 0 <= samples <= MAX_SAMPLES:
        raise UsageError(f"--samples must be in [0, {MAX_SAMPLES}], got {samples}")
    if not 0 <= seed < 2**63:
        raise UsageError(f"--seed must be an integer in [0, 2**63), got {seed}")


def boundary_points(pop: Population, coverage: float, points: int) -> tuple[np.ndarray, np.ndarray]:
    """(stature m, mass kg) rows (points, 2) on the ``coverage`` ellipse of ``pop`` and their angles (deg)."""
    r = pop.correlation
    angles = 360.0 * np.arange(points) / points
    theta = np.radians(angles)
    # the standardised correlation matrix's eigenvectors and square-rooted eigenvalues, as columns
    axes = np.array([[1.0, 1.0], [1.0, -1.0]]) / math.sqrt(2.0) * np.sqrt([1.0 + r, 1.0 - r])
    z = np.column_stack([np.cos(theta), np.sin(theta)]) @ axes.T  # standardised (stature, mass) per point
    return pop.mean + coverage_radius(coverage) * z * pop.sd, angles


def make_family(
    sexes: tuple[str, ...], coverage: float = 0.95, points: int = 8, samples: int = 0, seed: int = 0
) -> list[Member]:
    """Per sex: the boundary manikins (``points`` on the ``coverage`` ellipse), the mean manikin and ``samples``
    random draws (reproducible from ``seed``; each sex has its own stream of that seed, so a sex's samples
    do not depend on which other sexes are drawn)."""
    check_family_args(coverage, points, samples, seed)
    members = []
    tag = f"c{round(100 * coverage, 2):g}".replace(".", "_")
    for sex in sexes:
        pop = population(sex)
        if points:
            size, angles = boundary_points(pop, coverage, points)
            for k, ((h, m), angle) in enumerate(zip(size, angles, strict=True), start=1):
                name = f"{sex}_{tag}_{k:0{len(str(points))}d}"
                members.append(Member(name, sex, "boundary", *_rounded(h, m, pop.measurements(h, m)), float(angle)))
        h, m = pop.mean
        members.append(Member(f"{sex}_mean", sex, "mean", *_rounded(h, m, pop.measurements(h, m))))
        if samples:
            size, extra = pop.sample(samples, np.random.default_rng([seed, SEXES.index(sex)]))
            for k in range(samples):
                values = dict(zip(pop.extras, extra[k], strict=True))
                members.append(
                    Member(f"{sex}_s{k + 1:0{len(str(samples))}d}", sex, "sample", *_rounded(*size[k], values))
                )
    return members


def _rounded(stature: float, mass: float, extra: dict[str, float]) -> tuple[float, float, dict[str, float]]:
    """Stature and extra measurements to 0.1 mm, mass to 10 g: the precision a body file keeps."""
    return round(float(stature), 4), round(float(mass), 2), {k: round(float(v), 4) for k, v in extra.items()}
