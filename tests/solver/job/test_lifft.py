"""LiFFT (Gallagher et al. 2017, Applied Ergonomics 63:142-150) with the damage and risk formulas of the authors'
calculator (LiFFT v1.4.0): damage per lift, cumulative damage, probability of a high-risk job, the horizontal distance,
and the published worked examples.

Where the sources were read: the paper's author manuscript and the v1.4.0 workbook's formula cells as transcribed
(two passes) in github.com/nbarr1/ErgonomicTool (docs/methods/lifft.md, methods/lifft/transcription/); we did not
hold the paper, the workbook or the calculator page ourselves."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from solver.job.lifft import BETA0, BETA1, cumulative_damage, damage_per_lift, horizontal_distance, probability

LB = 4.4482216152605  # N per pound-force
INCH = 0.0254  # m
G = 9.80665  # m/s^2, the paper's kg loads as weights


def test_calculator_guide_mono_task_30_lb_at_16_in_760_times_is_a_40_percent_high_risk_job() -> None:
    """LiFFT calculator's instructions page (v1.4.1, 08/26/2019), mono-task example: "a 30-pound load that is
    performed 760 times during the workday, involving a maximal horizontal distance of 16 inches" gives "a 40%
    probability of being a high-risk job". The v1.4.0 formulas give 40.8 % (CD 0.0090; the page prints no CD); the
    1,902,416 reading of Zelik et al. 2022 would give 33 %."""
    plm = 30 * LB * 16 * INCH  # N*m, = 40 ft*lb
    assert plm == pytest.approx(40 * 1.3558179, rel=1e-6)
    cd = cumulative_damage([(plm, 760)])
    assert round(cd, 4) == 0.0090  # the workbook rounds each task's damage to 4 decimals
    assert 0.40 <= probability(cd) < 0.41


def test_paper_mono_task_13_kg_at_40_cm_400_times() -> None:
    """Gallagher et al. 2017, section 2.2 (manuscript p. 4, Figure 3): 13 kg placed 40 cm from L5/S1, 400 times a
    day: "40 cm x 13 kg = 51 Nm", DPC "0.000011", CD daily dose "0.0043" (we get 0.0042: the paper's tool was v1.1,
    its printed DPC and CD disagree in the last digit themselves, 400 x 0.000011 = 0.0044). Its "25.39%" risk came
    from the first damage-risk curve, which the calculator replaced in v1.3.0 and v1.4.0 (we get 33 %): not tested."""
    plm = 13 * G * 0.40
    assert round(plm) == 51
    assert f"{damage_per_lift(plm):.1e}" == "1.1e-05"
    assert cumulative_damage([(plm, 400)]) == pytest.approx(0.0043, abs=1.2e-4)


def test_damage_per_lift_is_the_workbook_formula_and_the_paper_eq1_scale_902416() -> None:
    """v1.4.0: 10^(-5.81636 + 0.0222878 M), M in ft*lb; in N*m that is 1/(902,416 exp(-(0.038 PLM + 0.32))) to
    the printed digits (within 3 % up to 150 N*m), not 1/(1,902,416 ...), which is 2.1x lower."""
    assert damage_per_lift(0.0) == pytest.approx(10**-5.81636221052493, rel=1e-9)
    assert damage_per_lift(40 * 1.3558179483314004) == pytest.approx(1.18892e-05, rel=1e-4)  # 10^-4.92485
    for plm in (0.0, 30.0, 76.0, 150.0):
        assert damage_per_lift(plm) == pytest.approx(math.exp(0.038 * plm + 0.32) / 902_416, rel=0.03)
        assert damage_per_lift(plm) / (math.exp(0.038 * plm + 0.32) / 1_902_416) > 2.0


def test_zelik_2022_a_30_Nm_assist_cuts_cumulative_damage_by_about_70_percent() -> None:
    """Zelik et al. 2022, abstract: an exoskeleton giving 30 N*m of lumbar moment "is projected to reduce cumulative
    back damage by ~70%" (the source rounds; we get 68 %), whatever the task's own moment and repetitions."""
    for plm, lifts in [(60.0, 500), (120.0, 1200)]:
        cut = 1 - cumulative_damage([(plm - 30.0, lifts)]) / cumulative_damage([(plm, lifts)])
        assert round(cut, 1) == 0.7


def test_cumulative_damage_sums_tasks_and_zero_repetitions_give_no_damage_and_no_risk() -> None:
    assert cumulative_damage([(50.0, 0)]) == 0.0
    assert probability(0.0) == 0.0
    both = cumulative_damage([(50.0, 300), (80.0, 200)])
    assert both == pytest.approx(300 * damage_per_lift(50.0) + 200 * damage_per_lift(80.0))


def test_probability_is_one_half_where_the_logit_is_zero_and_rises_with_damage() -> None:
    """Y = 1.7229 + 1.0239 log10(CD) (v1.4.0; Zelik et al. 2022 round to 1.72 and 1.03): P = 0.5 at
    CD = 10^(-1.7229/1.0239) (a level's edge)."""
    edge = 10 ** (-BETA0 / BETA1)
    assert probability(edge) == pytest.approx(0.5, abs=1e-12)
    assert probability(edge * 0.99) < 0.5 < probability(edge * 1.01)
    assert probability(1.0) == pytest.approx(math.exp(1.7229) / (1 + math.exp(1.7229)))


def test_horizontal_distance_is_across_gravity_from_l5_s1_to_the_hands_midpoint() -> None:
    frame = SimpleNamespace(
        gravity=np.array([0.0, 0.0, -9.81]),
        tcp_position={"hand_r": np.array([-0.2, -0.5, 0.4]), "hand_l": np.array([0.2, -0.3, 0.4])},
        pos=lambda name: np.array([0.0, 0.0, 1.0]),
    )
    assert horizontal_distance(frame, ("hand_r", "hand_l")) == pytest.approx(0.4)
    assert horizontal_distance(frame, ("hand_r",)) == pytest.approx(math.hypot(0.2, 0.5))
