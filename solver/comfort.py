"""The comfort function h(x) the solver maximises in the constraints' null space (thesis §3.3).

h = -(w_range * range + w_load * load + w_contact * contact), all dimensionless:

* range   = sum_i c_i tan^2(u_i), u_i = (pi/2)(theta_i - n_i)/(hi_i - n_i) above the neutral value n_i and
            (pi/2)(theta_i - n_i)/(n_i - lo_i) below it: the thesis's tan^2 form, generalised to asymmetric
            limits; 0 at the neutral value, infinite at a limit (u is capped at 0.48 pi to stay finite).
* load    = sum_i c_i (tau_i / s_i)^2, tau_i the moment about joint i's axis (eq. 3.10-3.11) and s_i the
            joint's strength in the direction the muscles must act (so the square is the strain).
* contact = sum_k (w_k / body weight)^2, a small preference for spreading contact forces evenly.

c_i is the model's per-joint comfort weight (1/17 per thoracolumbar vertebra, so bending the whole region
costs like one joint). Gradients are analytic; :meth:`Comfort.derivatives` also gives a diagonal
curvature model of -h that the solver uses as the metric of its steps.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .model import GRAVITY, Model
from .state import State

U_MAX = 0.48 * np.pi


@dataclass(frozen=True)
class ComfortWeights:
    """Weights of the three comfort terms (dimensionless)."""

    range: float = 1.0
    load: float = 1.0
    contact: float = 0.01


DEFAULT_COMFORT = ComfortWeights()


class Comfort:
    """Value and gradient of h(x) for one model."""

    def __init__(self, model: Model, weights: ComfortWeights = DEFAULT_COMFORT) -> None:
        self.model = model
        self.weights = weights
        lo, hi, mid = model.lower, model.upper, model.neutral
        finite = np.isfinite(lo) & np.isfinite(hi) & (hi > lo)
        self.range_weight = np.where(finite, model.range_weight, 0.0)
        self.span_up = np.where(finite, np.maximum(hi - mid, 1e-9), 1.0)
        self.span_down = np.where(finite, np.maximum(mid - lo, 1e-9), 1.0)
        strength = np.where(np.isfinite(model.strength) & (model.strength > 0), model.strength, np.inf)
        self.inv_strength = 1.0 / strength  # (n, 2): for negative and positive muscle moments
        self._inv_negative = self.inv_strength[:, 0].copy()
        self._inv_positive = self.inv_strength[:, 1].copy()
        self.load_weight = np.where(model.prismatic, 0.0, model.range_weight)
        self.body_weight = model.total_mass * float(np.linalg.norm(GRAVITY))

    def _range_terms(self, theta: np.ndarray, derivatives: bool = True) -> tuple[np.ndarray, ...]:
        """tan^2(u) per joint and (with ``derivatives``) its first and second derivative (per rad or m);
        past |u| = U_MAX continued linearly (C1)."""
        d = theta - self.model.neutral
        span = np.where(d >= 0.0, self.span_up, self.span_down)
        u = 0.5 * np.pi * d / span
        t = np.tan(np.clip(u, -U_MAX, U_MAX))
        t2 = t * t
        slope = 2.0 * t * (1.0 + t2)
        beyond = np.abs(u) - U_MAX
        value = t2 + np.where(beyond > 0.0, np.abs(slope) * beyond, 0.0)
        if not derivatives:
            return (value,)
        du = 0.5 * np.pi / span
        curvature = 2.0 * (1.0 + t2) * (1.0 + 3.0 * t * t) * du * du
        return value, slope * du, curvature

    def _range_of(self, state: State) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """:meth:`_range_terms` with derivatives at ``state``, computed once per state (value and step share it)."""
        cached = state.cache.get(self)
        if cached is None:
            cached = state.cache[self] = self._range_terms(state.theta)
        return cached

    def _strain_scale(self, tau: np.ndarray) -> np.ndarray:
        # The muscles must produce -tau: positive capacity when tau < 0.
        return np.where(tau < 0.0, self._inv_positive, self._inv_negative)

    def parts(self, state: State) -> dict[str, float]:
        """The three (unweighted) terms, each >= 0, for reports."""
        rng = self._range_of(state)[0]
        out = {"range": float(self.range_weight @ rng), "load": 0.0, "contact": 0.0}
        if self.weights.load:
            tau = state.statics.axis_loads()
            strain = tau * self._strain_scale(tau)
            out["load"] = float(self.load_weight @ (strain * strain))
        if len(state.w):
            out["contact"] = float(np.sum((state.w / self.body_weight) ** 2))
        return out

    def value(self, state: State) -> float:
        """h(x) (<= 0; larger is more comfortable)."""
        return self.total(self.parts(state))

    def total(self, parts: dict[str, float]) -> float:
        """h from its :meth:`parts` (the weighted sum, negated)."""
        w = self.weights
        return -(w.range * parts["range"] + w.load * parts["load"] + w.contact * parts["contact"])

    def derivatives(self, state: State) -> tuple[np.ndarray, np.ndarray]:
        """dh/dx (n_x,) and a positive diagonal curvature model of -h (n_x,).

        The curvature is exact for the range and contact terms and the diagonal of the Gauss-Newton matrix
        for the load term; the solver uses it as the metric of its steps.
        """
        n, wts = self.model.n, self.weights
        grad = np.zeros(state.n_x)
        curv = np.zeros(state.n_x)
        _, d_rng, dd_rng = self._range_of(state)
        grad[:n] -= wts.range * self.range_weight * d_rng
        curv[:n] += wts.range * self.range_weight * dd_rng
        if wts.load:
            tau = state.statics.axis_loads()
            scale = self._strain_scale(tau)
            coef = 2.0 * self.load_weight * tau * scale * scale
            rows = 2.0 * wts.load * self.load_weight * scale * scale
            lin, sq = state.statics.axis_load_contractions(coef, rows)
            grad -= wts.load * lin
            curv += sq
        if len(state.w):
            grad[n:] -= wts.contact * 2.0 * state.w / self.body_weight**2
            curv[n:] += wts.contact * 2.0 / self.body_weight**2
        return grad, curv

    def gradient(self, state: State) -> np.ndarray:
        """dh/dx, shape (n_x,)."""
        return self.derivatives(state)[0]
