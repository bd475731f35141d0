"""Key paths into a parsed scenario (its TOML tables as dicts and lists): where a study's parameter goes.

A path is dotted keys with list indices, e.g. ``targets.hand_r.position[2]`` or ``obstacles."table top".center[2]``:

* ``word`` or ``"quoted words"`` is the key of a table; on an array of tables (``[[targets]]``, ``[[obstacles]]``,
  ``[[loads]]``) it picks the one entry whose ``name``, else whose ``tcp``, is that word (it must be just one);
* ``[i]`` is the i-th item of a list (from 0), e.g. ``position[2]`` (z) or ``keys[1]`` (a motion's second key).

Every key the path names must be in the scenario file: the file holds the value a run without the parameter uses,
and a typo then fails at once, one line naming the study file, the parameter and the path.
"""

from __future__ import annotations

import functools
import math
import re
from typing import Any

TOKEN = re.compile(r'\s*(?:"(?P<quoted>[^"]*)"|(?P<word>[A-Za-z0-9_\-]+)|\[(?P<index>\d+)\]|(?P<dot>\.))')

Step = str | int  # a table key (str) or a list index (int)


def parse(path: str) -> list[Step]:
    """The steps of ``path``; ValueError saying what is wrong for a malformed one."""
    steps: list[Step] = []
    at, need_key = 0, True
    while at < len(path):
        m = TOKEN.match(path, at)
        if m is None or m.end() == at:
            raise ValueError(f'cannot read {path[at:]!r} (keys are words or "quoted", indices [0], [1], ...)')
        at = m.end()
        if m.group("dot") is not None:
            if need_key:
                raise ValueError("a key is missing before or after a '.'")
            need_key = True
        elif m.group("index") is not None:
            if need_key:
                raise ValueError("an index [i] must follow a key")
            steps.append(int(m.group("index")))
        else:
            if not need_key:
                raise ValueError("keys must be separated by '.'")
            steps.append(m.group("quoted") if m.group("quoted") is not None else m.group("word"))
            need_key = False
    if need_key:
        raise ValueError("empty path or a trailing '.'" if steps or not path.strip() else "empty path")
    return steps


def _pick(entries: list, key: str) -> int:
    """The index of the one table in ``entries`` named ``key`` (by ``name``, else by ``tcp``)."""
    for field in ("name", "tcp"):
        found = [i for i, e in enumerate(entries) if isinstance(e, dict) and e.get(field) == key]
        if len(found) == 1:
            return found[0]
        if len(found) > 1:
            raise ValueError(f"{len(found)} entries have {field} = {key!r}; pick one by its index [i]")
    names = [e.get("name", e.get("tcp")) for e in entries if isinstance(e, dict)]
    raise ValueError(f"no entry named {key!r} (by name or tcp; there are: {', '.join(map(str, names)) or 'none'})")


def locate(data: dict, steps: list[Step] | tuple[Step, ...]) -> tuple[dict | list, str | int]:
    """The container holding the value at ``steps`` and its key there; ValueError naming the first missing step."""
    node: Any = data
    shown = ""
    for i, step in enumerate(steps):
        if isinstance(step, str) and isinstance(node, list):
            step = _pick(node, step)
        if isinstance(step, int):
            if not isinstance(node, list) or step >= len(node):
                size = f"a list of {len(node)}" if isinstance(node, list) else type(node).__name__
                raise ValueError(f"{shown or 'the file'}[{step}]: no such item ({size})")
            shown += f"[{step}]"
        else:
            if not isinstance(node, dict) or step not in node:
                raise ValueError(f"{shown + '.' if shown else ''}{step}: not in the scenario file")
            shown += f".{step}" if shown else step
        if i == len(steps) - 1:
            return node, step
        node = node[step]
    raise ValueError("empty path")


def kind(value: Any) -> str:
    """The kind of a TOML value a parameter may replace it with: number, boolean, string, list or table."""
    if isinstance(value, bool):
        return "boolean"
    if isinstance(value, int | float):
        return "number"
    return {str: "string", list: "list", dict: "table"}.get(type(value), type(value).__name__)


def check(data: dict, path: str, values: list, add: bool) -> None:
    """Refuse a path that is not in ``data`` or whose value the parameter's ``values`` cannot replace (``add``:
    every value and the file's value must be numbers); ValueError saying why."""
    container, key = locate(data, parse(path))
    old = container[key]
    if add:
        if kind(old) != "number":
            raise ValueError(f"add needs a number there, the file has {old!r}")
        return
    for value in values:
        if kind(value) != kind(old):
            raise ValueError(f"the file has a {kind(old)} there ({old!r}), the parameter gives {value!r}")


@functools.lru_cache(maxsize=256)  # a study applies its few paths every run
def _steps(path: str) -> tuple[Step, ...]:
    """:func:`parse` of ``path``, kept (a malformed path is not: it raises every time)."""
    return tuple(parse(path))


def apply(data: dict, path: str, value: Any, add: bool) -> None:
    """Set (or, with ``add``, shift) the value at ``path`` in ``data`` in place (:func:`check` passed)."""
    container, key = locate(data, _steps(path))
    new = container[key] + value if add else value
    if isinstance(new, float) and not math.isfinite(new):
        raise ValueError(f"{path}: {new} is not a finite number")
    container[key] = new
