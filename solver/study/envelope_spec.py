"""A study's ``[envelope]`` table: reach envelopes of every study manikin for every combination of its settings
(docs/tutorials/study.md, "Reach envelopes in a study"). Every problem is one ScenarioError line naming the
study file and the key.

::

    [envelope]
    name = "reach"            # the rows' scenario column (default "envelope")
    hand = "right"            # "right", "left", "both", or a list of hands
    load_kg = [0.0, 10.0]     # kg in the hand: a number or a list (one envelope each)
    feet = ["planted", "step"]   # "planted", "step" or both
    sole_scale = 1.0          # the centre of pressure kept in the soles scaled by this: a number or a list
    frequency = 3             # geodesic sphere: 10 f^2 + 2 directions
    hemisphere = "all"        # or front, back, upper, lower, left, right
    tolerance = 0.02          # m, the reach's resolution
    rotation = [1, 0, 0, 0]   # the hand's fixed orientation (w, x, y, z); absent: free
    plot = true               # a PNG of sections per envelope

Every list is a study parameter (``p_hand``, ``p_load_kg``, ``p_feet``, ``p_sole_scale`` columns); the envelope of
each combination is computed by :func:`solver.envelope.job.compute_envelope`, as ``python -m solver envelope`` does.
"""

from __future__ import annotations

import itertools
import re
from dataclasses import dataclass

from ..envelope.directions import HEMISPHERES, MAX_FREQUENCY
from ..envelope.job import HANDS, EnvelopeSettings
from ..envelope.reach import FEET_MODES, MAX_LOAD
from ..io.table_reader import TableReader, is_number

KEYS = {"name", "hand", "load_kg", "feet", "sole_scale", "frequency", "hemisphere", "tolerance", "rotation",
        "plot"}  # fmt: skip
PARAMETERS = ("hand", "load_kg", "feet", "sole_scale")  # the settings a row varies (its p_ columns)


@dataclass(frozen=True)
class EnvelopeStudy:
    """A parsed ``[envelope]`` table (see the module docstring)."""

    name: str
    hands: tuple[str, ...]
    loads: tuple[float, ...]
    feet: tuple[str, ...]
    sole_scales: tuple[float, ...]
    frequency: int
    hemisphere: str
    tolerance: float
    rotation: tuple[float, ...] | None
    plot: bool

    def grid(self) -> list[dict]:
        """Every combination of the varied settings, {hand, load_kg, feet, sole_scale} (hands slowest)."""
        combos = itertools.product(self.hands, self.loads, self.feet, self.sole_scales)
        return [dict(zip(PARAMETERS, combo, strict=True)) for combo in combos]

    def inputs(self) -> dict:
        """What every row shares (its run id hashes them): the fixed settings (not ``plot``, a file choice)."""
        return dict(kind="envelope", name=self.name, frequency=self.frequency, hemisphere=self.hemisphere,
                    tolerance=self.tolerance, rotation=self.rotation)  # fmt: skip

    def settings(self, values: dict) -> EnvelopeSettings:
        """The settings of the combination ``values`` (one of :meth:`grid`)."""
        return EnvelopeSettings(values["load_kg"], self.rotation, self.tolerance, values["sole_scale"],
                                values["feet"], self.frequency, self.hemisphere)  # fmt: skip


def mesh_name(manikin: str, values: dict) -> str:
    """The file name stem of one envelope of a study (``<manikin>_<hand>_<load>kg_<feet>[_sole<scale>]``, the
    manikin's name with anything but letters, digits, ``_``, ``.`` and ``-`` made a ``-``)."""
    name = f"{re.sub(r'[^A-Za-z0-9_.-]+', '-', manikin)}_{values['hand']}_{values['load_kg']:g}kg_{values['feet']}"
    return name + (f"_sole{values['sole_scale']:g}" if values["sole_scale"] != 1.0 else "")


def _listed(t: TableReader, key: str, default, ok, expected: str) -> tuple:
    """The value at ``key`` as a tuple: one value or a non-empty list of distinct ones, each passing ``ok``."""
    value = t.get(key, default)
    items = value if isinstance(value, list) else [value]
    if not items or not all(ok(v) for v in items) or len({repr(v) for v in items}) != len(items):
        raise t.fail(key, f"{expected}, or a non-empty list of distinct ones", value)
    return tuple(items)


def load_envelope(t: TableReader) -> EnvelopeStudy:
    """The ``[envelope]`` table read by ``t``; a ScenarioError line for a bad or unknown key."""
    t.known(KEYS)
    hands = _listed(t, "hand", "right", lambda v: v in HANDS, 'a hand: "right", "left" or "both"')
    hands = tuple(dict.fromkeys(side for h in hands for side in HANDS[h]))
    loads = _listed(t, "load_kg", 0.0, lambda v: is_number(v) and 0.0 <= v <= MAX_LOAD,
                    f"kg in [0, {MAX_LOAD:g}]")  # fmt: skip
    feet = _listed(t, "feet", "planted", lambda v: v in FEET_MODES, " or ".join(f'"{f}"' for f in FEET_MODES))
    scales = _listed(t, "sole_scale", 1.0, lambda v: is_number(v) and 0.1 <= v <= 1.0, "a fraction in [0.1, 1]")
    rotation = None
    if "rotation" in t.data:
        q = t.vector("rotation", 4, limit=1e6)
        if sum(v * v for v in q) < 1e-18:
            raise t.fail("rotation", "a non-zero quaternion [w, x, y, z]", t.get("rotation"))
        rotation = tuple(float(v) for v in q)
    hemisphere = t.get("hemisphere", "all")
    if hemisphere not in HEMISPHERES:
        raise t.fail("hemisphere", "one of " + ", ".join(HEMISPHERES), hemisphere)
    return EnvelopeStudy(
        name=t.string("name", "envelope"),
        hands=hands,
        loads=tuple(float(v) for v in loads),
        feet=feet,
        sole_scales=tuple(float(v) for v in scales),
        frequency=t.integer("frequency", 3, 1, MAX_FREQUENCY),
        hemisphere=hemisphere,
        tolerance=t.number("tolerance", 0.02, 0.001, 0.2, "m"),
        rotation=rotation,
        plot=t.boolean("plot", True),
    )
