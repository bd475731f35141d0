"""The note of a place that stepped first names the feet's whole move from where they stood (the walk-up and the
stance finder's last step together), measured from the facing (-y), left positive."""

from __future__ import annotations

import numpy as np
import pytest

from solver.operations.stance import net_step, turn_deg


@pytest.mark.parametrize(("end", "direction"), [((0.0, -0.12), 0.0), ((0.1, 0.0), 90.0), ((-0.1, 0.0), -90.0),
                                                ((0.1, -0.1), 45.0)])  # fmt: skip
def test_a_step_s_direction_is_from_the_facing(end, direction) -> None:
    step = net_step("foot_l", np.array([0.08, 0.0, 0.0]), np.array([0.08 + end[0], end[1], 0.0]), 0.0)
    assert step.length == pytest.approx(float(np.hypot(*end)))
    assert step.direction_deg == pytest.approx(direction)


def test_forward_reads_forward() -> None:
    text = net_step("foot_r", np.zeros(3), np.array([0.0, -0.12, 0.0]), 0.0).text()
    assert text == "foot_r stepped 0.12 m, straight forward, turned 0 deg"


def test_a_turn_to_the_left_is_positive() -> None:
    c, s = np.cos(np.radians(20.0)), np.sin(np.radians(20.0))
    assert turn_deg(np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])) == pytest.approx(20.0)
    assert turn_deg(None) == 0.0
