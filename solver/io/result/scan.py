"""Reading a result file piece by piece, so a long motion is never in memory at once.

:func:`scan` opens either format and yields its parts in file order: ``("key", name, value)`` for each top-level
entry of the result JSON other than its frames (``scenario``, ``interrupted``; for the compact file the header's
entries), and ``("frame", index, raw dict)`` for each frame. The result JSON is parsed in chunks (any layout, old
indented files too); the compact file line by line. A malformed file raises ``error`` with one line naming it.
"""

from __future__ import annotations

import json
import re
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import IO, Any

from ...errors import ManikinError
from ..files import read_error
from ..parse_limits import check_depth, too_deep, too_many_digits
from .document import COMPACT_FORMAT

CHUNK = 1 << 20  # characters read at a time
_SPACE = re.compile(r"[ \t\n\r]*")
_COMPACT_START = re.compile(r'\s*\{\s*"format"\s*:\s*"' + COMPACT_FORMAT + '"')
Part = tuple[str, Any, Any]


class JsonScanner:
    """JSON values read one after another from a text stream in chunks (:meth:`value` parses the next one)."""

    def __init__(self, stream: IO[str], path: Path, error: type[ManikinError]) -> None:
        self.stream, self.path, self.error = stream, path, error
        self.buffer, self.pos, self.eof, self.lines = "", 0, False, 0
        self.decoder = json.JSONDecoder()

    def _more(self) -> bool:
        """Read another chunk (dropping what was parsed); False at the end of the file."""
        if self.eof:
            return False
        chunk = self.stream.read(CHUNK)
        if not chunk:
            self.eof = True
            return False
        self.lines += self.buffer.count("\n", 0, self.pos)
        self.buffer, self.pos = self.buffer[self.pos :] + chunk, 0
        return True

    def fail(self, message: str, pos: int | None = None) -> ManikinError:
        line = self.lines + self.buffer.count("\n", 0, self.pos if pos is None else pos) + 1
        return self.error(f"{self.path}: not JSON ({message} at line {line})")

    def _at_line(self, exc: ManikinError) -> ManikinError:
        """``exc`` with its line counted from the start of the file, not of the buffer."""
        text = str(exc)
        head, sep, rest = text.partition(": line ")
        number, sep2, tail = rest.partition(":")
        if not (sep and sep2 and number.isdigit()):
            return exc
        return self.error(f"{head}: line {self.lines + int(number)}:{tail}")

    def peek(self) -> str:
        """The next character that is not white space ("" at the end of the file), not consumed."""
        while True:
            self.pos = _SPACE.match(self.buffer, self.pos).end()
            if self.pos < len(self.buffer):
                return self.buffer[self.pos]
            if not self._more():
                return ""

    def expect(self, chars: str, what: str) -> str:
        """Consume the next character, one of ``chars``."""
        c = self.peek()
        if not c or c not in chars:
            raise self.fail(f"Expecting {what}")
        self.pos += 1
        return c

    def value(self) -> Any:
        """The next JSON value; a value cut by the end of a chunk is parsed again with more text."""
        self.peek()
        while True:
            try:
                value, end = self.decoder.raw_decode(self.buffer, self.pos)
            except json.JSONDecodeError as exc:
                cut = exc.pos >= len(self.buffer) - 16 or exc.msg.startswith("Unterminated") or "escape" in exc.msg
                if cut and self._more():
                    continue
                raise self.fail(exc.msg, exc.pos) from None
            except ValueError:  # int() refused a number of more than 4,300 digits
                raise self._at_line(too_many_digits(self.path, self.buffer, self.error, self.pos)) from None
            except RecursionError:
                raise self._at_line(too_deep(self.path, self.buffer, self.error, self.pos)) from None
            if end == len(self.buffer) and self._more():
                continue  # a number may go on in the next chunk
            self.pos = end
            return value


def _json_parts(stream: IO[str], path: Path, error: type[ManikinError]) -> Iterator[Part]:
    """The parts of a result JSON: its top-level keys, the "frames" list element by element."""
    s = JsonScanner(stream, path, error)
    if s.peek() != "{":
        kind = {"[": "list", '"': "str", "": "nothing"}.get(s.peek(), "a value")
        raise error(f'{path}: expected a JSON object with a "frames" list, got {kind}')
    s.pos += 1
    if s.peek() == "}":
        s.pos += 1
    else:
        while True:
            key = s.value()
            if not isinstance(key, str):
                raise s.fail("Expecting property name enclosed in double quotes")
            s.expect(":", "':' delimiter")
            if key == "frames" and s.peek() == "[":
                s.pos += 1
                index = 0
                while s.peek() != "]":
                    if index:
                        s.expect(",", "',' delimiter")
                    yield "frame", index, s.value()
                    index += 1
                s.pos += 1
            else:
                yield "key", key, s.value()
            if s.expect(",}", "',' delimiter") == "}":
                break
    if s.peek():
        raise s.fail("Extra data")


