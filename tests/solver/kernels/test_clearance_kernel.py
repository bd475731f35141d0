"""The clearance rows by the compiled kernels equal the NumPy path's to rounding: the capsules' world ends, the
floor's rows, the body's own pairs (distances, closest points, normals, the movement bound that decides which
poses are measured), box, capsule and sphere obstacles and the carried box; random poses and segment pairs with
parallel, crossing and zero-length segments."""

from __future__ import annotations

import numpy as np
import pytest
from helpers import close_to_rounding

from solver import kernels
from solver.collision import Box, Capsule, Sphere
from solver.collision.body import capsules_of
from solver.collision.boxes import box_rows
from solver.collision.carried import Carried
from solver.collision.distance import capsule_pairs, closest_on_axes
from solver.problem.problem import Problem, ProblemSpec, Target

pytest.importorskip("numba")


def _segments(rng: np.random.Generator, m: int) -> tuple[np.ndarray, ...]:
    """m random segment pairs, every fifth parallel, crossing, touching at an end, zero-length or both points."""
    p0, p1, q0, q1 = (rng.normal(scale=0.3, size=(m, 3)) for _ in range(4))
    for k in range(m):
        kind = k % 8
        if kind == 1:  # parallel, overlapping or not
            q1[k] = q0[k] + rng.uniform(-2.0, 2.0) * (p1[k] - p0[k])
        elif kind == 2:  # crossing: the axes meet (the normal is made perpendicular to both)
            mid = 0.5 * (p0[k] + p1[k])
            q0[k], q1[k] = mid - rng.normal(size=3), mid
            q1[k] = 2 * mid - q0[k]
        elif kind == 3:  # zero-length first
            p1[k] = p0[k]
        elif kind == 4:  # zero-length second
            q1[k] = q0[k]
        elif kind == 5:  # both points, the same point
            p1[k] = p0[k]
            q0[k] = q1[k] = p0[k]
        elif kind == 6:  # collinear, end to end
            q0[k], q1[k] = p1[k], 2 * p1[k] - p0[k]
    return p0, p1, q0, q1


@pytest.mark.parametrize("seed", range(4))
def test_axes_and_pairs(seed):
    """closest_on_axes and capsule_pairs: parameters, witnesses, normals, distances."""
    rng = np.random.default_rng(seed)
    p0, p1, q0, q1 = _segments(rng, 64)
    got = {}
    for compiled in (False, True):
        with kernels.using(compiled):
            axes = closest_on_axes(p0, p1, q0, q1)
            both0, both1 = np.concatenate([p0, q0]), np.concatenate([p1, q1])
            radii = rng.uniform(0.0, 0.1, size=128) if not compiled else got[False][2]
            pairs = capsule_pairs(both0, both1, radii, np.arange(64), 64 + np.arange(64))
            one_radius = capsule_pairs(both0, both1, 0.05, list(range(64)), list(range(64, 128)))  # as sweep.py asks
            got[compiled] = (axes, pairs, radii, one_radius)
    for a, b in zip(
        got[True][0] + got[True][1] + got[True][3], got[False][0] + got[False][1] + got[False][3], strict=True
    ):
        close_to_rounding(a, b)
    normal = got[True][0][4]
    close_to_rounding(np.linalg.norm(normal, axis=1), np.ones(64))  # unit, the crossing rows too


def _problem(model) -> Problem:
    """Feet on the floor, the hands holding a box in front; a box, a capsule and a sphere near the body."""
    zero = model.forward(model.zero_pose())
    feet = [Target(f, zero.tcp_frame(model.tcp(f))[1], support=True) for f in ("foot_r", "foot_l")]
    hands = [
        Target(h, np.array([0.2 * side, -0.35, 1.0]), lock=("x", "y", "z"))
        for h, side in (("hand_r", -1.0), ("hand_l", 1.0))
    ]
    obstacles = [
        Box(np.array([0.0, -0.45, 0.8]), np.array([0.6, 0.3, 0.05]), name="table"),
        Capsule(np.array([-0.4, -0.3, 0.2]), np.array([0.4, -0.3, 1.4]), 0.05, name="bar"),
        Sphere(np.array([0.3, -0.2, 1.1]), 0.12, name="ball"),
    ]
    box = Carried(np.array([0.35, 0.30, 0.24]), ("hand_r", "hand_l"), "box")
    return Problem(model, ProblemSpec(feet + hands, obstacles=obstacles, carried=box))


