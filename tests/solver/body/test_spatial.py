"""SO(3) helpers: exp/log round trips (near 0 and near pi), quaternions, slerp, the inverse left Jacobian."""

from __future__ import annotations

import numpy as np
import pytest
from helpers import finite_difference

from solver.body.spatial import (
    Arc,
    cross,
    exp_so3,
    left_jacobian_inverse_so3,
    length,
    log_so3,
    matrix_to_quat,
    quat_to_matrix,
    skew,
    slerp,
)


@pytest.mark.parametrize("angle", [0.0, 1e-9, 1e-5, 0.3, 2.0, np.pi - 1e-3, np.pi - 1e-6])
def test_log_inverts_exp(angle):
    rng = np.random.default_rng(int(angle * 1e6) % 1000)
    for _ in range(20):
        axis = rng.normal(size=3)
        w = axis / np.linalg.norm(axis) * angle
        np.testing.assert_allclose(log_so3(exp_so3(w)), w, atol=1e-8)


def test_quaternion_round_trip_and_slerp():
    rng = np.random.default_rng(1)
    for _ in range(50):
        r = exp_so3(rng.normal(size=3))
        np.testing.assert_allclose(quat_to_matrix(matrix_to_quat(r)), r, atol=1e-12)
    for axis in np.eye(3):  # half turns and near them: a negative trace, each diagonal entry the largest in turn
        for angle in (np.pi, np.pi - 1e-3, 2.5):
            r = exp_so3(angle * (axis + 0.05 * rng.normal(size=3)))
            q = matrix_to_quat(r)
            assert q[0] >= 0 and abs(np.linalg.norm(q) - 1) < 1e-15
            np.testing.assert_allclose(quat_to_matrix(q), r, atol=1e-12)
    q0, q1 = matrix_to_quat(np.eye(3)), matrix_to_quat(exp_so3([0, 0, 1.0]))
    np.testing.assert_allclose(log_so3(quat_to_matrix(slerp(q0, q1, 0.25))), [0, 0, 0.25], atol=1e-12)


def test_left_jacobian_inverse_is_the_derivative_of_log():
    rng = np.random.default_rng(2)
    for angle in (1e-7, 0.5, 3.0):
        w = rng.normal(size=3)
        w *= angle / np.linalg.norm(w)
        r = exp_so3(w)
        numeric = finite_difference(lambda d, r=r: log_so3(exp_so3(d) @ r), np.zeros(3))
        np.testing.assert_allclose(left_jacobian_inverse_so3(w), numeric, atol=1e-6)


def test_cross_and_skew_agree_with_numpy():
    rng = np.random.default_rng(3)
    a, b = rng.normal(size=(5, 3)), rng.normal(size=(5, 3))
    np.testing.assert_allclose(cross(a, b), np.cross(a, b))
    np.testing.assert_allclose(skew(a[0]) @ b[0], np.cross(a[0], b[0]))


def test_cross_and_length_are_numpys_numbers_bit_for_bit():
    """The ergonomics uses them in place of np.cross and np.linalg.norm: its report must not change by a bit. Exact on
    any CPU: the same correctly rounded products and differences as np.cross, the same dot product as norm's."""
    rng = np.random.default_rng(4)
    a, b = rng.normal(size=(200, 3)) * 10.0 ** rng.integers(-8, 8, (200, 1)), rng.normal(size=(200, 3))
    assert np.array_equal(cross(a, b), np.cross(a, b))
    assert np.array_equal(cross(np.array([0.0, 0.0, 1.0]), b), np.cross([0.0, 0.0, 1.0], b))  # broadcast
    assert all(length(v) == np.linalg.norm(v) for v in np.vstack([a, b, np.zeros((1, 3)), [[-0.0, 3e-300, 1e300]]]))


def _slerp_afresh(q0, q1, t):
    """slerp as it was before :class:`Arc` (everything computed at each t)."""
    q0, q1 = np.asarray(q0, dtype=float) / np.linalg.norm(q0), np.asarray(q1, dtype=float) / np.linalg.norm(q1)
    dot = float(q0 @ q1)
    if dot < 0.0:
        q1, dot = -q1, -dot
    if dot > 0.9995:
        q = q0 + t * (q1 - q0)
        return q / np.linalg.norm(q)
    angle = np.arccos(dot)
    return (np.sin((1.0 - t) * angle) * q0 + np.sin(t * angle) * q1) / np.sin(angle)


def test_an_arc_gives_the_slerp_computed_afresh_bit_for_bit():
    """A keyed target's rotation at every frame: the arc between two keys built once gives each t the numbers slerp
    computed afresh gives (the same operations on the same numbers: exact on any CPU), and quat_to_matrix in Python
    floats the numbers of the NumPy scalars; two keys of one rotation give one matrix at every t (zeros of either
    sign)."""
    rng = np.random.default_rng(5)
    q = rng.normal(size=4)
    pairs = [(rng.normal(size=4), rng.normal(size=4), False) for _ in range(40)]
    pairs += [(q, q + 1e-4 * rng.normal(size=4), False), (q, q, True), (q, -q, True)]
    pairs += [([-0.0, 1.0, -0.0, 0.0], [0.0, 2.0, 0.0, -0.0], True)]
    for q0, q1, still in pairs:
        arc = Arc(q0, q1)
        held = set()
        for t in (0.0, 1e-9, 0.25, 0.5, 0.999, 1.0):
            q = arc.at(t)
            assert np.array_equal(q, _slerp_afresh(q0, q1, t)) and np.array_equal(q, slerp(q0, q1, t))
            w, x, y, z = q / np.linalg.norm(q)  # NumPy scalars, as quat_to_matrix computed them
            expected = [[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]]  # fmt: skip
            assert np.array_equal(quat_to_matrix(q), np.array(expected))
            held.add(q.tobytes())
        assert arc.still == still and (len(held) == 1 or not still)
    with pytest.raises(ValueError):
        quat_to_matrix([np.nan, 0.0, 0.0, 1.0])
