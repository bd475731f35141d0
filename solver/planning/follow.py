"""The whole body along a way: the posture solved with the hand at each way point (balance, joint limits, the
clearance rows of the problem), and the swept check between consecutive postures (:mod:`solver.collision.sweep`,
:class:`solver.motion.between_frames.MotionSweep`: every body capsule, and a carried box), so that not only the hand
stays clear. Where the body cannot follow (the hand's way is clear but the forearm passes through a bench between
two way points) a way point is added half-way and the posture solved there, up to ``splits`` times per piece; what
still crosses, or a way point the hand cannot reach, is reported in one line each.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from ..iteration import solve
from ..iteration.result import Result
from ..motion.between_frames import MotionSweep
from ..options import DEFAULT_OPTIONS, SolverOptions
from ..problem.problem import Problem

SPLITS = 3  # halvings of a piece whose postures cross something at most (up to 7 added way points per piece)


@dataclass
class Followed:
    """The postures along a way: ``points`` (k, 3) m the way points followed (the given ones and any added),
    ``results`` one solved posture each, ``added`` how many way points were added, ``problems`` one line per
    crossing or unreachable way point ([] when the body follows the whole way)."""

    points: np.ndarray
    results: list[Result]
    added: int = 0
    problems: list[str] = field(default_factory=list)

    @property
    def clear(self) -> bool:
        return not self.problems


class _Walker:
    """Solves the postures of one way for :func:`follow`."""

    def __init__(self, problem: Problem, tcp: str, options: SolverOptions, splits: int) -> None:
        index = [i for i, t in enumerate(problem.all_targets) if t.tcp == tcp]
        if not index:
            raise ValueError(f"no target holds {tcp!r}: add one for the hand that follows the way")
        self.problem, self.index, self.options, self.splits = problem, index[0], options, splits
        self.sweep = MotionSweep(resolve=False)
        self.body = self.sweep.body(problem)
        self.n = problem.model.n

    def at(self, point: np.ndarray, x: np.ndarray | None) -> Result:
        """The posture with the hand's target at ``point`` (m), solved from ``x``."""
        targets = list(self.problem.all_targets)
        targets[self.index] = replace(targets[self.index], position=np.asarray(point, dtype=float))
        return solve(self.problem.with_targets(targets), x, self.options)

    def crossings(self, a: Result, b: Result) -> list[str]:
        """What the body (and a carried box) passes through on the way between the postures ``a`` and ``b``."""
        out = []
        if self.body is not None:
            out += [f"{c.part} passes through {c.obstacle}" for c in self.sweep.check(self.body, a.x[: self.n],
                                                                             b.x[: self.n]).crossings]  # fmt: skip
        if self.problem.carried_obstacle_constraint is not None:
            boxed = self.sweep.carried_crossings(self.problem, a.x[: self.n], b.x[: self.n])
            out += [f"{self.problem.carried.name} passes through {name}" for name in dict(boxed)]
        return out

    def piece(self, p: np.ndarray, q: np.ndarray, a: Result, depth: int) -> tuple[list, list[str]]:
        """[(point, posture)] from ``p`` (posture ``a``) to ``q`` (``q``'s last), halved while the body crosses
        something, and the crossings left."""
        b = self.at(q, a.x)
        crossed = self.crossings(a, b)
        if not crossed:
            return [(q, b)], []
        if depth >= self.splits:
            return [(q, b)], crossed
        mid = 0.5 * (p + q)
        first, left = self.piece(p, mid, a, depth + 1)
        second, right = self.piece(mid, q, first[-1][1], depth + 1)
        return first + second, left + right


def follow(problem: Problem, tcp: str, way: np.ndarray, x0: np.ndarray | None = None,
           options: SolverOptions = DEFAULT_OPTIONS, splits: int = SPLITS) -> Followed:  # fmt: skip
    """The postures of ``problem`` with the target of ``tcp`` moved along ``way`` (k, 3) m, each solved from the one
    before (the first from ``x0``), checked between each other; see :class:`Followed`."""
    walker = _Walker(problem, tcp, options, splits)
    way = np.asarray(way, dtype=float)
    first = walker.at(way[0], x0)
    points, results, problems = [way[0]], [first], []
    if not first.converged:
        problems.append(f"{tcp} cannot be held at way point 1 {_at(way[0])}: {', '.join(first.unmet)}")
    for i in range(1, len(way)):
        got, crossed = walker.piece(way[i - 1], way[i], results[-1], 0)
        problems += [f"{what} between way points {i} and {i + 1}" for what in dict.fromkeys(crossed)]
        last = got[-1][1]
        if not last.converged:
            problems.append(f"{tcp} cannot be held at way point {i + 1} {_at(way[i])}: {', '.join(last.unmet)}")
        points += [p for p, _ in got]
        results += [r for _, r in got]
    return Followed(np.array(points), results, len(points) - len(way), problems)


def _at(p: np.ndarray) -> str:
    return "(" + ", ".join(f"{v:.2f}" for v in p) + ") m"
