"""The compact file's line of a frame built as text: the same characters as ``json.dumps(compact_frame_dict(...),
separators=(",", ":"))``, cheaper (issue 37: the 10,000-frame motion).

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
from .document import compact_frame_dict, compact_wrenches, frame_status, rotation_quaternion
from .frame_text import COMPACT_JSON, SLOT, template

if TYPE_CHECKING:
    from ...body.state import State
    from ...constraints.clearance import Closeness
    from ...iteration.result import Result

_ENCODE = COMPACT_JSON.encode
_STRING = json.encoder.encode_basestring_ascii  # what the encoder writes a str with (ensure_ascii)
_HEAD = ("frame", "converged", "stop", "iterations", "time_s", "unmet", "broken", "shortfall", "notes")
_FLOATS = {float, np.float64}  # the number types JSON writes as float.__repr__ does
_TEMPLATES = 64  # layouts kept; more are made again as needed
_CLEARANCE = (CLEARANCE,)


class TextCache:
    """The JSON texts of a vector's numbers, each kept while its bits stay (-0.0 is not 0.0); a vector of another
    length keeps the texts of the numbers they share at the start."""

    def __init__(self) -> None:
        self._bits: np.ndarray | None = None
        self._texts: np.ndarray = np.array([], dtype=object)

    def __call__(self, a: np.ndarray) -> list[str] | None:
        """The text of each number of the float64 vector ``a`` (kept: not to be changed after); None when one is not
        finite (JSON's NaN is not repr's nan)."""
        bits, old = a.view(np.int64), self._bits
        if old is not None and len(old) == len(bits):
            changed = bits != old
        else:
            changed = np.ones(len(bits), dtype=bool)
            texts = np.empty(len(bits), dtype=object)
            if old is not None:
                kept = min(len(old), len(bits))
                changed[:kept] = bits[:kept] != old[:kept]
                texts[:kept] = self._texts[:kept]
            self._texts = texts
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


def _count(value: object) -> int:
    """How many floats ``value`` holds (the slots :func:`_slotted` puts in)."""
    if isinstance(value, dict):
        return sum(_count(v) for v in value.values())
    if isinstance(value, list):
        return sum(_count(v) for v in value)
    return isinstance(value, float)


def _near(closest: list[Closeness]) -> np.ndarray:
    """The closest pairs' numbers pair by pair (distance, clearance, point, other_point), a -0.0 (a touching pair's
    exact zero) as 0.0, as :meth:`~solver.constraints.clearance.Closeness.to_dict` writes them."""
    if not closest:
        return np.empty(0)
    out = np.empty((len(closest), 8))
    out[:, :2] = [(c.distance, c.clearance) for c in closest]
    out[:, 2:] = np.concatenate([p for c in closest for p in (c.point, c.other_point)]).reshape(len(closest), 6)
    out += 0.0
    return out.ravel()


class CompactText:
    """``json.dumps(compact_frame_dict(result, frame, state), separators=(",", ":"))`` of frame after frame."""

    def __init__(self) -> None:
        self._numbers = TextCache()  # the joint values, the line's other floats but time_s, the closest pairs' last
        self._templates: dict[tuple, tuple[str, int, int, int]] = {}  # layout -> (template, its number counts)
        self._pairs: dict[tuple[str, str], str] = {}  # a closest pair's names -> its entry's template
        self._quaternions: dict[bytes, np.ndarray] = {}  # a rotation's bits -> its quaternion (rotation_quaternion)

    def __call__(self, result: Result, frame: int = 1, state: State | None = None) -> str:
        """The compact file's line of one frame (without its newline)."""
        state = result.state if state is None else state
        line = self._line(result, frame, state)
        return line if line is not None else _ENCODE(compact_frame_dict(result, frame, state))

    def _line(self, result: Result, frame: int, state: State) -> str | None:
        """The line through the layout's template, or None for anything it does not cover."""
        problem = result.problem
        targets, carried, steps = problem.target_frames(state), problem.carried_constraint, step_dicts(result)
        residuals, terms, closest = result.residuals, result.comfort_parts, result.closest
        loads = list(zip(problem.loads, state.statics.load_points, strict=True))
        scalars = [
            *residuals.values(),
            result.comfort,
            *terms.values(),
            *[v for c in closest for v in (c.distance, c.clearance)],
        ]
        # the line's numbers as the arrays they are, joined once (not each made a list, then an array again)
        theta = result.theta
        parts = [theta]
        quaternion = self._quaternion
        for rotation, position in targets.values():
            parts += (position, quaternion(rotation))
        parts += (scalars[: len(scalars) - 2 * len(closest)], result.com)
        ends = [sum(map(len, parts)) - len(theta)]
        if carried is not None:
            centre, rotation = carried.frame(state)
            parts += (carried.carried.size, centre, quaternion(rotation), _CLEARANCE)
        ends.append(sum(map(len, parts)) - len(theta))
        for c in result.contacts:
            parts += (c["point"], c["force"], c["moment"])
        for ld, point in loads:
            parts += (point, ld.force)
        ends.append(sum(map(len, parts)) - len(theta))
        if not set(map(type, scalars)) <= _FLOATS:  # an int, a None: JSON writes them otherwise
            return None
        box = None if carried is None else (carried.carried.name, tuple(carried.carried.tcps), tuple(carried.excluded))
        wrenches = tuple([c["tcp"] for c in result.contacts]), tuple([ld.tcp.name for ld, _ in loads])
        key = (tuple(targets), tuple(residuals), tuple(terms), box, steps is None, wrenches)
        made = self._templates.get(key) or self._template(key, result, frame, state)
        parts.append(_near(closest))  # the closest pairs last: their count varies
        a = np.concatenate(parts, dtype=float)
        texts = self._numbers(a)
        if texts is None or made[1:] != tuple(ends):
            return None
        values, texts = "[" + ",".join(texts[: len(theta)]) + "]", texts[len(theta) :]
        pairs = []
        for i, c in enumerate(closest):
            pair = self._pairs.get((c.part, c.other)) or self._pair(c)
            if pair is None:
                return None
            pairs.append(pair % tuple(texts[ends[2] + 8 * i : ends[2] + 8 * i + 8]))
        feet = '"planted"' if steps is None else '"step","steps":' + _ENCODE(steps)
        head = [_small(getattr(result, name)) for name in ("converged", "iterations", "time_s")]
        fills = (
            _small(frame), head[0], _small(None if result.stop is None else result.stop.value), head[1], head[2],
            _small(list(result.unmet)), _small(list(result.broken)), _small(result.shortfall),
            _small(list(result.notes)), *texts[: ends[0]], "[" + ",".join(pairs) + "]", *texts[ends[0] : ends[1]],
            feet, values, *texts[ends[1] : ends[2]],
        )  # fmt: skip
        return made[0] % fills

    def _quaternion(self, rotation: np.ndarray) -> np.ndarray:
        """:func:`~.document.rotation_quaternion` of a rotation matrix as an array, kept by its bits (a held target's
        rotation: the same bits frame after frame)."""
        bits = np.asarray(rotation, dtype=float).tobytes()
        found = self._quaternions.get(bits)
        if found is None:
            if len(self._quaternions) >= _TEMPLATES * 4:
                self._quaternions.clear()
            found = self._quaternions[bits] = np.array(rotation_quaternion(rotation))
        return found

    def _pair(self, c: Closeness) -> str | None:
        """The template of a closest pair's entry (:meth:`~solver.constraints.clearance.Closeness.to_dict`); None
        if it does not hold the 8 numbers :func:`_near` gathers."""
        text, slots = template(_slotted(c.to_dict()), separators=(",", ":"))
        if slots != 8:
            return None
        if len(self._pairs) >= _TEMPLATES * 16:
            self._pairs.clear()
        self._pairs[c.part, c.other] = text
        return text

    def _template(self, key: tuple, result: Result, frame: int, state: State) -> tuple[str, int, int, int]:
        """The layout's template from the frame's own dicts: (text, the number counts up to the closest pairs, up to
        the feet, up to the end)."""
        status = frame_status(result, frame, state)
        status.pop("steps", None)
        status["joint_values"] = SLOT
        status |= compact_wrenches(result, state)
        for name in (*_HEAD, "closest", "feet", "joint_values"):
            status[name] = SLOT
        keys = list(status)
        parts = keys[len(_HEAD) : keys.index("closest")], keys[keys.index("closest") : keys.index("feet")], keys
        ends = tuple(sum(_count(status[k]) for k in part) for part in parts)
        text, _ = template({k: _slotted(v) for k, v in status.items()}, separators=(",", ":"))
        if len(self._templates) >= _TEMPLATES:
            self._templates.clear()
        made = self._templates[key] = (text, ends[0], ends[0] + ends[1], ends[2])
        return made
