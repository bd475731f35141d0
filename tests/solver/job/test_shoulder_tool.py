"""The Shoulder Tool (Bani Hani et al. 2021, Ergonomics 64(1):39-54) with the strength, arm moment and risk curve of
the authors' calculator (Shoulder Tool v1.0.0): the paper's worked examples and the method on the example job.

Where the sources were read: the paper's text and the workbook's formula cells as transcribed (two passes) in
github.com/nbarr1/ErgonomicTool (methods/shoulder-tool/transcription/); the English-unit inputs and CDs of the
examples (Bani Hani 2019 dissertation, Appendix A) as quoted there by a second public note. We did not hold the
paper, the dissertation or the workbook ourselves."""

from __future__ import annotations

from pathlib import Path

import pytest

from solver.job.shoulder_tool import FT_LB, arm_moment, damage_per_cycle, level, probability, shoulder_moment

LB = 4.4482216152605  # N per pound-force
INCH = 0.0254  # m


def _job(load_n: float, lever_m: float, reps: int) -> tuple[float, float]:
    """(CD, P) of one shoulder's mono-task job."""
    cd = reps * damage_per_cycle(shoulder_moment(load_n, lever_m))
    return cd, probability(cd)


def test_paper_mono_task_a_load_at_41_cm_2880_times_a_day_is_a_20_8_percent_clinic_visit() -> None:
    """Bani Hani et al. 2021, p. 46: "a 9 N load is handled using the right shoulder and the lever arm is 41 cm. The
    repetitions per workday is 2880. The probability of a right shoulder outcome is relatively low at 20.8%." The
    calculator's inputs were 2 lb at 16 in (CD 0.00428, dissertation App. A); 9 N and 41 cm are their rounded
    metric values, with which we get 21.0 %."""
    cd, p = _job(2 * LB, 16 * INCH, 2880)
    assert round(cd, 5) == 0.00428 and round(p, 3) == 0.208
    assert _job(9.0, 0.41, 2880)[1] == pytest.approx(0.208, abs=0.003)


def test_paper_two_handed_45_N_panel_at_46_cm_4800_times_a_day() -> None:
    """Bani Hani et al. 2021, p. 47: a 45 N panel, 22.5 N in each hand, lever arm 46 cm, 4800 times per shift; the
    calculator's inputs were 5 lb per hand at 18 in: CD 0.03331, P 37.6 % (dissertation App. A); metric: 38.1 %."""
    cd, p = _job(5 * LB, 18 * INCH, 4800)
    assert round(cd, 5) == 0.03331 and round(p, 3) == 0.376
    assert _job(22.5, 0.46, 4800)[1] == pytest.approx(0.376, abs=0.006)


def test_arm_moment_is_the_calculators_three_piece_fit_in_ft_lb() -> None:
    assert arm_moment(1.7 * INCH) == 0.0
    assert arm_moment(16 * INCH) == pytest.approx((-8.27 + 4.8223 * 16) / 12 * FT_LB)
    assert arm_moment(27 * INCH) == arm_moment(40 * INCH) == pytest.approx(121.9 / 12 * FT_LB)


def test_no_damage_no_risk_and_the_papers_heat_map_edges() -> None:
    """P = 0 without damage; green at 25 % or less, red at 50 % or more (p. 51-52)."""
    assert probability(0.0) == 0.0
    assert [level(p) for p in (0.25, 0.2501, 0.4999, 0.5)] == [0, 1, 1, 2]


def test_the_example_job_rates_both_shoulders_and_the_worse_one_rules(example: tuple[dict, Path]) -> None:
    """The example box lift (10 kg, both hands, 800 lifts): 49 N per hand; each shoulder's peak moment is its
    per-frame maximum, and the job's CD is the larger shoulder's."""
    shoulder = example[0]["methods"]["shoulder_tool"]
    assert shoulder["load_per_hand_N"] == pytest.approx(10 * 9.81 / 2, rel=0.01)
    sides = shoulder["shoulders"]
    assert set(sides) == {"r", "l"}
    for s, side in sides.items():
        assert side["peak_moment_Nm"] == max(shoulder["per_frame"][f"shoulder_tool_moment_{s}_Nm"])
        assert 0.1 < side["lever_arm_m"] < 1.0
    assert shoulder["cumulative_damage"] == max(side["cumulative_damage"] for side in sides.values())
    assert 0 < shoulder["probability_clinic_visit"] < 1
