"""How far one hand reaches along one direction from its shoulder, with the feet planted or stepping, in balance or
not.

A point is *reached* when a solve meets every constraint there: the hand on the point (position; and the orientation
when it is fixed), both feet on their start places (all six axes: planted; or, stepping, flat on the floor within
the stance bounds of :mod:`solver.stance.limits`), the floor and the body's own clearances,
and, with balance, the static balance of the whole body with its contact forces inside the friction cones and the
soles (priority 1 in :mod:`solver.problem.priorities`) under the hand-held load. The reach along a ray is found by
a bracket-and-bisect search on the radius, each test a converged solve warm-started from the last reached pose, and
is a radius verified reached at least half the search tolerance short of the nearest one found unreached: right at
the edge a test's verdict, and whether a solve with comfort holds the point again, hang on the last bits of the
arithmetic (which differ between CPUs' BLAS and SIMD kernels), half a tolerance inside they do not. A ray is assumed
to be reached from the shoulder out to one radius (star-shaped); where it is not (a ray through the head), the
search returns the end of the reached stretch it started on. Units: m, kg, N.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ..body.model import GRAVITY, Model
from ..constraints import AXES
from ..errors import ModelError, UsageError
from ..iteration import TUNING, attempt
from ..options import SolverOptions
from ..problem.problem import Problem
from ..problem.specs import ExternalLoad, ProblemSpec, Target
from ..stance.limits import StanceBounds, stance_limits

SIDES = {"right": "r", "left": "l"}
FEET = ("foot_l", "foot_r")
# what each feet mode locks of a sole: planted, all six axes; stepping, flat on the floor (z, roll, pitch) while it
# slides and turns about z within the bounds of :mod:`solver.stance.limits`
FEET_MODES = {"planted": AXES, "step": ("z", "rx", "ry")}
# A reach test needs no comfort (the farthest point, not the nicest pose): pure least squares from a warm start meets
# a reachable point in 3-10 iterations; the budget bounds what an unreachable one costs before it is called so.
TEST_OPTIONS = SolverOptions(max_iterations=30, optimize_comfort=False, restarts=0)
COLD_OPTIONS = SolverOptions(max_iterations=100, optimize_comfort=False, restarts=0)  # from the zero pose
# ... and a test whose error falls by less than 10 % over three iterations is a miss (the solver's default, 2 %,
# is for getting as close as possible): a third less work per envelope, the same radii within a millimetre.
TEST_TUNING = replace(TUNING, stagnation_gain=0.1)
FIRST_STEP = 0.04  # m: the first step outward from a reached radius; it doubles while the points are reached
MAX_RADIUS = 3.0  # m from the shoulder: no human hand reaches farther with its feet planted
MIN_RADIUS = 0.05  # m: a ray not reached this far counts as not reached
SHRINK = 0.85  # an unreached seed radius is tried again this much nearer the shoulder
# The bracket is bisected down to half the tolerance and the reach is a radius reached that much short of its
# reached end (one more test, inward): within the tolerance of the edge, and never closer to it than half of it,
# where the tests' verdicts (and a comfort solve's) flip on the last bits of the arithmetic.
MARGIN = 0.5  # of the tolerance
MAX_LOAD = 100.0  # kg in the hand


def check_tolerance(tolerance: float) -> float:
    """The radius tolerance of a search (m), refused with a UsageError line outside [0.001, 0.2]."""
    if not (isinstance(tolerance, (int, float)) and np.isfinite(tolerance) and 1e-3 <= tolerance <= 0.2):
        raise UsageError(f"--tolerance: expected m in [0.001, 0.2], got {tolerance!r}")
    return float(tolerance)


@dataclass(frozen=True)
class ReachSetup:
    """What stays the same over a manikin's rays: the model, the hand and shoulder TCPs, the planted feet, the load,
    the hand's fixed orientation (3x3, world; None = free) and whether balance is required. ``base`` is the problem
    whose targets each test replaces (so contacts, clearances and comfort are built once)."""

    model: Model
    hand: str
    shoulder: np.ndarray  # (3,) m, the shoulder (glenohumeral) centre in the zero pose
    feet: tuple[Target, ...]
    load_kg: float
    rotation: np.ndarray | None
    balance: bool
    base: Problem
    feet_mode: str = "planted"

    def problem(self, point: np.ndarray) -> Problem:
        """The problem of holding the hand on ``point`` (m, world)."""
        lock = ("x", "y", "z") if self.rotation is None else ("x", "y", "z", "rx", "ry", "rz")
        hand = Target(self.hand, np.asarray(point, dtype=float), rotation=self.rotation, lock=lock)
        return self.base.with_targets([hand, *self.feet])


def reach_setup(
    model: Model,
    side: str = "right",
    load_kg: float = 0.0,
    rotation: np.ndarray | None = None,
    balance: bool = True,
    sole_scale: float = 1.0,
    feet: str = "planted",
) -> ReachSetup:
    """The setup of ``model``'s ``side`` hand ("right" or "left") holding ``load_kg`` (its weight hangs from the
    hand), its orientation fixed to ``rotation`` (3x3, world) or free, with or without balance; the centre of
    pressure kept inside each sole scaled by ``sole_scale`` about its centre (1: the whole sole, the static limit;
    less keeps a margin of stability); ``feet`` "planted" (all six axes held) or "step" (each sole flat on the
    floor, free to slide and turn within the bounds of :mod:`solver.stance.limits`)."""
    if side not in SIDES:
        raise UsageError(f"--hand: expected right or left, got {side!r}")
    if not (np.isfinite(load_kg) and 0.0 <= load_kg <= MAX_LOAD):
        raise UsageError(f"--load: expected kg in [0, {MAX_LOAD:g}], got {load_kg!r}")
    if not (np.isfinite(sole_scale) and 0.1 <= sole_scale <= 1.0):
        raise UsageError(f"--sole-scale: expected a fraction in [0.1, 1], got {sole_scale!r}")
    if feet not in FEET_MODES:
        raise UsageError(f"--feet: expected {' or '.join(FEET_MODES)}, got {feet!r}")
    s = SIDES[side]
    needed = (f"hand_{s}", f"shoulder_{s}", *FEET)
    missing = [name for name in needed if name not in model.tcps]
    if missing:
        raise ModelError(f"manikin {model.name}: a reach envelope needs the TCPs {', '.join(missing)} (a human body)")
    zero = model.forward(model.zero_pose())
    lock = FEET_MODES[feet]
    soles = tuple(
        Target(f, zero.tcp_frame(model.tcp(f))[1], lock=lock, support=True, friction=0.6,
               sole=_scaled(model, f, sole_scale))
        for f in FEET
    )  # fmt: skip
    extra = [] if feet == "planted" else [StanceBounds(model, stance_limits(model), {f: zero.tcp_frame(model.tcp(f))
                                                                                    for f in FEET})]  # fmt: skip
    weight = np.asarray(GRAVITY) * load_kg
    loads = [ExternalLoad(f"hand_{s}", weight)] if load_kg > 0.0 else []
    start_hand = Target(f"hand_{s}", zero.tcp_frame(model.tcp(f"hand_{s}"))[1], lock=("x", "y", "z"))
    base = Problem(model, ProblemSpec([start_hand, *soles], loads=loads, balance=balance, extra_constraints=extra))
    shoulder = zero.tcp_frame(model.tcp(f"shoulder_{s}"))[1]
    rot = None if rotation is None else np.asarray(rotation, dtype=float)
    return ReachSetup(model, f"hand_{s}", shoulder, soles, float(load_kg), rot, balance, base, feet)


def _scaled(model: Model, foot: str, scale: float) -> np.ndarray | None:
    """The sole of ``foot`` scaled about the TCP by ``scale`` (None: the TCP's own sole, unscaled)."""
    sole = model.tcp(foot).sole
    return None if scale == 1.0 or sole is None else np.asarray(sole, dtype=float) * scale


def arm_length(model: Model, side: str = "right") -> float:
    """Shoulder centre to the palm's grasp point with the arm straight (the zero pose), m: the radius of the
    envelope of the arm alone, trunk and legs still."""
    s = SIDES[side]
    zero = model.forward(model.zero_pose())
    hand, shoulder = (zero.tcp_frame(model.tcp(f"{name}_{s}"))[1] for name in ("hand", "shoulder"))
    return float(np.linalg.norm(hand - shoulder))


@dataclass
class RayReach:
    """The reach along one ray: ``radius`` m (0 when not reached), the ``pose`` (joint values) at it (None when not
    reached), how many solves the search took (``tests``) and their ``iterations``."""

    radius: float
    pose: np.ndarray | None
    tests: int = 0
    iterations: int = 0

    @property
    def reached(self) -> bool:
        return self.pose is not None


class _Tester:
    """Reach tests along one ray, counting solves and iterations."""

    def __init__(self, setup: ReachSetup, direction: np.ndarray) -> None:
        self.setup = setup
        self.direction = direction
        self.tests = 0
        self.iterations = 0

    def __call__(self, radius: float, start: np.ndarray | None, options: SolverOptions = TEST_OPTIONS):
        """The joint values holding the hand at ``radius`` along the ray (None if not reached)."""
        problem = self.setup.problem(self.setup.shoulder + radius * self.direction)
        end = attempt(problem, problem.start(start), options, TEST_TUNING)
        self.tests += 1
        self.iterations += end.iterations
        return problem.to_x(end.trial.x)[: self.setup.model.n].copy() if end.trial.worst <= 1.0 else None


def search_ray(
    setup: ReachSetup,
    direction: np.ndarray,
    seed_radius: float,
    seed_pose: np.ndarray | None = None,
    known: bool = False,
    tolerance: float = 0.02,
    retry: bool = True,
) -> RayReach:
    """The farthest radius (within ``tolerance`` m) reached along the unit ``direction`` from the shoulder, at least
    MARGIN x ``tolerance`` short of the nearest radius found unreached.

    The search starts at ``seed_radius`` warm-started from ``seed_pose`` (joint values; None: the zero pose); a
    ``known`` seed (a pose already reaching that radius, e.g. the balanced reach when balance is off) is not tested
    again and the answer is never less. An unreached seed is retried nearer the shoulder (x SHRINK down to
    MIN_RADIUS) if ``retry``, else the ray counts as not reached (one test: does this pose get that far?). From the
    reached radius the step outward doubles until a point is not reached, then the bracket is halved down to
    MARGIN x ``tolerance`` and the answer tested MARGIN x ``tolerance`` inside its reached end.
    """
    d = np.asarray(direction, dtype=float)
    d = d / np.linalg.norm(d)
    test = _Tester(setup, d)
    lo, pose = _seed(test, float(np.clip(seed_radius, MIN_RADIUS, MAX_RADIUS)), seed_pose, known, retry)
    if pose is None:
        return RayReach(0.0, None, test.tests, test.iterations)
    seed = (lo, pose)
    margin = MARGIN * tolerance
    hi, step = None, FIRST_STEP
    while hi is None or hi - lo > margin * (1.0 + 1e-9):  # a bracket of the margin (up to rounding) is narrow enough
        radius = min(lo + step, MAX_RADIUS) if hi is None else 0.5 * (lo + hi)
        if hi is None and radius <= lo:
            break  # at MAX_RADIUS
        reached = test(radius, pose)
        if reached is not None:
            lo, pose, step = radius, reached, 2.0 * step
        else:
            hi = radius
    if hi is not None:
        lo, pose = _inside(test, lo - margin, (lo, pose), seed, known)
    return RayReach(lo, pose, test.tests, test.iterations)


def _inside(
    test: _Tester, radius: float, end: tuple[float, np.ndarray], seed: tuple[float, np.ndarray], known: bool
) -> tuple[float, np.ndarray]:
    """(radius, pose) of the answer: ``radius`` (MARGIN x tolerance short of the reached ``end``) tested from the
    end's pose; a ``known`` seed at or beyond it as it is (reached with its own margin in a tighter setup). Should
    that test fail (a ray reached in pieces), the seed if it lies inside, else the reached end itself."""
    if known and seed[0] >= radius:
        return seed
    radius = max(radius, MIN_RADIUS)
    if radius >= end[0]:
        return end  # reached no farther than MIN_RADIUS: nothing nearer counts
    reached = test(radius, end[1])
    if reached is not None:
        return radius, reached
    return seed if seed[0] <= radius else end


def _seed(
    test: _Tester, radius: float, pose: np.ndarray | None, known: bool, retry: bool
) -> tuple[float, np.ndarray | None]:
    """(a reached radius, its pose), trying ``radius`` and (if ``retry``) nearer the shoulder; (0, None) if none is
    reached."""
    if known and pose is not None:
        return radius, pose
    options = TEST_OPTIONS if pose is not None else COLD_OPTIONS
    while radius >= MIN_RADIUS:
        reached = test(radius, pose, options)
        if reached is not None or not retry:
            return (radius, reached) if reached is not None else (0.0, None)
        radius *= SHRINK
    return 0.0, None
