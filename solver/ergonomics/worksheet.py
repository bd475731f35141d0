"""A per-frame worksheet like the thesis's SES result (Delfs 2012 §5.4, fig. 5.2): back bend, hands in the
standard working area, shoulder pose, neck, forces; each item green / yellow / red with its threshold stated.

Sources of the thresholds:

* Trunk inclination, lateral bend, head tilt and neck flexion: ISO 11226:2000 and EN 1005-4 guideline values as
  tabulated (green / yellow / red) in "A kinematic posture analysis of neurological assistants in their daily
  working practice - a pilot study", J. Occup. Med. Toxicol. 2020, doi:10.1186/s12995-020-00286-9, table 2:
  trunk 0-20 / 20-60 / >60 or extension; lateral +-10 / 10-20 / >20; head tilt 0-25 / 25-85 / >85 or
  backwards; neck (head to trunk) 0-25 / - / >25 or extension.
  Trunk twist uses the lateral bands (PROJECT DEFAULT; EN 1005-4 calls >= 10 deg clearly visible).
* Upper-arm elevation 0-20 / 20-60 / >60 deg: EN 1005-4 (as given in the Dassault Systemes 3DEXPERIENCE
  ergonomics help); the yellow band is "acceptable depending on frequency / holding time".
* Working area: the workspace box of thesis §6.1.2 from the manikin's own zero pose (:mod:`.manikin`); a hand up
  to 10 cm outside is yellow (PROJECT DEFAULT), farther is red.
* L4/L5 compression: NIOSH 1981 action limit 3400 N, maximum permissible limit 6400 N (:mod:`.loads`).
* Joint strength: the highest percent of strength of any joint, green <= 30 %, yellow <= 60 %, red above
  (PROJECT DEFAULT; the strengths themselves are partly estimates, see solver/body/humans/anthropometry.py).
"""

from __future__ import annotations

import math

import numpy as np

from ..io.result.frame import Frame
from .base import SEVERITY, FrameInputs, Score, Verdict
from .manikin import WorkingArea, feet_frame, to_feet

ISO = "ISO 11226 / EN 1005-4"
AREA_MARGIN_M = 0.10  # PROJECT DEFAULT: yellow up to 10 cm outside the working area
STRENGTH_BANDS = (30.0, 60.0)  # PROJECT DEFAULT: percent of strength, green / yellow upper bounds


def _band(value: float, green: float, yellow: float | None, negative_red: bool = True) -> str:
    v = round(value)
    if negative_red and v < 0:
        return "red"
    v = abs(v)
    if v <= green:
        return "green"
    return "yellow" if yellow is not None and v <= yellow else "red"


def _item(value, unit: str, level: str | None, threshold: str, source: str, **extra) -> dict:
    return dict(value=value, unit=unit, level=level, threshold=threshold, source=source, **extra)


def _missing(reason: str) -> dict:
    return _item(None, "", None, "", "", reason=reason)


def posture_items(posture: dict) -> dict:
    if "reason" in posture:
        r = posture["reason"]
        return {k: _missing(r) for k in ("back_bend", "back_twist", "neck", "head_tilt", "shoulder_l", "shoulder_r")}
    twist = max(abs(posture["trunk_side_bend"]), abs(posture["trunk_twist"]))
    items = dict(
        back_bend=_item(round(posture["trunk_flexion"], 1), "deg", _band(posture["trunk_flexion"], 20, 60),
                        "green 0-20, yellow 20-60, red > 60 deg forward or any extension", ISO),
        back_twist=_item(round(twist, 1), "deg", _band(twist, 10, 20, negative_red=False),
                         "green <= 10, yellow 10-20, red > 20 deg sideways bend or twist",
                         ISO + " (lateral bend); twist: project default"),
        neck=_item(round(posture["neck_flexion"], 1), "deg", _band(posture["neck_flexion"], 25, None),
                   "green 0-25 deg head flexion to the trunk, red > 25 or extension", ISO),
        head_tilt=_item(round(posture["head_tilt"], 1), "deg", _band(posture["head_tilt"], 25, 85),
                        "green 0-25, yellow 25-85, red > 85 deg forward or backwards", ISO),
    )  # fmt: skip
    for s in ("l", "r"):
        e = posture[s]["upper_arm_elevation"]
        items[f"shoulder_{s}"] = _item(
            round(e, 1), "deg", _band(e, 20, 60, negative_red=False),
            "green 0-20, yellow 20-60 (depends on frequency), red > 60 deg upper-arm elevation to the trunk",
            "EN 1005-4",
        )  # fmt: skip
    return items


