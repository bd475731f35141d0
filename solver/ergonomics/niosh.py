"""Revised NIOSH lifting equation (Waters, Putz-Anderson, Garg & Fine 1993; NIOSH Applications Manual, DHHS
(NIOSH) Pub. 94-110, 1994, revised 2021) for the lift between two frames of a motion.

RWL = LC HM VM DM AM FM CM, LI = load / RWL (manual p. 1, 7). Metric: LC 23 kg, HM = 25/H, VM = 1 - 0.003|V - 75|,
DM = 0.82 + 4.5/D, AM = 1 - 0.0032 A (H, V, D in cm, A in degrees); U.S. units: LC 51 lb, HM = 10/H,
VM = 1 - 0.0075|V - 30|, DM = 0.82 + 1.8/D (inches). Restrictions (manual pp. 8-15): H below 25 cm is set to
25, above 63 cm HM = 0; V above 175 cm VM = 0; D below 25 cm is set to 25, above 175 cm DM = 0; A above 135 deg
AM = 0; F below 0.2 lifts/min is set to 0.2. FM from Table 5 (transcribed from published_data.py NIOSH_FM) by
the origin's V, linearly interpolated between frequencies (manual p. 7); CM from Table 7 (good 1.00; fair 0.95
below V = 75 cm, 1.00 above; poor 0.90) at the V of the point evaluated.

Measured on the manikin: the hands' point is the midpoint of the knuckles (``knuckles_l``/``knuckles_r`` TCPs,
the "large middle knuckle" of the manual); H is its horizontal distance from the midpoint between the ankle
joints, V its height above the floor, A the angle between the line from the ankles' midpoint to it and the
feet's forward direction (the mid-sagittal line), D = |V_destination - V_origin|.
LI levels (manual p. 20): <= 1 green (design goal), 1-3 yellow (increased risk for some workers), > 3 red.
"""

from __future__ import annotations

import math

import numpy as np

from ..body.spatial import length
from ..io.result.frame import Frame
from .base import FrameInputs, MotionScore
from .loads import hand_load_kg
from .manikin import feet_frame
from .options import ErgoOptions

FM_ROWS = (0.2, 0.5) + tuple(float(f) for f in range(1, 16))
# Table 5, per row: (<=1 h V<75, <=1 h V>=75, 1-2 h V<75, 1-2 h V>=75, 2-8 h V<75, 2-8 h V>=75)
FM_TABLE = (
    (1.00, 1.00, .95, .95, .85, .85), (.97, .97, .92, .92, .81, .81), (.94, .94, .88, .88, .75, .75),
    (.91, .91, .84, .84, .65, .65), (.88, .88, .79, .79, .55, .55), (.84, .84, .72, .72, .45, .45),
    (.80, .80, .60, .60, .35, .35), (.75, .75, .50, .50, .27, .27), (.70, .70, .42, .42, .22, .22),
    (.60, .60, .35, .35, .18, .18), (.52, .52, .30, .30, 0, .15), (.45, .45, .26, .26, 0, .13),
    (.41, .41, 0, .23, 0, 0), (.37, .37, 0, .21, 0, 0), (0, .34, 0, 0, 0, 0), (0, .31, 0, 0, 0, 0),
    (0, .28, 0, 0, 0, 0),
)  # fmt: skip
DURATION_COLUMN = {"short": 0, "moderate": 2, "long": 4}
CM_TABLE = {"good": (1.00, 1.00), "fair": (0.95, 1.00), "poor": (0.90, 0.90)}  # (V < 75 cm, V >= 75 cm)


def multipliers(h: float, v: float, d: float, a: float, units: str = "metric") -> dict:
    """HM, VM, DM, AM for H, V, D (cm, or inches with units="us") and A (deg), with the manual's limits."""
    if units == "us":
        h_min, h_max, v_opt, v_k, v_max, d_min, d_max, d_k = 10.0, 25.0, 30.0, 0.0075, 70.0, 10.0, 70.0, 1.8
    else:
        h_min, h_max, v_opt, v_k, v_max, d_min, d_max, d_k = 25.0, 63.0, 75.0, 0.003, 175.0, 25.0, 175.0, 4.5
    hm = 0.0 if h > h_max else h_min / max(h, h_min)
    vm = 0.0 if v > v_max or v < 0 else 1.0 - v_k * abs(v - v_opt)
    dm = 0.0 if d > d_max else 0.82 + d_k / max(d, d_min)
    am = 0.0 if a > 135.0 else 1.0 - 0.0032 * a
    return dict(HM=hm, VM=vm, DM=dm, AM=am)


