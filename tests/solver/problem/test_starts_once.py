"""The behaviour start's per-model values (standing hip, crouch, rested pose) are computed once and handed out as
copies: a caller that changes its start does not change the next solve's."""

from __future__ import annotations

import numpy as np

from solver.io.scenario.bodies import load_body
from solver.problem import starts


def test_poses_are_fresh_copies_of_the_once_computed_values() -> None:
    model = load_body(preset="male_50")
    for pose in (starts.rested_pose, starts.crouched_pose):
        first = pose(model)
        expected = first.copy()
        first += 1.0  # a caller's change of its own start
        again = pose(model)
        np.testing.assert_array_equal(again, expected)
        assert again is not pose(model)
    knee = model.joint_names.index("knee_r_flexion")
    assert starts.crouched_pose(model)[knee] > 0.5 and starts.rested_pose(model)[knee] == 0.0
    assert starts.crouched_pose(load_body(preset="snake")) is None
    assert 0.7 < starts._once(model, "hip", starts._standing_hip) < 1.2  # m: the standing hip joint's height
