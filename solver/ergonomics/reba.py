"""REBA, Rapid Entire Body Assessment (Hignett & McAtamney 2000, Applied Ergonomics 31:201-205).

Group A (trunk, neck, legs) and group B (upper arm, lower arm, wrist) bands follow the paper's tables 1-2 (as
reprinted in Hignett & McAtamney, "Rapid Entire Body Assessment", Handbook of Human Factors and Ergonomics
Methods, ch. 8, 2004, and the REBA employee assessment worksheet). Tables A, B and C are transcribed from
shared/reference/published_data.py (REBA_A/B/C). Load: 0 below 5 kg, +1 for 5-10 kg, +2 above 10 kg, +1 shock;
coupling good 0, fair 1, poor 2, unacceptable 3; activity +1 each for static (> 1 min), repeated (> 4/min).
Risk levels of the score: 1 negligible, 2-3 low, 4-7 medium, 8-10 high, 11+ very high. Angles are rounded to
whole degrees; word thresholds are the PROJECT DEFAULTS of :mod:`.options`. Both sides; ``score`` is the worse.
"""

from __future__ import annotations

from . import options as opt
from .base import Bands, FrameInputs, Score, Verdict

TABLE_A = {  # [trunk][neck][legs - 1]
    1: {1: [1, 2, 3, 4], 2: [1, 2, 3, 4], 3: [3, 3, 5, 6]},
    2: {1: [2, 3, 4, 5], 2: [3, 4, 5, 6], 3: [4, 5, 6, 7]},
    3: {1: [2, 4, 5, 6], 2: [4, 5, 6, 7], 3: [5, 6, 7, 8]},
    4: {1: [3, 5, 6, 7], 2: [5, 6, 7, 8], 3: [6, 7, 8, 9]},
    5: {1: [4, 6, 7, 8], 2: [6, 7, 8, 9], 3: [7, 8, 9, 9]},
}
TABLE_B = {  # [upper arm][lower arm][wrist - 1]
    1: {1: [1, 2, 2], 2: [1, 2, 3]},
    2: {1: [1, 2, 3], 2: [2, 3, 4]},
    3: {1: [3, 4, 5], 2: [4, 5, 5]},
    4: {1: [4, 5, 5], 2: [5, 6, 7]},
    5: {1: [6, 7, 8], 2: [7, 8, 8]},
    6: {1: [7, 8, 8], 2: [8, 9, 9]},
}
TABLE_C = [  # [score A - 1][score B - 1]
    [1, 1, 1, 2, 3, 3, 4, 5, 6, 7, 7, 7], [1, 2, 2, 3, 4, 4, 5, 6, 6, 7, 7, 8],
    [2, 3, 3, 3, 4, 5, 6, 7, 7, 8, 8, 8], [3, 4, 4, 4, 5, 6, 7, 8, 8, 9, 9, 9],
    [4, 4, 4, 5, 6, 7, 8, 8, 9, 9, 9, 9], [6, 6, 6, 7, 8, 8, 9, 9, 10, 10, 10, 10],
    [7, 7, 7, 8, 9, 9, 9, 10, 10, 11, 11, 11], [8, 8, 8, 9, 10, 10, 10, 10, 10, 11, 11, 11],
    [9, 9, 9, 10, 10, 10, 11, 11, 11, 12, 12, 12], [10, 10, 10, 11, 11, 11, 11, 12, 12, 12, 12, 12],
    [11, 11, 11, 11, 12, 12, 12, 12, 12, 12, 12, 12], [12] * 12,
]  # fmt: skip
COUPLING = {"good": 0, "fair": 1, "poor": 2, "unacceptable": 3}


def trunk(flexion: float) -> int:
    """1: upright; 2: 0-20 deg flexion or extension; 3: 20-60 flexion or > 20 extension; 4: > 60 flexion."""
    f = round(flexion)
    if f == 0:
        return 1
    if f < 0:
        return 2 if f >= -20 else 3
    return 2 if f <= 20 else 3 if f <= 60 else 4


def neck(flexion: float) -> int:
    """1: 0-20 deg flexion; 2: > 20 deg flexion or in extension."""
    f = round(flexion)
    return 1 if 0 <= f <= 20 else 2


def legs(bilateral: bool, knee_flexion: float) -> int:
    """1: bilateral weight bearing; 2: unilateral; +1 knee(s) 30-60 deg flexion; +2 above 60 deg."""
    k = round(knee_flexion)
    return (1 if bilateral else 2) + (2 if k > 60 else 1 if k >= 30 else 0)


def upper_arm(flexion: float, elevation: float) -> int:
    """1: 20 deg extension to 20 flexion; 2: > 20 extension or 20-45 flexion; 3: 45-90; 4: > 90 deg."""
    e = round(elevation)
    if flexion < 0 and e > 20:
        return 2
    return 1 if e <= 20 else 2 if e <= 45 else 3 if e <= 90 else 4


