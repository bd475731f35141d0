"""A study's files in its output folder: the journal of finished runs and the tables of rows.

* ``runs.jsonl``: every finished row as one JSON line, appended as runs finish. It is what a rerun resumes from
  (rows whose run id is in the study are not run again); a line cut short by a crash is ignored.
* ``rows.csv``: one row per run in the study's order, a header of column names; empty cells are missing values
  (a failed run has no scores; NIOSH only for lifts), booleans ``true`` / ``false``.
* ``rows.npz``: the same table by columns (NumPy's ``.npz``, no pickles): ``np.load("rows.npz")`` holds one
  array per column, all of the row count's length, and ``__columns__`` (the column names in order). Numbers are
  float64 (NaN where missing) or int64 when none is missing and all are whole; booleans are bool (float 1 / 0 /
  NaN when some are missing); anything else is a Unicode string array ("" where missing).
  ``pandas.DataFrame({c: z[c] for c in z["__columns__"]})`` makes it a data frame.
"""

from __future__ import annotations

import csv
import io
import json
import math
from pathlib import Path
from typing import IO, Any

import numpy as np

from ..errors import UsageError
from ..io.files import open_output

JOURNAL, CSV, NPZ = "runs.jsonl", "rows.csv", "rows.npz"


def read_journal(folder: Path) -> dict[str, dict]:
    """The rows already in ``folder``'s journal, by run id (the last one of a run id wins)."""
    path = folder / JOURNAL
    rows: dict[str, dict] = {}
    if not path.exists():
        return rows
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise UsageError(f"{path}: cannot read the study's journal ({exc})") from None
    for line in text.splitlines():
        try:
            row = json.loads(line)
        except json.JSONDecodeError:
            continue  # a line a crash cut short: that run is done again
        if isinstance(row, dict) and isinstance(row.get("run_id"), str):
            rows[row["run_id"]] = row
    return rows


class Journal:
    """The journal opened for appending: :meth:`add` writes rows and flushes, so a crash loses only runs under way."""

    def __init__(self, folder: Path) -> None:
        self.path = folder / JOURNAL
        try:
            folder.mkdir(parents=True, exist_ok=True)
            cut = _ends_cut(self.path)
            self.stream: IO = open(self.path, "a", encoding="utf-8")  # noqa: SIM115 (closed by close)
            _lock(self.stream, folder)
            if cut:  # a crash cut the last line short: end it, so the next row starts a line of its own
                self.stream.write("\n")
        except OSError as exc:
            raise UsageError(f"{folder}: cannot write the study's output folder ({exc.strerror or exc})") from None

    def add(self, rows: list[dict]) -> None:
        try:
            self.stream.write("".join(json.dumps(row) + "\n" for row in rows))  # a NIOSH LI may be inf (Infinity)
            self.stream.flush()
        except OSError as exc:  # a full disk: the rows before stay, a cut line is ended by the next run
            raise UsageError(f"{self.path}: cannot write ({exc.strerror or exc})") from None

    def close(self) -> None:
        try:
            self.stream.close()
        except OSError as exc:
            raise UsageError(f"{self.path}: cannot write ({exc.strerror or exc})") from None


def _lock(stream: IO, folder: Path) -> None:
    """Hold the journal for this study run alone (released when it closes): a second run on the same folder at the
    same time would do the same runs twice. Where there is no fcntl (Windows), nothing is locked."""
    try:
        import fcntl
    except ImportError:
        return
    try:
        fcntl.flock(stream.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError:
        stream.close()
        raise UsageError(f"-o {folder}: another study is writing this folder now; wait for it or use another") from None


def _ends_cut(path: Path) -> bool:
    """Whether the file ``path`` exists and its last line has no line end."""
    if not path.exists() or path.stat().st_size == 0:
        return False
    with open(path, "rb") as fh:
        fh.seek(-1, io.SEEK_END)
        return fh.read(1) != b"\n"


def cell(value: Any) -> Any:
    """A value as the CSV writes it."""
    if value is None:
        return ""
    if isinstance(value, bool):
        return "true" if value else "false"
    return value


def write_csv(path: Path, columns: list[str], rows: list[dict]) -> None:
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(columns)
    for row in rows:
        writer.writerow([cell(row.get(c)) for c in columns])
    with open_output(path) as fh:
        fh.write(buffer.getvalue())


def column_array(values: list) -> np.ndarray:
    """One column as an array (see the module docstring for the types)."""
    present = [v for v in values if v is not None]
    if present and all(isinstance(v, bool) for v in present):
        if len(present) == len(values):
            return np.array(values, dtype=bool)
        return np.array([math.nan if v is None else float(v) for v in values])
    if present and all(isinstance(v, int | float) and not isinstance(v, bool) for v in present):
        if len(present) == len(values) and all(isinstance(v, int) for v in present):
            return np.array(values, dtype=np.int64)
        return np.array([math.nan if v is None else float(v) for v in values], dtype=float)
    return np.array(["" if v is None else str(v) for v in values], dtype=str)


def write_npz(path: Path, columns: list[str], rows: list[dict]) -> None:
    arrays = {c: column_array([row.get(c) for row in rows]) for c in columns}
    arrays["__columns__"] = np.array(columns, dtype=str)
    buffer = io.BytesIO()  # zipped in memory: a zip cut by a full disk would complain again when collected
    np.savez_compressed(buffer, **arrays)
    with open_output(path, binary=True) as fh:
        fh.write(buffer.getbuffer())


def write_tables(folder: Path, columns: list[str], rows: list[dict]) -> list[Path]:
    """rows.csv and rows.npz of ``rows`` (in order) in ``folder``; their paths."""
    write_csv(folder / CSV, columns, rows)
    write_npz(folder / NPZ, columns, rows)
    return [folder / CSV, folder / NPZ]
