"""Published body data for the human manikin, with sources; every value not from a source is marked ``# estimate``.

Lengths are fractions of stature H (dimensionless), masses fractions of body mass, angles in degrees (converted
to rad where the model is built), strengths in N*m.
"""

from __future__ import annotations

import math

G = 9.81  # m/s^2

# fmt: off
# ---- Drillis & Contini 1966 via Winter (2009), Biomechanics and Motor Control of Human Movement, Fig 4.1 ----
# Fractions of stature H. Transcribed from shared/reference/published_data.py (WINTER_H).
WINTER_H: dict[str, float] = dict(
    eye_height=0.936, chin_height=0.870, shoulder_height=0.818, chest_height=0.720, elbow_height=0.630,
    wrist_height=0.485, fingertip_height=0.377, hip_height=0.530, buttock_height=0.485, knee_height=0.285,
    ankle_height=0.039, head_length=0.130, shoulder_width=0.259, hip_width=0.191, nipple_width=0.174,
    foot_width=0.055, foot_length=0.152, upper_arm=0.186, forearm=0.146, hand=0.108, upper_body=0.520,
    thigh=0.245, shank=0.246,
)

# ---- de Leva 1996 (J Biomech 29(9):1223-1230), Table 4 ----
# segment: (endpoints, male mass fraction, male CM fraction, female mass fraction, female CM fraction);
# the CM fraction is measured from the FIRST endpoint. Transcribed from published_data.py (DELEVA).
DELEVA: dict[str, tuple[str, float, float, float, float]] = {
    "head":        ("VERT-MIDG", 0.0694, 0.5976, 0.0668, 0.5894),
    "trunk":       ("SUPR-MIDH", 0.4346, 0.4486, 0.4257, 0.4151),
    "upper_trunk": ("SUPR-XYPH", 0.1596, 0.2999, 0.1545, 0.2077),
    "mid_trunk":   ("XYPH-OMPH", 0.1633, 0.4502, 0.1465, 0.4512),
    "low_trunk":   ("OMPH-MIDH", 0.1117, 0.6115, 0.1247, 0.4920),
    "upper_arm":   ("SJC-EJC",   0.0271, 0.5772, 0.0255, 0.5754),
    "forearm":     ("EJC-WJC",   0.0162, 0.4574, 0.0138, 0.4559),
    "hand":        ("WJC-MET3",  0.0061, 0.7900, 0.0056, 0.7474),
    "thigh":       ("HJC-KJC",   0.1416, 0.4095, 0.1478, 0.3612),
    "shank":       ("KJC-AJC",   0.0433, 0.4395, 0.0481, 0.4352),
    "foot":        ("HEEL-TTIP", 0.0137, 0.4415, 0.0129, 0.4014),
}
# Segments that together make the whole body (the trunk enters through its three sub-segments).
BODY_SEGMENTS = ("head", "upper_trunk", "mid_trunk", "low_trunk") + ("upper_arm", "forearm", "hand",
                                                                     "thigh", "shank", "foot") * 2

# ---- Anderson, Madigan & Nussbaum 2007 (J Biomech 40:3105), Table 3: peak torque = c1 * m * g * H ----
# c1 for (male_18_25, female_18_25); transcribed from published_data.py (ANDERSON_C1, first two columns).
ANDERSON_C1: dict[tuple[str, str], tuple[float, float]] = {
    ("hip", "ext"): (0.161, 0.181), ("hip", "flex"): (0.113, 0.127),
    ("knee", "ext"): (0.163, 0.159), ("knee", "flex"): (0.087, 0.080),
    ("ankle", "pf"): (0.095, 0.104), ("ankle", "df"): (0.033, 0.027),
}

