"""Variable reduction x = phi(beta): the map, its Jacobian through the solver, bounds, scenario switch, and the
Högfors shoulder rhythm (its formulas, frame reading, analytic Jacobian, fit and forward kinematics)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from helpers import finite_difference
from scipy.spatial.transform import Rotation

from solver import load_scenario
from solver.body.reduction import DEFAULT_GROUPS, GROUPS
from solver.body.shoulder_rhythm import JOINTS, LOWER, REST, UPPER, bone_angles_deg, build_rhythm, rhythm_angles
from solver.comfort import DEFAULT_COMFORT, STANDARD
from solver.errors import ScenarioError
from solver.io.scenario.bodies import load_body
from solver.iteration import solve
from solver.motion.frames import MotionLimits, variable_steps
from solver.problem.problem import Problem, ProblemSpec, Target

ROOT = Path(__file__).resolve().parents[3]
DEG = np.pi / 180


@pytest.fixture(scope="module")
def male50():
    return load_body(preset="male_50")


@pytest.fixture(scope="module")
def rhythm(male50):
    return build_rhythm(male50)


def reach(model, groups=GROUPS, position=(-0.2, -0.45, 1.1), weights=DEFAULT_COMFORT):
    zero = model.forward(model.zero_pose())
    feet = [
        Target(f, zero.tcp_frame(model.tcp(f))[1], lock=("z", "rx", "ry"), support=True) for f in ("foot_l", "foot_r")
    ]
    hand = Target("hand_r", np.array(position), lock=("x", "y", "z"))
    return Problem(model, ProblemSpec([*feet, hand], reduction=groups, comfort_weights=weights))


def box_points(rng, count: int) -> np.ndarray:
    """(alpha_h, beta_h) rad: uniform in the box, and as many within 0.01 deg of its edges."""
    inner = rng.uniform(LOWER, UPPER, size=(count, 2))
    edge = rng.uniform(LOWER, UPPER, size=(count, 2))
    side = rng.integers(0, 2, size=count)
    for k in range(count):
        near = LOWER[side[k]] + 1e-4 * DEG if rng.random() < 0.5 else UPPER[side[k]] - 1e-4 * DEG
        edge[k, side[k]] = near
    return np.vstack([inner, edge])


def test_groups_shrink_the_variables(male50):
    p = reach(male50)
    assert p.n_x - p.n_var == 63 + 2 * 19 + 2 * 7  # spine 72 -> 9, fingers 2 x 20 -> 1, shoulders 2 x 9 -> 2
    names = p.variable_names()
    assert {"lumbar_rx", "thoracic_ry", "cervical_rz", "grasp_l", "grasp_r"} <= set(names)
    assert {"shoulder_r_alpha_h", "shoulder_r_beta_h", "shoulder_l_alpha_h", "shoulder_l_beta_h"} <= set(names)
    assert names[:6] == list(male50.joint_names[:6])  # exterior joints first, unchanged
    assert not any(n.startswith(("clavicle", "scapula")) for n in names)
    assert reach(male50, GROUPS[:4]).reduction.linear and not p.reduction.linear


@pytest.mark.parametrize("groups", [DEFAULT_GROUPS, ("lumbar", "grasp"), GROUPS])
def test_sparse_products_with_the_basis_equal_the_dense_ones(male50, groups):
    red = reach(male50, groups).reduction
    rng = np.random.default_rng(1)
    a = rng.standard_normal((5, red.basis.shape[0]))
    beta = rng.standard_normal(red.n)
    np.testing.assert_allclose(red.times_basis(a), a @ red.basis, atol=1e-12)
    np.testing.assert_allclose(red.times_basis(a[0], squared=True), a[0] @ red.basis**2, atol=1e-12)
    # exact on any CPU: each row of the basis has at most one nonzero, so every summation order gives that product
    np.testing.assert_array_equal(red.basis_times(beta), red.basis @ beta)


def test_phi_keeps_joints_inside_their_ranges(male50):
    p = reach(male50)
    rng = np.random.default_rng(0)
    shoulder = p.reduction.shoulder_vars.ravel()
    for _ in range(20):
        v = rng.uniform(np.maximum(p.bounds.lower, -3), np.minimum(p.bounds.upper, 3))
        x = p.to_x(v)
        assert np.all(x >= p.x_bounds.lower - 1e-12) and np.all(x <= p.x_bounds.upper + 1e-12)
        back = p.to_variables(x)
        np.testing.assert_allclose(np.delete(back, shoulder), np.delete(v, shoulder), atol=1e-12)
        np.testing.assert_allclose(back[shoulder], v[shoulder], atol=1e-8)  # from_x(phi(beta)) = beta


def test_reduced_jacobian_and_gradient_match_finite_differences(male50):
    p = reach(male50)
    rng = np.random.default_rng(1)
    margin = np.minimum(0.01, 0.25 * (p.bounds.upper - p.bounds.lower))  # finite differences stay inside the ranges
    for spread in (0.05, 1.0):  # near the start, then the shoulders anywhere in their box
        v = p.start() + rng.normal(scale=0.05, size=p.n_var)
        shoulder = p.reduction.shoulder_vars
        v[shoulder] += spread * rng.uniform(0, 1, size=shoulder.shape) * (p.bounds.upper - p.bounds.lower)[shoulder]
        v = np.clip(v, p.bounds.lower + margin, p.bounds.upper - margin)
        state = p.state(v)
        numeric = finite_difference(lambda vv: p.scaled_error(p.state(vv)), v) * p.scale[None, :]
        jac = p.scaled_jacobian(state)
        # clearance rows in contact (met, within the hold band) carry the distance's Jacobian though their error is
        # zero (the step holds them); that Jacobian is checked in test_self_clearance / test_clearance
        contact = (p.scaled_error(state) == 0.0) & jac.any(axis=1)
        numeric[contact] = jac[contact]
        np.testing.assert_allclose(jac, numeric, atol=1e-4 * np.abs(numeric).max())
        grad, curv = p.comfort_derivatives(state)
        numeric_h = finite_difference(lambda vv: [p.comfort.value(p.state(vv))], v)[0]
        np.testing.assert_allclose(grad, numeric_h, rtol=1e-5, atol=1e-6)
        dphi = p.reduction.jacobian(v)
        _, curv_x = p.comfort.derivatives(state)
        np.testing.assert_allclose(curv, (dphi * dphi).T @ curv_x)
        # a state built from x alone (no variables on it) gets the same Jacobian through the fit
        np.testing.assert_allclose(p.scaled_jacobian(p.state_of_x(state.x)), p.scaled_jacobian(state), atol=1e-6)
        # the joint change the solver limits far from the constraints is d phi / d beta applied to the step
        dv = 1e-6 * rng.normal(size=p.n_var)
        exact = p.to_x(v + dv)[: male50.n] - p.to_x(v)[: male50.n]
        np.testing.assert_allclose(p.joint_change(state, dv), exact, atol=1e-9)


def test_reduced_solve_meets_targets_and_couples_the_spine(male50):
    result = solve(reach(male50))
    assert result.converged, result.summary()
    theta = dict(zip(male50.joint_names, result.theta, strict=True))
    lumbar = [theta[f"l{i}_rx"] for i in range(1, 6)]
    np.testing.assert_allclose(lumbar, lumbar[0], atol=1e-12)  # equal ranges -> equal share
    assert all(abs(theta[f"{f}_r_mcp_abduction"]) < 1e-12 for f in ("index", "middle", "ring", "little"))


@pytest.mark.parametrize("position", [(-0.2, -0.45, 1.1), (-0.3, -0.55, 1.45), (-0.55, -0.1, 1.15)])
def test_solve_with_the_shoulder_rhythm(male50, rhythm, position):
    """The standard model (trunk 0): the behaviour model's elbow, resting bent, reaches the first target with the
    upper arm lifted 1.4 deg, not the 5 the test looks for."""
    p = reach(male50, position=position, weights=STANDARD)
    result = solve(p)
    assert result.converged, result.summary()
    x = result.x
    assert np.all(x >= p.x_bounds.lower - 1e-9) and np.all(x <= p.x_bounds.upper + 1e-9)
    ab = p.to_variables(x)[p.reduction.shoulder_vars]
    assert np.all(ab >= LOWER - 1e-12) and np.all(ab <= UPPER + 1e-12)
    np.testing.assert_allclose(x[rhythm.joints], rhythm.values(ab), atol=1e-9)  # the nine joints follow the rhythm
    assert ab[0, 1] > REST[1] + 5 * DEG  # the reaching (right) arm was lifted


def per_side_difference(fun, both: np.ndarray) -> np.ndarray:
    """Finite differences (n_sides, 9, 2) of fun(ab)[i] (n_sides, 9) w.r.t. ab[i], side by side."""

    def moved(v: np.ndarray, i: int) -> np.ndarray:
        out = both.copy()
        out[i] = v
        return fun(out)[i]

    return np.array([finite_difference(lambda v, i=i: moved(v, i), both[i]) for i in range(len(both))])


def test_rhythm_jacobian_matches_finite_differences(rhythm):
    rng = np.random.default_rng(2)
    points = box_points(rng, 60)
    for k, ab in enumerate(points):
        both = np.array([ab, points[-1 - k]])
        # the rhythm itself, then clipped to the joint ranges (the bodies below a clipped one compensate)
        free = per_side_difference(lambda v: rhythm_angles(v, derivatives=False)[0], both)
        np.testing.assert_allclose(rhythm_angles(both)[1], free, atol=1e-7)
        clipped = per_side_difference(rhythm.values, both)
        np.testing.assert_allclose(rhythm.values_and_jacobian(both)[1], clipped, atol=1e-7)


def test_rest_posture_is_the_zero_pose(male50, rhythm):
    """The standard model (trunk 0), whose start is the zero pose (the behaviour model's rests the elbows at 60 deg;
    the shoulder variables start at REST either way)."""
    np.testing.assert_allclose(rhythm.values(np.array([REST, REST])), 0.0, atol=1e-12)
    np.testing.assert_allclose(reach(male50).start()[reach(male50).reduction.shoulder_vars], [REST, REST], atol=1e-9)
    p = reach(male50, weights=STANDARD)
    v = p.start()
    np.testing.assert_allclose(v[p.reduction.shoulder_vars], [REST, REST], atol=1e-9)
    np.testing.assert_allclose(p.to_x(v)[: male50.n], male50.zero_pose(), atol=1e-9)
    # the thesis's formulas at rest (deg): clavicle (-20, 9, 3), scapula (220, -30.33, 90), humerus (0, -90, -45)
    angles, _ = bone_angles_deg(0.0, -90.0, False)
    np.testing.assert_allclose(angles, [[-20, 9, 3], [220, -140 + 94 * (1 + 45 / 270), 90], [0, -90, -45]])


def test_fit_recovers_the_variables(rhythm):
    rng = np.random.default_rng(3)
    points = box_points(rng, 40)
    for k in range(len(points)):
        ab = np.array([points[k], points[-1 - k]])
        np.testing.assert_allclose(rhythm.fit(rhythm.values(ab)), ab, atol=1e-7)


def upper_arm(model, theta, side: str) -> np.ndarray:
    kin = model.forward(theta)
    d = kin.tcp_frame(model.tcp(f"elbow_{side}"))[1] - kin.tcp_frame(model.tcp(f"shoulder_{side}"))[1]
    return d / np.linalg.norm(d)


@pytest.mark.parametrize(
    "ab_deg, right",  # world direction of the right upper arm (its right is -x, it faces -y)
    [
        ((0, -90), (0, 0, -1)),  # rest: hanging, for every plane alpha_h
        ((90, -90), (0, 0, -1)),
        ((0, -60), (-0.5, 0, -np.sqrt(0.75))),  # 30 deg abduction in the coronal plane
        ((0, -30), (-np.sqrt(0.75), 0, -0.5)),  # 60 deg abduction
        ((90, -30), (0, -np.sqrt(0.75), -0.5)),  # 60 deg forward flexion in the sagittal plane
        ((45, -45), (-0.5, -0.5, -np.sqrt(0.5))),
    ],
)
def test_upper_arm_points_where_the_rhythm_says(male50, rhythm, ab_deg, right):
    """Both sides through the model's forward kinematics, with the joint ranges applied; the left mirrors."""
    ab = np.radians([ab_deg, ab_deg])
    theta = male50.zero_pose()
    theta[rhythm.joints] = rhythm.values(ab)
    for side, mirror in (("r", 1.0), ("l", -1.0)):
        np.testing.assert_allclose(upper_arm(male50, theta, side), np.array(right) * [mirror, 1, 1], atol=1e-9)


