"""The box kernels of issue 37's speed work equal the NumPy path's to rounding: capsules against several boxes at once
(box obstacles, their flat rows), the body against the carried box, and the carried box's Jacobian rows; random
inputs with capsules touching, entering, parallel to and along a box's faces, of zero length, and thin boxes."""

from __future__ import annotations

import numpy as np
import pytest
from helpers import close_to_rounding

from solver import kernels
from solver.collision.carried import Carried, box_motion_jacobian, box_motion_terms, carried_frame
from solver.collision.kinds.box import Box, BoxGroup, box_set, boxes_distance
from solver.collision.kinds.plane import HalfSpace, halfspace_distance
from solver.problem.problem import Problem, ProblemSpec, Target

pytest.importorskip("numba")


def _boxes(rng: np.random.Generator, m: int) -> list[Box]:
    """m random boxes, every third thin (1 mm) along one axis."""
    out = []
    for i in range(m):
        rotation = np.linalg.qr(rng.normal(size=(3, 3)))[0]
        rotation *= np.linalg.det(rotation)
        size = rng.uniform(0.05, 0.5, 3)
        if i % 3 == 0:
            size[i % 3] = 1e-3
        out.append(Box(rng.normal(scale=0.3, size=3), size, rotation, name=f"box {i}"))
    return out


