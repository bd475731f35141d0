"""Reading text and JSON files and writing them atomically, every failure one line naming the file."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from ..errors import ManikinError


def read_text(path: Path, error: type[ManikinError] = ManikinError) -> str:
    """A text file's content; a missing or unreadable file raises ``error`` with one line naming it."""
    try:
        return path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise error(f"{path}: file not found") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise error(f"{path}: cannot read ({exc})") from None


def read_json(path: Path, error: type[ManikinError]) -> Any:
    """A JSON file's content; unreadable or malformed files raise ``error`` with one line naming the file."""
    try:
        return json.loads(read_text(path, error))
    except json.JSONDecodeError as exc:
        raise error(f"{path}: not JSON ({exc.msg} at line {exc.lineno})") from None


def temporary_beside(path: Path) -> Path:
    """The temporary file a write to ``path`` goes into before it is renamed onto ``path``."""
    return path.with_name(path.name + ".tmp")


def write_text(path: Path, text: str) -> Path:
    """Write ``text`` to ``path`` through a temporary file beside it (a reader never sees half a file)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = temporary_beside(path)
    tmp.write_text(text, encoding="utf-8")
    tmp.replace(path)
    return path


def write_json(path: Path, data: Any, allow_nan: bool = True) -> Path:
    """Write ``data`` as indented JSON (one space per level), atomically; ``allow_nan=False`` refuses NaN/inf."""
    return write_text(path, json.dumps(data, indent=1, allow_nan=allow_nan))
