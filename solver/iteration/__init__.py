"""The iteration: dx = -J^+ g(x) + lambda (I - J^+ J) grad h(x) (thesis eq. 2.4), made fast and robust.

Per iteration, in scaled variables (rows / tolerance, forces / body weight, joints / half their range):

1. Task step (``least_squares``): damped least squares on the Jacobian of the free variables, from a Cholesky
   factor of J J^T (m ~ 24 rows), Tikhonov-damped near singularities, inside a trust region.
2. Comfort step (``step``, ``curvature_memory``) in the null space of the undamped row space, in the metric
   W = diag(curvature of -h) + mu: a diagonal Newton step on comfort (for large mu exactly the thesis step with
   lambda = 1/mu), plus a limited-memory BFGS model of the Lagrangian's curvature gathered near the constraints.
3. Bounds (``step``): variables the step pushes past a bound are saturated there and the step is solved again
   without them; contact edge weights (>= 0) carry a log barrier's curvature in the metric.
4. Trials (``trial``, ``line_search``): far from the constraints a step is shortened so no joint turns more than
   ``max_turn`` and must lower the error (comfort may ride along); near them task + comfort must lower the exact-penalty
   merit after a second-order correction; rejected steps are halved, then the task part is tried alone.
5. Phases (``loop``, ``phases``): comfort first, then the constraints restored without comfort if needed;
   stopping rules (``stopping``) record a :class:`StopReason`; a failed solve restarts from the other side of the
   joints it left at a limit (``restarts``). Every knob is one field of :class:`Tuning` (``tuning``).

What a solve returns is :class:`~solver.iteration.result.Result` (``result``). Importing this package loads no
numerics: its names load on first use, so the result type can be read without SciPy.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ..lazy import lazy_attributes

_HOMES = {
    "TUNING": "tuning",
    "CurvatureMemory": "curvature_memory",
    "LeastSquares": "least_squares",
    "StopReason": "stopping",
    "Tuning": "tuning",
    "attempt": "phases",
    "null_space_newton": "curvature_memory",
    "restart_pose": "restarts",
    "solve": "phases",
}
__all__ = [
    "TUNING",
    "CurvatureMemory",
    "LeastSquares",
    "StopReason",
    "Tuning",
    "attempt",
    "null_space_newton",
    "restart_pose",
    "solve",
]

if TYPE_CHECKING:
    from .curvature_memory import CurvatureMemory, null_space_newton
    from .least_squares import LeastSquares
    from .phases import attempt, solve
    from .restarts import restart_pose
    from .stopping import StopReason
    from .tuning import TUNING, Tuning

__getattr__ = lazy_attributes(__name__, _HOMES, globals())