def _seen(problem: Problem, x: np.ndarray) -> dict:
    """What each clearance gives the iteration at x: the bound (before measuring), error, value, Jacobian rows,
    the near pairs."""
    state = problem.state_of_x(x)
    out = {}
    rows = [problem.floor_constraint, problem.self_constraint, problem.obstacle_constraint, problem.carried_constraint]
    for c in rows:
        bound = c._least_bound(state) if c._reference is not None else np.inf
        clear = c._clear_by(state, c.watch)
        rows_, jac = c.jacobian_rows(state)
        # by name: pairs at one distance to rounding (two capsules' shared joint nearest) may swap places
        near = sorted(c.closest(state), key=lambda n: n.pair)
        out[c.name] = dict(bound=bound, clear=clear, error=c.error(state), value=c.value(state), rows=rows_, jac=jac,
                           pairs=[n.pair for n in near], distance=[n.distance for n in near],
                           points=[np.r_[n.point, n.other_point] for n in near])  # fmt: skip
    return out


@pytest.mark.parametrize("size", [0.002, 0.05, 0.3, 1.0])
def test_clearance_rows(model, size):
    """A random walk of poses (small to large moves: arms through the trunk, parts under the floor and inside the
    obstacles and the box), each path with its own problem: every clearance's rows, Jacobian rows, near pairs and
    the self pairs' movement bound (which poses skip the query) agree."""
    problems = {compiled: _problem(model) for compiled in (False, True)}
    rng = np.random.default_rng(int(size * 1000))
    x = problems[False].start()
    measured = skipped = 0
    near = {name: 0 for name in ("floor", "self_collision", "obstacles", "carried")}
    for _ in range(20):
        step = np.r_[rng.uniform(-size, size, model.n), np.zeros(len(x) - model.n)]
        x = problems[False].x_bounds.clip(x + step)
        seen = {}
        for compiled, problem in problems.items():
            with kernels.using(compiled):
                seen[compiled] = _seen(problem, x)
        for name, want in seen[False].items():
            got = seen[True][name]
            assert got["clear"] == want["clear"] and got["pairs"] == want["pairs"], name
            np.testing.assert_array_equal(got["rows"], want["rows"])
            for key in ("bound", "error", "value", "jac", "distance", "points"):
                close_to_rounding(got[key], want[key])
        for name in near:
            near[name] += len(seen[True][name]["pairs"])
        skipped += seen[True]["self_collision"]["clear"]
        measured += not seen[True]["self_collision"]["clear"]
    assert measured  # both branches of the bound were taken by the walk at some size
    if size == 0.002:
        assert skipped


def test_capsule_ends(model):
    """The capsules' world ends at random poses."""
    capsules, rng = capsules_of(model), np.random.default_rng(3)
    for _ in range(5):
        kin = model.forward(rng.uniform(-1.0, 1.0, model.n))
        with kernels.using(False):
            want = capsules.world(kin)
        with kernels.using(True):
            got = capsules.world(kin)
        close_to_rounding(got[0], want[0])
        close_to_rounding(got[1], want[1])


@pytest.mark.parametrize("seed", range(3))
def test_box_rows(seed):
    """Capsules vs boxes row by row, per-row boxes and one box for all: apart, axes through the box, ends on its
    surface, segments along a box axis (a coordinate that does not move) and of zero length."""
    rng = np.random.default_rng(seed)
    m = 96
    p0, p1 = rng.normal(scale=0.5, size=(m, 3)), rng.normal(scale=0.5, size=(m, 3))
    center, half = rng.normal(scale=0.2, size=(m, 3)), rng.uniform(0.05, 0.3, size=(m, 3))
    rotation = np.array([np.linalg.qr(rng.normal(size=(3, 3)))[0] for _ in range(m)])
    rotation *= np.linalg.det(rotation)[:, None, None]  # proper rotations
    for k in range(0, m, 6):
        p1[k] = p0[k]  # zero length
        p0[k + 1] = p1[k + 1] + 0.3 * rotation[k + 1][:, 0]  # along the box's x axis
        p0[k + 2] = center[k + 2] + rotation[k + 2] @ (half[k + 2] * [1.0, 0.5, -0.2])  # an end on a face
        p1[k + 3] = center[k + 3]  # into the box
    radii = rng.uniform(0.0, 0.1, size=m)
    for box in ((center, rotation, half), tuple(np.broadcast_to(x[0], x.shape) for x in (center, rotation, half))):
        got = {}
        for compiled in (False, True):
            with kernels.using(compiled):
                got[compiled] = box_rows(p0, p1, radii, *box)
        assert np.any(got[False].distance + radii < 0.0) and np.any(got[False].distance > 0.0)
        for a, b in zip(got[True], got[False], strict=True):
            close_to_rounding(a, b)
