"""LiFFT, the Lifting Fatigue Failure Tool (Gallagher, Sesek, Schall & Huangfu 2017, "Development and validation of
an easy-to-use risk assessment tool for cumulative low back loading: The Lifting Fatigue Failure Tool (LiFFT)",
Applied Ergonomics 63:142-150): a daily dose of low-back loading by fatigue-failure theory.

Each lift's peak load moment PLM = the load's weight x the largest horizontal distance from the low back to the load
during the lift. The paper prints cycles to failure = 902,416 x exp(-0.162 x %US) (its eq. 1, %US the compression
as % of an average spine's ultimate strength, about 6 kN) and the inverse as damage per lift, but neither the
PLM -> %US regression nor the risk curve's coefficients. Those are taken from the authors' own calculator, the Excel
"LiFFT v1.4.0" (06/05/2018), whose formulas are, with the moment M in ft*lb (lever arm in inch / 12 x load in lb)::

    damage per lift  = 10^(-5.81636221052493 + 0.0222878437409416 x M)
    CD               = sum over tasks of lifts per day x damage per lift   (Palmgren-Miner)
    P(high-risk job) = exp(Y) / (1 + exp(Y)),  Y = 1.7229 + 1.0239 x log10(CD)

(a high-risk job: 12+ low-back injuries per 200,000 h worked, Marras et al. 1993). In N*m this is
exp(0.03785 x PLM) / 655,182, i.e. 1 / (902,416 x exp(-(0.038 x PLM + 0.32))) to the printed digits; Zelik et al.
2022 (Applied Ergonomics 99:103619, eq. 1) as quoted by two code repositories read 1,902,416 there, a damage 2.1x
lower that reproduces neither the paper's nor the calculator's worked example (see tests/solver/job/test_lifft.py).

Several tasks add up as the paper's and the calculator's multi-task form does (Palmgren-Miner): the job's CD is
the sum over its tasks of lifts per day x damage per lift, and P follows from that sum (:meth:`Lifft.combine`).

Here each motion is one task: its lift's PLM is the largest over the frames of the load's weight x the horizontal
distance from the lumbosacral joint (L5/S1, the body's ``l5_rx``) to the hands holding the load (their midpoint
for both hands); the lifts per day are the job's cycles per shift x lifts per cycle.
"""

from __future__ import annotations

import math

import numpy as np

from ..io.result.frame import Frame
from .base import JobInputs, Method, TaskResult, lever, verdict

FT_LB = 1.3558179483314004  # N*m per ft*lb (0.3048 m x 4.4482216152605 N): the calculator works in ft*lb
LOG10_SCALE = -5.81636221052493  # log10 damage per lift at no moment (LiFFT v1.4.0 workbook, damage cells)
LOG10_PER_FT_LB = 0.0222878437409416  # log10 damage per lift per ft*lb of peak load moment (same cells)
BETA0, BETA1 = 1.7229, 1.0239  # logistic model of a high-risk job on log10(CD) (LiFFT v1.4.0 workbook, N35)
SPINE = "l5_rx"  # the lumbosacral (L5/S1) joint the horizontal distance is measured from


def damage_per_lift(plm: float) -> float:
    """LiFFT damage of one lift with peak load moment ``plm`` (N*m); dimensionless."""
    return 10.0 ** (LOG10_SCALE + LOG10_PER_FT_LB * plm / FT_LB)


def cumulative_damage(tasks: list[tuple[float, float]]) -> float:
    """CD of a day's tasks, each (PLM N*m, lifts per day): the sum of lifts x damage per lift."""
    return sum(lifts * damage_per_lift(plm) for plm, lifts in tasks)


def probability(cd: float) -> float:
    """Probability (0-1) that a job of cumulative damage ``cd`` is a high-risk job; 0 for no damage (no lifts)."""
    if cd <= 0.0:
        return 0.0
    y = BETA0 + BETA1 * math.log10(cd)
    return 1.0 / (1.0 + math.exp(-y))


def horizontal_distance(frame: Frame, hands: tuple[str, ...]) -> float:
    """m from L5/S1 to the hands (their midpoint), across gravity."""
    down = frame.gravity / np.linalg.norm(frame.gravity)
    d = np.mean([frame.tcp_position[h] for h in hands], axis=0) - frame.pos(SPINE)
    return float(np.linalg.norm(d - np.dot(d, down) * down))


