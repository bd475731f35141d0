"""Self-clearance: the body's own parts stay apart (hands and forearms out of the trunk, head and thighs; shank
from shank), one row per pair of :mod:`solver.collision.self_pairs`, g = the capsules' surface distance (m).

The Jacobian of a row is n . (velocity of the witness on the first capsule - velocity of the witness on the
second), n the unit normal from the second to the first: the distance's gradient is n at one witness and -n at
the other (the witnesses' own sliding drops out, as for obstacles). Joints that carry both parts move them
rigidly together and cancel.

A new state is not measured while the capsules' movement since the last exact query proves every pair clear of its
watch band (``ClearanceRows._clear_by``): the error, the Jacobian rows and the near pairs the
iteration asks for are then known without a query, and the same as a query's (docs/TUNING.md).
"""

from __future__ import annotations

import numpy as np

from .. import kernels
from ..body.model import Model
from ..body.state import State
from ..collision.body import BodyCapsules, capsules_of
from ..collision.distance import capsule_pairs
from ..collision.proximity import PairProximity
from ..collision.self_pairs import self_pairs
from ..kernels.clearance import clearance_jacobian
from .clearance import HOLD, ClearanceRows
from .per_model import fresh, per_model


class SelfClearance(ClearanceRows):
    """The pairs of ``model``'s capsules that :func:`~solver.collision.self_pairs.self_pairs` names, each at least
    its least distance apart."""

    name = "self_collision"
    watch = HOLD

    def __init__(self, model: Model, capsules: BodyCapsules, n_x: int, margin: float = 0.05) -> None:
        self.model, self.capsules, self.n_x, self.margin = model, capsules, n_x, margin
        self.pairs = self_pairs(model, capsules)
        names = capsules.names
        self._parts = [names[i] for i in self.pairs.first]
        self._others = [names[j] for j in self.pairs.second]
        self._pairs = [f"{a} vs {b}" for a, b in zip(self._parts, self._others, strict=True)]
        self.floor = self.pairs.least.copy()
        # exact at any range and ~40 array operations per query: bounded by the capsules' movement (docs/TUNING.md)
        self._bounded, self._row_capsule, self._row_other = True, self.pairs.first, self.pairs.second
        pair_ends = (self.pairs.first, self.pairs.second)
        self._links = tuple(np.ascontiguousarray(capsules.link[p], dtype=np.int64) for p in pair_ends)  # the kernel's

    def _proximity(self, state: State) -> PairProximity:
        """Every pair's distance, witnesses and normal at ``state``, once per state."""
        key = (self, "pairs")
        got = state.cache.get(key)
        if got is None:
            p0, p1 = self._ends(state)
            got = state.cache[key] = capsule_pairs(p0, p1, self.capsules.radius, self.pairs.first, self.pairs.second)
        return got

    def _distances(self, state: State) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        got = self._proximity(state)
        return got.distance, got.point, got.normal, self.pairs.first

    def _jacobian_of(self, state: State, rows: np.ndarray) -> np.ndarray:
        out = np.zeros((len(rows), self.n_x))
        if rows.size and kernels.active():  # both parts' rows in one loop
            got = self._proximity(state)
            clearance_jacobian(got.point, got.normal, self._links[0], got.point_other, self._links[1],
                               np.asarray(rows, np.int64), self.model.descendant, state.kin.twist, out)  # fmt: skip
        elif rows.size:
            got = self._proximity(state)
            normal = got.normal[rows]
            mask = self.model.descendant[:, self.capsules.link[self.pairs.second[rows]]].T.astype(float)
            away = state.kin.jacobian_rows(got.point_other[rows], normal, np.zeros_like(normal), mask)
            out[:, : self.model.n] = self._part_rows(state, rows) - away
        return out


def self_clearance(model: Model, n_x: int) -> SelfClearance:
    """The self-clearance rows of ``model``'s capsules (:func:`~solver.collision.body.capsules_of`) for ``n_x``
    variables: its pairs found once per model, its last query its own."""
    return fresh(per_model(model, ("self clearance", n_x), lambda: SelfClearance(model, capsules_of(model), n_x)))
