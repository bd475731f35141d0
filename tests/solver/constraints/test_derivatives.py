"""Every Jacobian and gradient against central finite differences, at random and near-singular poses."""

from __future__ import annotations

import numpy as np
import pytest
from helpers import finite_difference, random_tree

from solver.body.spatial import exp_so3, log_so3
from solver.comfort import ComfortWeights
from solver.constraints import FrameConstraint, Inequality, lock_operator
from solver.problem.problem import ExternalLoad, Loop, Problem, ProblemSpec, Target


def random_pose(model, rng, spread=1.0):
    theta = rng.uniform(-spread, spread, model.n)
    return np.clip(theta, model.lower + 0.05, model.upper - 0.05)


def make_problem(model, rng, balance=True):
    targets = [
        Target("t0", rng.normal(size=3), exp_so3(rng.normal(size=3)), support=True, friction=0.5),
        Target("t1", rng.normal(size=3), exp_so3(rng.normal(size=3)), lock=("z", "rx", "ry"), support=True),
        Target("t2", rng.normal(size=3), exp_so3(rng.normal(size=3)), lock=("x", "y", "z", "rx", "ry")),
    ]
    loops = [Loop("t3", "t2", rng.normal(scale=0.2, size=3), exp_so3(rng.normal(size=3)), lock=tuple("xyz") + ("rz",))]
    loads = [ExternalLoad("t3", np.array([3.0, -2.0, -40.0]))]
    weights = ComfortWeights(1.0, 1.0, 0.3)
    return Problem(model, ProblemSpec(targets, loops, loads, balance=balance, comfort_weights=weights))


def state_x(problem, rng):
    theta = random_pose(problem.model, rng)
    w = rng.uniform(0.0, 50.0, problem.contacts.n_vars)
    return np.concatenate([theta, w])


def random_case(seed, stream, balance=True):
    """(model, problem, x, rng): a random tree, its problem and a random state, from random stream ``stream + seed``."""
    model = random_tree(seed)
    rng = np.random.default_rng(stream + seed)
    problem = make_problem(model, rng, balance=balance)
    return model, problem, state_x(problem, rng), rng


@pytest.mark.parametrize("seed", range(4))
def test_tcp_frame_jacobian(seed):
    model = random_tree(seed)
    rng = np.random.default_rng(seed)
    theta = random_pose(model, rng)
    for tcp in model.tcps.values():
        kin = model.forward(theta)
        r0, o0 = kin.tcp_frame(tcp)
        jac = kin.frame_jacobian(tcp.link, o0)
        lin = finite_difference(lambda t, tcp=tcp: model.forward(t).tcp_frame(tcp)[1], theta)
        ang = finite_difference(lambda t, tcp=tcp, r0=r0: log_so3(model.forward(t).tcp_frame(tcp)[0] @ r0.T), theta)
        np.testing.assert_allclose(jac[:3], lin, atol=1e-6)
        np.testing.assert_allclose(jac[3:], ang, atol=1e-6)


@pytest.mark.parametrize("seed", range(4))
def test_constraint_jacobians(seed):
    """Every constraint's Jacobian is d error / dx; a one-sided row met with room to spare (error zero) may still
    give the step its dg/dx (a clearance watched near contact): those rows are checked against g itself."""
    _, problem, x, _ = random_case(seed, 100)
    for c in problem.constraints:
        state = problem.state(x)
        analytic = c.jacobian(state)
        numeric = finite_difference(lambda xx, c=c: c.error(problem.state(xx)), x)
        if isinstance(c, Inequality):
            watched = (c.slack(state) > 0.0) & analytic.any(axis=1)
            numeric[watched] = finite_difference(lambda xx, c=c: c.value(problem.state(xx)), x)[watched]
        scale = max(1.0, np.abs(numeric).max())
        np.testing.assert_allclose(analytic, numeric, atol=2e-6 * scale, err_msg=c.name)


def test_rotation_error_jacobian_large_error():
    """Exact log Jacobian: rotation errors near 170 degrees, not only small ones."""
    model = random_tree(5)
    rng = np.random.default_rng(5)
    theta = random_pose(model, rng)
    tcp = model.tcps["t2"]
    r, o = model.forward(theta).tcp_frame(tcp)
    axis = rng.normal(size=3)
    target_r = r @ exp_so3(axis / np.linalg.norm(axis) * np.deg2rad(170))
    c = FrameConstraint("t2", tcp, target_r, o + 0.3, lock_operator(("x", "y", "z", "rx", "ry", "rz")), model.n)
    problem = Problem(model, ProblemSpec(balance=False))
    err = c.error(problem.state(theta))
    assert np.linalg.norm(err[3:]) > np.deg2rad(160)
    numeric = finite_difference(lambda t: c.error(problem.state(t)), theta)
    np.testing.assert_allclose(c.jacobian(problem.state(theta)), numeric, atol=1e-5)


