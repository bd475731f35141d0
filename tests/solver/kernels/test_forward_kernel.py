"""Forward kinematics by the compiled loop equals the NumPy chains-and-jumps version to rounding."""

from __future__ import annotations

import numpy as np
import pytest

from solver import kernels
from solver.io.scenario.bodies import load_body

pytest.importorskip("numba")


@pytest.mark.parametrize("preset", ["male_50", "female_5"])
def test_the_loop_gives_the_chains_frames(preset: str) -> None:
    model = load_body(preset=preset)
    rng = np.random.default_rng(3)
    for _ in range(5):
        theta = rng.uniform(model.lower, model.upper)
        with kernels.using(False):
            numpy_kin = model.forward(theta)
        with kernels.using(True):
            loop_kin = model.forward(theta)
        for name in ("rotation", "position", "axis", "com"):
            np.testing.assert_allclose(getattr(loop_kin, name), getattr(numpy_kin, name), rtol=0, atol=1e-12)
