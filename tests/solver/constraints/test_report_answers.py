"""What a result reports of its constraints (unmet, residuals, closest rows, contact wrenches) equals the plain
definitions, computed here from each constraint's error and evaluated rows: the shortcuts that make a frame's report
cheap (a clearance's least row kept per state, Python floats per near row, one bound for all rows, per-support
slices) answer as the definitions do, on poses with rows unmet, met and NaN."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from helpers import close_to_rounding

import solver
from solver import kernels
from solver.body.contacts import ContactSet, Support, build_contacts
from solver.body.spatial import cross
from solver.constraints import BalanceConstraint, FrameGroup
from solver.constraints.carried_obstacles import CarriedObstacles
from solver.constraints.clearance import ClearanceRows
from solver.iteration.result import Result
from solver.problem.problem import Target

SCENARIOS = Path(__file__).resolve().parents[3] / "presets" / "scenarios"


@pytest.fixture(scope="module")
def problem():
    """The box lift with every kind of row (frames, balance, floor, obstacles, self, carried box, box vs obstacles);
    the hands' targets relaxed otherwise: x, z, rz (components apart) and a general operator (no selection)."""
    lift = solver.load_scenario(SCENARIOS / "box_lift_motion.toml").problem
    hand_r, hand_l, *feet = lift.all_targets
    operator = np.array([[1.0, 0.5, 0.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0, 0.3, 0.0, 1.0]])
    targets = [Target(hand_r.tcp, hand_r.position, hand_r.rotation, lock=("x", "z", "rz")),
               Target(hand_l.tcp, hand_l.position, hand_l.rotation, operator=operator), *feet]  # fmt: skip
    return lift, lift.with_targets(targets)


def poses(problem) -> list[np.ndarray]:
    """x of: the start (hands far from their targets), a crouch through the floor, the table and the box (many rows
    unmet), and the start with the pelvis height NaN."""
    model = problem.model
    start = problem.to_x(problem.start())
    low = start.copy()
    rng = np.random.default_rng(5)
    low[: model.n] += rng.uniform(-0.4, 0.4, model.n)
    low[2] = -0.8  # root lowered: legs, hips and the box through the floor
    for side in ("r", "l"):
        low[model.joint_index(f"knee_{side}_flexion")] = np.radians(110.0)
        low[model.joint_index(f"shoulder_{side}_flexion")] = np.radians(80.0)
    nan = start.copy()
    nan[2] = np.nan
    return [start, low, nan]


def met_rows(c, state) -> np.ndarray:
    return np.abs(c.error(state)) <= c.tolerance() * (1 + 1e-9)


def unmet(c, state) -> list[str]:
    met = met_rows(c, state)
    if isinstance(c, FrameGroup):
        return [m.name for m, rows in zip(c.members, c.member_rows, strict=True) if not met[rows].all()]
    if isinstance(c, ClearanceRows):
        return sorted({c._pairs[i] for i in np.flatnonzero(~met)})
    return [] if met.all() else [c.name]


def residuals(c, state) -> dict[str, float]:
    if isinstance(c, FrameGroup):
        out = {}
        for m, err in zip(c.members, c.evaluate(state).full, strict=True):
            if not m._is_selection:
                relaxed = m.operator @ err
                out[m.name] = math.sqrt(float(relaxed @ relaxed))
                continue
            locked = m.operator.sum(axis=0) > 0
            for part, mask in (("position", locked * [1, 1, 1, 0, 0, 0]), ("rotation", locked * [0, 0, 0, 1, 1, 1])):
                if mask.any():
                    kept = err[mask.astype(bool)]
                    out[f"{m.name}.{part}"] = math.sqrt(float(kept @ kept))
        return out
    if isinstance(c, BalanceConstraint):
        err = c.error(state)
        return {"balance.force": float(np.linalg.norm(err[:3])), "balance.moment": float(np.linalg.norm(err[3:]))}
    return {f"{c.name}.shortfall": abs(float(np.min(c.error(state), initial=0.0)))}


