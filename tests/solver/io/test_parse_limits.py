"""check_depth at its limit: values nested exactly MAX_DEPTH levels pass (an empty list or table too), one level more
is refused with the key path of the first too deep value (the usual data is told apart without building a key path
per value)."""

from __future__ import annotations

import pytest

from solver.errors import ScenarioError
from solver.io.parse_limits import MAX_DEPTH, check_depth


def _nested(levels: int, leaf: object) -> object:
    value = leaf
    for i in range(levels):
        value = [value] if i % 2 else {"k": value}
    return value


@pytest.mark.parametrize("leaf", [1.0, "text", None, [], {}])
def test_values_nested_to_the_limit_pass_and_one_level_more_is_refused(leaf: object) -> None:
    check_depth({"a": 1, "b": [_nested(MAX_DEPTH - 2, leaf)]}, "f.toml", ScenarioError)
    deeper = {"a": 1, "b": [_nested(MAX_DEPTH - 1, leaf)]}  # the leaf at depth MAX_DEPTH + 1
    with pytest.raises(ScenarioError, match=rf"f.toml: b\[0\]\.k.*nested more than {MAX_DEPTH} levels deep"):
        check_depth(deeper, "f.toml", ScenarioError)


class _Items(list):
    """A list of another type (as some parsers give): still walked."""


@pytest.mark.parametrize("kind", [list, _Items])
def test_a_too_deep_value_after_many_numbers_is_found(kind: type) -> None:
    """A long list of numbers is told apart in one pass; one container among them is still walked into."""
    numbers = kind([0.5] * 200 + [_nested(MAX_DEPTH, 1.0)] + [2] * 10)
    check_depth({"a": kind([0.5] * 200 + [True, None, "s"])}, "f.toml", ScenarioError)
    with pytest.raises(ScenarioError, match=rf"f.toml: a\[200\].*nested more than {MAX_DEPTH} levels deep"):
        check_depth({"a": numbers}, "f.toml", ScenarioError)
