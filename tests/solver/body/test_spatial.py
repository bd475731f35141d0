"""SO(3) helpers: exp/log round trips (near 0 and near pi), quaternions, slerp, the inverse left Jacobian."""

from __future__ import annotations

import numpy as np
import pytest
from helpers import finite_difference

from solver.body.spatial import (
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