def _capsules(rng: np.random.Generator, k: int, boxes: list[Box]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """k capsules: random, zero-length, along a box's axis, an end on a face (touching), into a box, parallel to a
    face just outside it."""
    p0, p1 = rng.normal(scale=0.4, size=(k, 3)), rng.normal(scale=0.4, size=(k, 3))
    for c in range(k):
        box = boxes[c % len(boxes)]
        kind = c % 6
        if kind == 1:
            p1[c] = p0[c]
        elif kind == 2:
            p1[c] = p0[c] + 0.3 * box.rotation[:, 0]
        elif kind == 3:
            p0[c] = box.center + box.rotation @ (box.half * [1.0, 0.5, -0.2])
        elif kind == 4:
            p1[c] = box.center
        elif kind == 5:
            p0[c] = box.center + box.rotation @ (box.half * [0.3, 0.2, 1.0]) + 0.01 * box.rotation[:, 2]
            p1[c] = p0[c] + 0.2 * box.rotation[:, 1]
    return p0, p1, rng.uniform(0.0, 0.08, k)


@pytest.mark.parametrize("seed", range(4))
def test_boxes_distance_and_flat_rows(seed):
    """Every field of every box's Proximity; the flat rows as the clearance's NumPy path builds them (far where not
    finite); margins from none to unbounded."""
    rng = np.random.default_rng(seed)
    boxes = _boxes(rng, 7)
    p0, p1, radii = _capsules(rng, 60, boxes)
    margins = np.array([0.0, 0.02, 0.1, 0.5, np.inf, 0.05, 1e-3])
    got = {}
    for compiled in (False, True):
        with kernels.using(compiled):
            got[compiled] = boxes_distance(p0, p1, radii, box_set(boxes), margins)
    distances = np.concatenate([g.distance for g in got[False]])
    assert np.any(distances + np.tile(radii, 7) < 0.0) and np.any(np.isinf(distances))  # inside and out of reach
    for mine, theirs in zip(got[True], got[False], strict=True):
        np.testing.assert_array_equal(np.isinf(mine.distance), np.isinf(theirs.distance))
        for a, b in zip(mine, theirs, strict=True):
            close_to_rounding(np.where(np.isinf(a), 0.0, a), np.where(np.isinf(b), 0.0, b))
    far = margins + 1.0
    with kernels.using(True):
        flat = BoxGroup(boxes, ()).flat_rows(p0, p1, radii, margins, far)
    kept = [np.where(np.isfinite(g.distance), g.distance, f) for g, f in zip(got[False], far, strict=True)]
    want = [np.concatenate(kept), np.concatenate([g.point for g in got[False]]),
            np.concatenate([g.normal for g in got[False]])]  # fmt: skip
    for a, b in zip(flat, want, strict=True):
        close_to_rounding(a, b)


def _held(model) -> Problem:
    """The hands holding a box in front of the belly, feet on the floor."""
    zero = model.forward(model.zero_pose())
    feet = [Target(f, zero.tcp_frame(model.tcp(f))[1], support=True) for f in ("foot_r", "foot_l")]
    sides = (("hand_r", -1), ("hand_l", 1))
    hands = [Target(h, np.array([0.2 * s, -0.3, 1.0]), lock=("x", "y", "z")) for h, s in sides]
    return Problem(model, ProblemSpec(feet + hands, carried=Carried(np.array([0.4, 0.5, 0.3]), ("hand_r", "hand_l"))))


@pytest.mark.parametrize("size", [0.05, 0.4, 1.2])
def test_carried_rows_and_jacobian(model, size):
    """The body against the carried box (values, witnesses, normals; the Jacobian of every row) at random poses,
    some with parts deep inside the box; and the box's motion terms for random points and normals, the hands one
    above the other among them (the frame's other reference)."""
    problem = _held(model)
    c = problem.carried_constraint
    rng = np.random.default_rng(int(size * 100))
    inside = 0
    for _ in range(8):
        x = problem.start()
        x[: model.n] += rng.uniform(-size, size, model.n)
        x = problem.x_bounds.clip(x)
        seen = {}
        for compiled in (False, True):
            with kernels.using(compiled):
                state = problem.state_of_x(x)
                seen[compiled] = (*c._distances(state), c._jacobian_of(state, np.arange(c.rows)))
        for a, b in zip(seen[True], seen[False], strict=True):
            close_to_rounding(a, b)
        inside += int(np.sum(seen[False][0] < 0.0))
        on_box, normal = rng.normal(scale=0.3, size=(9, 3)), rng.normal(size=(9, 3))
        for compiled in (False, True):
            with kernels.using(compiled):
                state = problem.state_of_x(x)
                if compiled:
                    got = box_motion_jacobian(state, c.tcps, on_box, normal, problem.n_x)
                else:
                    links, where, along = box_motion_terms(state, c.tcps, on_box, normal)
                    moved = state.kin.jacobian_rows(where, along, np.zeros_like(along),
                                                    model.descendant[:, links].T.astype(float))  # fmt: skip
                    want = np.zeros((9, problem.n_x))
                    want[:, : model.n] = moved[:9] + moved[9:]
        close_to_rounding(got, want)
    assert inside or size < 0.4


def test_carried_jacobian_with_the_hands_one_above_the_other(model):
    """A box held between hands one above the other (its x axis near vertical: world y is the reference)."""
    problem = _held(model)
    c = problem.carried_constraint
    rng = np.random.default_rng(5)
    state = problem.state_of_x(problem.start())
    held = np.array([state.kin.tcp_frame(t)[1] for t in c.tcps])
    held[1] = held[0] + [0.001, 0.0, 0.4]
    state.cache[("carried box", *(t.name for t in c.tcps))] = (held, *carried_frame(held[0], held[1]))
    on_box, normal = rng.normal(scale=0.3, size=(6, 3)), rng.normal(size=(6, 3))
    with kernels.using(True):
        got = box_motion_jacobian(state, c.tcps, on_box, normal, problem.n_x)
    with kernels.using(False):
        links, where, along = box_motion_terms(state, c.tcps, on_box, normal)
        moved = state.kin.jacobian_rows(where, along, np.zeros_like(along), model.descendant[:, links].T.astype(float))
    close_to_rounding(got[:, : model.n], moved[:6] + moved[6:])


def test_halfspace_distance():
    """Capsules and points (a box's corners: p1 is p0) vs a tilted half-space: ends level (a tie: p0), one radius
    for all and one each, a capsule lying in the plane."""
    rng = np.random.default_rng(11)
    plane = HalfSpace(np.array([0.1, -0.2, 0.3]), np.array([0.2, -0.1, 1.0]))
    p0, p1 = rng.normal(scale=0.5, size=(40, 3)), rng.normal(scale=0.5, size=(40, 3))
    side = np.cross(plane.normal, [1.0, 0.0, 0.0])
    p1[::5] = p0[::5] + 0.3 * side  # level ends
    p0[1::5] = plane.point + 0.2 * side  # in the plane
    p1[1::5] = plane.point - 0.1 * side
    for ends, radii in (((p0, p1), rng.uniform(0.0, 0.1, 40)), ((p0, p0), 0.0), ((p0, p1), 0.05)):
        got = {}
        for compiled in (False, True):
            with kernels.using(compiled):
                got[compiled] = halfspace_distance(*ends, radii, plane)
        np.testing.assert_array_equal(got[True].t, got[False].t)
        for a, b in zip(got[True], got[False], strict=True):
            close_to_rounding(a, b)
