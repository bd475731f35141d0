"""What a study row can record: the groups of a study file's ``record`` list and their columns (units m, N, %).

``shortfall`` (the unmet targets and their summed shortfall), then every ergonomic score that has study columns
(:mod:`solver.ergonomics.registry`: the peaks of RULA and REBA), the loads (``l4_l5``: the peak L4/L5 compression;
``strength``: the peak percent of strength and its joint), then the motion scores (``niosh``: the lifting index
and the RWL). A score registered there is a group here, under its name, without a line in this package.
"""

from __future__ import annotations

from ..ergonomics.registry import frame_scores, motion_scores

LOADS = {"l4_l5": ["l4_l5_peak_N"], "strength": ["strength_peak_pct", "strength_joint"]}
GROUPS: dict[str, list[str]] = {"shortfall": ["unmet", "shortfall_m"]}
GROUPS |= {s.name: s.study_columns() for s in frame_scores() if s.study_columns()}
GROUPS |= LOADS
GROUPS |= {s.name: s.study_columns() for s in motion_scores() if s.study_columns()}
RECORD = tuple(GROUPS)  # every group, in the order of the row's columns (the default of ``record``)
ERGONOMIC = RECORD[1:]  # the groups that need the ergonomics of a run

# the scores plot's panels: (recorded group, column, title, limits drawn): each score's peak, then the loads'
PANELS = [(s.name, s.study_columns()[0], f"{s.title} (peak)", ()) for s in frame_scores()
          if s.value is not None and s.study_columns()]  # fmt: skip
PANELS += [
    ("l4_l5", "l4_l5_peak_N", "L4/L5 compression, N (peak)", (3400.0, 6400.0)),
    ("strength", "strength_peak_pct", "joint strength, % (peak)", (30.0, 60.0)),
]