def closest(c, state) -> list[tuple]:
    """(part, other, distance, clearance, point, other point) of the rows within the margin, nearest first (for the
    carried box, the nearest row per obstacle)."""
    distance, points, normals, capsule = c._evaluate(state)
    near = np.flatnonzero(distance - c.floor < c.margin)
    rows = near[np.argsort(distance[near], kind="stable")]
    if isinstance(c, CarriedObstacles):  # its points: on the box, on the obstacle (the cached evaluation's 2nd, 4th)
        first = {c._others[i]: i for i in rows[::-1]}
        rows = [i for i in rows if first[c._others[i]] == i]
        return [(c._parts[i], c._others[i], distance[i], c.floor[i], points[i], capsule[i]) for i in rows]
    surface = points[rows] - c.capsules.radius[capsule[rows]][:, None] * normals[rows]
    other = surface - distance[rows][:, None] * normals[rows]
    return [(c._parts[i], c._others[i], distance[i], c.floor[i], p, q)
            for i, p, q in zip(rows, surface, other, strict=True)]  # fmt: skip


def same_numbers(a: dict[str, float], b: dict[str, float]) -> None:
    assert list(a) == list(b)
    close_to_rounding([a[k] for k in a], [b[k] for k in a])


@pytest.mark.parametrize("relaxed", [False, True], ids=["lift", "relaxed hands"])
def test_unmet_residuals_and_closest_are_the_definitions(problem, relaxed):
    problem = problem[relaxed]
    seen = set()
    for x in poses(problem):
        report, plain = problem.state_of_x(x.copy()), problem.state_of_x(x.copy())
        for c in problem.constraints:
            got = c.unmet(report)
            assert got == unmet(c, plain), (c.name, got)
            seen |= {(c.name, "unmet")} if got else set()
            same_numbers(c.residuals(report), residuals(c, plain))
            assert c.met_rows(report).tolist() == met_rows(c, plain).tolist()
            if isinstance(c, ClearanceRows) and np.isfinite(x).all():
                got = [(n.part, n.other, n.distance, n.clearance, n.point, n.other_point) for n in c.closest(report)]
                want = closest(c, plain)
                assert [g[:2] for g in got] == [w[:2] for w in want]
                for g, w in zip(got, want, strict=True):
                    close_to_rounding(np.hstack(g[2:]), np.hstack(w[2:]))
                seen |= {(c.name, "closest")} if got else set()
        assert problem.unmet(report) == [name for c in problem.constraints for name in unmet(c, plain)]
    kinds = {"frames", "balance", "floor", "obstacles", "carried", "carried_obstacles"}
    assert {(k, "unmet") for k in kinds} <= seen  # every kind answered with rows unmet too
    assert {(k, "closest") for k in kinds - {"frames", "balance"}} <= seen


def test_rows_at_their_tolerance(problem):
    """Rows just within and just past TOLERANCE below their clearance, -0.0 and NaN: each clearance answers as the
    definitions (its evaluation set in the state's cache, as an evaluation leaves it)."""
    lift = problem[0]
    for c in (c for c in lift.constraints if isinstance(c, ClearanceRows)):
        x = lift.to_x(lift.start())
        report, plain = lift.state_of_x(x.copy()), lift.state_of_x(x.copy())
        distance = c.floor + 1.0
        distance[:6] = c.floor[:6] + [-1e-3, -1e-3 * (1 + 2e-9), -0.6e-3, -0.0, 0.0, np.nan]
        rows = np.zeros((c.rows, 3)), np.tile([0.0, 0.0, 1.0], (c.rows, 1)), np.zeros(c.rows, dtype=int)
        report.cache[c] = plain.cache[c] = (distance, *rows)
        assert c.met_rows(report).tolist()[:6] == met_rows(c, plain).tolist()[:6] == [True, False, True, True, True,
                                                                                        False]  # fmt: skip
        assert c.unmet(report) == unmet(c, plain)
        same_numbers(c.residuals(report), residuals(c, plain))
        got = [(n.part, n.other, n.distance) for n in c.closest(report)]
        assert got == [w[:3] for w in closest(c, plain)]


def wrenches(contacts: ContactSet, kin, w) -> list[dict]:
    points, forces = contacts.corner_points(kin), contacts.corner_forces(w)
    out = []
    for s, support in enumerate(contacts.supports):
        sel = contacts.corner_support == s
        pts, fs = points[sel], forces[sel]
        pressure = fs @ support.normal_frame[:, 2]
        cop = (pressure @ pts) / pressure.sum() if pressure.sum() > 1e-9 else pts.mean(axis=0)
        out.append(dict(tcp=support.tcp.name, point=cop, force=fs.sum(axis=0),
                        moment=cross(pts - cop, fs).sum(axis=0)))  # fmt: skip
    return out


