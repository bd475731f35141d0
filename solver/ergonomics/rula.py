"""RULA, Rapid Upper Limb Assessment (McAtamney & Corlett 1993, Applied Ergonomics 24(2):91-99).

Body-part scores follow the paper's figures 1-2 (ranges quoted below); tables A, B and C are transcribed from
shared/reference/published_data.py (RULA_A/B/C, cross-checked there against three implementations). Angles come
from :mod:`.postures` and are rounded to whole degrees before banding (the bands are whole degrees). Where the
paper uses words without a number ("twisted", "neutral", "evenly"), :mod:`.options` gives the PROJECT DEFAULT.
Both sides are scored; the report's ``score`` is the worse side.
"""

from __future__ import annotations

from . import options as opt
from .base import Bands, FrameInputs, Score, Verdict

# McAtamney & Corlett 1993, Table 1 ("Table A"): [upper arm-1][lower arm-1][(wrist-1)*2 + (twist-1)]
TABLE_A = [
    [[1, 2, 2, 2, 2, 3, 3, 3], [2, 2, 2, 2, 3, 3, 3, 3], [2, 3, 3, 3, 3, 3, 4, 4]],
    [[2, 3, 3, 3, 3, 4, 4, 4], [3, 3, 3, 3, 3, 4, 4, 4], [3, 4, 4, 4, 4, 4, 5, 5]],
    [[3, 3, 4, 4, 4, 4, 5, 5], [3, 4, 4, 4, 4, 4, 5, 5], [4, 4, 4, 4, 4, 5, 5, 5]],
    [[4, 4, 4, 4, 4, 5, 5, 5], [4, 4, 4, 4, 4, 5, 5, 5], [4, 4, 4, 5, 5, 5, 6, 6]],
    [[5, 5, 5, 5, 5, 6, 6, 7], [5, 6, 6, 6, 6, 7, 7, 7], [6, 6, 6, 7, 7, 7, 7, 8]],
    [[7, 7, 7, 7, 7, 8, 8, 9], [8, 8, 8, 8, 8, 9, 9, 9], [9, 9, 9, 9, 9, 9, 9, 9]],
]
# Table 2 ("Table B"): [neck-1][(trunk-1)*2 + (legs-1)]
TABLE_B = [
    [1, 3, 2, 3, 3, 4, 5, 5, 6, 6, 7, 7],
    [2, 3, 2, 3, 4, 5, 5, 5, 6, 7, 7, 7],
    [3, 3, 3, 4, 4, 5, 5, 6, 6, 7, 7, 7],
    [5, 5, 5, 6, 6, 7, 7, 7, 7, 7, 8, 8],
    [7, 7, 7, 7, 7, 8, 8, 8, 8, 8, 8, 8],
    [8, 8, 8, 8, 8, 8, 8, 9, 9, 9, 9, 9],
]
# Figure 6 ("Table C"): [min(score C, 8)-1][min(score D, 7)-1]
TABLE_C = [
    [1, 2, 3, 3, 4, 5, 5], [2, 2, 3, 4, 4, 5, 5], [3, 3, 3, 4, 4, 5, 6], [3, 3, 3, 4, 5, 6, 6],
    [4, 4, 4, 5, 6, 7, 7], [4, 4, 5, 6, 6, 7, 7], [5, 5, 6, 6, 7, 7, 7], [5, 5, 6, 7, 7, 7, 7],
]  # fmt: skip
ACTION_LEVELS = {  # the paper's action levels for the grand score
    1: "acceptable if not maintained or repeated for long periods",
    2: "further investigation needed, changes may be required",
    3: "investigation and changes required soon",
    4: "investigation and changes required immediately",
}


def upper_arm(flexion: float, elevation: float) -> int:
    """1: 20 deg extension to 20 deg flexion; 2: extension > 20 or flexion 20-45; 3: 45-90; 4: > 90 deg."""
    e = round(elevation)
    if flexion < 0 and e > 20:  # behind the trunk: extension
        return 2
    return 1 if e <= 20 else 2 if e <= 45 else 3 if e <= 90 else 4


def lower_arm(elbow_flexion: float) -> int:
    """1: 60-100 deg flexion; 2: below 60 or above 100 deg."""
    return 1 if 60 <= round(elbow_flexion) <= 100 else 2


def wrist(flexion: float) -> int:
    """1: neutral; 2: 0-15 deg flexion or extension; 3: more than 15 deg."""
    f = abs(round(flexion))
    return 1 if f <= opt.NEUTRAL_DEG else 2 if f <= 15 else 3


def neck(flexion: float) -> int:
    """1: 0-10 deg flexion; 2: 10-20; 3: more than 20; 4: in extension."""
    f = round(flexion)
    return 4 if f < 0 else 1 if f <= 10 else 2 if f <= 20 else 3


def trunk(flexion: float) -> int:
    """1: upright; 2: 0-20 deg flexion; 3: 20-60; 4: more than 60 (extension scored by its size: project default)."""
    f = abs(round(flexion))
    return 1 if f == 0 else 2 if f <= 20 else 3 if f <= 60 else 4


