"""Shared fixtures (the helpers they use are in helpers.py, importable from every test module)."""

from __future__ import annotations

import pytest
from helpers import random_tree

from solver.body.model import Model


@pytest.fixture(params=[0, 1, 2])
def tree(request) -> Model:
    return random_tree(request.param)
