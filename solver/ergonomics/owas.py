"""OWAS posture codes (Karhu, Kansi & Kuorinka 1977, Applied Ergonomics 8(4):199-201).

The four-digit code back-arms-legs-load, with the class boundaries of the usual OWAS summaries (e.g. the OWAS
(1980) method slides): back 1 straight, 2 bent (inclination > 20 deg), 3 twisted or bent sideways (> 20 deg),
4 bent and twisted; arms 1 both below shoulder level, 2 one, 3 both at or above it (an arm is "above" when its
elbow is above the shoulder joint); legs 1 sitting, 2 standing on both straight legs, 3 on one straight leg,
4 on both legs with knees bent, 5 on one bent leg, 6 kneeling, 7 walking; load 1 <= 10 kg, 2 10-20 kg,
3 > 20 kg. "Knee bent" is knee flexion beyond :data:`.options.KNEE_BENT_DEG` (PROJECT DEFAULT); a static pose
never gives 1 (the manikin has no seat support) or 7.

The action category (1-4) comes from the 252-entry OWAS table (Karhu, Kansi & Kuorinka 1977; Karhu et al. 1981).
No primary copy of the table could be read here, so it is transcribed from an implementation:
github.com/rs9000/ergonomics ``owas.py`` (commit 7c25f46). Twelve other public implementations were compared cell
by cell: 246 cells agree everywhere; the disputed cells are in :data:`DISPUTED` and are reported with the other
value. Category meanings: 1 normal posture, no action; 2 slightly harmful, corrective action in the near future;
3 distinctly harmful, corrective action as soon as possible; 4 extremely harmful, corrective action immediately.
"""

from __future__ import annotations

from ..io.result.frame import Frame
from . import options as opt
from .base import FrameInputs, Score, Verdict

OWAS_TWIST_DEG = 20.0  # twisted / side bent beyond 20 deg (the OWAS summary quoted above)

# ACTION_TABLE[back-1][arms-1][legs-1] = (category for load 1, 2, 3)
ACTION_TABLE = (
    (  # back 1 straight
        ((1, 1, 1), (1, 1, 1), (1, 1, 1), (2, 2, 2), (2, 2, 2), (1, 1, 1), (1, 1, 1)),
        ((1, 1, 1), (1, 1, 1), (1, 1, 1), (2, 2, 2), (2, 2, 2), (1, 1, 1), (1, 1, 1)),
        ((1, 1, 1), (1, 1, 1), (1, 1, 1), (2, 2, 3), (2, 2, 3), (1, 1, 1), (1, 1, 2)),
    ),
    (  # back 2 bent
        ((2, 2, 3), (2, 2, 3), (2, 2, 3), (3, 3, 3), (3, 3, 3), (2, 2, 2), (2, 3, 3)),
        ((2, 2, 3), (2, 2, 3), (2, 3, 3), (3, 4, 4), (3, 4, 4), (3, 3, 4), (2, 3, 4)),
        ((3, 3, 4), (2, 2, 3), (3, 3, 3), (3, 4, 4), (4, 4, 4), (4, 4, 4), (2, 3, 4)),
    ),
    (  # back 3 twisted or bent sideways
        ((1, 1, 1), (1, 1, 1), (1, 1, 2), (3, 3, 3), (4, 4, 4), (1, 1, 1), (1, 1, 1)),
        ((2, 2, 3), (1, 1, 1), (1, 1, 2), (4, 4, 4), (4, 4, 4), (3, 3, 3), (1, 1, 1)),
        ((2, 2, 3), (1, 1, 1), (2, 3, 3), (4, 4, 4), (4, 4, 4), (4, 4, 4), (1, 1, 2)),
    ),
    (  # back 4 bent and twisted
        ((2, 3, 3), (2, 2, 3), (2, 3, 3), (4, 4, 4), (4, 4, 4), (4, 4, 4), (2, 3, 4)),
        ((3, 3, 4), (2, 3, 4), (3, 3, 4), (4, 4, 4), (4, 4, 4), (4, 4, 4), (2, 3, 4)),
        ((4, 4, 4), (2, 3, 4), (3, 3, 4), (4, 4, 4), (4, 4, 4), (4, 4, 4), (2, 3, 4)),
    ),
)
# code: the value other public implementations of the table give instead
DISPUTED = {"1343": 2, "1353": 2, "1373": 1, "2253": 3, "3373": 1, "4132": 2}
ACTIONS = {
    1: "normal posture, no action needed",
    2: "slightly harmful, corrective action in the near future",
    3: "distinctly harmful, corrective action as soon as possible",
    4: "extremely harmful, corrective action immediately",
}


