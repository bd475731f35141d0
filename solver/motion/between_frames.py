"""A motion's frames kept from passing through things between them: the swept check of
:mod:`solver.collision.sweep` on the way from each solved frame to the next, against the floor and every obstacle
the frame's clearance rows keep (the same pairs: a support's foot is not checked against the floor it stands on),
and between the body's own parts that its self-collision rows keep apart. A support planted in both frames (the same
TCP held at the same place) has its whole limb left out of the floor pairs (:func:`planted_parts`).

A frame whose way from its predecessor crosses something is solved again from the previous frame in N sub-steps
(N: how far the crossing capsules moved on the first try over their radius, 2..``MAX_SUBSTEPS``): the targets move
from the previous frame's to this frame's a share of the way each time, each sub-step is held within ``SHARE``/N of
the per-frame bound of the one before, and each sub-step's own way is checked. The sub-steps stop where the way was
last clear, or after the first one that does not converge (blocked: the clearance rows hold the part on the near
side). If the way from the previous frame to that pose is clear, it is the frame (a note says so); else the frame
is not converged and its ``unmet`` names each crossing, e.g. "hand_r passes through shelf between frames 12 and 13".
"""

from __future__ import annotations

import math
import operator
from collections.abc import Callable
from typing import TYPE_CHECKING

import numpy as np

from ..collision.body import capsules_of
from ..collision.carried import carried_frame, held_frame
from ..collision.sweep import TOLERANCE, Pose, SweepReport, SweptBody
from ..constraints.carried_obstacles import CarriedObstacles, box_corners
from ..constraints.clearance import FLOOR, Clearance
from ..iteration import solve
from ..iteration.result import Result
from ..options import SolverOptions
from ..problem.problem import Problem
from ..problem.specs import Target, same_frame
from ..problem.tracks import blend_targets

if TYPE_CHECKING:
    from ..body.state import State

MARGIN = 0.05  # m: the least margin of a mesh query (farther rows count as this far)
MAX_SUBSTEPS = 64  # sub-steps of a re-solved frame at most
BOX_STEP = 0.02  # m: a carried box's corners move about this far at most between the samples of its way
PLANTED = 1e-4  # m: a support held within this of its place in the frame before stays planted
Placed = tuple[np.ndarray, np.ndarray, np.ndarray]  # a carried box's centre (m), rotation and corners (8, 3) m
SHARE = 2.0  # a sub-step may change each joint by this many times its share of the per-frame bound