# ---- Range of motion, degrees: normal adult ranges, 38 CFR 4.71a Plates I-II (published_data.py ROM_DEG) ----
# The spine values come from the same regulation's notes and were not cross-checked (published_data.py says so).
ROM_DEG: dict[tuple[str, str], float] = {
    ("hip", "flexion"): 125, ("hip", "extension"): 30, ("hip", "abduction"): 45, ("hip", "adduction"): 25,
    ("hip", "external_rotation"): 60, ("hip", "internal_rotation"): 40,
    ("knee", "flexion"): 140, ("ankle", "dorsiflexion"): 20, ("ankle", "plantarflexion"): 45,
    ("shoulder", "flexion"): 180, ("shoulder", "abduction"): 180,
    ("shoulder", "external_rotation"): 90, ("shoulder", "internal_rotation"): 90,
    ("elbow", "flexion"): 145, ("forearm", "supination"): 85, ("forearm", "pronation"): 80,
    ("wrist", "extension"): 70, ("wrist", "flexion"): 80, ("wrist", "radial_deviation"): 20,
    ("wrist", "ulnar_deviation"): 45,
    ("cervical", "flexion"): 45, ("cervical", "extension"): 45, ("cervical", "lateral_flexion"): 45,
    ("cervical", "rotation"): 80, ("thoracolumbar", "flexion"): 90, ("thoracolumbar", "extension"): 30,
    ("thoracolumbar", "lateral_flexion"): 30, ("thoracolumbar", "rotation"): 30,
}
# fmt: on
GLENOHUMERAL_SHARE = 2.0 / 3.0  # estimate: the glenohumeral joint gives ~2/3 of arm elevation, the girdle the rest

# ---- Spine geometry (estimates) ----
LUMBAR = ("l5", "l4", "l3", "l2", "l1")
THORACIC = tuple(f"t{i}" for i in range(12, 0, -1))
CERVICAL = tuple(f"c{i}" for i in range(7, 0, -1))
VERTEBRA_HEIGHT_H = {"l": 0.0195, "t": 0.0135, "c": 0.0098}  # estimate: spine length split by region, / H
LUMBOSACRAL_H = 0.575  # estimate: height of the L5/S1 joint, / H
OMPH_SPLIT = 0.274  # estimate: OMPH above MIDH as a share of SUPR-MIDH (de Leva's mean sub-segment lengths)
XYPH_SPLIT = 0.321  # estimate: XYPH below SUPR as a share of SUPR-MIDH (de Leva's mean sub-segment lengths)

# ---- Other geometry (estimates), fractions of H unless noted ----
HIP_JOINT_SHARE = 0.5  # estimate: hip joint centres lie inside the trochanters: x_hip = 0.5 * hip_width / 2
EYE_FORWARD_H = 0.045  # estimate: eyes in front of the body line
STERNOCLAVICULAR_H = (-0.012, -0.040, 0.812)  # estimate: right SC joint (x, y from the body line, z)
ACROMIOCLAVICULAR_H = (-0.095, 0.005, 0.826)  # estimate: right AC joint (x, y from the body line, z)
GLENOHUMERAL_X_H = -0.110  # estimate: right GH joint x; its z is WINTER shoulder_height
MET3_HAND = 0.45  # estimate: knuckle line (MET3) below the wrist, share of WINTER hand length
PALM_HAND = 0.30  # estimate: palm centre below the wrist, share of WINTER hand length
PALM_DEPTH_H = 0.01  # estimate: palm surface from the hand's mid-plane
THUMB_BASE_HAND = 0.10  # estimate: thumb CMC below the wrist, share of hand length
FINGER_Y_H = {"index": -0.0165, "middle": -0.0055, "ring": 0.0055, "little": 0.0165}  # estimate: MCP spread
PHALANX_H = (0.025, 0.015, 0.012)  # estimate: proximal, middle, distal phalanx lengths
THUMB_BASE_Y_H = -0.015  # estimate: thumb CMC in front of the hand's mid-line
THUMB_H = (0.025, 0.017, 0.014)  # estimate: thumb metacarpal, proximal, distal lengths
MTP_FOOT = 0.73  # estimate: MTP line from the heel, share of foot length
MTP_HEIGHT_H = 0.01  # estimate: MTP joint height
FOOT_CM_HEIGHT = 0.5  # estimate: the foot CM lies at half the ankle height

