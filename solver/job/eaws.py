"""EAWS (Ergonomic Assessment Work-Sheet; Schaub, Caragnano, Britzke & Bruder 2013, "The European Assembly
Worksheet", Theoretical Issues in Ergonomics Science 14(6):616-639; the form v1.3.x): INPUTS ONLY, not a score.

What was read, in a stored copy of the form "Ergonomic Assessment Worksheet v1.3.6" (English): the overall result,
Whole Body = Postures + Forces + Loads + Extra (the higher of it and the Upper Limbs score rules), and its traffic
light: 0-25 points green (low risk), > 25-50 yellow (possible risk), > 50 red (high risk). The point tables of
sections 1 (postures), 2 (action forces), 3 (manual load handling) and 4 (upper limbs) were NOT read first-hand, so
no points are given here. What the motion can give the analyst is measured instead: the seconds per minute of the
work cycle spent in each trunk-flexion band and with the arms raised (section 1's inputs), and the load and its
handlings per shift (section 3's inputs). docs/guide/job.md ("EAWS") says what is missing.

Section 1 rates static postures, those held at least 4 s (two independent descriptions of the form agree: Haufe
Arbeitsschutz Office, "EAWS Modul 1: Körperhaltungen", and the ema software's user manual, "Ergonomie-Zwischenwerte";
shorter postures are rated with the cycle's main posture, rows 1-2 when standing). So each band also gives the time in
holds of at least 4 s (STATIC_HOLD); shorter stays in a band are counted in its total only. Several tasks: each
task's inputs, and the cycle's (:meth:`Eaws.combine`: each task's seconds in a band x its repetitions per cycle, per
minute of the cycle; the handlings of each load).
"""

from __future__ import annotations

from .base import JobInputs, Method, TaskResult, verdict

# (key, label, test on a frame's posture report); degrees. Bands as the form's section 1 rows are commonly named
# (upright / bent forward 20-60 deg / strongly bent > 60 deg; elbows at or above shoulder level; hands above head);
# the rows' exact definitions and points are in the form and its manual, not read here.
BANDS = (
    ("trunk_under_20", "trunk flexion < 20 deg", lambda p, _: p["trunk_flexion"] < 20.0),
    ("trunk_20_60", "trunk flexion 20-60 deg", lambda p, _: 20.0 <= p["trunk_flexion"] <= 60.0),
    ("trunk_over_60", "trunk flexion > 60 deg", lambda p, _: p["trunk_flexion"] > 60.0),
    ("elbow_at_or_above_shoulder", "an upper arm raised 90 deg or more",
     lambda p, s: max(p[k]["upper_arm_elevation"] for k in s) >= 90.0),
    ("hand_above_shoulder", "a hand above its shoulder", lambda p, s: any(p[k]["hand_above_shoulder"] for k in s)),
)  # fmt: skip
LIGHTS = ((25.0, "green", 0), (50.0, "yellow", 1), (float("inf"), "red", 2))
STATIC_HOLD = 4.0  # s: section 1 rates a posture held at least this long (module 1: "mindestens 4s")


def traffic_light(points: float) -> tuple[str, int]:
    """The form's traffic light of a total of ``points``: green 0-25, yellow > 25-50, red > 50; (colour, severity)."""
    for limit, colour, severity in LIGHTS:
        if points <= limit:
            return colour, severity
    raise AssertionError("unreachable")  # the last limit is infinite


def band_times(postures: list[dict | None], frame_time: float, cycle_time: float) -> dict[str, dict]:
    """Per band: frames, s in the motion and s per minute of the cycle (the form counts per minute); and the same
    for the frames in holds of at least STATIC_HOLD s (a run of consecutive frames in the band, n x frame_time s)."""
    out = {}
    for key, label, test in BANDS:
        inside = [_in_band(p, test) for p in postures]
        count = sum(inside)
        static = sum(run for run in _runs(inside) if run * frame_time >= STATIC_HOLD - 1e-9)
        seconds, static_seconds = count * frame_time, static * frame_time
        out[key] = dict(label=label, frames=count, seconds=seconds, s_per_min=60.0 * seconds / cycle_time,
                        static_frames=static, static_seconds=static_seconds,
                        static_s_per_min=60.0 * static_seconds / cycle_time)  # fmt: skip
    return out


def _in_band(p: dict | None, test) -> bool:
    """True when posture report ``p`` (None: not measured) lies in the band ``test`` describes."""
    sides = [s for s in ("l", "r") if p and isinstance(p.get(s), dict)]
    return bool(p and "trunk_flexion" in p and sides and test(p, sides))


def _runs(inside: list[bool]) -> list[int]:
    """Lengths of the runs of consecutive True values."""
    runs, n = [], 0
    for flag in inside + [False]:
        if flag:
            n += 1
        elif n:
            runs.append(n)
            n = 0
    return runs