def force_score(load_kg: float, activity: str, shock: bool) -> int:
    """0: < 2 kg intermittent; 1: 2-10 kg intermittent; 2: 2-10 kg static/repeated or > 10 kg intermittent;
    3: > 10 kg static/repeated, or shocks."""
    if shock:
        return 3
    held = activity in ("static", "repeated")
    if load_kg < 2.0:
        return 0
    if load_kg <= 10.0:
        return 2 if held else 1
    return 3 if held else 2


def action_level(score: int) -> int:
    return 1 if score <= 2 else 2 if score <= 4 else 3 if score <= 6 else 4


def grand_score(score_c: int, score_d: int) -> int:
    return TABLE_C[min(max(score_c, 1), 8) - 1][min(max(score_d, 1), 7) - 1]


def rula(posture: dict, load_kg: float, o: opt.ErgoOptions) -> dict:
    """RULA of both sides from :func:`.postures.measure` output; ``score`` is the worse side."""
    if "reason" in posture:
        return dict(score=None, reason=posture["reason"])
    twisted = abs(posture["neck_twist"]) > opt.TWIST_DEG
    side_bent = abs(posture["neck_side_bend"]) > opt.TWIST_DEG
    neck_s = neck(posture["neck_flexion"]) + int(twisted) + int(side_bent)
    trunk_s = trunk(posture["trunk_flexion"]) + int(abs(posture["trunk_twist"]) > opt.TWIST_DEG)
    trunk_s += int(abs(posture["trunk_side_bend"]) > opt.TWIST_DEG)
    shares = [posture[s]["weight_share"] for s in ("l", "r")]
    # no contact forces in the result (balance off): taken as standing evenly on both feet
    even = posture["supported_feet"] == 0 or all(w is not None and w >= opt.EVEN_WEIGHT_SHARE for w in shares)
    legs_s = 1 if even else 2
    muscle = int(o.activity in ("static", "repeated"))
    force = force_score(load_kg, o.activity, o.shock)
    score_b = TABLE_B[min(neck_s, 6) - 1][(min(trunk_s, 6) - 1) * 2 + legs_s - 1]
    score_d = score_b + muscle + force
    sides = {}
    for s in ("l", "r"):
        p = posture[s]
        ua = upper_arm(p["upper_arm_flexion"], p["upper_arm_elevation"])
        ua += int(p["shoulder_elevation"] > opt.SHOULDER_RAISED_DEG) + int(p["upper_arm_abduction"] > opt.ABDUCTED_DEG)
        la = lower_arm(p["elbow_flexion"])
        la += int(p["hand_lateral"] < 0 or p["hand_lateral"] > p["shoulder_width_half"] + opt.OUT_TO_SIDE_M)
        wr = wrist(p["wrist_flexion"]) + int(abs(p["wrist_deviation"]) > opt.NEUTRAL_DEG)
        twist = 2 if p["forearm_rotation_share"] > opt.TWIST_END_SHARE else 1
        score_a = TABLE_A[min(ua, 6) - 1][min(la, 3) - 1][(min(wr, 4) - 1) * 2 + twist - 1]
        score_c = score_a + muscle + force
        g = grand_score(score_c, score_d)
        sides[s] = dict(upper_arm=ua, lower_arm=la, wrist=wr, wrist_twist=twist, score_a=score_a, score_c=score_c,
                        score=g)  # fmt: skip
    worst = max(sides, key=lambda s: sides[s]["score"])
    score = sides[worst]["score"]
    level = action_level(score)
    return dict(
        score=score, side=worst, action_level=level, action=ACTION_LEVELS[level], neck=neck_s, trunk=trunk_s,
        legs=legs_s, score_b=score_b, score_d=score_d, muscle_use=muscle, force_load=force, load_kg=load_kg,
        left=sides["l"], right=sides["r"],
    )  # fmt: skip


class Rula(Score):
    """RULA's grand score (1-7) of the worse side, with its parts (:func:`rula`)."""

    name = "rula"
    pose_only = True
    title = "RULA"
    source = "McAtamney & Corlett 1993, Appl. Ergon. 24(2):91-99"
    bands = Bands("RULA grand score", (0.5, 2.5, 4.5, 7.5), "1-2 acceptable, 3-4 investigate, 5+ change")

    def evaluate(self, inputs: FrameInputs) -> dict:
        return rula(inputs.posture, inputs.load_kg, inputs.options)

    def verdict(self, frame: dict) -> Verdict | None:
        """The grand score with its action level (1: green, 2: yellow, 3-4: red, as the scores plot's bands)."""
        entry = frame[self.name]
        level = entry.get("action_level")
        if level is None:
            return Verdict(f"{self.title} n/a", entry.get("reason"))
        return Verdict(self.brief(frame), f"action level {level}: {entry['action']}", min(level - 1, 2))
