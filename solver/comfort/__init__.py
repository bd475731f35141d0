"""The comfort function h(x) the solver maximises in the constraints' null space (thesis §3.3).

h = -sum_k weight_k cost_k(x) over :class:`ComfortTerm` objects, one per module: ``joint_range`` (tan^2 of each
joint's deviation from neutral), ``joint_load`` (squared joint strain), ``contact_spread`` (squared contact forces),
``trunk_tilt`` (the trunk's lean from vertical), ``gaze`` (the head turned away from the hands). A new term is a new
module with a ComfortTerm; :class:`Comfort` takes any list of (weight, term). The standard terms, which every
problem has unless it brings its own, are registered by name in :mod:`.standard` (one line each), weighted by
:class:`ComfortWeights`.
"""

from __future__ import annotations

from functools import partial

import numpy as np

from ..body.model import Model
from ..body.state import State
from .base import ComfortTerm
from .contact_spread import ContactSpread
from .gaze import Gaze
from .joint_load import JointLoad
from .joint_range import JointRange
from .standard import BEHAVIOUR, DEFAULT_COMFORT, STANDARD, STANDARD_TERMS, ComfortWeights, StandardTerm, standard_terms
from .trunk_tilt import TrunkTilt

_NO_ROWS = ComfortTerm.curvature_rows  # the base class's: no low-rank curvature rows


class Comfort:
    """h(x) = -sum weight x cost over ``terms`` (each a (weight, :class:`ComfortTerm`) pair)."""

    def __init__(self, terms: list[tuple[float, ComfortTerm]], weights: ComfortWeights | None = None) -> None:
        self.terms = list(terms)
        self.weights = weights  # the standard weights these terms came from, if they did

    @classmethod
    def standard(cls, model: Model, weights: ComfortWeights = DEFAULT_COMFORT) -> Comfort:
        """The standard terms (:data:`STANDARD_TERMS`) with ``weights``."""
        return cls(standard_terms(model, weights), weights)

    def with_targets(self, targets: list) -> Comfort:
        """This comfort for a problem of ``targets`` (itself when no term reads them)."""
        terms = [(weight, term.with_targets(targets) if weight else term) for weight, term in self.terms]
        if all(new is old for (_, new), (_, old) in zip(terms, self.terms, strict=True)):
            return self
        return Comfort(terms, self.weights)

    def parts(self, state: State) -> dict[str, float]:
        """Each term's unweighted cost (>= 0), for reports; a term of zero weight is not part of comfort (0)."""
        return {term.name: term.cost(state) if weight else 0.0 for weight, term in self.terms}

    def total(self, parts: dict[str, float]) -> float:
        """h from its :meth:`parts` (the weighted sum, negated)."""
        out = 0.0
        for weight, term in self.terms:
            out += weight * parts[term.name]
        return -out

    def relative_size(self, parts: dict[str, float]) -> float:
        """The weighted cost of the terms that set the relative comfort tolerance (>= 0), from :meth:`parts`."""
        return sum(weight * parts[term.name] for weight, term in self.terms if term.relative)

    def value(self, state: State) -> float:
        """h(x) (<= 0; larger is more comfortable)."""
        return self.total(self.parts(state))

    def derivatives(self, state: State) -> tuple[np.ndarray, np.ndarray]:
        """dh/dx (n_x,) and a positive diagonal curvature model of -h (n_x,), which the solver uses as the metric
        of its steps; once per state (not to be written to)."""
        return state.once(self, "derivatives", partial(self._derivatives, state))

    def _derivatives(self, state: State) -> tuple[np.ndarray, np.ndarray]:
        grad = np.zeros(state.n_x)
        curv = np.zeros(state.n_x)
        for weight, term in self.terms:
            if weight:
                g, c = term.derivatives(state, weight)
                grad -= g
                curv += c
        return grad, curv

    def curvature_rows(self, state: State) -> np.ndarray | None:
        """The terms' low-rank curvature rows stacked (k, n_x), None when no term has any."""
        # asked every iteration: a term that keeps ComfortTerm's (no rows) is not called
        with_rows = [(w, term) for w, term in self.terms if w and type(term).curvature_rows is not _NO_ROWS]
        rows = [term.curvature_rows(state, weight) for weight, term in with_rows]
        rows = [r for r in rows if r is not None]
        return np.concatenate(rows) if rows else None

    def gradient(self, state: State) -> np.ndarray:
        """dh/dx, shape (n_x,)."""
        return self.derivatives(state)[0]


__all__ = ["BEHAVIOUR", "DEFAULT_COMFORT", "STANDARD", "STANDARD_TERMS", "Comfort", "ComfortTerm", "ComfortWeights",
           "ContactSpread", "Gaze", "JointLoad", "JointRange", "StandardTerm", "TrunkTilt"]  # fmt: skip
