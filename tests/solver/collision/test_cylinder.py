"""The cylinder obstacle kind (solver/collision/kinds/cylinder.py, the kind added as one module and one registration
line): its distances against meshes that enclose it and that it encloses (an independent bracket, the mesh queries
being tested on their own), known depths inside, derivatives against central differences, and the solver's rows."""

from __future__ import annotations

import numpy as np
import pytest
from helpers import finite_difference

from solver import Problem, ProblemSpec, Target, load_scenario, solve
from solver.collision import Mesh, MeshIndex, mesh_distance
from solver.collision.carried import Carried
from solver.collision.generate import axis_frame
from solver.collision.kinds import Cylinder
from solver.constraints.carried_obstacles import CarriedObstacles
from solver.errors import ScenarioError
from solver.io.scenario.bodies import load_body

POST = Cylinder((0.1, -0.2, 0.3), (0.3, -0.5, 1.1), 0.12, name="post")
SIDES = 720  # of the prisms that bracket the cylinder: R (1 / cos(pi / 720) - 1) < 1e-5 R


def prism(cylinder: Cylinder, radius: float) -> Mesh:
    """A closed SIDES-gon prism of corner ``radius`` (m) around the cylinder's axis, written out here."""
    frame = axis_frame(cylinder.b - cylinder.a)
    angle = 2.0 * np.pi * np.arange(SIDES) / SIDES
    ring = radius * (np.cos(angle)[:, None] * frame[:, 0] + np.sin(angle)[:, None] * frame[:, 1])
    vertices = np.vstack([cylinder.a + ring, cylinder.b + ring, [cylinder.a, cylinder.b]])
    j, k = np.arange(SIDES), (np.arange(SIDES) + 1) % SIDES
    low, top = np.full(SIDES, 2 * SIDES), np.full(SIDES, 2 * SIDES + 1)
    faces = np.vstack([np.column_stack([j, k, SIDES + k]), np.column_stack([j, SIDES + k, SIDES + j]),
                       np.column_stack([low, k, j]), np.column_stack([top, SIDES + j, SIDES + k])])  # fmt: skip
    return Mesh(vertices, faces)


