"""The sequence-level summary of the per-frame scores (:mod:`solver.ergonomics`: RULA, REBA, OWAS): the time the
motion spends at each RULA action level, REBA risk level and OWAS action category (s, % of the motion, % of the
work cycle), not only the worst frame. Each frame stands for 1/fps s. The levels are the sources' own (McAtamney &
Corlett 1993 for RULA, Hignett & McAtamney 2000 for REBA, Karhu, Kansi & Kuorinka 1977 for OWAS). Several tasks:
each task's table, and the job's time-weighted one (:meth:`Sequence.combine`: each task's seconds at a level x its
repetitions per shift, as minutes per shift and % of the tasks' time in the shift)."""

from __future__ import annotations

from .base import JobInputs, Method, TaskResult, verdict

REBA_RISKS = ("negligible", "low", "medium", "high", "very high")
# score: (entry key, its levels in order, how the level is named, severity of each level: as the ergo verdicts)
SCORES = {
    "rula": ("action_level", (1, 2, 3, 4), "RULA action level", (0, 1, 2, 2)),
    "reba": ("risk", REBA_RISKS, "REBA risk", (0, 0, 1, 2, 2)),
    "owas": ("action_category", (1, 2, 3, 4), "OWAS action category", (0, 1, 2, 2)),
}


def time_at_levels(levels: list, order: tuple, frame_time: float, cycle_time: float) -> list[dict]:
    """Per level of ``order``: frames, s, % of the motion, % of the cycle (``levels``: one per frame, None unrated)."""
    n = len(levels)
    out = []
    for level in order:
        count = sum(1 for v in levels if v == level)
        seconds = count * frame_time
        out.append(dict(level=level, frames=count, seconds=seconds, percent_of_motion=100.0 * count / n if n else 0.0,
                        percent_of_cycle=100.0 * seconds / cycle_time))  # fmt: skip
    return out


class Sequence(Method):
    name = "sequence"
    title = "Time at each RULA / REBA / OWAS level"
    source = "per-frame scores of solver.ergonomics (RULA, REBA, OWAS), summed over the motion's frames"

    def evaluate(self, inputs: JobInputs) -> dict:
        frames = inputs.ergo["frames"]
        numbers = [f["frame"] for f in frames]
        out: dict = {"per_frame": {}}
        texts, severity, drivers = [], 0, []
        for score, (key, order, what, severities) in SCORES.items():
            levels = [(f.get(score) or {}).get(key) for f in frames]
            table = time_at_levels(levels, order, inputs.frame_time, inputs.job.cycle_time)
            rated = [i for i, v in enumerate(levels) if v in order]
            if not rated:
                out[score] = dict(levels=table, worst=None)
                continue
            worst = max((levels[i] for i in rated), key=order.index)
            at_worst = [numbers[i] for i in rated if levels[i] == worst]
            row = table[order.index(worst)]
            out[score] = dict(levels=table, worst=worst, worst_frames=at_worst, unrated_frames=len(levels) - len(rated))
            out["per_frame"][f"{score}_{key}"] = levels
            texts.append(f"{what} {worst} for {row['seconds']:.1f} s ({row['percent_of_motion']:.0f} % of the motion)")
            severity = max(severity, severities[order.index(worst)])
            drivers.append(at_worst[0])
        out["verdict"] = verdict("; ".join(texts) or "not rated", severity if texts else None, sorted(set(drivers)))
        out["plot"] = dict(kind="levels", order={"reba_risk": list(REBA_RISKS)}, title="score levels over the motion")
        return out

    def detail(self, result: dict) -> list[tuple[str, list[str], list[list]]]:
        """Per score: the time at each of its levels."""
        tables = []
        for score in SCORES:
            levels = (result.get(score) or {}).get("levels") or []
            if levels and "minutes_per_shift" in levels[0]:  # the job's time-weighted table of several tasks
                rows = [[r["level"], r["minutes_per_shift"], r["percent_of_task_time"]] for r in levels]
                tables.append((f"{score.upper()}: time at each level over the shift (worst in: "
                               f"{', '.join(result[score].get('worst_tasks', []))})",
                               ["level", "min per shift", "% of the tasks' time"], rows))  # fmt: skip
            elif result.get(score):
                rows = [[r["level"], r["frames"], r["seconds"], r["percent_of_motion"], r["percent_of_cycle"]]
                        for r in result[score]["levels"]]  # fmt: skip
                worst = ", ".join(map(str, result[score].get("worst_frames", [])[:10]))
                tables.append((f"{score.upper()}: time at each level (worst frames: {worst})",
                               ["level", "frames", "s", "% of motion", "% of cycle"], rows))  # fmt: skip
        return tables

    def combine(self, job, tasks: list[TaskResult]) -> dict:
        """Per score and level: minutes per shift (each task's seconds x its repetitions per shift) and % of the
        tasks' time; the worst level over the tasks, the verdict naming the task reaching it first."""
        if len(tasks) == 1:
            return tasks[0].result
        weights = [t.repetitions for t in tasks] if any(t.repetitions for t in tasks) else [1] * len(tasks)
        total = sum(w * t.motion_time for w, t in zip(weights, tasks, strict=True))  # s of task time per shift
        out: dict = {"per_task": [dict(task=t.name, repetitions_per_shift=t.repetitions) for t in tasks]}
        texts, severity, frames, drive = [], 0, [], None
        for score, (_, order, what, severities) in SCORES.items():
            rated = [t for t in tasks if (t.result.get(score) or {}).get("worst") is not None]
            levels = [dict(level=lv, minutes_per_shift=sum(w * t.result[score]["levels"][i]["seconds"]
                                                           for w, t in zip(weights, tasks, strict=True)
                                                           if t.result.get(score)) / 60.0)
                      for i, lv in enumerate(order)]  # fmt: skip
            for row in levels:
                row["percent_of_task_time"] = 100.0 * 60.0 * row["minutes_per_shift"] / total if total else 0.0
            if not rated:
                out[score] = dict(levels=levels, worst=None)
                continue
            top = max((t.result[score]["worst"] for t in rated), key=order.index)
            at = [t for t in rated if t.result[score]["worst"] == top]
            row = levels[order.index(top)]
            out[score] = dict(levels=levels, worst=top, worst_tasks=[t.name for t in at])
            names = ", ".join(t.name for t in at)
            texts.append(f"{what} {top} for {row['minutes_per_shift']:.0f} min per shift "
                         f"({row['percent_of_task_time']:.0f} % of the tasks' time; in {names})")  # fmt: skip
            level_severity = severities[order.index(top)]
            if drive is None or level_severity > severity:  # the first score at the highest severity drives
                drive, frames = at[0], [at[0].result[score]["worst_frames"][0]]
            severity = max(severity, level_severity)
        text = "; ".join(texts) or "not rated"
        out["verdict"] = verdict(text, severity if texts else None, frames, drive.name if drive else None)
        return out