class Lifft(Method):
    name = "lifft"
    title = "LiFFT low-back cumulative damage"
    source = (
        "Gallagher, Sesek, Schall & Huangfu 2017, Applied Ergonomics 63:142-150 (LiFFT); damage and risk equations "
        "from the authors' calculator, LiFFT v1.4.0 (Excel, 06/05/2018)"
    )

    def evaluate(self, inputs: JobInputs) -> dict:
        job = inputs.job
        missing = [h for h in job.hands if h not in inputs.frames[0].tcp_position]
        if SPINE not in inputs.frames[0].index or missing:
            return dict(verdict=verdict(f"not rated: the manikin has no {SPINE} or {', '.join(missing)}", None))
        weight = job.load_mass * float(np.linalg.norm(inputs.frames[0].gravity))  # N
        distance = [horizontal_distance(f, job.hands) for f in inputs.frames]
        moment = [weight * d for d in distance]
        peak = int(np.argmax(moment))
        plm = moment[peak]
        per_lift = damage_per_lift(plm)
        cd = cumulative_damage([(plm, job.lifts)])
        p = probability(cd)
        number, at = inputs.frames[peak].number, inputs.frames[peak]
        hands = np.mean([at.tcp_position[h] for h in job.hands], axis=0)
        text = f"P(high-risk job) {100 * p:.0f} % (CD {cd:.3g}, PLM {plm:.0f} N*m at frame {number}, {job.lifts} lifts)"
        if p >= 0.5:
            text += ": more likely than not a high-risk job"
        return dict(
            verdict=verdict(text, 2 if p >= 0.5 else None, [number]),
            peak_load_moment_Nm=plm, peak_frame=number, horizontal_distance_m=distance[peak], load_weight_N=weight,
            lifts_per_shift=job.lifts, damage_per_lift=per_lift, cumulative_damage=cd, probability_high_risk=p,
            per_frame={"lifft_horizontal_distance_m": distance, "lifft_load_moment_Nm": moment},
            plot=dict(kind="line", y=["lifft_load_moment_Nm"], label="N*m", marks=[peak],
                      title="load moment about L5/S1 (LiFFT)"),
            levers=[lever(number, at.pos(SPINE), hands, distance[peak], "L5/S1 to the hands")],
        )  # fmt: skip

    def combine(self, job, tasks: list[TaskResult]) -> dict:
        """The job's CD: the sum of its tasks' (each lifts per shift x damage per lift at its PLM); P of that sum.
        The verdict names the task with the largest share of the damage."""
        if len(tasks) == 1:
            return tasks[0].result
        rated = [t for t in tasks if "cumulative_damage" in t.result]
        if not rated:
            return dict(verdict=verdict("not rated: no task could be rated", None))
        cd = sum(t.result["cumulative_damage"] for t in rated)
        p = probability(cd)
        share = {t.name: 100.0 * t.result["cumulative_damage"] / cd if cd > 0 else 0.0 for t in rated}
        drive = max(rated, key=lambda t: t.result["cumulative_damage"])
        r = drive.result
        text = (f"P(high-risk job) {100 * p:.0f} % (CD {cd:.3g} over {len(rated)} tasks; {drive.name} "
                f"{share[drive.name]:.0f} % of it: PLM {r['peak_load_moment_Nm']:.0f} N*m at frame {r['peak_frame']}, "
                f"{r['lifts_per_shift']} lifts)")  # fmt: skip
        if p >= 0.5:
            text += ": more likely than not a high-risk job"
        per_task = [dict(task=t.name, peak_load_moment_Nm=t.result["peak_load_moment_Nm"],
                         peak_frame=t.result["peak_frame"], lifts_per_shift=t.result["lifts_per_shift"],
                         damage_per_lift=t.result["damage_per_lift"], cumulative_damage=t.result["cumulative_damage"],
                         share_of_damage_pct=share[t.name]) for t in rated]  # fmt: skip
        return dict(verdict=verdict(text, 2 if p >= 0.5 else None, [r["peak_frame"]], drive.name),
                    lifts_per_shift=sum(t.result["lifts_per_shift"] for t in rated), cumulative_damage=cd,
                    probability_high_risk=p, driving_task=drive.name, per_task=per_task)  # fmt: skip