def rwl(h: float, v: float, d: float, a: float, fm: float, cm: float, units: str = "metric") -> float:
    """Recommended weight limit (kg, or lb with units="us")."""
    m = multipliers(h, v, d, a, units)
    lc = 51.0 if units == "us" else 23.0
    return lc * m["HM"] * m["VM"] * m["DM"] * m["AM"] * fm * cm


def frequency_multiplier(frequency: float, duration: str, v_origin_cm: float) -> float:
    """FM from Table 5, linear between tabulated frequencies; 0 above 15 lifts/min."""
    col = DURATION_COLUMN[duration] + (1 if v_origin_cm >= 75.0 else 0)
    f = max(frequency, 0.2)
    if f > FM_ROWS[-1]:
        return 0.0
    values = [row[col] for row in FM_TABLE]
    return float(np.interp(f, FM_ROWS, values))


def coupling_multiplier(coupling: str, v_cm: float) -> float:
    """CM from Table 7 ("unacceptable" coupling, a REBA class, is taken as poor)."""
    low, high = CM_TABLE.get(coupling, CM_TABLE["poor"])
    return low if v_cm < 75.0 else high


def hand_point(frame: Frame, feet: tuple | None = None) -> dict | None:
    """H, V (cm) and A (deg) of the knuckles' midpoint in one frame; None without knuckles, ankles or feet.
    ``feet``: the frame's :func:`.manikin.feet_frame` if the caller has it."""
    ankles = ("ankle_l_dorsiflexion", "ankle_r_dorsiflexion")
    feet = feet if feet is not None else feet_frame(frame.tcp_position, frame.tcp_rotation)
    if not {"knuckles_l", "knuckles_r"} <= set(frame.tcp_position) or not frame.has(*ankles) or feet is None:
        return None
    hands = 0.5 * (frame.tcp_position["knuckles_l"] + frame.tcp_position["knuckles_r"])
    ankle = 0.5 * (frame.pos(ankles[0]) + frame.pos(ankles[1]))
    line = hands - ankle
    line[2] = 0.0
    _, forward, left = feet
    h = length(line)
    a = abs(math.degrees(math.atan2(line @ left, line @ forward))) if h > 1e-9 else 0.0
    return dict(H=100.0 * h, V=100.0 * float(hands[2]), A=a)


def _point(p: dict, d: float, fm: float, coupling: str) -> dict:
    cm = coupling_multiplier(coupling, p["V"])
    m = multipliers(p["H"], p["V"], d, p["A"])
    value = 23.0 * m["HM"] * m["VM"] * m["DM"] * m["AM"] * fm * cm
    return dict(p, D=d, **m, FM=fm, CM=cm, RWL=value)


def lift_between(first: Frame, last: Frame, o: ErgoOptions) -> dict:
    """The lift from frame ``first`` to frame ``last`` (the same object for a one-frame lift)."""
    start, end = hand_point(first), hand_point(last)
    if start is None or end is None:
        return dict(LI=None, reason="no knuckles, ankles or feet TCPs: the body is not the human manikin")
    notes = []
    d = abs(end["V"] - start["V"])
    if first is last:
        d = 100.0 * o.travel if o.travel is not None else 25.0
        notes.append("one frame: origin = destination; D from --travel" if o.travel is not None
                     else "one frame: origin = destination; D unknown, the manual's minimum 25 cm used")  # fmt: skip
    load = o.load_mass if o.load_mass is not None else hand_load_kg(first)
    fm = frequency_multiplier(o.frequency, o.duration, start["V"])
    origin = dict(frame=first.number, **_point(start, d, fm, o.coupling))
    destination = dict(frame=last.number, **_point(end, d, fm, o.coupling))
    governing = min(origin["RWL"], destination["RWL"]) if o.destination_control else origin["RWL"]
    li = load / governing if governing > 0 else (math.inf if load > 0 else 0.0)
    level = "green" if li <= 1.0 else "yellow" if li <= 3.0 else "red"
    return dict(
        origin=origin, destination=destination, load_kg=load, frequency=o.frequency, duration=o.duration,
        coupling=o.coupling, destination_control=o.destination_control, RWL=governing,
        LI=li if math.isfinite(li) else None, level=level, notes=notes,
        source="Waters et al. 1993; NIOSH Applications Manual (Pub. 94-110)",
    )  # fmt: skip