def working_area_item(frame: Frame, area: WorkingArea | None, feet: tuple | None = None) -> dict:
    """``feet``: the frame's :func:`.manikin.feet_frame` if the caller has it."""
    feet = feet if feet is not None else feet_frame(frame.tcp_position, frame.tcp_rotation)
    hands = [t for t in ("hand_l", "hand_r") if t in frame.tcp_position]
    if area is None or feet is None or len(hands) < 2:
        return _missing("no working area: needs the human manikin (scenario or --manikin) with hands and feet")
    outside = {t: area.outside_by(to_feet(frame.tcp_position[t], feet)) for t in hands}
    worst = max(outside.values())
    level = "green" if worst <= 1e-3 else "yellow" if worst <= AREA_MARGIN_M else "red"
    return _item(
        round(worst, 3), "m outside", level,
        f"green: both palms inside the box; yellow: up to {AREA_MARGIN_M:.2f} m outside; red: farther",
        "box: Delfs 2012 §6.1.2 (manikin's zero pose); margin: project default",
        box=area.rounded(),
        outside={t: round(v, 3) for t, v in outside.items()},
    )  # fmt: skip


def force_items(frame: Frame, percent: np.ndarray, l4_l5: dict) -> dict:
    items = {}
    c = l4_l5.get("compression")
    if c is None:
        items["l4_l5_compression"] = _missing(l4_l5.get("reason", "no L4/L5"))
    else:
        items["l4_l5_compression"] = _item(
            round(c), "N", l4_l5["level"], "green < 3400 N, yellow 3400-6400 N, red > 6400 N",
            "NIOSH 1981 action / maximum limits; compression: estimate (single-muscle model)",
        )  # fmt: skip
    finite = np.where(np.isfinite(percent))[0]
    if len(finite) == 0:
        items["joint_strength"] = _missing("no joint strengths (no manikin and none in the result)")
    else:
        worst = int(finite[np.argmax(percent[finite])])
        value = float(percent[worst])
        g, y = STRENGTH_BANDS
        level = "green" if value <= g else "yellow" if value <= y else "red"
        items["joint_strength"] = _item(
            round(value, 1), "% of strength", level,
            f"green <= {g:g} %, yellow <= {y:g} %, red > {y:g} % (worst joint)",
            "project default bands; strengths: solver/body/humans/anthropometry.py", joint=frame.joint_names[worst],
        )  # fmt: skip
    return items


def worksheet(
    frame: Frame, posture: dict, percent: np.ndarray, l4_l5: dict, area: WorkingArea | None, feet: tuple | None = None
) -> dict:
    """All items of one frame, plus ``overall``: the worst level among them (``feet``: as :func:`working_area_item`)."""
    items = posture_items(posture)
    items["hands_working_area"] = working_area_item(frame, area, feet)
    items.update(force_items(frame, percent, l4_l5))
    order = {"green": 0, "yellow": 1, "red": 2}
    levels = [it["level"] for it in items.values() if it["level"] is not None]
    items["overall"] = max(levels, key=order.get) if levels else None
    return items


def level_number(level: str | None) -> float:
    """green 0, yellow 1, red 2 (NaN for none): for tables and plots."""
    return {"green": 0.0, "yellow": 1.0, "red": 2.0}.get(level, math.nan)


# The body angles a worksheet row shows (posture keys; (side, key) for each arm and leg), deg
ANGLES = [("trunk_flexion",), ("trunk_side_bend",), ("trunk_twist",), ("neck_flexion",), ("head_tilt",)]
ANGLES += [(s, k) for s in ("l", "r") for k in ("upper_arm_elevation", "elbow_flexion", "knee_flexion")]


