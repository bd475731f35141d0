"""The Shoulder Tool (Bani Hani, Huangfu, Sesek, Schall, Davis & Gallagher 2021, "Development and validation of a
cumulative exposure shoulder risk assessment tool based on fatigue failure theory", Ergonomics 64(1):39-54): a daily
dose of shoulder loading by fatigue-failure theory, and the probability of a clinic visit for a shoulder disorder.

The paper prints the tendon S-N curve S = 101.25 - 14.83 log10(N) (eq. 1, S = % of ultimate strength), damage per
cycle = 1 / N, CD = sum of damage per cycle x repetitions (eq. 2) and P = exp(Y) / (1 + exp(Y)), Y = b0 + b1 log10(CD)
(eq. 3-4), the larger CD of the two shoulders rating the job, but neither the shoulder strength, the arm's own
moment nor b0 and b1. Those come from the authors' calculator, the Excel "Shoulder Tool v1.0.0" (6/11/2019), in
inch, lb and ft*lb: a "Handling Load" task's moment M = lever arm / 12 x load + the arm's moment, which is 0 below a
1.715 in lever arm, (-8.27 + 4.8223 x lever arm) / 12 up to 27 in and 121.9 / 12 beyond; S = 100 x M x 12 / 681
(681 in*lb: 3DSSPP's shoulder strength, 50th percentile male, standing); Y = 0.864 + 0.928 log10(CD).

Here each hand holding the load is one shoulder's task: its lever arm is the horizontal distance from that shoulder
(the body's ``shoulder_*_flexion`` joint) to the hand, its load the load's weight shared evenly between the hands
holding it (the paper's two-handed example); the peak moment over the motion counts once per lift (the job's cycles
per shift x lifts per cycle). Several tasks add up per shoulder (eq. 2's sum over tasks): each shoulder's CD is
the sum of its tasks', and the larger rates the job (:meth:`ShoulderTool.combine`).
"""

from __future__ import annotations

import math

import numpy as np

from .base import JobInputs, Method, TaskResult, verdict
from .base import lever as _lever  # "lever" names the lever arms below

INCH = 0.0254  # m
FT_LB = 1.3558179483314004  # N*m per ft*lb
STRENGTH = 681.0 * INCH * 4.4482216152605  # N*m: 681 in*lb, the calculator's shoulder strength
S_N = (101.25, 14.83)  # S = a - b log10(N), S in % of ultimate strength (eq. 1, Schechtman & Bader 1997)
BETA0, BETA1 = 0.864, 0.928  # clinic visit (first-time office visit) on log10(CD): the calculator's cell P35
SIDE = {"r": "right", "l": "left"}
ARM = {"r": ("shoulder_r_flexion", "hand_r"), "l": ("shoulder_l_flexion", "hand_l")}  # shoulder joint, hand TCP


def arm_moment(lever: float) -> float:
    """N*m the arm's own weight adds about the shoulder at a lever arm of ``lever`` m (the calculator's fit)."""
    inches = lever / INCH
    if inches < 1.715:
        return 0.0
    return (121.9 if inches >= 27.0 else -8.27 + 4.8223 * inches) / 12.0 * FT_LB


def shoulder_moment(load: float, lever: float) -> float:
    """N*m about the shoulder of a handled ``load`` (N) at ``lever`` m, with the arm's weight."""
    return load * lever + arm_moment(lever)


def damage_per_cycle(moment: float) -> float:
    """Damage of one exertion of ``moment`` N*m about the shoulder; dimensionless."""
    s = 100.0 * moment / STRENGTH
    return 10.0 ** (-(S_N[0] - s) / S_N[1])


def probability(cd: float) -> float:
    """Probability (0-1) of a clinic visit for a shoulder disorder at cumulative damage ``cd``; 0 for none."""
    if cd <= 0.0:
        return 0.0
    return 1.0 / (1.0 + math.exp(-(BETA0 + BETA1 * math.log10(cd))))


def level(p: float) -> int:
    """The paper's heat map: 0 (green) at 25 % or less, 2 (red) at 50 % or more, 1 between (p. 51-52)."""
    return 0 if p <= 0.25 else (2 if p >= 0.5 else 1)