# ---- Joint limits in degrees (lower = opposite motion, upper = named motion), by "<bone>_<motion>" ----
N_THORACOLUMBAR, N_CERVICAL = len(LUMBAR) + len(THORACIC), len(CERVICAL)
_TL = {
    k: ROM_DEG["thoracolumbar", k] / N_THORACOLUMBAR for k in ("flexion", "extension", "lateral_flexion", "rotation")
}
_CV = {k: ROM_DEG["cervical", k] / N_CERVICAL for k in ("flexion", "extension", "lateral_flexion", "rotation")}
# fmt: off
LIMITS_DEG: dict[str, tuple[float, float]] = {
    # each vertebra takes an equal share of its region's range
    "thoracolumbar_rx": (-_TL["extension"], _TL["flexion"]),
    "thoracolumbar_ry": (-_TL["lateral_flexion"], _TL["lateral_flexion"]),
    "thoracolumbar_rz": (-_TL["rotation"], _TL["rotation"]),
    "cervical_rx": (-_CV["extension"], _CV["flexion"]),
    "cervical_ry": (-_CV["lateral_flexion"], _CV["lateral_flexion"]),
    "cervical_rz": (-_CV["rotation"], _CV["rotation"]),
    "eyes_yaw": (-35.0, 35.0), "eyes_pitch": (-30.0, 45.0),  # estimate
    # girdle (estimates): with the glenohumeral 2/3 share the arm reaches about 180 degrees of elevation
    "clavicle_rx": (-20.0, 20.0), "clavicle_elevation": (-10.0, 30.0), "clavicle_protraction": (-20.0, 20.0),
    "scapula_tilt": (-30.0, 20.0), "scapula_upward_rotation": (-10.0, 30.0), "scapula_protraction": (-20.0, 20.0),
    "shoulder_flexion": (-40.0, GLENOHUMERAL_SHARE * ROM_DEG["shoulder", "flexion"]),  # extension 40: estimate
    "shoulder_abduction": (-30.0, GLENOHUMERAL_SHARE * ROM_DEG["shoulder", "abduction"]),  # adduction: estimate
    "shoulder_rotation": (-ROM_DEG["shoulder", "external_rotation"], ROM_DEG["shoulder", "internal_rotation"]),
    "elbow_flexion": (0.0, ROM_DEG["elbow", "flexion"]),
    "forearm_pronation": (-ROM_DEG["forearm", "supination"], ROM_DEG["forearm", "pronation"]),
    "wrist_flexion": (-ROM_DEG["wrist", "extension"], ROM_DEG["wrist", "flexion"]),
    "wrist_deviation": (-ROM_DEG["wrist", "ulnar_deviation"], ROM_DEG["wrist", "radial_deviation"]),
    "finger_mcp_flexion": (-20.0, 90.0), "finger_mcp_abduction": (-20.0, 20.0),  # estimate
    "finger_pip": (0.0, 100.0), "finger_dip": (0.0, 80.0),  # estimate
    "thumb_cmc_flexion": (-20.0, 50.0), "thumb_cmc_abduction": (0.0, 60.0),  # estimate
    "thumb_mcp": (0.0, 60.0), "thumb_ip": (0.0, 80.0),  # estimate
    "hip_flexion": (-ROM_DEG["hip", "extension"], ROM_DEG["hip", "flexion"]),
    "hip_abduction": (-ROM_DEG["hip", "adduction"], ROM_DEG["hip", "abduction"]),
    "hip_rotation": (-ROM_DEG["hip", "external_rotation"], ROM_DEG["hip", "internal_rotation"]),
    "knee_flexion": (0.0, ROM_DEG["knee", "flexion"]),
    "ankle_dorsiflexion": (-ROM_DEG["ankle", "plantarflexion"], ROM_DEG["ankle", "dorsiflexion"]),
    "ankle_inversion": (-15.0, 35.0), "toes_flexion": (-70.0, 40.0),  # estimate
}