@pytest.mark.parametrize("seed", range(4))
def test_axis_load_jacobian(seed):
    model, problem, x, rng = random_case(seed, 200)
    n = model.n
    d_theta, d_w = problem.state(x).statics.axis_load_jacobian()
    numeric = finite_difference(lambda xx: problem.state(xx).statics.axis_loads(), x)
    interior = ~model.prismatic
    np.testing.assert_allclose(d_theta[interior], numeric[interior, :n], atol=1e-5)
    np.testing.assert_allclose(d_w[interior], numeric[interior, n:], atol=1e-5)
    # the solver's contractions (no dense n x n block) equal the same products of the dense Jacobian
    jac = np.hstack([d_theta, d_w])
    coef, weight = rng.normal(size=n), rng.random(n)
    lin, sq = problem.state(x).statics.axis_load_contractions(coef, weight)
    np.testing.assert_allclose(lin, coef @ jac, rtol=1e-10, atol=1e-10 * np.abs(jac).max())
    np.testing.assert_allclose(sq, weight @ (jac * jac), rtol=1e-10, atol=1e-10 * (jac * jac).max())


@pytest.mark.parametrize("seed", range(4))
@pytest.mark.parametrize("balance", [True, False])
def test_comfort_gradient(seed, balance):
    _, problem, x, _ = random_case(seed, 300, balance)
    grad = problem.comfort.gradient(problem.state(x))
    numeric = finite_difference(lambda xx: [problem.comfort.value(problem.state(xx))], x)[0]
    np.testing.assert_allclose(grad, numeric, rtol=1e-5, atol=1e-6)


def test_near_singular_pose_jacobians():
    """At a stretched-out (singular) configuration the analytic Jacobians still match."""
    model = random_tree(7)
    rng = np.random.default_rng(7)
    problem = make_problem(model, rng)
    x = np.concatenate([np.zeros(model.n), np.full(problem.contacts.n_vars, 10.0)])
    for c in problem.constraints:
        numeric = finite_difference(lambda xx, c=c: c.error(problem.state(xx)), x)
        np.testing.assert_allclose(c.jacobian(problem.state(x)), numeric, atol=2e-6 * max(1, np.abs(numeric).max()))


@pytest.mark.parametrize("seed", range(3))
def test_axis_loads_and_balance_totals_by_brute_force(seed):
    """Every point force summed joint by joint: moment about the joint on its axis (force along it if prismatic)."""
    model, problem, x, _ = random_case(seed, 300)
    state = problem.state(x)
    kin, statics = state.kin, state.statics
    contacts = problem.contacts
    points = [(k, kin.com[k], model.mass[k] * np.array([0.0, 0.0, -9.81])) for k in range(model.n)]
    corner_force = contacts.corner_of_var @ (state.w[:, None] * contacts.var_direction)
    corners = contacts.corner_points(kin)
    points += [(contacts.corner_link[c], corners[c], corner_force[c]) for c in range(len(corners))]
    for ld in problem.loads:
        points.append((ld.tcp.link, kin.tcp_frame(ld.tcp)[1], ld.force))
    expected = np.zeros(model.n)
    for j in range(model.n):
        a, p = kin.axis[j], kin.position[j]
        on = [(q, f) for link, q, f in points if model.descendant[j, link]]
        if model.prismatic[j]:
            expected[j] = sum(a @ f for _, f in on)
        else:
            expected[j] = sum(a @ np.cross(q - p, f) for q, f in on)
    np.testing.assert_allclose(statics.axis_loads(), expected, atol=1e-9 * max(1.0, np.abs(expected).max()))
    total_force = sum(f for _, _, f in points)
    total_moment = sum(np.cross(q, f) for _, q, f in points)
    np.testing.assert_allclose(statics.balance_error(), np.concatenate([total_force, total_moment]), atol=1e-9)


