"""OWAS posture codes (Karhu, Kansi & Kuorinka 1977, Applied Ergonomics 8(4):199-201).

The four-digit code back-arms-legs-load, with the class boundaries of the usual OWAS summaries (e.g. the OWAS
(1980) method slides): back 1 straight, 2 bent (inclination > 20 deg), 3 twisted or bent sideways (> 20 deg),
4 bent and twisted; arms 1 both below shoulder level, 2 one, 3 both at or above it (an arm is "above" when its
elbow is above the shoulder joint); legs 1 sitting, 2 standing on both straight legs, 3 on one straight leg,
4 on both legs with knees bent, 5 on one bent leg, 6 kneeling, 7 walking; load 1 <= 10 kg, 2 10-20 kg,
3 > 20 kg. "Knee bent" is knee flexion beyond :data:`.options.KNEE_BENT_DEG` (PROJECT DEFAULT); a static pose
never gives 1 (the manikin has no seat support) or 7.

The OWAS action category (1-4) is a published 252-entry table that could not be transcribed from a verified
source for this version, so ``action_category`` is reported as null with that reason rather than guessed.
"""

from __future__ import annotations

from . import options as opt
from .frames import Frame

OWAS_TWIST_DEG = 20.0  # twisted / side bent beyond 20 deg (the OWAS summary quoted above)


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
    return dict(
        code=f"{back}{arms}{legs}{load}",
        back=back,
        arms=arms,
        legs=legs,
        load=load,
        action_category=None,
        reason="action category table not transcribed from a verified source; codes only",
    )
