"""% capable: the strength of Anderson, Madigan & Nussbaum 2007 (J Biomech 40(14):3105-3113, Table 3, ages 18-25)
for Manikin's reference man and woman, % capable = Phi((mean - required) / SD), on hand-made moments and the example.

Where the source was read: Table 3's means and SDs as transcribed in rbdl's Millard2016TorqueMuscle.cc
(Anderson2007Table3Mean / Anderson2007Table3Std); the means of c1 are those of shared/reference/published_data.py.
We did not hold the paper ourselves."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from solver.job.capable import ANDERSON, BODY, capable, joint_capable, strength

MGH_MAN = 72.7 * 9.81 * 1.740  # N*m: the reference man's weight x stature


def test_table_3_values_to_the_tables_three_decimals() -> None:
    """Anderson et al. 2007, Table 3, ages 18-25: knee extensors c1 0.163 (SD 0.040) for men, 0.159 (0.028) for
    women; hip extensors 0.161 (0.049) and 0.181 (0.047); ankle plantarflexors 0.095 (0.022), 0.104 (0.034)."""
    assert [ANDERSON["knee", "ext"][i][0] for i in (0, 1)] == [(0.163, 0.040), (0.159, 0.028)]
    assert [ANDERSON["hip", "ext"][i][0] for i in (0, 1)] == [(0.161, 0.049), (0.181, 0.047)]
    assert [ANDERSON["ankle", "ext"][i][0] for i in (0, 1)] == [(0.095, 0.022), (0.104, 0.034)]


def test_at_the_curves_peak_the_mean_strength_is_c1_m_g_h() -> None:
    """At theta = c3 (knee 1.133 rad, 65 deg, for men) T = c1 m g H: 0.163 x 72.7 x 9.81 x 1.74 = 202 N*m."""
    mean, sd = strength("knee", "ext", "men", 1.133)
    assert mean == pytest.approx(0.163 * MGH_MAN) and round(mean) == 202
    assert sd == pytest.approx(0.040 * MGH_MAN)
    mass, stature = BODY["women"]
    assert strength("knee", "ext", "women", 1.274)[0] == pytest.approx(0.159 * mass * 9.81 * stature)


def test_the_normal_distributions_edges_mean_one_and_two_sds() -> None:
    """Half the population holds its mean strength; mean - 1 SD: 84.1 %; mean + 2 SD: 2.3 %."""
    assert capable(100.0, 100.0, 10.0) == pytest.approx(50.0)
    assert round(capable(90.0, 100.0, 10.0), 1) == 84.1
    assert round(capable(120.0, 100.0, 10.0), 1) == 2.3
    assert capable(0.0, 0.0, 0.0) == 100.0 and capable(1.0, 0.0, 0.0) == 0.0 and capable(0.0, 1.0, 1.0) == 100.0


def test_the_muscles_answer_the_moments_sign_and_no_moment_is_everyone() -> None:
    """tau > 0 needs the extensors (negative direction), tau < 0 the flexors; 0 N*m: 100 % of both sexes."""
    knee = 1.133
    ext = strength("knee", "ext", "men", knee)
    flex = strength("knee", "flex", "men", knee)
    assert joint_capable(150.0, knee, "knee")["men"] == pytest.approx(capable(150.0, *ext))
    assert joint_capable(-50.0, knee, "knee")["men"] == pytest.approx(capable(50.0, *flex))
    assert all(v == pytest.approx(100.0) for v in joint_capable(0.0, knee, "knee").values())


def test_far_from_the_peak_the_curve_stops_at_zero() -> None:
    """Where cos(c2 (theta - c3)) <= 0 there is no strength: nobody holds any moment."""
    angle = 1.133 + math.pi / (2 * 1.258) + 0.1
    assert strength("knee", "ext", "men", angle) == (0.0, 0.0)
    assert joint_capable(1.0, angle, "knee")["men"] == 0.0


def test_the_example_job_has_a_curve_per_sex_and_its_minimum(example: tuple[dict, Path]) -> None:
    report, out = example
    result = report["methods"]["capable"]
    men, women = result["per_frame"]["capable_men_pct"], result["per_frame"]["capable_women_pct"]
    assert len(men) == len(women) == len(report["frames"])
    assert result["minimum_men_pct"] == pytest.approx(min(men)) and result["minimum_women_pct"] == min(women)
    assert all(0.0 <= v <= 100.0 for v in men + women)
    assert result["limiting_joint_women"] in {f"{j}_{s}" for j in ("hip", "knee", "ankle") for s in "rl"}
    assert result["verdict"]["frames"] and "elbow, shoulder, torso (L5/S1) not" in result["verdict"]["text"]
    header = (out / "job.csv").read_text().splitlines()[0].split(",")
    assert {"capable_men_pct", "capable_women_pct", "capable_limiting_joint", "capable_knee_l_women_pct"} <= set(header)
    assert "% of men and women capable" in (out / "job.html").read_text()


def test_a_one_frame_motion_is_rated(one_frame: tuple[dict, str]) -> None:
    """One frame: its values are the minimum."""
    result = one_frame[0]["methods"]["capable"]
    assert result["minimum_men_frame"] == 30 and result["minimum_men_pct"] == result["per_frame"]["capable_men_pct"][0]


def test_a_joint_pushed_into_its_limit_leaves_the_moment_to_the_limit() -> None:
    """A knee locked straight (at its 0 rad limit) under a hyperextending moment (tau < 0) needs no muscle; the same
    moment off the limit, or the opposite moment at it, does."""
    from types import SimpleNamespace

    import numpy as np

    from solver.job.capable import at_limit

    def knee(value: float) -> SimpleNamespace:
        return SimpleNamespace(index={"knee_r_flexion": 0}, joint_range=np.array([[0.0, 2.44]]),
                               joint_value=np.array([value]))  # fmt: skip

    assert at_limit(knee(0.0), "knee_r_flexion", -90.0)
    assert not at_limit(knee(0.1), "knee_r_flexion", -90.0) and not at_limit(knee(0.0), "knee_r_flexion", 90.0)
    assert at_limit(knee(2.44), "knee_r_flexion", 5.0)
