"""A plan's problem at each frame: the hands, feet and gaze targets, the held object's weight and box, and the
resting objects as obstacles. Problems are built once per set of supports, held object and resting places, and
moved to each frame's targets (:meth:`~solver.problem.problem.Problem.with_targets`). Units: m, s, N.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..body.model import GRAVITY
from ..body.spatial import matrix_to_quat, quat_to_matrix, slerp
from ..collision import Box
from ..collision.carried import Carried, carried_frame
from ..problem.problem import Problem
from ..problem.specs import ExternalLoad, Target
from .objects import moved, origin_of
from .stance import swing_at
from .timeline import Plan, Segment
from .timing import min_jerk
from .ways import polyline_at

FOOT_LOCK = ("x", "y", "z", "rx", "ry")  # a foot free to turn about z, as the presets' supports
GAZE_LOCK = ("rx", "rz")  # the eyes' view axis (their -y) aimed; free to roll about it and anywhere in space
GRIP_ROOM = 0.03  # m: the object being gripped is this much narrower on each side face while the hands close on it
EYE_HEIGHT = 1.55  # m above the feet: where the gaze is aimed from (the eyes' height standing, about)


class Poser:
    """The problem at any time of ``plan`` for the scenario's first-frame ``base`` problem."""

    def __init__(self, base: Problem, plan: Plan) -> None:
        self.base, self.plan = base, plan
        self.feet = {t.tcp: t for t in base.all_targets if t.support}
        self.kept = [t for t in base.all_targets if not t.support]  # the scenario's other targets stay
        self._problems: dict[tuple, Problem] = {}

    def segment_at(self, time: float) -> tuple[Segment, float]:
        """The segment running at ``time`` s and the minimum-jerk share of it done."""
        segments = self.plan.segments
        for s in segments:
            if time <= s.t1 + 1e-9:
                span = max(s.t1 - s.t0, 1e-9)
                return s, float(min_jerk((time - s.t0) / span))
        return segments[-1], 1.0

    def problem_at(self, time: float) -> Problem:
        s, share = self.segment_at(time)
        targets = self._feet(s, share) + self._hands(s, share) + self._gaze(s) + self.kept
        key = (tuple(t.tcp for t in targets if t.support), s.carried, s.taking,
               tuple((n, tuple(np.round(o, 4))) for n, o in sorted(s.resting.items())))  # fmt: skip
        problem = self._problems.get(key)
        if problem is None:
            problem = self._problems[key] = Problem(self.base.model, self.base.spec.replace(
                targets=targets, loads=self._loads(s), carried=self._carried(s, targets),
                obstacles=[*self.base.spec.obstacles, *self._resting(s)], comfort=self.base.comfort))
        return problem.with_targets(targets)

    def _feet(self, s: Segment, share: float) -> list[Target]:
        out = []
        for tcp, (a, b) in s.feet.items():
            base = self.feet[tcp]
            if np.allclose(a, b):
                out.append(replace(base, position=np.asarray(b, dtype=float)))
            else:  # swinging: no support, on its way
                out.append(replace(base, position=swing_at(a, b, share), support=False, priority=1, lock=FOOT_LOCK))
        return out

    def _hands(self, s: Segment, share: float) -> list[Target]:
        out = []
        for tcp, h in s.hands.items():
            q = slerp(matrix_to_quat(h.start), matrix_to_quat(h.end), share)
            out.append(Target(tcp, polyline_at(h.points, share), quat_to_matrix(q), lock=h.lock, priority=h.priority))
        return out

    def _gaze(self, s: Segment) -> list[Target]:
        if s.gaze is None:
            return []
        middle = sum(b for _, b in s.feet.values()) / len(s.feet)
        eyes = middle + np.array([0.0, 0.0, EYE_HEIGHT])
        view = s.gaze - eyes
        view /= max(float(np.linalg.norm(view)), 1e-9)
        y = -view  # the eyes look along their -y
        x = np.cross(y, [0.0, 0.0, 1.0])
        x = x / np.linalg.norm(x) if np.linalg.norm(x) > 1e-6 else np.array([1.0, 0.0, 0.0])
        rotation = np.column_stack([x, y, np.cross(x, y)])
        return [Target("eyes", eyes, rotation, lock=GAZE_LOCK, priority=2)]

    def _loads(self, s: Segment) -> list[ExternalLoad]:
        if s.carried is None:
            return []
        name, tcps = s.carried
        force = self.plan.objects[name].mass * GRAVITY / len(tcps)  # the weight shared by the holding hands
        return [ExternalLoad(tcp, force) for tcp in tcps]

    def _carried(self, s: Segment, targets: list[Target]) -> Carried | None:
        """Two hands: the object's bounds as a carried box between them (one hand: its weight only)."""
        if s.carried is None or len(s.carried[1]) != 2:
            return None
        name, tcps = s.carried
        obj = self.plan.objects[name]
        at = {t.tcp: t.position for t in targets}
        _, frame = carried_frame(at[tcps[0]], at[tcps[1]])
        size = np.abs(frame.T @ obj.rotation) @ obj.size  # the object's edges along the carried box's axes
        return Carried(np.round(size, 6), (tcps[0], tcps[1]), name)

    def _resting(self, s: Segment) -> list:
        """The resting objects where they are; a box both hands close on narrowed by :data:`GRIP_ROOM` m on each
        side face (the palms grip 1 cm off its faces; the trunk, bent over it, keeps out of it); an object one hand
        closes on, or not a box, left out."""
        objects, out = self.plan.objects, []
        for n, o in s.resting.items():
            shape = moved(objects[n].shape, o - origin_of(objects[n].shape))
            if s.taking is not None and n == s.taking[0]:
                if not isinstance(shape, Box) or s.taking[1] < 2:
                    continue  # a part taken in one hand is left out (the hand closes round it)
                narrow = np.maximum(np.asarray(shape.size) - np.array([2 * GRIP_ROOM, 2 * GRIP_ROOM, 0.0]), 0.01)
                shape = replace(shape, size=narrow)
            out.append(shape)
        return out
