"""Optional measurements of a human body (m) and the segment lengths they give; the rest stay stature fractions.

A body TOML may add any subset of :data:`MEASUREMENTS` to ``[body]`` (sex, stature and mass stay required)::

    sitting_height = 0.92     # m, erect, seat to vertex: splits stature into legs and trunk + head
    shoulder_breadth = 0.41   # m, biacromial: the acromioclavicular and glenohumeral joints' lateral offsets
    upper_arm_length = 0.335  # m, acromion to radiale: the shoulder-elbow segment
    forearm_length = 0.268    # m, radiale to stylion: the elbow-wrist segment
    hip_breadth = 0.35        # m, standing, across the hips: Winter's hip width (it places the hip joints)
    foot_length = 0.27        # m, heel to the longest toe: Winter's foot length

How each one acts (every length not named here stays Winter's fraction of stature, masses stay de Leva's
fractions of body mass):

- ``sitting_height``: the stature stays the body's height; the hip joints move down (or up) by the sitting
  height's excess over its nominal value, the legs (thigh, shank, ankle height) scale to the new hip height and
  everything above the hips (spine, shoulders, neck, head, eyes) stretches to fill the rest, so a longer trunk
  means shorter legs. The nominal value is the ANSUR II mean ratio to stature (below).
- ``shoulder_breadth``, ``upper_arm_length``, ``forearm_length``: the model has joint centres, the survey
  surface landmarks, so each scales its model length by the measurement over its nominal value (the ANSUR II mean
  ratio times stature).
- ``hip_breadth``, ``foot_length``: the same definitions as Winter's hip width and foot length; used as given.
"""

from __future__ import annotations

from collections.abc import Mapping

from ...errors import ModelError, is_number
from . import anthropometry as A

# Allowed range of each measurement as a fraction of stature. Every subject of the ANSUR II public data (below)
# lies inside; the margins beyond them are an estimate.
MEASUREMENTS: dict[str, tuple[float, float]] = {
    "sitting_height": (0.44, 0.62),
    "shoulder_breadth": (0.16, 0.30),
    "upper_arm_length": (0.15, 0.23),
    "forearm_length": (0.10, 0.19),
    "hip_breadth": (0.13, 0.32),
    "foot_length": (0.12, 0.19),
}
# Nominal measurement / stature, (male, female): means over subjects of the ratio in the ANSUR II public data
# (Gordon et al. 2014, NATICK/TR-15/007; 4082 men, 1986 women), computed by us, see solver/population/ansur2.py.
NOMINAL_H: dict[str, tuple[float, float]] = {
    "sitting_height": (0.5231, 0.5262),  # sittingheight
    "shoulder_breadth": (0.2368, 0.2244),  # biacromialbreadth
    "upper_arm_length": (0.1909, 0.1911),  # acromionradialelength
    "forearm_length": (0.1525, 0.1482),  # radialestylionlength
}
# Winter's landmark heights (fractions of stature) that the sitting height moves.
HEIGHTS = tuple(k for k in A.WINTER_H if k.endswith("_height"))


def validate_measurements(measures: Mapping, stature: float) -> dict[str, float]:
    """The measurements as floats (m); a ModelError names the first unknown key or value out of its range."""
    out = {}
    for key, value in measures.items():
        if key not in MEASUREMENTS:
            raise ModelError(f"unknown measurement {key!r} (known: {', '.join(MEASUREMENTS)})")
        lo, hi = (f * stature for f in MEASUREMENTS[key])
        what = f"a number in [{lo:.3f}, {hi:.3f}] m ({MEASUREMENTS[key][0]}-{MEASUREMENTS[key][1]} x stature)"
        if not is_number(value):
            raise ModelError(f"{key} must be {what}, got {value!r}")
        if not lo <= value <= hi:
            raise ModelError(f"{key} must be {what}, got {value}")
        out[key] = float(value)
    return out


def nominal(key: str, sex: str, stature: float) -> float:
    """The nominal value (m) of measurement ``key`` for ``sex`` and ``stature`` (m): the ANSUR II mean ratio."""
    return NOMINAL_H[key][0 if sex == "male" else 1] * stature


def body_lengths(sex: str, stature: float, measures: Mapping[str, float] | None = None) -> dict:
    """The human model's lengths and landmark positions (m) for ``sex``, ``stature`` (m) and any ``measures``.

    Keys: Winter's lengths and heights (see :data:`~.anthropometry.WINTER_H`), ``z_ls`` (L5/S1 height),
    ``vertebra`` (height of one lumbar, thoracic and cervical vertebra, by region letter), ``sc`` and ``ac``
    (right sternoclavicular and acromioclavicular joints: x, y from the body line, z) and ``gh_x`` (right
    glenohumeral joint x).
    """
    h, given = float(stature), dict(measures or {})
    d: dict = {k: v * h for k, v in A.WINTER_H.items()}
    d["z_ls"] = A.LUMBOSACRAL_H * h
    d["vertebra"] = {r: f * h for r, f in A.VERTEBRA_HEIGHT_H.items()}
    d["sc"] = tuple(f * h for f in A.STERNOCLAVICULAR_H)
    d["ac"] = tuple(f * h for f in A.ACROMIOCLAVICULAR_H)
    d["gh_x"] = A.GLENOHUMERAL_X_H * h
    if "sitting_height" in given:
        _split_stature(d, h, given["sitting_height"] - nominal("sitting_height", sex, h))
    if "shoulder_breadth" in given:
        k = given["shoulder_breadth"] / nominal("shoulder_breadth", sex, h)
        d["ac"] = (k * d["ac"][0], *d["ac"][1:])
        d["gh_x"] *= k
    for key, segment in (("upper_arm_length", "upper_arm"), ("forearm_length", "forearm")):
        if key in given:
            d[segment] *= given[key] / nominal(key, sex, h)
    if "hip_breadth" in given:
        d["hip_width"] = given["hip_breadth"]
    if "foot_length" in given:
        d["foot_length"] = given["foot_length"]
    return d


def _split_stature(d: dict, h: float, excess: float) -> None:
    """Move the hip joints down by ``excess`` (m, the sitting height over its nominal value): the legs scale to
    the new hip height, everything above the hips stretches to fill the stature ``h`` (m)."""
    hip = d["hip_height"]
    new_hip = hip - excess
    legs, upper = new_hip / hip, (h - new_hip) / (h - hip)

    def z(height: float) -> float:
        return height * legs if height <= hip else new_hip + (height - hip) * upper

    for key in HEIGHTS:
        d[key] = z(d[key])
    d["thigh"] *= legs
    d["shank"] *= legs
    d["z_ls"] = z(d["z_ls"])
    d["vertebra"] = {r: v * upper for r, v in d["vertebra"].items()}
    d["sc"] = (*d["sc"][:2], z(d["sc"][2]))
    d["ac"] = (*d["ac"][:2], z(d["ac"][2]))