# ---- Strength (capacity for negative moments, capacity for positive moments), N*m ----
# Hip, knee, ankle: Anderson et al. 2007 (see ANDERSON_C1), key -> (joint, negative, positive direction).
ANDERSON_JOINTS = {"hip_flexion": ("hip", "ext", "flex"), "knee_flexion": ("knee", "ext", "flex"),
                   "ankle_dorsiflexion": ("ankle", "pf", "df")}
# Upper body: one trained subject (rbdl GymnastWholeBody data, quoted in published_data.py): an upper bound.
STRENGTH_MEASURED: dict[str, tuple[float, float]] = {
    "shoulder_flexion": (127.0, 91.0), "elbow_flexion": (70.0, 101.0), "wrist_flexion": (16.0, 39.0),  # (ext, flex)
    "thoracolumbar_rx": (688.0, 212.0),  # (ext, flex): the lumbar value, used for each thoracolumbar joint
}
STRENGTH_ESTIMATE: dict[str, tuple[float, float]] = {  # estimate: no source at hand; by key, else by bone
    "thoracolumbar": (150.0, 150.0), "cervical_rx": (50.0, 30.0), "cervical": (30.0, 30.0),
    "clavicle": (60.0, 60.0), "scapula": (60.0, 60.0), "shoulder_abduction": (90.0, 90.0),
    "shoulder_rotation": (40.0, 40.0), "forearm": (10.0, 10.0), "wrist_deviation": (16.0, 16.0),
    "finger": (10.0, 10.0), "thumb": (10.0, 10.0), "hip_abduction": (120.0, 120.0), "hip_rotation": (60.0, 60.0),
    "ankle_inversion": (40.0, 40.0), "toes": (20.0, 20.0), "eyes": (1.0, 1.0),
}
# fmt: on


def segment(name: str, sex: str) -> tuple[float, float]:
    """(mass fraction, CM fraction from the first endpoint) of a de Leva segment for ``sex``."""
    row = DELEVA[name]
    return (row[1], row[2]) if sex == "male" else (row[3], row[4])


def mass_fractions(sex: str) -> dict[str, float]:
    """De Leva mass fractions for ``sex``, rescaled to sum to exactly 1 (the female column sums to 0.9999)."""
    total = sum(segment(s, sex)[0] for s in BODY_SEGMENTS)
    return {s: segment(s, sex)[0] / total for s in DELEVA if s != "trunk"}


def joint_strength(key: str, sex: str, mass: float, stature: float) -> tuple[float, float]:
    """(negative, positive) muscle capacity, N*m, of joint kind ``key`` for a body of ``mass`` kg, ``stature`` m."""
    if key in ANDERSON_JOINTS:  # Anderson et al. 2007, ages 18-25: c1 * m * g * H
        joint, negative, positive = ANDERSON_JOINTS[key]
        col, scale = (0 if sex == "male" else 1), mass * G * stature
        return (ANDERSON_C1[joint, negative][col] * scale, ANDERSON_C1[joint, positive][col] * scale)
    if key in STRENGTH_MEASURED:
        return STRENGTH_MEASURED[key]
    return STRENGTH_ESTIMATE[key] if key in STRENGTH_ESTIMATE else STRENGTH_ESTIMATE[key.split("_")[0]]


def limits_rad(key: str) -> tuple[float, float]:
    """Joint limits of joint kind ``key`` (see LIMITS_DEG), rad."""
    lo, hi = LIMITS_DEG[key]
    return math.radians(lo), math.radians(hi)
