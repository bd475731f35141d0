"""% capable (3DSSPP-style): for every frame, the share of men and of women whose static joint strength covers the
moment the solver computes at a joint (:mod:`solver.ergonomics.loads`, ``axis_moment``), the limiting joint, and the
job's minimum over the motion.

Strength: Anderson, Madigan & Nussbaum 2007, "Maximum voluntary joint torque as a function of joint angle and angular
velocity: model development and application to the lower limb", J Biomech 40(14):3105-3113, Table 3 (ages 18-25):
the isometric (zero-velocity) torque T = c1 x m g H x cos(c2 (theta - c3)), theta in rad (flexion / dorsiflexion
positive), m g H the body's weight x stature; the table gives the mean and SD of c1, c2, c3 per joint, direction and
sex. Here the strength of a sex is normal with that mean curve and an SD of SD(c1) x m g H x cos(c2 (theta - c3)) (the
SDs of c2 and c3 are not used), for Manikin's reference body of that sex (1.740 m, 72.7 kg; 1.610 m, 62.2 kg:
presets/manikins, 50th-percentile British stature, mass BMI 24 x stature^2), so % capable = Phi((mean - required) /
SD). A joint pushed into a limit of its range (a knee locked straight) leaves that moment to the limit, not the
muscles: it counts as 0 N*m there. Anderson's table covers the hip, knee and ankle only; the elbow, shoulder and
torso (L5/S1) are not rated: no published mean and SD of their strength could be read (docs/guide/job.md).
Several tasks: the job's minimum is the smallest over its tasks (:meth:`PercentCapable.combine`).
"""

from __future__ import annotations

import math

from .base import JobInputs, Method, TaskResult, verdict

G = 9.81  # m/s^2: Anderson et al. normalised by m x 9.81 x H
# (joint, direction) -> ((c1 mean, c1 SD), c2, c3) for (male, female), ages 18-25; direction "ext" = extensors
# (plantarflexors at the ankle), "flex" = flexors (dorsiflexors). Transcribed from rbdl's Millard2016TorqueMuscle.cc
# (Anderson2007Table3Mean / Anderson2007Table3Std); the means of c1 agree with shared/reference/published_data.py.
ANDERSON = {
    ("hip", "ext"): (((0.161, 0.049), 0.958, 0.932), ((0.181, 0.047), 0.697, 1.242)),
    ("hip", "flex"): (((0.113, 0.025), 0.738, -0.214), ((0.127, 0.033), 0.650, -0.350)),
    ("knee", "ext"): (((0.163, 0.040), 1.258, 1.133), ((0.159, 0.028), 1.187, 1.274)),
    ("knee", "flex"): (((0.087, 0.015), 0.869, 0.522), ((0.080, 0.015), 0.873, 0.635)),
    ("ankle", "ext"): (((0.095, 0.022), 1.391, 0.408), ((0.104, 0.034), 1.399, 0.424)),
    ("ankle", "flex"): (((0.033, 0.005), 1.510, -0.187), ((0.027, 0.006), 1.079, -0.302)),
}
SEXES = ("men", "women")
BODY = {"men": (72.7, 1.740), "women": (62.2, 1.610)}  # kg, m: Manikin's reference bodies (see above)
# joint of the model -> (Anderson's joint, side); positive joint value = flexion (dorsiflexion at the ankle)
JOINTS = {f"{j}_{s}_{axis}": (j, s) for j, axis in (("hip", "flexion"), ("knee", "flexion"),
                                                    ("ankle", "dorsiflexion")) for s in "rl"}  # fmt: skip
LIMIT_TOLERANCE = math.radians(0.5)  # rad: a joint this close to a limit of its range sits at it
NOT_RATED = ("elbow", "shoulder", "torso (L5/S1)")


def strength(joint: str, direction: str, sex: str, angle: float) -> tuple[float, float]:
    """(mean, SD) N*m of the static strength of ``joint``'s ``direction`` muscles ("ext" or "flex") for ``sex``
    ("men"/"women") at ``angle`` rad; both 0 where the curve's cosine is not positive."""
    (c1, sd), c2, c3 = ANDERSON[joint, direction][SEXES.index(sex)]
    mass, stature = BODY[sex]
    shape = max(math.cos(c2 * (angle - c3)), 0.0) * mass * G * stature
    return c1 * shape, sd * shape


def capable(required: float, mean: float, sd: float) -> float:
    """% of a normal population (``mean``, ``sd`` N*m) at least as strong as ``required`` N*m; nothing required:
    everyone."""
    if required <= 0.0:
        return 100.0
    if sd <= 0.0:
        return 100.0 if mean >= required else 0.0
    return 50.0 * (1.0 + math.erf((mean - required) / (sd * math.sqrt(2.0))))


def joint_capable(tau: float, angle: float, joint: str) -> dict[str, float]:
    """% of men and of women able to hold the axis moment ``tau`` N*m (the muscles must give -tau) at ``angle``."""
    need = -tau
    direction = "flex" if need > 0 else "ext"
    return {sex: capable(abs(need), *strength(joint, direction, sex, angle)) for sex in SEXES}


def at_limit(frame, name: str, tau: float) -> bool:
    """True when joint ``name`` sits at a limit of its range (within LIMIT_TOLERANCE) and the external moment
    ``tau`` N*m pushes it further into that limit."""
    i = frame.index[name]
    lower, upper = frame.joint_range[i]
    value = frame.joint_value[i]
    return bool((tau < 0 and value <= lower + LIMIT_TOLERANCE) or (tau > 0 and value >= upper - LIMIT_TOLERANCE))


