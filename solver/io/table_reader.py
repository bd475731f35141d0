"""Typed access to a parsed TOML or JSON table: each getter checks one key, and every failure is one line.

The message names the file, the key's full path and what was expected, then what was found::

    scene.toml: targets[1].position: expected 3 finite numbers, got [0.1, 0.2]

The error class is the reader's (:class:`~solver.errors.ScenarioError` for scenarios,
:class:`~solver.errors.ResultFileError` for result files, ...), so one reader serves every file format.
"""

from __future__ import annotations

import math
from collections.abc import Collection
from pathlib import Path
from typing import Any

import numpy as np

from ..body.spatial import quat_to_matrix
from ..errors import ManikinError, shown
from ..errors import is_number as finite_number
from ..options import AXES

_MISSING = object()
QUATERNION_LIMIT = 1e6  # a quaternion's components: normalised when read, but beyond this its norm overflows
OPERATOR_RANGE = (1e-6, 1e3)  # an operator row's largest |entry|: its scale cancels in its tolerance, but a zero
# row has no tolerance and a huge one overflows


def is_number(value: Any) -> bool:
    """A finite int or float (not a bool, not an int too large for a float): :func:`solver.errors.is_number`."""
    return finite_number(value)


def span(low: float, high: float) -> str:
    """ "a number in [low, high]", or ">= low" / "<= high" when the other end is open."""
    if high == -low == math.inf:
        return "a finite number"
    if high == math.inf:
        return f"a number >= {low:g}"
    if low == -math.inf:
        return f"a number <= {high:g}"
    return f"a number in [{low:g}, {high:g}]"


def unit_of(unit: str) -> str:
    return f" {unit}" if unit else ""


