"""The time at each level (s, % of the motion, % of the cycle) from per-frame levels."""

from __future__ import annotations

import pytest

from solver.job.sequence import REBA_RISKS, time_at_levels


def test_time_at_levels_counts_frames_times_the_frame_time() -> None:
    table = time_at_levels([1, 2, 2, 4, None], (1, 2, 3, 4), 0.5, 10.0)
    assert [r["frames"] for r in table] == [1, 2, 0, 1]
    assert table[1]["seconds"] == pytest.approx(1.0)
    assert table[1]["percent_of_motion"] == pytest.approx(40.0)  # the unrated frame counts in the motion's time
    assert table[1]["percent_of_cycle"] == pytest.approx(10.0)


def test_one_frame_motion_spends_all_its_time_at_its_level() -> None:
    table = time_at_levels(["medium"], REBA_RISKS, 1 / 24, 30.0)
    assert [r["percent_of_motion"] for r in table] == [0.0, 0.0, 100.0, 0.0, 0.0]
    assert table[2]["seconds"] == pytest.approx(1 / 24)