def lower_arm(elbow_flexion: float) -> int:
    """1: 60-100 deg flexion; 2: below 60 or above 100."""
    return 1 if 60 <= round(elbow_flexion) <= 100 else 2


def wrist(flexion: float) -> int:
    """1: 0-15 deg flexion or extension; 2: more than 15."""
    return 1 if abs(round(flexion)) <= 15 else 2


def load_score(load_kg: float, shock: bool) -> int:
    return (0 if load_kg < 5.0 else 1 if load_kg <= 10.0 else 2) + int(shock)


def risk(score: int) -> str:
    return (
        "negligible"
        if score <= 1
        else "low"
        if score <= 3
        else "medium"
        if score <= 7
        else ("high" if score <= 10 else "very high")
    )


def table_c(score_a: int, score_b: int) -> int:
    return TABLE_C[min(max(score_a, 1), 12) - 1][min(max(score_b, 1), 12) - 1]


def reba(posture: dict, load_kg: float, o: opt.ErgoOptions) -> dict:
    """REBA of both sides from :func:`.postures.measure` output; ``score`` is the worse side."""
    if "reason" in posture:
        return dict(score=None, reason=posture["reason"])
    tw = opt.TWIST_DEG
    trunk_s = trunk(posture["trunk_flexion"])
    trunk_s += int(abs(posture["trunk_twist"]) > tw or abs(posture["trunk_side_bend"]) > tw)
    neck_s = neck(posture["neck_flexion"]) + int(abs(posture["neck_twist"]) > tw or abs(posture["neck_side_bend"]) > tw)
    shares = [posture[s]["weight_share"] for s in ("l", "r")]
    bilateral = posture["supported_feet"] == 0 or all(w is not None and w >= opt.FEATHER_SHARE for w in shares)
    legs_s = legs(bilateral, max(posture["l"]["knee_flexion"], posture["r"]["knee_flexion"]))
    load = load_score(load_kg, o.shock)
    score_a = TABLE_A[min(trunk_s, 5)][min(neck_s, 3)][min(legs_s, 4) - 1] + load
    activity = int(o.activity == "static") + int(o.activity == "repeated")
    coupling = COUPLING[o.coupling]
    sides = {}
    for s in ("l", "r"):
        p = posture[s]
        ua = upper_arm(p["upper_arm_flexion"], p["upper_arm_elevation"])
        ua += int(p["upper_arm_abduction"] > opt.ABDUCTED_DEG) + int(p["shoulder_elevation"] > opt.SHOULDER_RAISED_DEG)
        la = lower_arm(p["elbow_flexion"])
        twisted = p["forearm_rotation_share"] > opt.TWIST_END_SHARE
        wr = wrist(p["wrist_flexion"]) + int(abs(p["wrist_deviation"]) > opt.NEUTRAL_DEG or twisted)
        score_b = TABLE_B[min(ua, 6)][min(la, 2)][min(wr, 3) - 1] + coupling
        score_c = table_c(score_a, score_b)
        sides[s] = dict(upper_arm=ua, lower_arm=la, wrist=wr, score_b=score_b, score_c=score_c,
                        score=score_c + activity)  # fmt: skip
    worst = max(sides, key=lambda s: sides[s]["score"])
    score = sides[worst]["score"]
    return dict(
        score=score, side=worst, risk=risk(score), trunk=trunk_s, neck=neck_s, legs=legs_s, load=load,
        load_kg=load_kg, score_a=score_a, coupling=coupling, activity=activity, left=sides["l"], right=sides["r"],
    )  # fmt: skip


class Reba(Score):
    """REBA's score (1-15) of the worse side and its risk level, with its parts (:func:`reba`)."""

    name = "reba"
    pose_only = True
    title = "REBA"
    source = "Hignett & McAtamney 2000, Appl. Ergon. 31:201-205"
    bands = Bands("REBA score", (0.5, 3.5, 7.5, 15.5), "1-3 negligible/low, 4-7 medium, 8+ high")

    def evaluate(self, inputs: FrameInputs) -> dict:
        return reba(inputs.posture, inputs.load_kg, inputs.options)

    def columns(self, first: dict) -> list[str]:
        return ["reba", "reba_risk"]

    def cells(self, frame: dict) -> list:
        return [frame["reba"]["score"], frame["reba"].get("risk")]

    def verdict(self, frame: dict) -> Verdict | None:
        """The score with its risk level (1-3 green, 4-7 yellow, 8+ red, as the scores plot's bands)."""
        entry = frame[self.name]
        score = entry.get("score")
        if score is None:
            return Verdict(f"{self.title} n/a", entry.get("reason"))
        return Verdict(self.brief(frame), f"{entry['risk']} risk", 0 if score <= 3 else 1 if score <= 7 else 2)
