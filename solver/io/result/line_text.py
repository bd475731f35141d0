"""The compact file's line of a frame built as text: the same characters as ``json.dumps(compact_frame_dict(...),
separators=(",", ":"))``, at a fraction of the cost (issue 37: the 10,000-frame motion).

Writing a float (its shortest ``repr``) is most of a line's cost, and most numbers of a frame keep their bits from
the frame before (a held target, a joint that did not move): :class:`TextCache` turns only the changed ones into
text. The rest of the line (keys, names, the closest pairs' names, the carried box's name) is a template made once
per layout by ``json.dumps`` of the frame's own dicts (:func:`~.document.frame_status`), each number a slot; a frame
only gathers its numbers in the dicts' order. Anything the template does not expect (a number that is not finite, a
value that is not a float) goes through the dicts as before.
"""

from __future__ import annotations

import json
from typing import TYPE_CHECKING

import numpy as np

from ...collision.carried import CLEARANCE
from ...stance.report import step_dicts
from ..values import floats
from .document import compact_frame_dict, compact_wrenches, frame_status, rotation_quaternion
from .frame_text import COMPACT_JSON, SLOT, template

if TYPE_CHECKING:
    from ...body.state import State
    from ...iteration.result import Result

_ENCODE = COMPACT_JSON.encode
_STRING = json.encoder.encode_basestring_ascii  # what the encoder writes a str with (ensure_ascii)
_HEAD = ("frame", "converged", "stop", "iterations", "time_s", "unmet", "broken", "shortfall", "notes")
_TEXT = ("feet", "joint_values")  # slots filled with text as a whole; "steps" (when stepping) goes in feet's slot
_TEMPLATES = 64  # layouts kept (the closest pairs come and go); more are made again as needed


class TextCache:
    """The JSON texts of a vector's numbers, each kept while its bits stay (-0.0 is not 0.0)."""

    def __init__(self) -> None:
        self._bits: np.ndarray | None = None
        self._texts: np.ndarray = np.array([], dtype=object)

    def __call__(self, values: np.ndarray | list[float]) -> list[str] | None:
        """The text of each number; None when one is not finite (JSON's NaN is not repr's nan)."""
        a = np.array(values, dtype=float)  # a copy: the bits kept for the next call
        bits = a.view(np.int64)
        if self._bits is None or len(bits) != len(self._bits):
            changed = np.ones(len(bits), dtype=bool)
            self._texts = np.empty(len(bits), dtype=object)
        else:
            changed = bits != self._bits
        text = repr(a[changed].tolist())
        if "n" in text:  # "nan", "inf": the only float reprs with an n
            self._bits = None
            return None
        if len(text) > 2:
            self._texts[changed] = text[1:-1].split(", ")
        self._bits = bits
        return self._texts.tolist()


def _small(value: object) -> str:
    """``json.dumps`` of a value of the line's head (compact separators), the common cases without the encoder."""
    kind = type(value)
    if kind is int:
        return int.__repr__(value)
    if kind is float:
        text = float.__repr__(value)
        return text if "n" not in text else _ENCODE(value)
    if value is None or kind is bool:
        return "null" if value is None else "true" if value else "false"
    if kind is str:
        return _STRING(value)
    if (kind is list or kind is dict) and not value:
        return "[]" if kind is list else "{}"
    return _ENCODE(value)


def _slotted(value: object) -> object:
    """``value`` with :data:`SLOT` in place of each float (the numbers a frame fills in)."""
    if isinstance(value, dict):
        return {k: _slotted(v) for k, v in value.items()}
    if isinstance(value, list):
        return [_slotted(v) for v in value]
    return SLOT if isinstance(value, float) else value