def capsules(seed: int, count: int = 200) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    p0 = rng.uniform(-0.4, 1.4, (count, 3))
    p1 = p0 + rng.normal(scale=0.3, size=(count, 3))
    p1[: count // 10] = p0[: count // 10]  # some points
    return p0, p1, rng.uniform(0.0, 0.05, count)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_apart_distances_lie_between_those_of_an_inner_and_an_outer_prism(seed) -> None:
    p0, p1, radii = capsules(seed)
    got = POST.distance(p0, p1, radii)
    inner = mesh_distance(p0, p1, radii, MeshIndex(prism(POST, POST.radius)), np.inf).distance
    outer = mesh_distance(p0, p1, radii, MeshIndex(prism(POST, POST.radius / np.cos(np.pi / SIDES))), np.inf).distance
    apart = outer > 0
    assert apart.sum() > 100
    assert (got.distance[apart] >= outer[apart] - 1e-12).all() and (got.distance[apart] <= inner[apart] + 1e-12).all()
    assert (got.distance[~apart] <= 1e-5).all()


def test_known_depths_inside() -> None:
    a, b, r = np.zeros(3), np.array([0.0, 0.0, 1.0]), 0.2
    drum = Cylinder(a, b, r)
    middle = np.array([[0.0, 0.0, 0.5]])
    assert drum.distance(middle, middle, 0.01).distance[0] == pytest.approx(-0.21, abs=1e-12)  # out by the side
    low = np.array([[0.05, 0.0, 0.1]])
    got = drum.distance(low, low, 0.0)
    assert got.distance[0] == pytest.approx(-0.1, abs=1e-12)  # out through the bottom
    np.testing.assert_allclose(got.normal[0], [0.0, 0.0, -1.0], atol=1e-12)
    along = drum.distance(np.array([0.1, 0.0, 0.3]), np.array([0.1, 0.0, 0.8]), 0.0)  # parallel, 0.1 from the side
    assert along.distance[0] == pytest.approx(-0.1, abs=1e-12)
    np.testing.assert_allclose(along.normal[0], [1.0, 0.0, 0.0], atol=1e-12)
    rim = drum.distance(np.array([0.5, 0.0, 1.4]), np.array([0.5, 0.0, 1.4]), 0.0)  # nearest the top rim
    assert rim.distance[0] == pytest.approx(0.5, abs=1e-12)
    np.testing.assert_allclose(rim.closest[0], [0.2, 0.0, 1.0], atol=1e-12)


def test_a_cylinder_needs_two_ends() -> None:
    with pytest.raises(ScenarioError, match="apart"):
        Cylinder((0.0, 0.0, 0.0), (0.0, 0.0, 0.0), 0.1, name="flat")


def test_apart_the_gradient_is_the_normal_split_by_the_witness() -> None:
    p0, p1, radii = capsules(5, 40)
    got = POST.distance(p0, p1, radii)
    for i in np.flatnonzero(got.distance > 1e-3)[4:16]:  # segments, not points (where any t is the witness)
        ends = np.concatenate([p0[i], p1[i]])
        numeric = finite_difference(lambda e, r=radii[i]: POST.distance(e[:3], e[3:], r).distance, ends, 1e-7)[0]
        np.testing.assert_allclose(numeric, np.r_[(1 - got.t[i]) * got.normal[i], got.t[i] * got.normal[i]],
                                   atol=2e-6)  # fmt: skip


@pytest.fixture(scope="module")
def male50():
    return load_body(preset="male_50")


def _standing(model, hand: np.ndarray) -> list[Target]:
    zero = model.forward(model.zero_pose())
    feet = [Target(f, zero.tcp_frame(model.tcp(f))[1], support=True) for f in ("foot_r", "foot_l")]
    return [*feet, Target("hand_r", hand, lock=("x", "y", "z"))]


def test_the_clearance_rows_match_central_differences(male50) -> None:
    """A post beside the hanging right arm, poses jittered around it: the rows apart from the post (smooth)."""
    post = Cylinder((-0.27, 0.0, 0.4), (-0.26, -0.02, 1.4), 0.04, name="post")
    problem = Problem(male50, ProblemSpec(_standing(male50, np.array([-0.25, -0.45, 1.1])), obstacles=[post]))
    rows = problem.obstacle_constraint
    rng = np.random.default_rng(7)
    seen = 0
    for _ in range(3):
        x = problem.start() + np.r_[rng.uniform(-0.15, 0.15, male50.n), np.zeros(problem.n_x - male50.n)]
        state = problem.state_of_x(x)
        value = rows.value(state)
        numeric = finite_difference(lambda v: rows.value(problem.state_of_x(v)), x, 1e-7)
        smooth = value > 1e-4
        seen += int((smooth & (value < 0.1)).sum())
        np.testing.assert_allclose(rows.value_jacobian(state)[smooth], numeric[smooth],
                                   atol=1e-6 * max(1.0, np.abs(numeric).max()))  # fmt: skip
    assert seen >= 3


def test_the_carried_box_rows_match_central_differences(male50) -> None:
    """A box between the hands and a post across its front face: the box's edges against the post, the post's rims
    against the box (apart rows)."""
    carried = Carried(np.array([0.4, 0.3, 0.3]), ("hand_r", "hand_l"), "crate")
    problem = Problem(male50, ProblemSpec(_standing(male50, np.array([-0.2, -0.4, 1.0]))[:2], carried=carried))
    zero = problem.state_of_x(problem.to_x(problem.start()))
    centre = 0.5 * (zero.kin.tcp_frame(male50.tcp("hand_r"))[1] + zero.kin.tcp_frame(male50.tcp("hand_l"))[1])
    post = Cylinder(centre + [-0.4, -0.17, 0.05], centre + [0.4, -0.17, -0.02], 0.04, name="post")
    rows = CarriedObstacles(male50, carried, [post], problem.n_x)
    assert rows.rows == 12 + 64
    rng = np.random.default_rng(2)
    seen = 0
    for _ in range(3):
        x = problem.start() + np.r_[rng.uniform(-0.05, 0.05, male50.n), np.zeros(problem.n_x - male50.n)]
        state = problem.state_of_x(x)
        value = rows.value(state)
        numeric = finite_difference(lambda v: rows.value(problem.state_of_x(v)), x, 1e-7)
        smooth = (value > 1e-4) & (value < 0.05)  # measured, apart
        seen += int(smooth.sum())
        np.testing.assert_allclose(rows.value_jacobian(state)[smooth], numeric[smooth],
                                   atol=1e-6 * max(1.0, np.abs(numeric).max()))  # fmt: skip
    assert seen >= 6


def test_a_scenario_post_keeps_the_hand_out(tmp_path) -> None:
    """kind = "cylinder" in a scenario: read, and a hand aimed into the post stops at its surface."""
    path = tmp_path / "post.toml"
    path.write_text(
        '[manikin]\npreset = "male_50"\n\n'
        '[[targets]]\ntcp = "foot_r"\nposition = [-0.083, 0.0, 0.0]\nsupport = true\n\n'
        '[[targets]]\ntcp = "foot_l"\nposition = [0.083, 0.0, 0.0]\nsupport = true\n\n'
        '[[targets]]\ntcp = "hand_r"\nposition = [-0.2, -0.45, 1.0]\nlock = ["x", "y", "z"]\n\n'
        '[[obstacles]]\nname = "post"\nkind = "cylinder"\na = [-0.2, -0.45, 0.0]\nb = [-0.2, -0.45, 1.6]\n'
        "radius = 0.05\nclearance = 0.01\n",
        encoding="utf-8",
    )
    scenario = load_scenario(path)
    (post,) = scenario.problem.obstacles
    assert isinstance(post, Cylinder) and post.radius == 0.05
    result = solve(scenario.problem, scenario.start, scenario.options)
    assert not result.converged and "hand_r" in result.unmet
    state = result.state
    caps = scenario.problem.obstacle_constraint
    assert caps.value(state).min() >= 0.01 - 1e-3  # every body part keeps the post's clearance
