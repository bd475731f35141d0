"""Fixtures of the kernel tests."""

from __future__ import annotations

import pytest

from solver.io.scenario.bodies import load_body


@pytest.fixture(scope="module")
def model():
    """The male_50 preset's model."""
    return load_body(preset="male_50")
