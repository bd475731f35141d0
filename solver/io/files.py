"""Reading text, TOML and JSON files and writing outputs safely, every failure one line naming the file.

Writing (:func:`open_output`): ``"-"`` is standard output; a path that exists and is not a regular file (a
device such as ``/dev/null``, a FIFO, ``/dev/stdout``) is written in place and never replaced; anything else is
written to a temporary file beside it that then replaces it, so a reader never sees half a file, and a failed
write leaves the old file and no temporary file behind (one a killed run left is removed by the next run writing
there: :mod:`.temporaries`).
"""

from __future__ import annotations

import json
import os
import stat
import sys
import tomllib
from collections.abc import Iterator
from contextlib import contextmanager, suppress
from pathlib import Path
from typing import IO, Any

from ..errors import ManikinError
from .parse_limits import check_depth, too_deep, too_many_digits
from .temporaries import make_temporary

STDOUT = "-"  # the output path that means standard output


def read_text(path: Path, error: type[ManikinError] = ManikinError) -> str:
    """A text file's content (a UTF-8 byte-order mark dropped); a missing or unreadable file raises ``error``."""
    try:
        return Path(path).read_text(encoding="utf-8-sig")
    except FileNotFoundError:
        raise error(f"{path}: file not found") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise read_error(path, exc, error) from None


def read_error(path: Path | str, exc: OSError | UnicodeDecodeError, error: type[ManikinError]) -> ManikinError:
    """The one line for an input that cannot be read: a folder (Windows says "permission denied" for one), text
    that is not UTF-8 (where), or the system's reason."""
    if isinstance(exc, IsADirectoryError) or (isinstance(exc, OSError) and os.path.isdir(path)):
        return error(f"{path}: is a folder, expected a file")
    if isinstance(exc, UnicodeDecodeError):
        byte = exc.object[exc.start : exc.start + 1].hex()
        return error(f"{path}: cannot read (not utf-8 text: byte 0x{byte}, {exc.reason}; save it as UTF-8)")
    return error(f"{path}: cannot read ({_reason(exc)})")


def read_toml(path: Path, error: type[ManikinError] = ManikinError) -> dict:
    """A TOML file's tables (the one TOML reader: scenarios and bodies); malformed TOML raises ``error``."""
    text = read_text(path, error)
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise error(f"{path}: malformed TOML ({exc})") from None
    except ValueError:  # int() refused a number of more than 4,300 digits
        raise too_many_digits(path, text, error) from None
    except RecursionError:
        raise too_deep(path, text, error) from None
    check_depth(data, path, error)
    return data


def read_json(path: Path, error: type[ManikinError]) -> Any:
    """A JSON file's content; unreadable or malformed files raise ``error`` with one line naming the file."""
    text = read_text(path, error)
    try:
        data = json.loads(text)
    except json.JSONDecodeError as exc:
        raise error(f"{path}: not JSON ({exc.msg} at line {exc.lineno})") from None
    except ValueError:  # int() refused a number of more than 4,300 digits
        raise too_many_digits(path, text, error) from None
    except RecursionError:
        raise too_deep(path, text, error) from None
    check_depth(data, path, error)
    return data


def writes_in_place(path: Path) -> bool:
    """Whether ``path`` is written where it is rather than replaced: it exists and is not a regular file, or it is
    an open file of this process (``/dev/stdout`` redirected to a file is the shell's file, /proc/self/fd/N)."""
    try:
        mode = os.stat(path).st_mode
    except OSError:
        return False
    return not stat.S_ISREG(mode) or _is_open_file(path)


def _is_open_file(path: Path) -> bool:
    """Whether ``path`` or a symbolic link on its way is a /proc or /dev/fd entry (a file descriptor)."""
    p = os.path.abspath(path)
    for _ in range(40):  # the kernel's own limit on links followed
        if p.startswith(("/proc/", "/dev/fd/")):
            return True
        if not os.path.islink(p):
            return False
        p = os.path.normpath(os.path.join(os.path.dirname(p), os.readlink(p)))
    return False


