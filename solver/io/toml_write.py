"""Plain data (dicts, lists, strings, numbers, booleans) -> TOML text that ``tomllib`` reads back the same."""

from __future__ import annotations

import json
import math
from typing import Any

from ..errors import ManikinError


def dumps_toml(data: dict, error: type[ManikinError] = ManikinError) -> str:
    """TOML text of ``data``: top-level plain keys, then its tables and arrays of tables; ``error`` for values
    TOML cannot hold (non-finite numbers, other types)."""
    lines = [f"{_key(k)} = {_value(v, error)}" for k, v in data.items() if not _is_table(v)]
    if lines:
        lines.append("")
    _children(lines, "", data, error)
    return "\n".join(lines).rstrip() + "\n"


def _value(value: Any, error: type[ManikinError]) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int | float):
        if not math.isfinite(value):
            raise error(f"cannot write the non-finite number {value!r} to TOML")
        return repr(value)
    if isinstance(value, str):
        return json.dumps(value, ensure_ascii=False)  # a JSON string is a valid TOML basic string
    if isinstance(value, list | tuple):
        return "[" + ", ".join(_value(v, error) for v in value) + "]"
    raise error(f"cannot write {type(value).__name__} values to TOML")


def _table(lines: list[str], header: str, table: dict, error: type[ManikinError]) -> None:
    """``header`` ("[a.b]" or "[[a]]") with its plain keys, then its sub-tables as [a.b.c] and its arrays of
    tables as [[a.c]] (e.g. a target's ``[[targets.keys]]``, which attach to the ``[[targets]]`` just written)."""
    plain = {k: v for k, v in table.items() if not _is_table(v)}
    if plain or header.startswith("[[") or not any(isinstance(v, dict) for v in table.values()):
        lines.append(header)
        lines.extend(f"{_key(k)} = {_value(v, error)}" for k, v in plain.items())
        lines.append("")
    _children(lines, header.strip("[]") + ".", table, error)


def _children(lines: list[str], prefix: str, table: dict, error: type[ManikinError]) -> None:
    """The sub-tables ([prefix.k]) and arrays of tables ([[prefix.k]]) of ``table``."""
    for k, v in table.items():
        if isinstance(v, dict):
            _table(lines, f"[{prefix}{_key(k)}]", v, error)
        elif _is_table(v):
            for item in v:
                _table(lines, f"[[{prefix}{_key(k)}]]", item, error)


def _key(key: str) -> str:
    return key if key.replace("_", "").replace("-", "").isalnum() and key.isascii() else json.dumps(key)


def _is_table(value: Any) -> bool:
    """A table or a non-empty array of tables (written under its own header)."""
    if isinstance(value, dict):
        return True
    return isinstance(value, list) and bool(value) and all(isinstance(v, dict) for v in value)
