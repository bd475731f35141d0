"""A report frame's JSON text with its joint loads written from arrays (:class:`~.loads.JointLoads`): the same
characters as ``json.dumps(..., allow_nan=False)`` of the dicts :func:`.report.frame_report` builds, cheaper.

The per-joint loads are most of a report frame (160 joints of the human body: 22 of its 27 KB). Their names and
keys are encoded once per body into a template (:func:`solver.io.result.frame_text.template`); each frame only turns its
numbers into text, a value that is not finite written as null as :meth:`~.loads.JointLoads.as_dict` has it.
"""

from __future__ import annotations

import json

import numpy as np

from ..io.result.frame_text import SLOT, Numbers, interleave, template
from .loads import JointLoads

_MARK = json.dumps(SLOT)


class LoadsText:
    """``json.dumps(loads.as_dict(), allow_nan=False)`` of frame after frame, the template kept while the joint
    names stay the same."""

    def __init__(self) -> None:
        self._names: list[str] | None = None
        self._template = ""
        self._slots = 0

    def __call__(self, loads: JointLoads) -> str:
        if loads.names != self._names:
            row = [SLOT]
            layout = {name: dict(moment=row, axis_moment=SLOT, percent_strength=SLOT) for name in loads.names}
            layout["l4_l5"] = SLOT
            self._template, self._slots = template(layout, allow_nan=False)
            self._names = list(loads.names)
        numbers = Numbers()
        moments, axis = _rows(loads.moment), numbers.items(loads.axis_moment)
        percent = _nulls(repr(loads.percent.tolist()))[1:-1].split(", ") if len(loads.percent) else []
        filled = (*interleave(moments, axis, percent), json.dumps(loads.l4_l5, allow_nan=False))
        finite = numbers.finite and not any("n" in m for m in moments[:1])  # _rows' first: all, if not finite
        if not finite or len(filled) != self._slots:  # a moment not finite, or names the dict merges
            return json.dumps(loads.as_dict(), allow_nan=False)
        return self._template % filled


def _nulls(text: str) -> str:
    """The repr of a list of floats with each nan, inf and -inf written as null (no other float repr holds them)."""
    return text.replace("-inf", "null").replace("inf", "null").replace("nan", "null") if "n" in text else text


def _rows(a: np.ndarray) -> list[str]:
    """The text inside the brackets of each row of an (n, 3) array (``"x, y, z"``, repr of each float), written
    once for a run of rows with the same bits (the joints of one ball joint share their moment); the first text is
    all the array's text instead when a number is not finite (it holds "nan" or "inf")."""
    a = np.ascontiguousarray(a, dtype=float)
    if not len(a):
        return []
    bits = a.view(np.int64)  # bits, not values: 0.0 and -0.0 are written differently
    starts = np.ones(len(a), dtype=bool)
    starts[1:] = (bits[1:] != bits[:-1]).any(axis=1)
    text = repr(a[starts].tolist())
    if "n" in text:  # "nan", "inf": the only float reprs with an n
        return [text] * len(a)
    texts = text[2:-2].split("], [")
    return [texts[i] for i in (np.cumsum(starts) - 1).tolist()]


def dumps_filled(value: object, filling: str) -> str | None:
    """``json.dumps(value, allow_nan=False)`` with the one :data:`~solver.io.result.frame_text.SLOT` string in ``value``
    replaced by the JSON text ``filling``; None if ``value`` does not hold it exactly once."""
    text = json.dumps(value, allow_nan=False)
    return text.replace(_MARK, filling) if text.count(_MARK) == 1 else None