def interleaved(contacts: ContactSet) -> ContactSet:
    """The same corners in another order: each support's corners apart (every other one)."""
    order = np.r_[np.arange(0, len(contacts.corner_link), 2), np.arange(1, len(contacts.corner_link), 2)]
    var_order = np.argsort(order)[contacts.var_corner]  # each variable's corner, renumbered
    return ContactSet(contacts.supports, contacts.corner_link[order], contacts.corner_local[order],
                      contacts.corner_support[order], var_order, contacts.var_direction,
                      contacts.corner_of_var[order])  # fmt: skip


def test_wrenches_are_the_definition(problem):
    """Per support: the lift's (four corners each), a sole and a point (corners unequal), corners apart (not
    adjacent), and no load (the COP at the corners' mean)."""
    lift = problem[0]
    model = lift.model
    frame = np.eye(3)
    mixed = build_contacts(model, [Support(model.tcp("foot_r"), frame, 0.6),
                                   Support(model.tcp("hand_r"), frame, 0.4, sole=np.zeros((1, 2)))])  # fmt: skip
    rng = np.random.default_rng(3)
    for contacts in (lift.contacts, mixed, interleaved(lift.contacts)):
        x = lift.to_x(lift.start())
        kin = model.forward(x[: model.n] + rng.uniform(-0.2, 0.2, model.n))
        for w in (rng.uniform(0.0, 50.0, contacts.n_vars), np.zeros(contacts.n_vars)):
            got, want = contacts.wrenches(kin, w), wrenches(contacts, kin, w)
            assert [list(g) for g in got] == [list(v) for v in want]
            for g, v in zip(got, want, strict=True):
                assert g["tcp"] == v["tcp"]
                close_to_rounding(np.hstack([g["point"], g["force"], g["moment"]]),
                                  np.hstack([v["point"], v["force"], v["moment"]]))  # fmt: skip


@pytest.mark.parametrize("relaxed", [False, True], ids=["lift", "relaxed hands"])
def test_one_report_pass_gives_each_constraints_answers(problem, relaxed):
    """Problem.report (unmet, residuals, closest in one pass, kept per constraint) equals each constraint asked on a
    state of its own, and asking again (the kept answers) gives the same."""
    problem = problem[relaxed]
    for x in poses(problem)[:2]:
        report, plain = problem.state_of_x(x.copy()), problem.state_of_x(x.copy())
        got = problem.report(report)
        near = [n for c in problem.constraints if isinstance(c, ClearanceRows) for n in c.closest(plain)]
        near.sort(key=lambda n: n.distance)
        assert got.unmet == [name for c in problem.constraints for name in c.unmet(plain)]
        assert got.residuals == {k: v for c in problem.constraints for k, v in c.residuals(plain).items()}
        assert [(n.part, n.other, n.distance) for n in got.closest] == [(n.part, n.other, n.distance) for n in near]
        for g, w in zip(got.closest, near, strict=True):
            assert np.array_equal(g.point, w.point) and np.array_equal(g.other_point, w.other_point)
        again = problem.report(report)
        assert again == got and again.closest is not got.closest  # the kept answers, in lists of the caller's own
        assert (problem.unmet(report), problem.residuals(report), problem.closest(report)) == tuple(got)


@pytest.mark.parametrize("compiled", [False, True], ids=["numpy", "kernels"])
def test_a_results_wrenches_from_the_statics_are_the_contacts_own(problem, compiled):
    """A result's contact wrenches take the corners' points and forces of the state's statics when the solve computed
    them (the balance's): the same as the contacts compute from the joint values and weights alone, with the statics'
    kernel and without, on varied poses and weights."""
    lift = problem[0]
    model = lift.model
    rng = np.random.default_rng(11)
    start = lift.to_x(lift.start())
    with kernels.using(compiled):
        for _ in range(4):
            x = start.copy()
            x[: model.n] += rng.uniform(-0.2, 0.2, model.n)
            x[model.n :] = rng.uniform(0.0, 60.0, lift.contacts.n_vars)
            state = lift.state_of_x(x)
            got = Result.from_state(lift, state, 0, 0.0).contacts
            assert "statics" in state.__dict__  # computed by the balance's report, before the wrenches
            want = lift.contacts.wrenches(model.forward(x[: model.n]), x[model.n :])
            assert [g["tcp"] for g in got] == [v["tcp"] for v in want]
            for g, v in zip(got, want, strict=True):
                close_to_rounding(np.hstack([g["point"], g["force"], g["moment"]]),
                                  np.hstack([v["point"], v["force"], v["moment"]]))  # fmt: skip