@dataclass(frozen=True)
class FrameLine:
    """A compact file's frame line not parsed yet (:func:`scan` with ``lazy``): the frame number it starts with,
    where it is (its line number and its index among the frames) and its text."""

    number: int
    line: int
    index: int
    text: str


# A frame line as the compact writer starts it: {"frame":N," (a number JSON reads as that int, one "frame" key)
_FRAME_START = re.compile(r'\{"frame":(-?(?:0|[1-9][0-9]{0,17})),"')


def _compact_parts(stream: IO[str], path: Path, error: type[ManikinError], lazy: bool = False) -> Iterator[Part]:
    """The parts of a compact file: the header line's entries, then each frame line (and an interrupted line);
    ``lazy``: a frame line that starts with its number as the writer puts it is ``("line", index, FrameLine)``."""
    index = 0
    for number, line in enumerate(stream, 1):
        if not line.strip():
            continue
        start = _FRAME_START.match(line) if lazy and number > 1 else None
        # its one "frame" key (no other, nor one spelled with a \u escape): the number JSON would read
        if start is not None and line.count('"frame"') == 1 and "\\u" not in line:
            yield "line", index, FrameLine(int(start.group(1)), number, index, line)
            index += 1
            continue
        data = _line_value(line, number, path, error)
        if number == 1:
            yield from (("key", k, v) for k, v in data.items())
        elif "interrupted" in data and "frame" not in data:
            yield "key", "interrupted", data["interrupted"]
        else:
            yield "frame", index, data
            index += 1


def _line_value(line: str, number: int, path: Path, error: type[ManikinError]) -> dict:
    """The JSON object on line ``number`` of a compact file."""
    try:
        data = json.loads(line)
    except json.JSONDecodeError as exc:
        raise error(f"{path}: line {number}: not JSON ({exc.msg})") from None
    except (ValueError, RecursionError) as exc:  # a number of more than 4,300 digits; nesting too deep
        limit = too_many_digits if isinstance(exc, ValueError) else too_deep
        raise error(str(limit(path, line, error)).replace(": line 1:", f": line {number}:", 1)) from None
    if not isinstance(data, dict):
        raise error(f"{path}: line {number}: expected a JSON object, got {type(data).__name__}")
    return data


def parse_line(frame: FrameLine, path: Path, error: type[ManikinError]) -> dict:
    """The raw frame of a :class:`FrameLine`, parsed and checked as :func:`scan` checks every frame."""
    data = _line_value(frame.text, frame.line, path, error)
    check_depth(data, path, error, f"frames[{frame.index}]")
    return data


def is_compact(path: Path, error: type[ManikinError]) -> bool:
    """Whether ``path`` starts with the header line of the compact format."""
    with _open(path, error) as stream:
        try:
            return bool(_COMPACT_START.match(stream.read(200)))
        except (OSError, UnicodeDecodeError) as exc:  # Latin-1 bytes, binary after a header
            raise read_error(path, exc, error) from None


def _open(path: Path, error: type[ManikinError]) -> IO[str]:
    try:
        return path.open(encoding="utf-8-sig")
    except FileNotFoundError:
        raise error(f"{path}: file not found") from None
    except OSError as exc:
        raise read_error(path, exc, error) from None


@dataclass(frozen=True)
class UncheckedFrame:
    """A result JSON's frame parsed but not yet held to :data:`~solver.io.parse_limits.MAX_DEPTH` (:func:`scan`
    with ``lazy``; :func:`checked_frame` checks it)."""

    data: Any
    index: int


def checked_frame(frame: UncheckedFrame, path: Path, error: type[ManikinError]) -> Any:
    """The raw frame of an :class:`UncheckedFrame`, checked as :func:`scan` checks every frame."""
    check_depth(frame.data, path, error, f"frames[{frame.index}]")
    return frame.data


def scan(path: Path, error: type[ManikinError], lazy: bool = False) -> Iterator[Part]:
    """The parts of the result file ``path`` in file order (either format), each value at most
    :data:`~solver.io.parse_limits.MAX_DEPTH` levels deep. ``lazy``: a compact file's frame lines that start with
    their number are ``("line", index, FrameLine)``, neither parsed nor checked (:func:`parse_line` does both); a
    result JSON's frames are ``("frame", index, UncheckedFrame)``, parsed, not checked (:func:`checked_frame`)."""
    compact = is_compact(path, error)
    with _open(path, error) as stream:
        try:
            parts = _compact_parts(stream, path, error, lazy) if compact else _json_parts(stream, path, error)
            for kind, name, value in parts:
                if lazy and kind == "frame" and not compact:  # a quick pass over the numbers: checked when built
                    value = UncheckedFrame(value, name)
                elif kind != "line":
                    check_depth(value, path, error, f"frames[{name}]" if kind == "frame" else str(name))
                yield kind, name, value
        except (OSError, UnicodeDecodeError) as exc:
            raise read_error(path, exc, error) from None