class Eaws(Method):
    name = "eaws"
    title = "EAWS inputs (not scored)"
    source = (
        "Schaub, Caragnano, Britzke & Bruder 2013, Theor Issues Ergon Sci 14(6):616-639; the form Ergonomic "
        "Assessment Worksheet v1.3.6 (stored copy): total and traffic light only; point tables not read, not applied; "
        "static = held >= 4 s (Haufe, EAWS Modul 1; ema user manual)"
    )

    def evaluate(self, inputs: JobInputs) -> dict:
        postures = [f.get("posture") for f in inputs.ergo["frames"]]
        if not any(p and "trunk_flexion" in p for p in postures):
            return dict(verdict=verdict("not rated: the manikin's posture cannot be measured", None))
        bands = band_times(postures, inputs.frame_time, inputs.job.cycle_time)
        numbers = [f.number for f in inputs.frames]
        per_frame = {"eaws_trunk_flexion_deg": [p.get("trunk_flexion") if p else None for p in postures]}
        flexion = [p.get("trunk_flexion", -1e9) if p else -1e9 for p in postures]
        bent = [max(range(len(flexion)), key=flexion.__getitem__)]  # the most bent frame drives the inputs
        job = inputs.job
        times = "; ".join(f"{b['label']} {b['s_per_min']:.1f} s/min ({b['static_s_per_min']:.1f} in holds >= 4 s)"
                          for b in bands.values() if b["frames"])  # fmt: skip
        text = (
            f"not scored (the form's point tables were not read first-hand); per minute of the "
            f"{job.cycle_time:g} s cycle: {times}; load {job.load_mass:g} kg, {job.lifts} handlings per shift"
        )
        return dict(
            verdict=verdict(text, None, [numbers[bent[0]]]), scored=False, bands=bands,
            load_kg=job.load_mass, handlings_per_shift=job.lifts, per_frame=per_frame,
            plot=dict(kind="line", y=list(per_frame), label="deg", marks=bent,
                      title="trunk flexion (EAWS section 1 bands: 20 and 60 deg)"),
        )  # fmt: skip

    def detail(self, result: dict) -> list[tuple[str, list[str], list[list]]]:
        """The time in each posture band; then the single numbers."""
        rows = [[b["label"], b["frames"], b["seconds"], b["s_per_min"], b["static_seconds"], b["static_s_per_min"]]
                for b in result.get("bands", {}).values()]  # fmt: skip
        head = ["band", "frames", "s", "s per min of cycle", "s in holds >= 4 s", "of which per min"]
        tables = [("EAWS section 1 inputs: time in each posture band", head, rows)] if rows else []
        return tables + super().detail(result)

    def combine(self, job, tasks: list[TaskResult]) -> dict:
        """Per band, s per minute of the cycle over all tasks (each task's s x its repetitions per cycle); the loads
        and their handlings per shift per task; the verdict's frame the most bent one of the most bent task."""
        if len(tasks) == 1:
            return tasks[0].result
        rated = [t for t in tasks if "bands" in t.result]
        if not rated:
            return dict(verdict=verdict("not rated: the manikin's posture cannot be measured", None))
        bands = {}
        for key, label, _ in BANDS:
            seconds = sum(t.result["bands"][key]["seconds"] * t.per_cycle for t in rated)
            static = sum(t.result["bands"][key]["static_seconds"] * t.per_cycle for t in rated)
            bands[key] = dict(label=label, frames=sum(t.result["bands"][key]["frames"] for t in rated),
                              seconds=seconds, s_per_min=60.0 * seconds / job.cycle_time, static_seconds=static,
                              static_s_per_min=60.0 * static / job.cycle_time)  # fmt: skip
        times = "; ".join(f"{b['label']} {b['s_per_min']:.1f} s/min ({b['static_s_per_min']:.1f} in holds >= 4 s)"
                          for b in bands.values() if b["seconds"] > 0)  # fmt: skip
        loads = ", ".join(f"{t.name} {t.result['load_kg']:g} kg x {t.result['handlings_per_shift']}" for t in rated)
        bent = max(rated, key=lambda t: max(v for v in t.result["per_frame"]["eaws_trunk_flexion_deg"]
                                            if v is not None))  # fmt: skip
        text = (f"not scored (the form's point tables were not read first-hand); per minute of the {job.cycle_time:g} "
                f"s cycle, all {len(rated)} tasks: {times}; loads per shift: {loads}")  # fmt: skip
        per_task = [dict(task=t.name, repetitions_per_cycle=t.per_cycle, load_kg=t.result["load_kg"],
                         handlings_per_shift=t.result["handlings_per_shift"]) for t in rated]  # fmt: skip
        return dict(
            verdict=verdict(text, None, bent.frames, bent.name),
            scored=False,
            bands=bands,
            handlings_per_shift=sum(t.result["handlings_per_shift"] for t in rated),
            per_task=per_task,
        )