class ShoulderTool(Method):
    name = "shoulder_tool"
    title = "The Shoulder Tool: shoulder cumulative damage"
    source = (
        "Bani Hani, Huangfu, Sesek, Schall, Davis & Gallagher 2021, Ergonomics 64(1):39-54 (The Shoulder Tool); "
        "strength, arm moment and risk coefficients from the authors' calculator, Shoulder Tool v1.0.0 (Excel, 2019)"
    )

    def evaluate(self, inputs: JobInputs) -> dict:
        job, first = inputs.job, inputs.frames[0]
        sides = [s for s, (j, h) in ARM.items() if h in job.hands and j in first.index and h in first.tcp_position]
        if not sides:
            reason = "not rated: the manikin has no shoulder joint or hand of the hands holding the load"
            return dict(verdict=verdict(reason, None))
        load = job.load_mass * float(np.linalg.norm(first.gravity)) / len(job.hands)  # N per hand
        per_frame, sides_out, marks, levers = {}, {}, [], []
        for s in sides:
            joint, hand = ARM[s]
            lever = [_horizontal(f, joint, hand) for f in inputs.frames]
            moment = [shoulder_moment(load, d) if load > 0 else 0.0 for d in lever]
            peak = int(np.argmax(moment))
            cd = job.lifts * damage_per_cycle(moment[peak]) if load > 0 else 0.0  # no load: no task (calculator)
            at = inputs.frames[peak]
            sides_out[s] = dict(peak_moment_Nm=moment[peak], lever_arm_m=lever[peak], load_N=load,
                                peak_frame=at.number, damage_per_cycle=damage_per_cycle(moment[peak]),
                                cumulative_damage=cd, probability_clinic_visit=probability(cd))  # fmt: skip
            per_frame[f"shoulder_tool_moment_{s}_Nm"] = moment
            marks.append(peak)
            levers.append(_lever(at.number, at.pos(joint), at.tcp_position[hand], lever[peak], f"{SIDE[s]} shoulder"))
        worst = max(sides_out, key=lambda s: sides_out[s]["cumulative_damage"])
        w = sides_out[worst]
        p = probability(w["cumulative_damage"])
        side = SIDE[worst]
        text = (f"P(shoulder clinic visit) {100 * p:.0f} % (CD {w['cumulative_damage']:.3g}, {side} shoulder, "
                f"{w['peak_moment_Nm']:.0f} N*m at frame {w['peak_frame']}, {job.lifts} lifts)")  # fmt: skip
        return dict(
            verdict=verdict(text, level(p), [w["peak_frame"]]), shoulders=sides_out, worst_shoulder=side,
            load_per_hand_N=load, lifts_per_shift=job.lifts, cumulative_damage=w["cumulative_damage"],
            probability_clinic_visit=p, per_frame=per_frame, levers=levers,
            plot=dict(kind="line", y=list(per_frame), label="N*m", marks=marks,
                      title="moment about each shoulder (The Shoulder Tool)"),
        )  # fmt: skip

    def combine(self, job, tasks: list[TaskResult]) -> dict:
        """Each shoulder's CD summed over the tasks; the larger rates the job; the verdict names its largest task."""
        if len(tasks) == 1:
            return tasks[0].result
        per_side: dict[str, list[tuple[TaskResult, dict]]] = {}
        for t in tasks:
            for s, r in t.result.get("shoulders", {}).items():
                per_side.setdefault(s, []).append((t, r))
        if not per_side:
            return dict(verdict=verdict("not rated: no task could be rated", None))
        cd = {s: sum(r["cumulative_damage"] for _, r in rows) for s, rows in per_side.items()}
        side = max(cd, key=cd.get)
        drive, r = max(per_side[side], key=lambda tr: tr[1]["cumulative_damage"])
        p = probability(cd[side])
        share = 100.0 * r["cumulative_damage"] / cd[side] if cd[side] > 0 else 0.0
        text = (f"P(shoulder clinic visit) {100 * p:.0f} % (CD {cd[side]:.3g} over {len(per_side[side])} tasks, "
                f"{SIDE[side]} shoulder; {drive.name} {share:.0f} % of it: {r['peak_moment_Nm']:.0f} N*m at frame "
                f"{r['peak_frame']}, {drive.result['lifts_per_shift']} lifts)")  # fmt: skip
        per_task = [
            dict(
                task=t.name,
                shoulder=SIDE[s],
                peak_moment_Nm=r["peak_moment_Nm"],
                peak_frame=r["peak_frame"],
                lifts_per_shift=t.result["lifts_per_shift"],
                damage_per_cycle=r["damage_per_cycle"],
                cumulative_damage=r["cumulative_damage"],
            )
            for s, rows in per_side.items()
            for t, r in rows
        ]
        return dict(verdict=verdict(text, level(p), [r["peak_frame"]], drive.name), worst_shoulder=SIDE[side],
                    cumulative_damage_right=cd.get("r", 0.0), cumulative_damage_left=cd.get("l", 0.0),
                    cumulative_damage=cd[side], probability_clinic_visit=p, driving_task=drive.name,
                    per_task=per_task)  # fmt: skip

    def detail(self, result: dict) -> list[tuple[str, list[str], list[list]]]:
        """Per shoulder: its lever arm, load share, moment, damage per cycle, CD and P; then the job's numbers."""
        header = ["shoulder", "lever arm (m)", "load share (N)", "peak moment (N*m)", "at frame", "damage per cycle",
                  "CD", "P(clinic visit)"]  # fmt: skip
        rows = [[SIDE[s], r["lever_arm_m"], r["load_N"], r["peak_moment_Nm"], r["peak_frame"], r["damage_per_cycle"],
                 r["cumulative_damage"], f"{100 * r['probability_clinic_visit']:.1f} %"]
                for s, r in result.get("shoulders", {}).items()]  # fmt: skip
        tables = [(f"{self.title}: per shoulder", header, rows)] if rows else []
        return tables + super().detail(result)


def _horizontal(frame, joint: str, hand: str) -> float:
    """m from the shoulder joint to the hand, across gravity."""
    down = frame.gravity / np.linalg.norm(frame.gravity)
    d = frame.tcp_position[hand] - frame.pos(joint)
    return float(np.linalg.norm(d - np.dot(d, down) * down))
