"""Parts of a problem that depend on its model and a few plain inputs only, built once per model and key
(:func:`solver.constraints.per_model.per_model`): the standard comfort, the contact set and its statics layout, the
variables' bounds and reduction. Nothing writes to them after they are built (a motion's frames share them already).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np

from ..body.contacts import ContactSet, Support, build_contacts
from ..body.model import Kinematics, Model
from ..body.reduction import Reduction, build_reduction
from ..body.statics import Load, StaticsLayout
from ..comfort import Comfort, ComfortWeights
from ..comfort.standard import STANDARD_TERMS
from ..constraints.per_model import exact, per_model
from .bounds import Bounds
from .specs import ExternalLoad, Target


def standard_comfort(model: Model, weights: ComfortWeights) -> Comfort:
    """:meth:`Comfort.standard` of ``model`` with ``weights`` (exact: by their repr), once per registry of terms."""
    key = ("standard comfort", repr(weights), tuple(STANDARD_TERMS.items()))
    return per_model(model, key, lambda: Comfort.standard(model, weights))


def statics_of(
    model: Model, supports: list[Target], loads: Sequence[ExternalLoad], rotation: Callable[[Target], np.ndarray]
) -> tuple[ContactSet, StaticsLayout]:
    """The contact set of the ``supports`` (targets, each standing on its frame: ``rotation`` of it, world) and the
    statics layout with ``loads`` (N) on ``model``. ``rotation`` of a target without one is the model's (its TCP in
    the zero pose), so the targets' fields name it."""
    key = ("statics", tuple((t.tcp, exact(t.rotation), float(t.friction).hex(), exact(t.sole)) for t in supports),
           tuple((ld.tcp, exact(ld.force)) for ld in loads))  # fmt: skip

    def build() -> tuple[ContactSet, StaticsLayout]:
        contacts = build_contacts(model, [Support(model.tcp(t.tcp), rotation(t), t.friction, t.sole) for t in supports])
        forces = [Load(model.tcp(ld.tcp), np.asarray(ld.force, dtype=float)) for ld in loads]
        return contacts, StaticsLayout(model, contacts, forces)

    return per_model(model, key, build)


def zero_kinematics(model: Model) -> Kinematics:
    """``model``'s kinematics in its zero pose (the frame of a target without a rotation of its own)."""
    return per_model(model, ("zero pose",), lambda: model.forward(model.zero_pose()))


def variables_of(
    model: Model, n_forces: int, body_weight: float, groups: Sequence[str]
) -> tuple[Bounds, Reduction | None, Bounds]:
    """The bounds of x = [joints, ``n_forces`` contact weights (in units of ``body_weight``, N)], the reduction of
    the reduction ``groups`` (None without one) and the bounds of the solver's variables."""

    def build() -> tuple[Bounds, Reduction | None, Bounds]:
        xb = Bounds.of_model(model, n_forces, body_weight)
        red = build_reduction(model, groups, xb.lower, xb.upper, xb.scale)
        return xb, red, xb if red is None else Bounds(red.lower, red.upper, red.scale, red.is_joint)

    return per_model(model, ("variables", n_forces, float(body_weight).hex(), tuple(groups)), build)