class TableReader:
    """The table ``data`` found at ``prefix`` (e.g. ``"targets[0]."``) in the file ``path``."""

    def __init__(self, path: Path | str, data: dict, prefix: str = "", error: type[ManikinError] = ManikinError):
        self.path, self.data, self.prefix, self.error = path, data, prefix, error

    def fail(self, key: str, expected: str, value: Any = _MISSING) -> ManikinError:
        """The error for ``key``: ``path: prefix.key: expected ..., got value`` (one line; a long value cut short)."""
        got = "" if value is _MISSING else f", got {shown(value)}"
        where = f"{self.prefix}{key}".rstrip(".")
        return self.error(f"{self.path}: {where}: expected {expected}{got}")

    def sub(self, key: str, data: dict) -> TableReader:
        """A reader of ``data``, the table under ``key``."""
        return TableReader(self.path, data, f"{self.prefix}{key}.", self.error)

    def known(self, keys: Collection[str]) -> None:
        """Refuse keys not in ``keys`` (a typo must not pass silently)."""
        for key in self.data:
            if key not in keys:
                raise self.fail(key, "one of " + ", ".join(sorted(keys)) + " (unknown key)")

    def required(self, *keys: str) -> None:
        """Refuse a table without each of ``keys``."""
        for key in keys:
            if key not in self.data:
                raise self.fail(key, "a value (missing)")

    def exactly_one(self, a: str, b: str, expected: str) -> str:
        """Which of the two keys ``a`` and ``b`` is given; refuse both or neither."""
        if (a in self.data) == (b in self.data):
            raise self.fail(a, expected)
        return a if a in self.data else b

    def get(self, key: str, default: Any = None) -> Any:
        return self.data.get(key, default)

    def number(
        self, key: str, default: float | None = None, low: float = -math.inf, high: float = math.inf, unit: str = ""
    ) -> float:
        """A finite number in [low, high] (``unit`` for the message, e.g. "kg"); ``default`` when absent (None:
        required)."""
        value = self.data.get(key, default)
        if value is None:
            raise self.fail(key, "a number (missing)")
        if not is_number(value) or not low <= value <= high:
            raise self.fail(key, span(low, high) + unit_of(unit), value)
        return float(value)

    def positive(self, key: str, high: float, unit: str = "") -> float:
        """A required number in (0, high] (a radius, a length: zero is not one)."""
        value = self.data.get(key)
        if value is None:
            raise self.fail(key, "a number (missing)")
        if not is_number(value) or not 0 < value <= high:
            raise self.fail(key, f"a number in (0, {high:g}]" + unit_of(unit), value)
        return float(value)

    def integer(self, key: str, default: int | None, low: float, high: float, what: str = "a whole number") -> int:
        """A whole number in [low, high] (``what`` says which, e.g. "a whole frame number")."""
        value = self.data.get(key, default)
        if value is None:
            raise self.fail(key, f"{what} (missing)")
        if not is_number(value) or value != int(value) or not low <= value <= high:
            raise self.fail(key, f"{what} in [{low:.0f}, {high:.0f}]", value)
        return int(value)

    def limit(self, key: str, unlimited: float, bound: float = math.inf, unit: str = "") -> float:
        """A number within +-``bound``, or ``unlimited`` (an infinity) when the key is absent or null."""
        return unlimited if self.data.get(key) is None else self.number(key, None, -bound, bound, unit)

    def boolean(self, key: str, default: bool) -> bool:
        value = self.data.get(key, default)
        if not isinstance(value, bool):
            raise self.fail(key, "true or false", value)
        return value

    def string(self, key: str, default: str | None = None) -> str:
        value = self.data.get(key, default)
        if not isinstance(value, str) or not value:
            raise self.fail(key, "a non-empty string", value)
        return value

    def choice(self, key: str, options: Collection[str], what: str) -> str:
        """A string among ``options`` (``what`` says which, e.g. "a TCP of the manikin")."""
        value = self.data.get(key)
        if key not in self.data:
            raise self.fail(key, f"{what}: " + ", ".join(sorted(options)) + " (missing)")
        if not isinstance(value, str) or value not in options:
            raise self.fail(key, f"{what}: " + ", ".join(sorted(options)), value)
        return value

    def vector(self, key: str, size: int, default: Any = None, limit: float = math.inf, unit: str = "") -> np.ndarray:
        """``size`` finite numbers, each within +-``limit`` (``unit`` for the message, e.g. "m")."""
        value = self.data.get(key, default)
        if not (isinstance(value, list) and len(value) == size and all(is_number(v) for v in value)):
            raise self.fail(key, f"{size} finite numbers" + (f" ({unit})" if unit else ""), value)
        if any(abs(v) > limit for v in value):
            raise self.fail(key, f"{size} numbers within +-{limit:g}" + unit_of(unit), value)
        return np.asarray(value, dtype=float)

    def points(self, key: str, dimension: int, what: str) -> np.ndarray:
        """A non-empty list of points of ``dimension`` finite numbers each (``what`` describes them)."""
        value = self.data.get(key)
        if not isinstance(value, list) or not value:
            raise self.fail(key, f"{what} (finite numbers)", value)
        for i, p in enumerate(value):  # the first bad point by its index
            if not (isinstance(p, list) and len(p) == dimension and all(is_number(c) for c in p)):
                raise self.fail(f"{key}[{i}]", f"{dimension} finite numbers", p)
        return np.asarray(value, dtype=float)

    def rotation(self, key: str, default: Any = None) -> np.ndarray | None:
        """The rotation matrix of the quaternion [w, x, y, z] at ``key``; None when absent and no default."""
        if key not in self.data and default is None:
            return None
        q = self.vector(key, 4, default, limit=QUATERNION_LIMIT)
        if np.linalg.norm(q) < 1e-9:
            raise self.fail(key, "a non-zero quaternion [w, x, y, z]", self.data.get(key, default))
        return quat_to_matrix(q)

    def lock(self, key: str, default: tuple[str, ...]) -> tuple[str, ...]:
        """A list of locked axes from ``AXES``."""
        value = self.data.get(key, list(default))
        if not isinstance(value, list) or not all(isinstance(a, str) and a in AXES for a in value):
            raise self.fail(key, f"a list of axes from {list(AXES)}", value)
        return tuple(value)

    def operator(self, key: str) -> np.ndarray | None:
        """A (k, 6) relaxation operator, or None when absent."""
        if key not in self.data:
            return None
        value = self.data[key]
        try:
            op = np.asarray(value, dtype=float)
        except (TypeError, ValueError):
            raise self.fail(key, "a list of rows of 6 numbers", value) from None
        if op.ndim != 2 or op.shape[1] != 6 or not 1 <= op.shape[0] <= 6 or not np.isfinite(op).all():
            raise self.fail(key, "1 to 6 rows of 6 finite numbers", value)
        for i, row in enumerate(np.abs(op)):
            if not OPERATOR_RANGE[0] <= row.max() <= OPERATOR_RANGE[1]:
                low, high = OPERATOR_RANGE
                raise self.fail(f"{key}[{i}]", f"a row whose largest |entry| is in [{low:g}, {high:g}]", value[i])
        return op

    def table(self, key: str) -> TableReader:
        """The table at ``key`` (empty when absent)."""
        value = self.data.get(key, {})
        if not isinstance(value, dict):
            raise self.fail(key, "a table", value)
        return self.sub(key, value)

    def table_list(self, key: str, non_empty: bool = False) -> list[TableReader]:
        """The array of tables at ``key`` (``[[key]]`` in TOML, a list of objects in JSON), one reader each."""
        value = self.data.get(key, [])
        if not isinstance(value, list) or not all(isinstance(v, dict) for v in value) or (non_empty and not value):
            raise self.fail(key, ("a non-empty " if non_empty else "an ") + "array of tables", value)
        return [TableReader(self.path, v, f"{self.prefix}{key}[{i}].", self.error) for i, v in enumerate(value)]

    def named_tables(self, key: str) -> dict[str, TableReader]:
        """The tables of the table at ``key`` by name (e.g. ``joints.<name>``), one reader each."""
        outer = self.table(key)
        named = {}
        for name in outer.data:
            named[name] = outer.table(name)
        return named