class CompactText:
    """``json.dumps(compact_frame_dict(result, frame, state), separators=(",", ":"))`` of frame after frame."""

    def __init__(self) -> None:
        self._joints = TextCache()  # the joint values
        self._numbers = TextCache()  # every other float of the line but time_s, in the line's order
        self._templates: dict[tuple, tuple[str, int, int]] = {}  # layout -> (template, numbers before feet, after)

    def joint_values(self, theta: np.ndarray) -> str | None:
        """The JSON array of joint values ``theta``; None when one is not finite."""
        texts = self._joints(theta)
        return None if texts is None else "[" + ",".join(texts) + "]"

    def __call__(self, result: Result, frame: int = 1, state: State | None = None) -> str:
        """The compact file's line of one frame (without its newline)."""
        state = result.state if state is None else state
        line = self._line(result, frame, state)
        return line if line is not None else _ENCODE(compact_frame_dict(result, frame, state))

    def _line(self, result: Result, frame: int, state: State) -> str | None:
        """The line through the layout's template, or None for anything it does not cover."""
        problem = result.problem
        targets = problem.target_frames(state)
        closest, carried, steps = result.closest, problem.carried_constraint, step_dicts(result)
        residuals, terms = result.residuals, result.comfort_parts
        loads = list(zip(problem.loads, state.statics.load_points, strict=True))
        scalars = [*residuals.values(), result.comfort, *terms.values()]
        nums: list[float] = []
        for rotation, position in targets.values():
            nums += floats(position)
            nums += rotation_quaternion(rotation)
        nums += scalars
        nums += floats(result.com)
        for c in closest:
            scalars += (c.distance, c.clearance)
            nums += (c.distance + 0.0, c.clearance + 0.0, *(np.asarray(c.point, dtype=float) + 0.0).tolist(),
                     *(np.asarray(c.other_point, dtype=float) + 0.0).tolist())  # fmt: skip
        if carried is not None:
            centre, rotation = carried.frame(state)
            nums += floats(carried.carried.size)
            nums += floats(centre)
            nums += rotation_quaternion(rotation)
            nums.append(CLEARANCE)
        split = len(nums)
        for c in result.contacts:
            nums += floats(c["point"])
            nums += floats(c["force"])
            nums += floats(c["moment"])
        for ld, point in loads:
            nums += floats(point)
            nums += floats(ld.force)
        if not all(isinstance(v, float) for v in scalars):  # an int, a None: JSON writes them otherwise
            return None
        box = None if carried is None else (carried.carried.name, tuple(carried.carried.tcps), tuple(carried.excluded))
        names = tuple([(c.part, c.other) for c in closest])
        wrenches = tuple([c["tcp"] for c in result.contacts]), tuple([ld.tcp.name for ld, _ in loads])
        key = (tuple(targets), tuple(residuals), tuple(terms), names, box, steps is None, wrenches)
        made = self._templates.get(key)
        if made is None:
            made = self._template(key, result, frame, state)
        text, before, after = made
        texts = self._numbers(nums)
        values = self.joint_values(result.theta)
        if texts is None or values is None or len(texts) != before + after or before != split:
            return None
        feet = '"planted"' if steps is None else '"step","steps":' + _ENCODE(steps)
        head = [_small(getattr(result, name)) for name in ("converged", "iterations", "time_s")]
        fills = (
            _small(frame), head[0], _small(None if result.stop is None else result.stop.value), head[1], head[2],
            _small(list(result.unmet)), _small(list(result.broken)), _small(result.shortfall),
            _small(list(result.notes)), *texts[:before], feet, values, *texts[before:],
        )  # fmt: skip
        return text % fills

    def _template(self, key: tuple, result: Result, frame: int, state: State) -> tuple[str, int, int]:
        """The layout's template from the frame's own dicts: (text, numbers before feet, numbers after)."""
        status = frame_status(result, frame, state)
        status.pop("steps", None)
        status["joint_values"] = SLOT
        status |= compact_wrenches(result, state)
        cut = list(status).index("feet")
        for name in _HEAD + _TEXT:
            status[name] = SLOT
        before = template({k: _slotted(v) for k, v in list(status.items())[:cut]}, separators=(",", ":"))[1]
        text, slots = template({k: _slotted(v) for k, v in status.items()}, separators=(",", ":"))
        if len(self._templates) >= _TEMPLATES:
            self._templates.clear()
        made = self._templates[key] = (text, before - len(_HEAD), slots - before - len(_TEXT))
        return made