@pytest.mark.parametrize("seed", range(2))
def test_live_rows_hold_every_nonzero_row(seed):
    """The step's rows (each constraint's jacobian_rows, stacked by live_jacobian) are the Jacobian's nonzero rows:
    the rows left out are zero in the full Jacobian, the rows kept equal it."""
    from solver import load_scenario
    from solver.io.scenario.bodies import PRESETS_DIR

    _, problem, x, _ = random_case(seed, 200)
    furnished = load_scenario(PRESETS_DIR / "scenarios" / "box_lift_motion.toml")
    at_shelf = furnished.problem_at(furnished.frames[0])
    for pb, xx in ((problem, x), (at_shelf, at_shelf.start(furnished.start))):
        state = pb.state(xx)
        for c in pb.constraints:
            rows, part = c.jacobian_rows(state)
            full = c.jacobian(state)
            np.testing.assert_array_equal(part, full[rows], err_msg=c.name)
            assert not np.delete(full, rows, axis=0).any(), c.name
        live, jac = pb.live_jacobian(state)
        dense = pb.scaled_jacobian(state)
        np.testing.assert_array_equal(dense[live], jac)
        assert not np.delete(dense, live, axis=0).any()
        assert len(live) < pb.n_rows or pb is problem  # the furnished scene leaves most clearance rows out


def carried_cases():
    """(problem, x) pairs with a carried box: the box lift's frames 1 and 30, their start pose bent a little and a
    lot at random (body parts through the box and just outside it; the start pose itself is a kink of the distance,
    its thighs square to the box's faces), and random trees holding a big box between t2 and t3."""
    from solver import load_scenario
    from solver.collision.carried import Carried
    from solver.io.scenario.bodies import PRESETS_DIR

    lift = load_scenario(PRESETS_DIR / "scenarios" / "box_lift_motion.toml")
    rng = np.random.default_rng(7)
    for frame in (1, 30):
        problem = lift.problem_at(frame)
        x = problem.start(lift.start)
        for spread in (0.05, 0.4, 0.4, 0.4):
            bent = x.copy()
            bent[: problem.model.n] += rng.uniform(-spread, spread, problem.model.n)
            yield problem, bent
    for seed in range(3):
        _, problem, x, _ = random_case(seed, 300)
        box = Carried(np.array([0.6, 0.5, 0.4]), ("t2", "t3"), "crate")
        spec = ProblemSpec(problem.all_targets, problem.loops, problem.load_specs, carried=box)
        yield Problem(problem.model, spec), x


def clearance_rows_against_differences(c, problem, x, plateau: bool = False, counted=slice(None)) -> np.ndarray:
    """Check one-sided clearance rows ``c`` at ``x`` against central differences: dg/dx of every row against g, and
    the step's Jacobian against the error, watched rows against g. Returns how many rows (of ``counted``) were
    inside, within the watch band, farther. ``plateau``: leave out rows reading exactly 0 (a segment through a closed
    mesh with none of its depth samples inside reads 0 until one is: flat, so differences see no slope there)."""
    state = problem.state(x)
    value = c.value(state)
    keep = value != 0.0 if plateau else np.ones(len(value), dtype=bool)
    numeric = finite_difference(lambda xx: c.value(problem.state(xx)), x, 1e-7)
    scale = max(1.0, np.abs(numeric).max())
    np.testing.assert_allclose(c.value_jacobian(state)[keep], numeric[keep], atol=1e-6 * scale)
    analytic = c.jacobian(state)
    error = finite_difference(lambda xx: c.error(problem.state(xx)), x, 1e-7)
    watched = (c.slack(state) > 0.0) & analytic.any(axis=1)
    error[watched] = numeric[watched]
    np.testing.assert_allclose(analytic[keep], error[keep], atol=1e-6 * scale)
    value = value[counted][keep[counted]]
    return np.array([(value < 0).sum(), ((value >= 0) & (value < c.watch)).sum(), (value >= c.watch).sum()])


def test_carried_box_jacobian():
    """The carried box's rows (the box moving with both TCPs) against central differences: dg/dx of every row
    against g, and the step's Jacobian against the error, watched rows against g; inside, near and clear rows."""
    seen = np.zeros(3, dtype=int)  # rows inside the box, within the watch band, farther
    for problem, x in carried_cases():
        seen += clearance_rows_against_differences(problem.carried_constraint, problem, x)
    assert (seen >= 3).all(), seen


def pyramid(tip: np.ndarray, axis: np.ndarray, name: str):
    """A closed square pyramid (its edges 30 cm long about ``axis``, a rotation whose z axis points from the tip
    into the pyramid), tip at ``tip`` (m)."""
    from solver.collision import Mesh

    base = [tip + axis @ [0.1 * x, 0.1 * y, 0.28] for x, y in ((-1, -1), (1, -1), (1, 1), (-1, 1))]
    faces = [[0, 4, 1], [1, 4, 2], [2, 4, 3], [3, 4, 0], [0, 1, 2], [0, 2, 3]]
    return Mesh(np.array([*base, tip]), np.array(faces), name=name)