class PercentCapable(Method):
    name = "capable"
    title = "% capable: share of men and women strong enough"
    source = (
        "strength: Anderson, Madigan & Nussbaum 2007, J Biomech 40(14):3105-3113, Table 3 (ages 18-25; mean and SD "
        "of c1, mean c2 and c3), for a reference man (1.740 m, 72.7 kg) and woman (1.610 m, 62.2 kg); "
        "% capable = Phi((mean - required) / SD) as in 3DSSPP (Chaffin, Andersson & Martin, Occupational "
        "Biomechanics); hip, knee and ankle only"
    )

    def evaluate(self, inputs: JobInputs) -> dict:
        frames, ergo = inputs.frames, inputs.ergo["frames"]
        rated = [n for n in JOINTS if n in frames[0].index]
        if not rated:
            return dict(verdict=verdict("not rated: the manikin has no hip, knee or ankle joint", None))
        per_frame: dict[str, list] = {f"capable_{s}_pct": [] for s in SEXES} | {"capable_limiting_joint": []}
        for name in rated:
            per_frame |= {f"capable_{name.rsplit('_', 1)[0]}_{s}_pct": [] for s in SEXES}
        for frame, report in zip(frames, ergo, strict=True):
            loads = report.get("joint_loads") or {}
            worst = {s: (101.0, "") for s in SEXES}
            for name in rated:
                tau = (loads.get(name) or {}).get("axis_moment")
                if tau is not None and at_limit(frame, name, tau):
                    tau = 0.0  # pushed into its limit (a knee locked straight): the limit holds it, not the muscles
                pct = joint_capable(tau, frame.value(name), JOINTS[name][0]) if tau is not None else None
                for s in SEXES:
                    per_frame[f"capable_{name.rsplit('_', 1)[0]}_{s}_pct"].append(pct[s] if pct else None)
                    if pct and pct[s] < worst[s][0]:
                        worst[s] = (pct[s], name.rsplit("_", 1)[0])
            for s in SEXES:
                per_frame[f"capable_{s}_pct"].append(worst[s][0] if worst[s][1] else None)
            per_frame["capable_limiting_joint"].append(worst["women"][1] or None)
        return self._summary(inputs, per_frame)

    def _summary(self, inputs: JobInputs, per_frame: dict[str, list]) -> dict:
        """The job's minimum per sex over the motion, its frame and limiting joint; the verdict and the plot."""
        numbers = [f.number for f in inputs.frames]
        out: dict = {}
        marks = []
        for s in SEXES:
            values = per_frame[f"capable_{s}_pct"]
            known = [i for i, v in enumerate(values) if v is not None]
            if not known:
                return dict(verdict=verdict("not rated: no joint moments in the motion", None), per_frame=per_frame)
            i = min(known, key=lambda k: values[k])
            joint = min((c for c in per_frame if c.endswith(f"_{s}_pct") and c != f"capable_{s}_pct"),
                        key=lambda c: per_frame[c][i] if per_frame[c][i] is not None else 101.0)  # fmt: skip
            out[f"minimum_{s}_pct"], out[f"minimum_{s}_frame"] = values[i], numbers[i]
            out[f"limiting_joint_{s}"] = joint[len("capable_") : -len(f"_{s}_pct")]
            marks.append(i)
        text = (f"{out['minimum_men_pct']:.0f} % of men (frame {out['minimum_men_frame']}, "
                f"{out['limiting_joint_men'].replace('_', ' ')}) and {out['minimum_women_pct']:.0f} % of women "
                f"(frame {out['minimum_women_frame']}, {out['limiting_joint_women'].replace('_', ' ')}) capable at "
                f"the weakest frame; hip, knee and ankle rated, {', '.join(NOT_RATED)} not")  # fmt: skip
        frames = sorted({out["minimum_men_frame"], out["minimum_women_frame"]})
        return out | dict(
            verdict=verdict(text, None, frames), not_rated=", ".join(NOT_RATED), per_frame=per_frame,
            plot=dict(kind="line", y=[f"capable_{s}_pct" for s in SEXES], label="% capable", marks=marks,
                      title="% of men and women capable, weakest rated joint"),
        )  # fmt: skip

    def combine(self, job, tasks: list[TaskResult]) -> dict:
        """Per sex, the minimum over the tasks; the verdict names each minimum's task; its frames are the women's."""
        if len(tasks) == 1:
            return tasks[0].result
        rated = [t for t in tasks if "minimum_women_pct" in t.result]
        if not rated:
            return dict(verdict=verdict("not rated: no task could be rated", None))
        out: dict = {}
        for s in SEXES:
            t = min(rated, key=lambda t: t.result[f"minimum_{s}_pct"])
            out |= {f"minimum_{s}_pct": t.result[f"minimum_{s}_pct"], f"minimum_{s}_task": t.name,
                    f"minimum_{s}_frame": t.result[f"minimum_{s}_frame"],
                    f"limiting_joint_{s}": t.result[f"limiting_joint_{s}"]}  # fmt: skip
        words = [
            f"{out[f'minimum_{s}_pct']:.0f} % of {s} ({out[f'minimum_{s}_task']}, frame "
            f"{out[f'minimum_{s}_frame']}, {out[f'limiting_joint_{s}'].replace('_', ' ')})"
            for s in SEXES
        ]
        text = (f"{' and '.join(words)} capable at the weakest frame of {len(rated)} tasks; hip, knee and ankle "
                f"rated, {', '.join(NOT_RATED)} not")  # fmt: skip
        per_task = [dict(task=t.name, minimum_men_pct=t.result["minimum_men_pct"],
                         minimum_women_pct=t.result["minimum_women_pct"]) for t in rated]  # fmt: skip
        return out | dict(verdict=verdict(text, None, [out["minimum_women_frame"]], out["minimum_women_task"]),
                          not_rated=", ".join(NOT_RATED), per_task=per_task)  # fmt: skip