def at_frame(frame: Frame, d: float, fm: float, coupling: str) -> dict | None:
    """H, V, A and the RWL (kg) of one frame's hand point with the lift's D and FM (None if not human)."""
    p = hand_point(frame)
    return None if p is None else _point(p, d, fm, coupling)


def at_point(point: dict | None, lift: dict, coupling: str) -> dict | None:
    """:func:`at_frame` for a frame's :func:`hand_point` and the motion's :func:`lift` (its D and FM; D 25 cm and
    FM 1 when the lift has no origin)."""
    if point is None:
        return None
    d = lift["origin"]["D"] if "origin" in lift else 25.0
    fm = lift["origin"]["FM"] if "origin" in lift else 1.0
    return _point(point, d, fm, coupling)


def _get(entry: dict | None, key: str):
    return entry.get(key) if isinstance(entry, dict) else None


class Niosh(MotionScore):
    """The revised NIOSH lifting equation for the lift from the options' origin frame to their destination frame
    (:func:`lift_between`, the report's top-level ``niosh``), then H, V, A and the RWL at every frame
    (:func:`at_point`). A study records the lifting index and the RWL of a lift with a load in the hands."""

    name = "niosh"
    pose_only = True
    title = "NIOSH"
    source = "Waters et al. 1993; NIOSH Applications Manual for the Revised Lifting Equation, Pub. 94-110"

    def ends(self, options: ErgoOptions) -> dict[str, int | None]:
        return {"origin": options.origin, "destination": options.destination}

    def motion(self, start: Frame, end: Frame, options: ErgoOptions) -> dict:
        return lift_between(start, end, options)

    def keep(self, frame: Frame) -> dict | None:
        return hand_point(frame)

    def at_frame(self, kept: dict | None, motion: dict, options: ErgoOptions) -> dict | None:
        return at_point(kept, motion, options.coupling)

    def evaluate(self, inputs: FrameInputs) -> dict | None:
        """:meth:`at_frame` of :meth:`keep`, the frame's feet frame taken from ``inputs``."""
        return at_point(hand_point(inputs.frame, inputs.feet), inputs.motion[self.name], inputs.options.coupling)

    def columns(self, first: dict) -> list[str]:
        return ["niosh_H_cm", "niosh_V_cm", "niosh_A_deg", "niosh_RWL_kg"]

    def cells(self, frame: dict) -> list:
        return [_get(frame.get(self.name), k) for k in ("H", "V", "A", "RWL")]

    def study_columns(self) -> list[str]:
        return ["niosh_li", "niosh_rwl_kg"]

    def summarise(self, report: dict) -> dict:
        """The lifting index and the governing RWL (kg) of a human body's lift with a load in the hands, else
        None; an RWL of 0 (outside the equation's limits) is an index of inf."""
        lift = report.get(self.name) or {}
        lifting = "origin" in lift and lift.get("load_kg", 0.0) > 0.0
        li = lift.get("LI") if lifting else None
        li = math.inf if lifting and li is None else li
        return dict(niosh_li=None if li is None else round(li, 4),
                    niosh_rwl_kg=round(lift["RWL"], 3) if lifting else None)  # fmt: skip

    def motion_lines(self, report: dict) -> list[str]:
        lift = report[self.name]
        if lift.get("LI") is None:
            return []
        return [f"NIOSH lift: RWL {lift['RWL']:.1f} kg, load {lift['load_kg']:.1f} kg, LI {lift['LI']:.2f}"]