def carried_obstacle_cases():
    """(problem, x) pairs: random trees holding a box between t2 and t3 among a box, a sphere, a capsule and a
    closed mesh and a tilted half-space placed at random around where the box is, the floor, and a pyramid whose
    tip is a little inside or outside the middle of the box's bottom face (its axis tilted at random)."""
    from solver.collision import Box, Capsule, HalfSpace, Mesh, Sphere
    from solver.collision.carried import Carried, carried_frame
    from solver.collision.generate import box_mesh

    for seed, depth in zip(range(4), (0.01, -0.004, 0.003, -0.007), strict=True):
        _, problem, x, rng = random_case(seed, 400)
        size = np.array([0.5, 0.4, 0.3])
        kin = problem.state(x).kin
        centre, rotation = carried_frame(*(kin.tcp_frame(problem.model.tcp(t))[1] for t in ("t2", "t3")))
        near = [centre + rng.uniform(-0.45, 0.45, 3) for _ in range(4)]
        turn = exp_so3(rng.normal(size=3))
        obstacles = [Box(near[0], np.array([0.3, 0.2, 0.25]), turn, name="b"), Sphere(near[1], 0.15, name="s"),
                     Capsule(near[2], near[2] + rng.normal(size=3) * 0.2, 0.08, name="c"),
                     Mesh(*box_mesh(near[3], np.array([0.3, 0.3, 0.2]), 2, turn), name="m"),
                     HalfSpace(centre - rng.uniform(0.05, 0.25) * turn[:, 2], turn[:, 2], name="h")]  # fmt: skip
        down = rotation @ np.diag([1.0, -1.0, -1.0]) @ exp_so3(rng.normal(scale=0.3, size=3))  # z: the box's -z, tilted
        tip = centre - (size[2] / 2 - depth) * rotation[:, 2]
        obstacles.append(pyramid(tip, down, "p"))
        spec = ProblemSpec(problem.all_targets, problem.loops, problem.load_specs, obstacles=obstacles,
                           carried=Carried(size, ("t2", "t3"), "crate"))
        yield Problem(problem.model, spec), x


def test_carried_box_obstacle_jacobian():
    """The carried box's rows against the obstacles and the floor (its edges against each obstacle, the obstacles'
    edges against it, its corners above the floor) against central differences; inside, near and clear rows, also
    among the meshes' own edges' rows alone (a box of triangles and a pyramid poking its tip into the box)."""
    from solver.collision import Mesh
    from solver.constraints.carried_obstacles import CarriedObstacles

    edge_rows = Mesh.nearest_edges

    seen, edges = np.zeros(3, dtype=int), np.zeros(3, dtype=int)
    kinds = set()
    for problem, x in carried_obstacle_cases():
        c = problem.carried_obstacle_constraint
        seen += clearance_rows_against_differences(c, problem, x, plateau=True)
        kinds |= {pair.other for pair in c.closest(problem.state(x))}
        meshes = [ob for ob in problem.obstacles if ob.name in ("m", "p")]
        alone = CarriedObstacles(problem.model, problem.carried, meshes, problem.n_x)  # 12 + edge_rows rows each
        assert alone.rows == 2 * (12 + edge_rows)
        reverse = np.r_[12 : 12 + edge_rows, 24 + edge_rows : 24 + 2 * edge_rows]
        edges += clearance_rows_against_differences(alone, problem, x, plateau=True, counted=reverse)
    assert (seen >= 3).all(), seen
    assert (edges >= 3).all(), edges
    assert kinds == {"b", "s", "c", "m", "h", "p"}, kinds


def test_carried_box_point_velocity():
    """carried_point_rows: n . (velocity of a point fixed in the carried box) per TCP velocity, against central
    differences of carried_frame; hands side by side, tilted, and one above the other (world y as reference)."""
    from solver.collision.carried import carried_frame, carried_point_rows

    rng = np.random.default_rng(3)
    pairs = [(rng.normal(size=3), rng.normal(size=3)) for _ in range(4)]
    pairs.append((np.array([0.1, -0.3, 0.9]), np.array([0.11, -0.32, 1.3])))  # nearly vertical
    for first, second in pairs:
        local, normal = rng.normal(size=(5, 3)), rng.normal(size=(5, 3))
        rotation = carried_frame(first, second)[1]
        n1, n2 = carried_point_rows(first, second, rotation, local, normal)

        def point(p, q, local=local):
            centre, rotation = carried_frame(p, q)
            return centre + local @ rotation.T

        for rows, moved in ((n1, lambda p, q=second: point(p, q)), (n2, lambda q, p=first: point(p, q))):
            start = first if rows is n1 else second
            velocity = finite_difference(lambda v, moved=moved: moved(v).ravel(), start).reshape(5, 3, 3)
            np.testing.assert_allclose(rows, np.einsum("ki,kij->kj", normal, velocity), atol=1e-8)