def action_category(back: int, arms: int, legs: int, load: int) -> int:
    """OWAS action category 1-4 of a posture code."""
    return ACTION_TABLE[back - 1][arms - 1][legs - 1][load - 1]


def back_code(posture: dict) -> int:
    bent = abs(posture["trunk_flexion"]) > opt.OWAS_BENT_DEG
    twisted = max(abs(posture["trunk_twist"]), abs(posture["trunk_side_bend"])) > OWAS_TWIST_DEG
    return 4 if bent and twisted else 3 if twisted else 2 if bent else 1


def legs_code(posture: dict, kneeling: bool) -> int:
    if kneeling:
        return 6
    shares = {s: posture[s]["weight_share"] for s in ("l", "r")}
    bent = {s: posture[s]["knee_flexion"] > opt.KNEE_BENT_DEG for s in ("l", "r")}
    standing_on = [s for s in ("l", "r") if shares[s] is not None and shares[s] >= opt.FEATHER_SHARE]
    if len(standing_on) == 2:
        return 4 if bent["l"] and bent["r"] else 2
    if len(standing_on) == 1:
        return 5 if bent[standing_on[0]] else 3
    return 2  # no contact forces in the result (balance off): taken as standing on both legs


def load_code(load_kg: float) -> int:
    return 1 if load_kg <= 10.0 else 2 if load_kg <= 20.0 else 3


def owas(frame: Frame, posture: dict, load_kg: float) -> dict:
    """OWAS codes of one frame; null with a reason for a body without a human posture."""
    if "reason" in posture:
        return dict(code=None, reason=posture["reason"])
    above = 0
    for s in ("l", "r"):
        elbow, gh = frame.pos(f"elbow_{s}_flexion"), frame.pos(f"shoulder_{s}_flexion")
        above += int(elbow[2] >= gh[2])
    kneeling = any(t.startswith("knee_") for t, _, _, _ in frame.contacts)
    back, arms, legs, load = back_code(posture), 1 + above, legs_code(posture, kneeling), load_code(load_kg)
    code = f"{back}{arms}{legs}{load}"
    category = action_category(back, arms, legs, load)
    out = dict(code=code, back=back, arms=arms, legs=legs, load=load, action_category=category,
               action=ACTIONS[category])  # fmt: skip
    if code in DISPUTED:
        out["table_note"] = f"published copies of the OWAS table disagree on {code}: {category} or {DISPUTED[code]}"
    return out


class Owas(Score):
    """The OWAS posture code of a frame and its action category (:func:`owas`); a code has no one number to
    plot or to take the peak of."""

    name = "owas"
    pose_only = True
    title = "OWAS"
    source = ("Karhu, Kansi & Kuorinka 1977, Appl. Ergon. 8(4):199-201; action categories transcribed from "
              "github.com/rs9000/ergonomics (disputed cells flagged)")  # fmt: skip
    value = None

    def evaluate(self, inputs: FrameInputs) -> dict:
        return owas(inputs.frame, inputs.posture, inputs.load_kg)

    def columns(self, first: dict) -> list[str]:
        return ["owas_code", "owas_category"]

    def cells(self, frame: dict) -> list:
        return [frame["owas"].get("code"), frame["owas"].get("action_category")]

    def brief(self, frame: dict) -> str | None:
        return f"OWAS {frame['owas'].get('code')}"

    def verdict(self, frame: dict) -> Verdict | None:
        """The code with its action category (1 green, 2 yellow, 3-4 red)."""
        entry = frame[self.name]
        category = entry.get("action_category")
        if category is None:
            return Verdict(f"{self.title} n/a", entry.get("reason"))
        return Verdict(self.brief(frame), f"action category {category}: {entry['action']}", min(category - 1, 2))

    def graph(self, frame: dict) -> float | None:
        """The action category (1-4): a code has no number to draw."""
        category = frame[self.name].get("action_category")
        return None if category is None else float(category)
