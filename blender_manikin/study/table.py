"""The study table's cells (plain Python, no bpy): what a run's row shows and under which header.

Its score columns are the peak over a run's motion of every registered score with one number per frame
(:mod:`solver.ergonomics.registry`: RULA, REBA), the scores a study's scores plot draws; a new score is a column
without a line here. The table keeps their titles with its rows (one string each, the cells separated by
:data:`SEP`), so a .blend shows its study as it was run. The registry is imported when a table is filled, not
with this module (enabling the add-on loads none of the solver's numerics).
"""

from __future__ import annotations

import math

SEP = "\t"  # between the cells kept in one string
START, END = ("Manikin", "Role", "Values"), ("L4/L5 N", "Short mm")  # the header around the score columns


def score_columns() -> list[tuple[str, str]]:
    """(title, study column) of each score the table shows: its peak over the run's frames ("RULA", "rula_peak")."""
    from ...solver.ergonomics.registry import frame_scores

    return [(s.title, s.study_columns()[0]) for s in frame_scores() if s.value is not None and s.study_columns()]


def cell(value, scale: float = 1.0, digits: int = 0) -> str:
    """A number times ``scale`` with ``digits`` decimals; "-" for none or one not finite."""
    if value is None or (isinstance(value, float) and not math.isfinite(value)):
        return "-"
    return f"{value * scale:.{digits}f}"


def score_cell(value) -> str:
    """A score's peak: a whole number as it is, another to two decimals at most; "-" for none."""
    if isinstance(value, float) and math.isfinite(value):
        return f"{round(value, 2):g}"
    return str(value) if isinstance(value, int) else "-"


def score_cells(row: dict, columns: list[tuple[str, str]]) -> str:
    """A study row's score cells, in the order of ``columns`` (:func:`score_columns`), as one string."""
    return SEP.join(score_cell(row.get(column)) for _, column in columns)


def split(cells: str) -> list[str]:
    """The cells of a string of :func:`score_cells` (or of the titles); none for an empty one."""
    return cells.split(SEP) if cells else []


def header(titles: str) -> tuple[str, ...]:
    """The table's header with the score columns' ``titles`` (a string of them)."""
    return (*START, *split(titles), *END)