class MotionSweep:
    """Swept checks between consecutive frames; keeps the capsule distances of the last few poses it queried."""

    KEPT = 4  # poses whose distances are kept (the previous frame, the attempts at this one)

    def __init__(self, resolve: bool = True) -> None:
        """``resolve``: re-solve a frame whose way crosses something (else only report it)."""
        self.resolve = resolve
        self._bodies: dict[tuple, SweptBody] = {}
        self._poses: dict[tuple, Pose] = {}
        self._distances: dict[tuple, np.ndarray] = {}
        self._anchor: tuple[SweptBody, Pose, np.ndarray] | None = None  # the last pose queried and its distances
        self._boxes: dict[tuple, tuple] = {}  # a carried box's placements (centre, rotation, corners) by joint values
        self._planted: tuple | None = None  # the last planted_parts: (model, the two problems' supports, parts)
        self._body_key: tuple | None = None  # the last body's clearance rows, own pairs, planted parts and dict key
        self._way: tuple | None = None  # the last anchored check's body, anchor, end pose and bound from one to other
        self._certified: tuple | None = None  # the last way the anchor certified: (anchor, start pose, end pose)
        self._travel: tuple | None = None  # the last carried box's corners at both ends and how far they moved (m)
        self.queries = 0  # poses whose distances were queried
        self.samples = 0  # in-between capsule-obstacle queries so far (0 when no motion came near anything)
        self.substeps = 0  # sub-step solves so far

    def body(self, problem: Problem, planted: tuple[str, ...] = ()) -> SweptBody | None:
        """The capsules and obstacles that ``problem``'s clearance rows keep apart, or None when there are none;
        the capsules named in ``planted`` (:func:`planted_parts`) not against the floor."""
        rows = [c for c in problem.constraints if isinstance(c, Clearance) and c.obstacles]
        own = problem.self_constraint.pairs if problem.self_constraint is not None else None
        if not rows and own is None:
            return None
        last = self._body_key  # the same rows as the last frame's (a motion's): their key without building it again
        if last is not None and last[1] is own and last[2] == planted and _same_objects(last[0], rows):
            key = last[3]
        else:
            key = (tuple((tuple(id(o) for o in c.obstacles), c.capsules.names) for c in rows), id(own), planted)
            self._body_key = (rows, own, planted, key)
        body = self._bodies.get(key)
        if body is None:
            if len(self._bodies) >= self.KEPT:  # a scene read afresh every frame (Blender) brings new obstacles
                self._bodies.pop(next(iter(self._bodies)))
            obstacles = list({id(o): o for c in rows for o in c.obstacles}.values())
            column = {id(o): i for i, o in enumerate(obstacles)}
            names = capsules_of(problem.model).names
            pairs = np.zeros((len(names), len(obstacles)), dtype=bool)
            for c in rows:
                kept = [names.index(name) for name in c.capsules.names]
                for o in c.obstacles:
                    pairs[kept, column[id(o)]] = True
            for o in (o for o in obstacles if o is FLOOR):
                pairs[[names.index(name) for name in planted], column[id(o)]] = False
            body = self._bodies[key] = SweptBody(problem.model, obstacles, pairs, own=own)
        return body

    def check(
        self, body: SweptBody, theta_a: np.ndarray, theta_b: np.ndarray, at_b: State | None = None
    ) -> SweepReport:
        """The crossings of ``body`` on the way from joint values ``theta_a`` to ``theta_b`` (``at_b``: a state there,
        whose kinematics serve for the pose at ``theta_b``).

        Distances are queried only when lower bounds do not already certify the way: the distances d_P at the last
        pose queried, less the bound on the way from there (d >= d_P - M_P), which is all a long motion of small
        steps with nothing near needs."""
        anchored = self._anchor is not None and self._anchor[0] is body
        if anchored:
            _, p, d_p = self._anchor
        if anchored and at_b is None:  # first the path bounds alone, which need no forward kinematics (the
            # tighter bounds below certify whatever they certify, and need none either with the state's at hand)
            length = body.length(np.array([p.theta, p.theta, theta_a]), np.array([theta_a, theta_b, theta_b]))
            if not body.any_uncertain(d_p, length[0], length[1], length[2]):
                return SweepReport(None, [], 0, 0)
        a, b = self._pose(body, theta_a), self._pose(body, theta_b, at_b)
        if anchored:
            last = self._certified  # a frame that did not move, again: the same way from the same anchor, certified
            if last is not None and last[0] is self._anchor and last[1] is a and last[2] is b:
                return SweepReport(b, [], 0, 0)
            bound = self._bounds(body, p, a, b)
            if not body.any_uncertain(d_p, bound[0], bound[1], bound[2]):
                self._certified = (self._anchor, a, b)
                return SweepReport(b, [], 0, 0)
        margin = max(float(body.bound(a, b).max(initial=0.0)) + 2.0 * body.tolerance, MARGIN)
        report = body.check(a, b, self._exact(body, a, margin), self._exact(body, b, margin), margin)
        self.samples += report.samples
        return report

    def _bounds(self, body: SweptBody, p: Pose, a: Pose, b: Pose) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``body.bounds([(p, a), (p, b), (a, b)])``; the first the last call's (p, b) when ``a`` is that ``b`` (the
        previous frame's end is this frame's start)."""
        last = self._way
        if last is not None and last[0] is body and last[1] is p and last[2] is a:
            pb, ab = body.bounds([(p, b), (a, b)])
            out = last[3], pb, ab
        else:
            out = tuple(body.bounds([(p, a), (p, b), (a, b)]))
        self._way = (body, p, b, out[1])
        return out

    def _pose(self, body: SweptBody, theta: np.ndarray, at: State | None = None) -> Pose:
        """``body``'s pose at joint values ``theta`` (from the kinematics of the state ``at`` when it is there: the
        same numbers), kept for the next queries."""
        key = (body, np.asarray(theta, dtype=float).tobytes())  # the body itself: its id is not reused while kept
        found = self._poses.get(key)
        if found is None:
            if len(self._poses) >= self.KEPT:
                self._poses.pop(next(iter(self._poses)))
            kin = None if at is None else at.kin
            if kin is not None and kin.model is body.model and kin.theta.tobytes() == key[1]:
                found = Pose(np.array(theta, dtype=float), *body.capsules.world(kin))  # body.pose without its FK
            else:
                found = body.pose(theta)
            self._poses[key] = found
        return found

    def _exact(self, body: SweptBody, pose: Pose, margin: float) -> np.ndarray:
        """The (k, m) distances at ``pose`` (a mesh's beyond the margin: the margin), kept for the next queries."""
        key = (body, pose.theta.tobytes())
        found = self._distances.get(key)
        if found is None:
            if len(self._distances) >= self.KEPT:
                self._distances.pop(next(iter(self._distances)))
            found = self._distances[key] = body.distances(pose, margin)
            self.queries += 1
        self._anchor = (body, pose, found)
        return found

    def guard(self, frames: tuple[int, int], problems: tuple[Problem, Problem, Problem], previous_x: np.ndarray,
              result: Result, options: SolverOptions, steps: Callable[[], np.ndarray]) -> Result:  # fmt: skip
        """``result`` (frame ``frames[1]``) if the way from ``previous_x`` (frame ``frames[0]``) is clear; else the
        frame re-solved in sub-steps, and reported if that still crosses. ``problems``: the previous frame's, this
        frame's and this frame's within the per-frame bound (the one solved); ``steps()``: the per-frame bound per
        solver variable (rad or m), asked for only when the frame is re-solved."""
        body = self.body(problems[1], self.planted(problems[0], problems[1]))
        if body is None:
            return result
        n = problems[1].model.n
        theta_a, theta_b = previous_x[:n], result.x[:n]
        report = self.check(body, theta_a, theta_b, result.state)
        boxed = self.carried_crossings(problems[1], theta_a, theta_b, result.state)
        if not (report.crossings or boxed):  # nothing to mark (a long motion's every frame but a few)
            return result
        if not self.resolve:
            mark(result, report, frames)
            return mark_carried(result, frames, boxed)
        retried, done, count = self._substeps(problems, previous_x, body, report, options, steps(), result.x)
        again = self.check(body, previous_x[:n], retried.x[:n])
        boxed_again = self.carried_crossings(problems[1], previous_x[:n], retried.x[:n])
        if len(again.crossings) + len(boxed_again) <= len(report.crossings) + len(boxed):
            went = ", ".join([f"{c.part} through {c.obstacle}" for c in report.crossings]
                             + [f"{problems[1].carried.name} through {name}" for name in dict(boxed)])  # fmt: skip
            how = f"in {count} sub-steps" if done == count else f"in sub-steps, blocked after {done} of {count}"
            retried.notes.append(f"frame {frames[1]}: its first solution went {went} on the way from frame "
                                 f"{frames[0]}; re-solved {how}")  # fmt: skip
            result, report, boxed = retried, again, boxed_again
        mark(result, report, frames)
        return mark_carried(result, frames, boxed)

    def planted(self, before: Problem, after: Problem) -> tuple[str, ...]:
        """:func:`planted_parts` of ``before`` and ``after``, kept while both hold the same support targets as the
        last two (a motion's feet: the same objects from frame to frame, or read again at the same frames by a bake,
        so planted the same way)."""
        supports = [t for t in before.all_targets if t.support], [t for t in after.all_targets if t.support]
        last = self._planted
        if last is not None and last[0] is after.model and all(map(_same_supports, last[1], supports)):
            return last[2]
        parts = planted_parts(before, after)
        self._planted = (after.model, supports, parts)
        return parts

    def _box_at(self, problem: Problem, theta: np.ndarray, at: State | None = None) -> Placed:
        """(centre m, rotation, corners (8, 3) m) of ``problem``'s carried box at joint values ``theta`` (``at``: a
        state there, whose placement of the box the solve made already), kept: a frame's end is the next frame's
        start."""
        rows = problem.carried_obstacle_constraint
        key = (rows.tcps[0].name, rows.tcps[1].name, theta.tobytes())
        found = self._boxes.get(key)
        if found is None or found[0] is not problem.model or not _same_array(found[1], rows.half):
            if len(self._boxes) >= self.KEPT:
                self._boxes.pop(next(iter(self._boxes)))
            if at is not None:  # the state's (its rows' held_frame: the sums of _placed, kept in the state)
                centre, rotation = held_frame(at, rows.tcps)[1:]
            else:
                centre, rotation = _placed(rows, problem.model.forward(theta))
            placed = centre, rotation, box_corners(centre, rotation, rows.half)
            found = self._boxes[key] = (problem.model, rows.half, placed)
        return found[2]

    def carried_crossings(self, problem: Problem, theta_a: np.ndarray, theta_b: np.ndarray,
                          at_b: State | None = None) -> list[tuple[str, float]]:  # fmt: skip
        """(obstacle, fraction of the way) where the box carried in ``problem`` is inside an obstacle or below the
        floor on the way from joint values ``theta_a`` to ``theta_b`` (``at_b``: a state there, if at hand;
        both ends excluded: each frame's rows keep its own).

        The way is sampled (joint values linearly in between) so that no corner of the box moves more than about
        ``BOX_STEP`` between samples: a box passing through anything between two frames is inside it at some
        sample, since it would have to move its own smallest size and the obstacle's thickness. Only when the box's
        bounds on the way meet an obstacle's."""
        rows = problem.carried_obstacle_constraint
        if rows is None:
            return []
        end = self._box_at(problem, theta_b, at_b)
        start = self._box_at(problem, theta_a)
        last = self._travel  # the same corners as the last time (a frame that did not move, again): their travel
        if last is None or last[0] is not start[2] or last[1] is not end[2]:
            last = self._travel = (start[2], end[2], _corner_travel(start[2], end[2]))
        moved = last[2]
        if moved <= BOX_STEP:
            return []
        if not rows.near_way(start[:2], end[:2], moved):
            return []
        found = []
        for s in np.linspace(0.0, 1.0, math.ceil(moved / BOX_STEP) + 1)[1:-1]:
            placed = _placed(rows, problem.model.forward(theta_a + s * (theta_b - theta_a)))
            found += [(name, float(s)) for name in rows.inside(*placed, TOLERANCE)]
        return found

    def _substeps(self, problems: tuple[Problem, Problem, Problem], previous_x: np.ndarray, body: SweptBody,
                  report: SweepReport, options: SolverOptions, steps: np.ndarray, first_x: np.ndarray):  # fmt: skip
        """(result, sub-steps kept, sub-steps planned): the frame solved again from ``previous_x`` in sub-steps, its
        targets moved from the previous frame's a share of the way each time, each sub-step within its share of the
        per-frame bound ``steps`` (per solver variable; see the module docstring). ``first_x``: the first try, whose
        crossing capsules' travel over their radius (a carried box's over BOX_STEP) sets the number of sub-steps."""
        before, _, problem = problems
        n = problem.model.n
        crossing = [body.capsules.names.index(c.part) for c in report.crossings]
        moved = body.bound(self._pose(body, previous_x[:n]), self._pose(body, first_x[:n]))[crossing]  # m
        room = body.capsules.radius[crossing] - 2.0 * body.tolerance
        box = 0.0 if problem.carried_obstacle_constraint is None else _corner_travel(
            self._box_at(problem, previous_x[:n])[2], self._box_at(problem, first_x[:n])[2]) / BOX_STEP  # fmt: skip
        count = min(MAX_SUBSTEPS, max(2, math.ceil(float(np.max(moved / room, initial=box)))))
        share = steps * min(1.0, SHARE / count)
        x, iterations, seconds, done = previous_x, 0, 0.0, 0
        for i in range(1, count + 1):
            targets = blend_targets(before.all_targets, problem.all_targets, i / count)
            aimed = problem.with_targets(targets) if targets is not None else problem
            last = solve(aimed.with_bounds(problem.bounds.around(problem.to_variables(x), share)), x, options)
            iterations, seconds = iterations + last.iterations, seconds + last.time_s
            self.substeps += 1
            if self.check(body, x[:n], last.x[:n]).crossings or self.carried_crossings(problem, x[:n], last.x[:n]):
                break  # the frame stays where its way was last clear
            x, done = last.x, i
            if not last.converged:  # blocked, or the targets need more than the sub-step's share: stop here
                break
        result = Result.from_state(problem, problem.state_of_x(x), iterations, seconds)
        result.stop = last.stop
        return result, done, count


def planted_parts(before: Problem, after: Problem) -> tuple[str, ...]:
    """The capsules of every limb whose support ``before`` and ``after`` both hold at the same place (position
    within ``PLANTED`` m, the same orientation): the support's link, what hangs from it and the links up to where the
    limb branches off (a foot's: the foot, shank and thigh).

    Why they are not checked against the floor between two frames: the way is a line in joint values, root included,
    on which a bending planted leg's foot leaves its place and its shank dips through the floor midway; the body does
    not move so: the foot stays put and the limb stays above the floor it stands on, as it is in both frames."""
    model = after.model
    held = {t.tcp: t for t in before.all_targets if t.support and t.enabled}
    links: set[int] = set()
    children = np.bincount(model.parent[1:], minlength=model.n)
    for t in after.all_targets:
        was = held.get(t.tcp)
        if not (t.support and t.enabled and was is not None and _same_place(was, t)):
            continue
        link = model.tcp(t.tcp).link
        links.update(np.flatnonzero(model.descendant[link]))  # the link and what hangs from it (toes)
        while model.parent[link] >= 0 and children[model.parent[link]] == 1:
            link = model.parent[link]
            links.add(link)
    caps = capsules_of(model)
    return tuple(name for name, link in zip(caps.names, caps.link, strict=True) if link in links)


def _corner_travel(start: np.ndarray, end: np.ndarray) -> float:
    """How far (m) the corner that moves most moves from corners ``start`` to ``end`` (each (8, 3) m)."""
    move = end - start
    # np.linalg.norm(move, axis=1).max(): its sums of squares, the square root (monotonic) of their largest (the
    # ufunc's reduce: .max() without its Python wrapper)
    return math.sqrt(np.maximum.reduce(np.add.reduce(move * move, axis=1)))


def _same_objects(a: list, b: list) -> bool:
    """Whether lists ``a`` and ``b`` hold the very same objects in the same order."""
    return len(a) == len(b) and all(map(operator.is_, a, b))


def _same_supports(a: list[Target], b: list[Target]) -> bool:
    """Whether support lists ``a`` and ``b`` hold the same TCPs, enabled alike, at the same frames."""
    if len(a) == len(b) and all(map(operator.is_, a, b)):  # a motion's feet: the very same targets
        return True
    return len(a) == len(b) and all(
        x is y or (x.tcp == y.tcp and x.enabled == y.enabled and same_frame(x, y)) for x, y in zip(a, b, strict=True)
    )


def _same_array(a: np.ndarray, b: np.ndarray) -> bool:
    """Whether arrays ``a`` and ``b`` are equal (at once when they are the same object)."""
    return a is b or np.array_equal(a, b)


def _same_place(a: Target, b: Target) -> bool:
    """Whether targets ``a`` and ``b`` hold their TCP at the same place and orientation."""
    if np.linalg.norm(np.asarray(a.position, dtype=float) - np.asarray(b.position, dtype=float)) > PLANTED:
        return False
    if a.rotation is None or b.rotation is None:
        return a.rotation is None and b.rotation is None
    return bool(np.allclose(a.rotation, b.rotation, atol=1e-6))


def _placed(rows: CarriedObstacles, kin) -> tuple[np.ndarray, np.ndarray]:
    """(centre m, rotation) of the box that ``rows`` keep out of obstacles, with the body at kinematics ``kin``."""
    # the positions of Kinematics.tcp_frame (its rotations are not needed here)
    return carried_frame(*(kin.position[tcp.link] + kin.rotation[tcp.link] @ tcp.position for tcp in rows.tcps))


def mark_carried(result: Result, frames: tuple[int, int], found: list[tuple[str, float]]) -> Result:
    """``result`` with each obstacle its carried box passes through on the way from the previous frame (``found``:
    :meth:`MotionSweep.carried_crossings`) named in its unmet (the frame is then not converged), e.g. "box passes
    through table between frames 12 and 13"."""
    problem = result.problem
    a, b = frames
    crossed: dict[str, float] = {}
    for obstacle, s in found:
        crossed.setdefault(obstacle, s)  # where it is first found inside
    for obstacle, s in crossed.items():
        name = f"{problem.carried.name} passes through {obstacle} between frames {a} and {b}"
        result.unmet.append(name)
        result.broken.append(name)
        result.notes.append(f"frame {b}: {name} (inside it at frame {a + s * (b - a):.2f}); more frames between "
                            "them, or a key that leads around it, would avoid it")  # fmt: skip
    if crossed:
        result.converged = False
    return result


def mark(result: Result, report: SweepReport, frames: tuple[int, int]) -> None:
    """Name each crossing in ``result``'s unmet (held at priority 1) and notes; the frame is not converged. A capsule
    whose axis got inside (deeper than its radius) "passes through", a shallower one "cuts into"."""
    a, b = frames
    for c in report.crossings:
        caps = capsules_of(result.problem.model)
        verb = "passes through" if c.depth >= caps.radius[caps.names.index(c.part)] else "cuts into"
        name = f"{c.part} {verb} {c.obstacle} between frames {a} and {b}"
        result.unmet.append(name)
        result.broken.append(name)
        result.notes.append(f"frame {b}: {name} ({c.depth * 1e3:.1f} mm deep at frame {a + c.s * (b - a):.2f}); "
                            "more frames between them, or a key that leads around it, would avoid it")  # fmt: skip
    if report.crossings:
        result.converged = False
