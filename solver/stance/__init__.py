"""Stances and stepping: where the feet may go when the manikin may step, what a step costs, and what the feet did.

Shared by a pose solve with ``--feet step`` (scenario ``[stance] feet = "step"``), the reach envelope's stepping
feet and the operations generator. The feet are planted by default ("can the worker do this from here?"); stepping
makes a problem whose feet are free on the floor, in balance and clear of obstacles (the problem's own balance and
clearance rows), within the stance rows:

* :mod:`.limits` the rows: each foot within one step (0.4 x stature) of where it stood, the feet at most a step
  apart and never crossed, each turned at most 45 deg (:class:`StanceBounds`, :func:`stance_limits`);
* :mod:`.cost` the step cost, a comfort term in the constraints' null space: (step / comfortable step)^2 per foot,
  the comfortable step 0.3 x stature, so a foot steps only as far as the step helps;
* :mod:`.step_problem` :func:`stepping` (a problem -> the same problem with stepping feet), :func:`check_feet`;
* :mod:`.report` :class:`Step` (foot, length m, direction deg from the facing, left positive, turn deg), the notes
  and the result file's ``steps``, and the per-frame foot moves of a stepping motion;
* :mod:`.find` :func:`find_stance`, the API the operations generator calls::

      from solver.stance import find_stance
      found = find_stance(problem)            # problem: feet planted on their support targets, hand targets set
      found.converged, found.message          # True, "foot_r stepped 0.41 m, 8 deg left of forward, turned 3 deg"
      found.steps                             # [Step(foot="foot_r", length=0.41, direction_deg=8.0, turn_deg=3.0, ...)]
      found.problem                           # the same problem with the feet planted at the new stance
      found.result.x                          # the pose there: a warm start for the next solve

  It solves the problem with stepping feet from ``start`` (default the zero pose; pass the current pose to step from
  it) and returns a :class:`StanceResult` (``problem``, ``steps``, ``converged``, ``message``, ``result``). Not
  converged: no stance within a step meets every target; ``message`` says what is short (call again from the found
  stance to take another step).

Units: m, rad inside; reports in m and deg.
"""

from __future__ import annotations

from ..lazy import lazy_attributes
from .limits import FEET, ROWS, StanceBounds, StanceLimits, stance_limits, stature_of
from .report import PLANTED_NOTE, Step, annotate, frame_moves, step_dicts, steps_of
from .step_problem import FEET_MODES, PLANTED, STEP, bounds_of, check_feet, foot_targets, stepping

__all__ = ["FEET", "FEET_MODES", "PLANTED", "PLANTED_NOTE", "ROWS", "STEP", "StanceBounds", "StanceLimits",
           "StanceResult", "Step", "annotate", "bounds_of", "check_feet", "find_stance", "foot_targets", "frame_moves",
           "plant", "stance_limits", "stature_of", "step_dicts", "steps_of", "stepping"]

# find_stance solves (the iteration, LAPACK): loaded on first use, so the result reader and the ergonomics that
# import the step report stay free of scipy (Blender enables without it)
_HOMES = {"StanceResult": "find", "find_stance": "find", "plant": "find"}
__getattr__ = lazy_attributes(__name__, _HOMES, globals())