def item_name(key: str) -> str:
    """An item's name as a person writes it: "shoulder_l" -> "left shoulder", "back_bend" -> "back bend"."""
    side = {"_l": "left ", "_r": "right "}.get(key[-2:], "")
    return side + (key[:-2] if side else key).replace("_", " ")


def _shown(item: dict) -> str:
    value = item["value"]
    return "n/a" if value is None else f"{value:g} {item['unit']}"


def _get(d: dict | None, *keys):
    for k in keys:
        if not isinstance(d, dict):
            return None
        d = d.get(k)
    return d


class Worksheet(Score):
    """The worksheet of a frame (:func:`worksheet`): its items' levels and the worst. Its CSV columns are the
    body angles and loads it is read from (trunk, neck, head, arms and knees in degrees, the L4/L5 flexion moment
    in N*m and compression in N, the joint with the highest percent of strength), then each item's level; its
    summary words are the L4/L5 compression and the worst level."""

    name = "worksheet"
    pose_only = True
    title = "worksheet"
    source = "Delfs 2012 §5.4 / fig. 5.2 (SES); thresholds ISO 11226, EN 1005-4, NIOSH 1981, project defaults"
    value = None

    def evaluate(self, inputs: FrameInputs) -> dict:
        loads = inputs.loads
        return worksheet(inputs.frame, inputs.posture, loads.percent, loads.l4_l5, inputs.area, inputs.feet)

    def sources(self) -> dict[str, str]:
        return {self.name: self.source, "working_area": "Delfs 2012 §6.1.2 workspace box from the manikin's zero pose"}

    def columns(self, first: dict) -> list[str]:
        header = ["_".join(a) if len(a) == 1 else f"{a[1]}_{a[0]}" for a in ANGLES]
        header += ["l4_l5_flexion_moment_Nm", "l4_l5_compression_N", "worst_joint", "worst_percent"]
        return header + [f"ws_{k}" for k in first["worksheet"] if k != "overall"] + ["ws_overall"]

    def cells(self, frame: dict) -> list:
        ws = frame["worksheet"]
        strength = ws.get("joint_strength", {})
        l45 = frame["joint_loads"]["l4_l5"]
        row = [_get(frame["posture"], *a) for a in ANGLES]
        row += [l45.get("flexion_moment"), l45.get("compression"), strength.get("joint"), strength.get("value")]
        return row + [ws[k]["level"] for k in ws if k != "overall"] + [ws["overall"]]

    def brief(self, frame: dict) -> str | None:
        c = frame["joint_loads"]["l4_l5"].get("compression")
        broken = str(frame.get("status", "")).startswith("NOT held")
        disc = "n/a" if c is None else ("not physical" if broken else f"{c:.0f} N")
        return f"L4/L5 {disc}, worksheet {frame['worksheet']['overall']}"

    def verdict(self, frame: dict) -> Verdict | None:
        """The words with the worst level and the items at that level (their values): what to change first."""
        ws = frame[self.name]
        overall = ws.get("overall")
        if overall is None:
            return Verdict(self.brief(frame))
        worst = [f"{item_name(k)} {_shown(it)}" for k, it in ws.items() if k != "overall" and it["level"] == overall]
        return Verdict(self.brief(frame), f"worst level {overall}: " + ", ".join(worst), SEVERITY[overall])

    def graph(self, frame: dict) -> float | None:
        """The worst level as a number: green 0, yellow 1, red 2."""
        overall = frame[self.name].get("overall")
        return None if overall is None else level_number(overall)

    def details(self, frame: dict) -> list[tuple[str, int | None]]:
        """Each item: its value, level and threshold ("back bend 65 deg: red (green 0-20, ...)")."""
        out = []
        for key, it in frame[self.name].items():
            if key == "overall":
                continue
            if it["level"] is None:
                out.append((f"{item_name(key)}: n/a ({it.get('reason', '')})", None))
            else:
                out.append((f"{item_name(key)} {_shown(it)}: {it['level']} ({it['threshold']})", SEVERITY[it["level"]]))
        return out