def test_bones_recompose_with_forward_kinematics(male50, rhythm):
    """Each link's world rotation relative to t1 is P R(beta) R(rest)^T P^T with R = Rz(a) Ry(-b) Rx(g) (the
    thesis's angles, our frame reading), for unclipped joint values."""
    rng = np.random.default_rng(4)
    links = {name: male50.link_index(name) for name in ("t1", "clavicle_r", "scapula_r", "upper_arm_r")}
    links_l = {name: male50.link_index(name) for name in ("clavicle_l", "scapula_l", "upper_arm_l")}

    def rot(angles_deg):
        a, b, g = np.radians(angles_deg)
        return Rotation.from_euler("ZYX", [a, -b, g]).as_matrix()

    rest = [rot(r) for r in bone_angles_deg(0.0, -90.0, False)[0]]
    for ab in rng.uniform(LOWER, UPPER, size=(10, 2)):
        theta = male50.zero_pose()
        theta[rhythm.joints] = rhythm.sign * rhythm_angles(np.array([ab, ab]), derivatives=False)[0]
        theta[:6] = rng.normal(scale=0.2, size=6)  # the thorax may be anywhere
        kin = male50.forward(theta)
        t1 = kin.rotation[links["t1"]]
        bones = bone_angles_deg(*np.degrees(ab), False)[0]
        for k, (right, left) in enumerate(zip(("clavicle_r", "scapula_r", "upper_arm_r"), links_l, strict=True)):
            d = rot(bones[k]) @ rest[k].T
            for name, p in ((right, np.diag([-1.0, -1, 1])), (left, np.diag([1.0, -1, 1]))):
                link = links.get(name, links_l.get(name))
                np.testing.assert_allclose(t1.T @ kin.rotation[link], p @ d @ p.T, atol=1e-9)


