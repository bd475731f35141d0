"""One envelope as plain settings, checked before any work and then computed: what ``python -m solver envelope`` and
a study's ``[envelope]`` table share (the same checks, the same sweep, the same statistics and files).

::

    settings = EnvelopeSettings(load_kg=10.0, feet="step", frequency=2)
    check_settings(model, "right", settings)           # a UsageError line for anything that cannot be done
    envelope, stats = compute_envelope(model, "right", settings)
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..body.model import Model
from .analysis import comparison
from .directions import DirectionSphere, direction_sphere
from .reach import check_tolerance, reach_setup
from .sweep import Envelope, sweep_envelope

HANDS = {"right": ("right",), "left": ("left",), "both": ("right", "left")}  # what a hand setting names


@dataclass(frozen=True)
class EnvelopeSettings:
    """What an envelope is asked for besides the manikin and the hand: the load (kg) in the hand, its orientation
    (a quaternion w, x, y, z; None: free), the reach ``tolerance`` (m), the soles' scale for the centre of pressure,
    the ``feet`` ("planted" or "step") and the directions
    (a geodesic sphere of ``frequency``, or its ``hemisphere``). Plain values: it travels to worker processes."""

    load_kg: float = 0.0
    rotation: tuple[float, ...] | None = None
    tolerance: float = 0.02
    sole_scale: float = 1.0
    feet: str = "planted"
    frequency: int = 3
    hemisphere: str = "all"

    def sphere(self) -> DirectionSphere:
        """The directions to search."""
        return direction_sphere(self.frequency, self.hemisphere)

    def matrix(self) -> np.ndarray | None:
        """The hand's fixed orientation (3x3, world), None when free."""
        if self.rotation is None:
            return None
        from ..body.spatial import quat_to_matrix
        from .run import rotation_of

        return quat_to_matrix(np.array(rotation_of(self.rotation)))


def check_settings(model: Model, side: str, settings: EnvelopeSettings) -> None:
    """Refuse, with one UsageError (or ModelError) line, settings the envelope of ``model``'s ``side`` hand cannot
    be computed with (before any work)."""
    settings.sphere()
    check_tolerance(settings.tolerance)
    reach_setup(model, side, settings.load_kg, settings.matrix(), True, settings.sole_scale, settings.feet)  # fmt: skip


def compute_envelope(
    model: Model, side: str, settings: EnvelopeSettings, progress: Callable[[int, int], None] | None = None
) -> tuple[Envelope, dict]:
    """The envelope of ``model``'s ``side`` hand with ``settings`` and its statistics (:func:`comparison`);
    ``progress(done, total)`` after each direction."""
    s = settings
    envelope = sweep_envelope(model, s.sphere(), side, s.load_kg, s.matrix(), s.tolerance, progress, s.sole_scale,
                              s.feet)  # fmt: skip
    return envelope, comparison(envelope)
