"""What a TOML or JSON parser cannot take, said in one line naming the file, the line and the key.

Python refuses to read an integer of more than 4,300 digits (``ValueError``: its guard against slow conversions)
and its parsers recurse once per level of nested arrays or tables (``RecursionError`` after a few hundred). Both
become one line here. A file that parses is then held to :data:`MAX_DEPTH` levels (:func:`check_depth`), so no
later step (a copy, an error line showing the value) meets a nesting it cannot handle either.
"""

from __future__ import annotations

import re
import sys
from pathlib import Path
from typing import Any

from ..errors import ManikinError

MAX_DEPTH = 32  # levels of nested arrays and tables a file may have (the deepest shipped file has 6)
_LIMIT = sys.get_int_max_str_digits() or 4300  # the most digits int() reads from text
_LONG = re.compile(r"\d[\d_]{" + str(_LIMIT) + ",}")  # a run of more digits than that
_KEY = re.compile(r"""["']?([\w.\-]+)["']?\s*[=:][^=:]*$""")  # the last `key = ` or `"key":` before a value


def key_before(text: str, pos: int) -> str:
    """The key whose value starts at ``pos`` in ``text`` (``key = ...``, ``"key": ...``), or "" when not found."""
    match = _KEY.search(text[max(0, pos - 200) : pos])
    return match.group(1) if match else ""


def where(text: str, pos: int) -> str:
    """``line N: key: `` for the position ``pos`` of ``text``."""
    key = key_before(text, pos)
    return f"line {text.count(chr(10), 0, pos) + 1}: " + (f"{key}: " if key else "")


def too_many_digits(path: Path | str, text: str, error: type[ManikinError], offset: int = 0) -> ManikinError:
    """The error for an integer longer than Python reads (the first such run of digits from ``offset``)."""
    match = _LONG.search(text, offset)
    if match is None:  # not found (cut by a chunk): still one line
        return error(f"{path}: an integer of more than {_LIMIT} digits")
    digits = sum(c.isdigit() for c in match.group())
    return error(f"{path}: {where(text, match.start())}expected a number, got an integer of {digits} digits")


def too_deep(path: Path | str, text: str, error: type[ManikinError], offset: int = 0) -> ManikinError:
    """The error for arrays or tables nested past what the parser takes: where they pass :data:`MAX_DEPTH`."""
    depth, quoted, pos = 0, False, len(text)
    for i in range(offset, len(text)):  # brackets outside double-quoted strings (enough to find the place)
        c = text[i]
        if c == '"' and text[i - 1] != "\\":
            quoted = not quoted
        elif not quoted and c in "[{":
            depth += 1
            if depth > MAX_DEPTH:
                pos = i
                break
        elif not quoted and c in "]}":
            depth -= 1
    return error(f"{path}: {where(text, pos)}arrays or tables nested more than {MAX_DEPTH} levels deep")


def check_depth(data: Any, path: Path | str, error: type[ManikinError], prefix: str = "") -> None:
    """Refuse ``data`` nested more than :data:`MAX_DEPTH` levels, naming the key path of the first too deep value."""
    if _depth_within(data):  # the usual case, told without building a key path per value
        return
    stack = [(data, prefix, 0)]
    while stack:  # iterative: the point is a depth Python's recursion cannot take
        value, key, depth = stack.pop()
        if depth > MAX_DEPTH:
            key = re.sub(r"(\[\d+\]){3,}", "[...]", key)  # not 33 indices in a row
            raise error(f"{path}: {key or 'the file'}: arrays or tables nested more than {MAX_DEPTH} levels deep")
        if isinstance(value, dict):
            stack += [(v, f"{key}.{k}" if key else str(k), depth + 1) for k, v in value.items()]
        elif isinstance(value, list):
            stack += [(v, f"{key}[{i}]", depth + 1) for i, v in enumerate(value)]


def _depth_within(data: Any) -> bool:
    """Whether no value of ``data`` is nested more than :data:`MAX_DEPTH` levels (as :func:`check_depth` counts)."""
    stack = [(data, 0)]
    while stack:
        value, depth = stack.pop()
        items = value.values() if isinstance(value, dict) else value if isinstance(value, list) else ()
        if items and depth >= MAX_DEPTH:  # its values are one level deeper
            return False
        if items and not _LEAVES.issuperset(map(type, items)):  # a list of numbers only: told in one pass in C
            stack += [(v, depth + 1) for v in items if isinstance(v, dict | list)]
    return True


_LEAVES = frozenset({float, int, str, bool, type(None)})  # what a parser gives besides dicts and lists