def test_the_shoulder_girdle_moves_like_one(rhythm):
    """Lifting the arm sideways elevates and retracts the clavicle and rotates the scapula upward with
    posterior tilt: the anatomical directions (the other product order turns the scapula downward)."""
    at = {j.format(s="r"): i for i, j in enumerate(JOINTS)}
    low, high = rhythm.values(np.radians([[0, -70], [0, -50]]))[0], rhythm.values(np.radians([[0, -50], [0, -70]]))[0]
    assert 0 < low[at["clavicle_r_elevation"]] < high[at["clavicle_r_elevation"]]
    assert 0 > low[at["clavicle_r_protraction"]] > high[at["clavicle_r_protraction"]]  # retraction
    assert 0 < low[at["scapula_r_upward_rotation"]] < high[at["scapula_r_upward_rotation"]]
    assert 0 > low[at["scapula_r_tilt"]] > high[at["scapula_r_tilt"]]  # +tilt turns the scapula's top forward
    assert 0 < high[at["shoulder_r_abduction"]]  # the glenohumeral joint takes the rest of the abduction


def test_motion_steps_bound_the_shoulder_joints(male50):
    """A per-frame step of one shoulder variable moves no joint more than the motion limit allows."""
    p = reach(male50)
    limits = MotionLimits()
    step = variable_steps(p, limits)
    shoulder = p.reduction.shoulder_vars
    assert np.all(np.isfinite(step[shoulder])) and np.all(step[shoulder] > 0)
    rng = np.random.default_rng(5)
    for ab in box_points(rng, 20):
        v = p.start()
        v[shoulder[0]] = ab
        for k in shoulder[0]:
            moved = v.copy()
            moved[k] = np.clip(v[k] + step[k], p.bounds.lower[k], p.bounds.upper[k])
            change = np.abs(p.to_x(moved) - p.to_x(v))[: male50.n]
            assert change.max() <= limits.max_joint_change * 1.05


def test_scenario_switch(tmp_path):
    text = (ROOT / "presets/scenarios/box_lift.toml").read_text()
    cases = (("true", DEFAULT_GROUPS), ('["lumbar", "grasp"]', ("lumbar", "grasp")), ('["shoulder"]', ("shoulder",)),
             ("false", ()))  # fmt: skip
    for value, expected in cases:
        path = tmp_path / "s.toml"
        path.write_text(text.replace("reduction = false", f"reduction = {value}"))
        assert load_scenario(path).problem.reduction_groups == expected
    assert "shoulder" in GROUPS
    path.write_text(text.replace("reduction = false", 'reduction = ["elbow"]'))
    with pytest.raises(ScenarioError, match="reduction.*shoulder"):
        load_scenario(path)
