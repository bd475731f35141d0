"""What a study row can record: the groups of a study file's ``record`` list and their columns (units m, N, %).

``shortfall`` (the unmet targets and their summed shortfall), then every ergonomic score that has study columns
(:mod:`solver.ergonomics.registry`: the peaks of RULA and REBA), the loads (``l4_l5``: the peak L4/L5 compression;
``strength``: the peak percent of strength and its joint), then the motion scores (``niosh``: the lifting index
and the RWL), then ``job`` (each job method's level and headline numbers, :mod:`.job_columns`; recorded only
for a study whose scenarios name a job). A score registered there is a group here, under its name, without a line
in this package.
"""

from __future__ import annotations

import operator

from ..ergonomics.registry import SCORES, frame_scores, motion_scores
from ..job.registry import METHODS
from .job_columns import GROUP as JOB
from .job_columns import job_columns

SHORTFALL = {"shortfall": ["unmet", "shortfall_m"]}
LOADS = {"l4_l5": ["l4_l5_peak_N"], "strength": ["strength_peak_pct", "strength_joint"]}
LOAD_PANELS = [  # (recorded group, column, title, limits drawn: NIOSH 1981, the worksheet's strength bands)
    ("l4_l5", "l4_l5_peak_N", "L4/L5 compression, N (peak)", (3400.0, 6400.0)),
    ("strength", "strength_peak_pct", "joint strength, % (peak)", (30.0, 60.0)),
]


def groups() -> dict[str, list[str]]:
    """Every group and its columns, in the order of a row's columns."""
    return {group: list(columns) for group, columns in _groups()}


def _groups() -> tuple[tuple[str, tuple[str, ...]], ...]:
    """:func:`groups`, made again only when a score or a job method was registered since (a run asks twice)."""
    registered = (*SCORES.values(), *METHODS.values())
    if _KNOWN and len(_KNOWN[0]) == len(registered) and all(map(operator.is_, _KNOWN[0], registered)):
        return _KNOWN[1]
    out = dict(SHORTFALL)
    out |= {s.name: s.study_columns() for s in frame_scores() if s.study_columns()}
    out |= LOADS
    out |= {s.name: s.study_columns() for s in motion_scores() if s.study_columns()}
    made = tuple((group, tuple(columns)) for group, columns in (out | {JOB: job_columns()}).items())
    _KNOWN[:] = [registered, made]
    return made


_KNOWN: list = []  # [the registered scores and job methods, their groups]


def record() -> tuple[str, ...]:
    """Every group's name (the default of ``record``)."""
    return tuple(g for g, _ in _groups())


def ergonomic() -> tuple[str, ...]:
    """The groups that need the ergonomics of a run (all but the shortfall and the job's, which rates it itself)."""
    return tuple(g for g, _ in _groups() if g not in SHORTFALL and g != JOB)


def panels() -> list[tuple[str, str, str, tuple]]:
    """The study's scores plot panels, (recorded group, column, title, limits drawn): the peak of each score with
    one number per frame, then the loads'."""
    scores = [s for s in frame_scores() if s.value is not None and s.study_columns()]
    return [(s.name, s.study_columns()[0], f"{s.title} (peak)", ()) for s in scores] + LOAD_PANELS