class OutputFile:
    """An output being written (see the module docstring): write to ``stream``, then :meth:`commit` puts it in place
    or :meth:`discard` drops it (a file being replaced keeps its old content). An OSError is one ManikinError line."""

    def __init__(self, path: str | Path, binary: bool = False) -> None:
        self.path = path
        self._tmp: str | None = None
        self._target: Path | None = None
        self._own = str(path) != STDOUT
        mode, text = ("wb", {}) if binary else ("w", {"encoding": "utf-8"})
        try:
            if not self._own:
                self.stream: IO = sys.stdout.buffer if binary else sys.stdout
            elif writes_in_place(Path(path)):
                self.stream = open(path, mode, **text)  # noqa: SIM115 (closed by commit or discard)
            else:
                self._target = Path(os.path.realpath(path))
                self._target.parent.mkdir(parents=True, exist_ok=True)
                fd, self._tmp = make_temporary(self._target.parent)  # (and a killed run's there removed)
                os.chmod(self._tmp, _mode_for(self._target))  # mkstemp's 0600 would make every output private
                self.stream = os.fdopen(fd, mode, **text)
        except OSError as exc:
            self.discard()
            in_the_way = isinstance(exc, FileExistsError | NotADirectoryError)  # mkdir met a file
            why = "a file is where its folder should be" if in_the_way else _reason(exc)
            raise ManikinError(f"{path}: cannot write ({why})") from None

    def write(self, data: str | bytes) -> int:
        """Write ``data`` to the stream; an OSError (a full disk) is one ManikinError line naming the file."""
        try:
            return self.stream.write(data)
        except OSError as exc:
            raise ManikinError(f"{self.path}: cannot write ({_reason(exc)})") from None

    def commit(self) -> None:
        """Finish the output: flush and close it, and rename a temporary file onto the path."""
        try:
            if self._own:
                self.stream.close()
            else:
                self.stream.flush()
            if self._tmp is not None:
                os.replace(self._tmp, self._target)
                self._tmp = None
        except OSError as exc:
            self.discard()
            raise ManikinError(f"{self.path}: cannot write ({_reason(exc)})") from None

    def discard(self) -> None:
        """Drop the output: close it and remove a temporary file (a device or standard output keeps what it got)."""
        if self._own and hasattr(self, "stream"):
            with suppress(OSError):
                self.stream.close()
        if self._tmp is not None:
            with suppress(FileNotFoundError):
                os.unlink(self._tmp)
            self._tmp = None

    @property
    def temporary(self) -> Path | None:
        """The temporary file being written, for a writer that opens it by its name (then :meth:`commit`); None
        when the output is written in place (a device, standard output)."""
        return None if self._tmp is None else Path(self._tmp)


@contextmanager
def open_output(path: str | Path, binary: bool = False) -> Iterator[IO]:
    """A stream to write ``path`` with, put in place when the block ends (see :class:`OutputFile`)."""
    out = OutputFile(path, binary)
    try:
        yield out.stream
    except OSError as exc:
        out.discard()
        raise ManikinError(f"{path}: cannot write ({_reason(exc)})") from None
    except BaseException:
        out.discard()
        raise
    out.commit()


def _mode_for(path: Path) -> int:
    """The permissions of the file being replaced, else those a new file gets (0666 less the umask)."""
    try:
        return stat.S_IMODE(os.stat(path).st_mode)
    except OSError:
        umask = os.umask(0)
        os.umask(umask)
        return 0o666 & ~umask


def _reason(exc: OSError | UnicodeDecodeError) -> str:
    return getattr(exc, "strerror", None) or str(exc)


def write_text(path: str | Path, text: str) -> Path | str:
    """Write ``text`` to ``path`` with :func:`open_output`; returns ``path``."""
    with open_output(path) as fh:
        fh.write(text)
    return path if str(path) == STDOUT else Path(path)


def write_texts(items: list[tuple[Path, str]]) -> list[Path]:
    """Write several files together: every text goes to its temporary file first and only when all are written
    are they put in place, in order (a failure before that leaves every old file as it was); their paths."""
    outputs: list[OutputFile] = []
    try:
        for path, text in items:
            outputs.append(OutputFile(path))
            outputs[-1].stream.write(text)
    except OSError as exc:
        for out in outputs:
            out.discard()
        raise ManikinError(f"{outputs[-1].path}: cannot write ({_reason(exc)})") from None
    except BaseException:
        for out in outputs:
            out.discard()
        raise
    for i, out in enumerate(outputs):
        try:
            out.commit()
        except ManikinError:
            for rest in outputs[i + 1 :]:
                rest.discard()
            raise
    return [Path(path) for path, _ in items]


def write_json(path: str | Path, data: Any, allow_nan: bool = True) -> Path | str:
    """Write ``data`` as indented JSON (one space per level); ``allow_nan=False`` refuses NaN/inf."""
    return write_text(path, json.dumps(data, indent=1, allow_nan=allow_nan))
