"""Collision-free ways for the hand, or a box carried in the hands, between two postures' points (m).

**Design.** The issue allows "a sampling-based planner such as RRT-Connect or a lazy PRM over postures the solver
keeps balanced, then shortened and smoothed; or an equivalent with its reason". We plan in the *workspace of one
point*: the hand's centre (a ball of :data:`~solver.planning.space.HAND_RADIUS` plus a margin for the forearm behind
it) or the carried box's centre, the box's orientation turned from the start's to the goal's as a function of that
point (:class:`~solver.planning.space.Space`). Why there and not over postures: a query is then a few NumPy distance
calls (no forward kinematics, no solve), so a way costs well under a second and leaves the issue's 10 s for a
four-operation sequence to the solves of its frames; and the whole posture is solved afterwards anyway, so the
planner needs to be right only about the part that leads (the hand, the box), the rest is checked.

Method: RRT-Connect (Kuffner & LaValle 2000; :mod:`.rrt`): two trees, from the start and from the goal, each grown
towards random points and then straight at the other; chosen because ways between two postures are single queries
(no roadmap to reuse) and it needs no tuning beyond a step length. The way is shortened (random shortcuts, then each
point joined to the farthest it sees) and smoothed (corner cutting where the cut is free). Deterministic with a
seed: nothing depends on the clock. Collisions are the project's own distances (each obstacle kind's, the box's
edges and the obstacles' skeletons as the carried box's clearance rows); a straight piece is certified free from
its two ends' room and how far the moving thing can travel on it (:meth:`~solver.planning.space.Space.free`).

Then the body (:mod:`.follow`): the posture solved with the hand at each way point (balance, limits, clearance)
and the swept check between consecutive postures, so the whole body stays clear; where it does not (the forearm
through a bench though the hand is clear), way points are added half-way, or the crossing is reported.
:func:`~solver.planning.resample.at_shares` turns a way into per-frame points by arc length for a timing law.

The call the operations generator makes: :func:`find_way` (start, goal, what is carried, obstacles) -> :class:`Way`
(its points, or ``blocked``: one line naming what blocks it).
"""

from .resample import arc_lengths, at_shares
from .space import HAND_RADIUS, MARGIN, CarriedBox
from .way import Way, find_way

__all__ = ["HAND_RADIUS", "MARGIN", "CarriedBox", "Way", "arc_lengths", "at_shares", "find_way"]
