"""Subtree and ancestor sums by prefix sums in preorder equal the dense descendant-matrix products they replace."""

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from solver.body.tree import TreeSums
from solver.io.scenario.bodies import load_body


def _dense_descendants(parent: np.ndarray) -> np.ndarray:
    n = len(parent)
    desc = np.zeros((n, n))
    for k in range(n):
        j = k
        while j >= 0:
            desc[j, k] = 1.0
            j = int(parent[j])
    return desc


@settings(max_examples=50, deadline=None)
@given(st.lists(st.integers(min_value=0, max_value=10**6), min_size=1, max_size=40), st.integers(0, 2**32 - 1))
def test_tree_sums_of_random_forests(picks, seed):
    # link k's parent is any earlier link or none (-1): every forest in topological order
    parent = np.array([-1] + [(p % (k + 1)) - 1 for k, p in enumerate(picks[1:], start=1)])
    values = np.random.default_rng(seed).standard_normal((len(parent), 3))
    sums, desc = TreeSums(parent), _dense_descendants(parent)
    np.testing.assert_allclose(sums.subtree(values), desc @ values, atol=1e-12)
    np.testing.assert_allclose(sums.ancestors(values), desc.T @ values, atol=1e-12)


def test_tree_sums_of_the_manikin_in_any_link_order():
    model = load_body(preset="male_50")
    values = np.random.default_rng(0).standard_normal((model.n, 9))
    expected = model.descendant.astype(float) @ values
    np.testing.assert_allclose(model.tree_sums.subtree(values), expected, atol=1e-12)
    np.testing.assert_allclose(model.tree_sums.ancestors(values), model.descendant.T.astype(float) @ values, atol=1e-12)
    # a parent listed after its child (not in topological order) still works
    parent = np.array([2, 0, -1, 1])
    np.testing.assert_allclose(TreeSums(parent).subtree(np.eye(4)), _dense_descendants(parent), atol=0)
    np.testing.assert_allclose(TreeSums(parent).ancestors(np.eye(4)), _dense_descendants(parent).T, atol=0)
