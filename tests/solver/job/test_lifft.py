"""LiFFT (Gallagher et al. 2017, Applied Ergonomics 63:142-150) in the form Zelik et al. 2022 (Applied Ergonomics
99:103619) print: damage per lift, cumulative damage, probability of a high-risk job, the horizontal distance."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from solver.job.lifft import BETA0, BETA1, cumulative_damage, damage_per_lift, horizontal_distance, probability


def test_zelik_2022_a_30_Nm_assist_cuts_cumulative_damage_by_about_70_percent() -> None:
    """Zelik et al. 2022, abstract: an exoskeleton giving 30 N*m of lumbar moment "is projected to reduce cumulative
    back damage by ~70%" (the source rounds; we get 68 %), whatever the task's own moment and repetitions."""
    for plm, lifts in [(60.0, 500), (120.0, 1200)]:
        cut = 1 - cumulative_damage([(plm - 30.0, lifts)]) / cumulative_damage([(plm, lifts)])
        assert round(cut, 1) == 0.7


def test_damage_per_lift_is_the_printed_equation() -> None:
    """1 / (1,902,416 x exp(-(0.038 PLM + 0.32))), hand-computed at 0 and 100 N*m."""
    assert damage_per_lift(0.0) == pytest.approx(math.exp(0.32) / 1_902_416, rel=1e-12)
    assert damage_per_lift(100.0) == pytest.approx(3.2358e-05, rel=1e-4)  # exp(4.12) / 1902416


def test_cumulative_damage_sums_tasks_and_zero_repetitions_give_no_damage_and_no_risk() -> None:
    assert cumulative_damage([(50.0, 0)]) == 0.0
    assert probability(0.0) == 0.0
    both = cumulative_damage([(50.0, 300), (80.0, 200)])
    assert both == pytest.approx(300 * damage_per_lift(50.0) + 200 * damage_per_lift(80.0))


def test_probability_is_one_half_where_the_logit_is_zero_and_rises_with_damage() -> None:
    """Y = 1.72 + 1.03 log10(CD): P = 0.5 at CD = 10^(-1.72/1.03) (a level's edge)."""
    edge = 10 ** (-BETA0 / BETA1)
    assert probability(edge) == pytest.approx(0.5, abs=1e-12)
    assert probability(edge * 0.99) < 0.5 < probability(edge * 1.01)
    assert probability(1.0) == pytest.approx(math.exp(1.72) / (1 + math.exp(1.72)))


def test_horizontal_distance_is_across_gravity_from_l5_s1_to_the_hands_midpoint() -> None:
    frame = SimpleNamespace(
        gravity=np.array([0.0, 0.0, -9.81]),
        tcp_position={"hand_r": np.array([-0.2, -0.5, 0.4]), "hand_l": np.array([0.2, -0.3, 0.4])},
        pos=lambda name: np.array([0.0, 0.0, 1.0]),
    )
    assert horizontal_distance(frame, ("hand_r", "hand_l")) == pytest.approx(0.4)
    assert horizontal_distance(frame, ("hand_r",)) == pytest.approx(math.hypot(0.2, 0.5))
