"""The human manikin: a 160-joint tree scaled from stature (m) and body mass (kg) with published segment data.

Zero pose: standing upright, arms hanging with the palms on the thighs (thumbs forward), soles flat on z = 0,
facing -y with the left side at +x. Every link frame is identity-rotated in the zero pose, so joints are placed
by their zero-pose world positions (m). Each joint's positive value is the motion its name says; the left side is
the mirror image of the right (positions x -> -x, axes (ax, ay, az) -> (ax, -ay, -az)).
Sources and estimates: see :mod:`.anthropometry`.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from ...errors import ModelError, is_number
from ..builder import ModelBuilder
from ..model import Model
from . import anthropometry as A
from .measurements import body_lengths, validate_measurements

X, Y, Z = (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)
NEG_X, NEG_Y = (-1.0, 0.0, 0.0), (0.0, -1.0, 0.0)
Point = tuple[float, float, float] | np.ndarray  # m, or an axis
SEXES = ("male", "female")
STATURE_RANGE = (0.5, 2.5)  # m
MASS_RANGE = (10.0, 300.0)  # kg


class _Side:
    """Right ("r"), left ("l") or midline (None): mirrors right-side positions and pseudovector axes."""

    def __init__(self, tag: str | None) -> None:
        self.tag = tag
        self.sx = -1.0 if tag == "l" else 1.0

    def p(self, v: Point) -> np.ndarray:
        """Mirror a right-side world position (m)."""
        return np.array([self.sx * v[0], v[1], v[2]], dtype=float)

    def a(self, axis: Point) -> tuple[float, float, float]:
        """Mirror a right-side rotation axis (pseudovector)."""
        return (axis[0], self.sx * axis[1], self.sx * axis[2])

    def name(self, bone: str, rest: str = "") -> str:
        """``bone_r_rest`` (or ``bone_rest`` on the midline)."""
        return "_".join(x for x in (bone, self.tag, rest) if x)


MIDLINE = _Side(None)


class _Body:
    """A ModelBuilder fed with zero-pose world positions (m), converted to link-local offsets."""

    def __init__(self, builder: ModelBuilder, sex: str, mass: float, stature: float) -> None:
        self.b, self.sex, self.mass, self.h = builder, sex, mass, stature
        self.world: dict[str, np.ndarray] = {}

    def joint(
        self, name: str, parent: str, axis: Point, at: Point, key: str, weight: float,
        link: str | None = None, mass: float = 0.0, com: Point | None = None,
    ) -> str:  # fmt: skip
        """Joint ``name`` of kind ``key`` (limits and strength from :mod:`.anthropometry`) at world point ``at``."""
        at = np.asarray(at, dtype=float)
        local_com = (0.0, 0.0, 0.0) if com is None else tuple(np.asarray(com, dtype=float) - at)
        made = self.b.add_joint(
            name, parent, tuple(axis), tuple(at - self.world[parent]), limits=A.limits_rad(key),
            strength=A.joint_strength(key, self.sex, self.mass, self.h), range_weight=weight, link=link,
            mass=mass, com=local_com,
        )  # fmt: skip
        self.world[made] = at
        return made

    def chain(
        self, side: _Side, parent: str, at: Point, bone: str, *motions: tuple[str, Point],
        link: str | None = None, mass: float = 0.0, com: Point | None = None,
    ) -> str:  # fmt: skip
        """Joints ``bone_<side>_<motion>`` at one right-side point ``at``, for (motion, right-side axis) pairs.

        The last joint's link is named ``link`` (a template: "{s}" becomes the side tag) and carries
        ``mass`` (kg) at right-side ``com``.
        """
        kind = "finger" if bone in A.FINGER_Y_H else bone
        weight = 0.1 if kind in ("finger", "thumb") else 0.2 if kind == "eyes" else 1.0
        for i, (motion, axis) in enumerate(motions):
            last = i == len(motions) - 1
            parent = self.joint(
                side.name(bone, motion), parent, side.a(axis), side.p(at), f"{kind}_{motion}", weight,
                link=link.format(s=side.tag) if last and link else None, mass=mass if last else 0.0,
                com=side.p(com) if last and com is not None else None,
            )  # fmt: skip
        return parent

    def tcp(
        self, name: str, link: str, at: Point, rotation: np.ndarray | None = None, sole: np.ndarray | None = None
    ) -> None:
        self.b.add_tcp(name, link, tuple(np.asarray(at, dtype=float) - self.world[link]), rotation, sole)


def _rect(half_x: float, half_y: float) -> np.ndarray:
    """Counter-clockwise rectangle in a TCP's x-y plane, m."""
    return np.array([[-half_x, -half_y], [half_x, -half_y], [half_x, half_y], [-half_x, half_y]])


def validate_human(sex: str, stature: float, mass: float) -> None:
    """Raise ModelError unless sex is male/female, stature (m) and mass (kg) are finite and in range."""
    if sex not in SEXES:
        raise ModelError(f"sex must be 'male' or 'female', got {sex!r}")
    for key, value, (lo, hi), unit in (("stature", stature, STATURE_RANGE, "m"), ("mass", mass, MASS_RANGE, "kg")):
        if not is_number(value):
            raise ModelError(f"{key} must be a finite number in [{lo}, {hi}] {unit}, got {value!r}")
        if not lo <= value <= hi:
            raise ModelError(f"{key} must be in [{lo}, {hi}] {unit}, got {value}")


def build_human(
    sex: str, stature: float, mass: float, name: str = "human", *, info: Mapping | None = None,
    measurements: Mapping[str, float] | None = None,
) -> Model:  # fmt: skip
    """Human manikin of ``sex`` ("male"/"female"), ``stature`` (m) and ``mass`` (kg); ``info`` adds to Model.info.

    ``measurements`` (m, any subset of :data:`.measurements.MEASUREMENTS`) override the segment lengths they
    determine; the others stay fractions of stature.
    """
    validate_human(sex, stature, mass)
    h, mass = float(stature), float(mass)
    measured = validate_measurements(measurements or {}, h)
    d = body_lengths(sex, h, measured)
    d["y_body"] = 0.25 * d["foot_length"]  # ankles, knees, hips and spine lie on the line y = y_body
    d["x_hip"] = A.HIP_JOINT_SHARE * 0.5 * d["hip_width"]
    segments = "de Leva 1996 (masses, CM); Drillis & Contini via Winter 2009 (lengths)"
    if measured:
        segments += "; measured: " + ", ".join(measured)
    body_info = dict(kind="human", sex=sex, stature=h, mass=mass, segments=segments) | dict(info or {})
    if measured:
        body_info["measurements"] = measured
    body = _Body(ModelBuilder(name, body_info), sex, mass, h)
    frac = A.mass_fractions(sex)
    body.b.add_exterior_root((0.0, d["y_body"], d["z_ls"]), link="pelvis")
    body.world["pelvis"] = np.array([0.0, d["y_body"], d["z_ls"]])
    _trunk(body, d, frac)
    for tag in ("r", "l"):
        _arm(body, d, frac, _Side(tag))
        _leg(body, d, frac, _Side(tag))
    return body.b.build()


def _trunk(body: _Body, d: dict, frac: dict) -> None:
    """Pelvis mass, 24 vertebrae (3 joints each), head and eyes, with their TCPs."""
    h, yb, mass = body.h, d["y_body"], body.mass
    supr, midh = d["shoulder_height"], d["hip_height"]
    omph = midh + A.OMPH_SPLIT * (supr - midh)
    xyph = supr - A.XYPH_SPLIT * (supr - midh)

    def cm(seg: str, top: float, bottom: float) -> np.ndarray:
        """De Leva CM of ``seg`` on the body line, its first endpoint at height ``top`` (m)."""
        return np.array([0.0, yb, top + A.segment(seg, body.sex)[1] * (bottom - top)])

    body.b.set_mass("pelvis", frac["low_trunk"] * mass, tuple(cm("low_trunk", omph, midh) - body.world["pelvis"]))
    # Each vertebra carries an equal share of its sub-segment, all at the sub-segment's CM (exact in the zero pose).
    share = {
        "l": (frac["mid_trunk"] * mass / len(A.LUMBAR), cm("mid_trunk", xyph, omph)),
        "t": (frac["upper_trunk"] * mass / len(A.THORACIC), cm("upper_trunk", supr, xyph)),
        "c": (0.0, None),
    }
    head_cm = cm("head", h, d["chin_height"])
    parent, z = "pelvis", d["z_ls"]
    for v in A.LUMBAR + A.THORACIC + A.CERVICAL:
        region = "cervical" if v[0] == "c" else "thoracolumbar"
        weight = 1.0 / (A.N_CERVICAL if v[0] == "c" else A.N_THORACOLUMBAR)
        vmass, vcom = (frac["head"] * mass, head_cm) if v == "c1" else share[v[0]]
        for motion, axis in (("rx", X), ("ry", Y), ("rz", Z)):
            last = motion == "rz"
            parent = body.joint(
                f"{v}_{motion}", parent, axis, (0.0, yb, z), f"{region}_{motion}", weight,
                link=("head" if v == "c1" else v) if last else None, mass=vmass if last else 0.0,
                com=vcom if last else None,
            )  # fmt: skip
        z += d["vertebra"][v[0]]
    eye = (0.0, yb - A.EYE_FORWARD_H * h, d["eye_height"])
    body.chain(MIDLINE, "head", eye, "eyes", ("yaw", Z), ("pitch", X), link="eyes")
    body.tcp("head", "head", head_cm)
    body.tcp("eyes", "eyes", eye)
    body.tcp("pelvis", "pelvis", (0.0, yb, midh))


def _arm(body: _Body, d: dict, frac: dict, side: _Side) -> None:
    """Shoulder girdle (9 joints), elbow, forearm, wrist and 20 finger joints of one side, with TCPs."""
    h, yb, s = body.h, d["y_body"], side.tag
    sc, ac = d["sc"], d["ac"]
    gh = np.array([d["gh_x"], yb, d["shoulder_height"]])
    elbow = gh - (0.0, 0.0, d["upper_arm"])
    wrist = elbow - (0.0, 0.0, d["forearm"])
    met3 = wrist - (0.0, 0.0, A.MET3_HAND * d["hand"])
    m = {k: frac[k] * body.mass for k in ("upper_arm", "forearm", "hand")}
    cm = {k: A.segment(k, body.sex)[1] for k in m}
    link = body.chain(side, "t1", (sc[0], yb + sc[1], sc[2]), "clavicle",
                      ("rx", X), ("elevation", Y), ("protraction", Z), link="clavicle_{s}")  # fmt: skip
    link = body.chain(side, link, (ac[0], yb + ac[1], ac[2]), "scapula",
                      ("tilt", X), ("upward_rotation", Y), ("protraction", Z), link="scapula_{s}")  # fmt: skip
    link = body.chain(side, link, gh, "shoulder", ("flexion", NEG_X), ("abduction", Y), ("rotation", Z),
                      link="upper_arm_{s}", mass=m["upper_arm"],
                      com=gh - (0.0, 0.0, cm["upper_arm"] * d["upper_arm"]))  # fmt: skip
    link = body.chain(side, link, elbow, "elbow", ("flexion", NEG_X))
    link = body.chain(side, link, elbow, "forearm", ("pronation", Z), link="forearm_{s}", mass=m["forearm"],
                      com=elbow - (0, 0, cm["forearm"] * d["forearm"]))  # fmt: skip
    hand = body.chain(side, link, wrist, "wrist", ("flexion", NEG_Y), ("deviation", NEG_X), link="hand_{s}",
                      mass=m["hand"], com=wrist + cm["hand"] * (met3 - wrist))  # fmt: skip
    for f, dy in A.FINGER_Y_H.items():
        mcp = met3 + (0.0, dy * h, 0.0)
        pip = mcp - (0.0, 0.0, A.PHALANX_H[0] * h)
        dip = pip - (0.0, 0.0, A.PHALANX_H[1] * h)
        spread = NEG_X if f in ("index", "middle") else X  # positive: index/middle radially, ring/little ulnarly
        link = body.chain(
            side, hand, mcp, f, ("mcp_flexion", NEG_Y), ("mcp_abduction", spread), link=f + "_{s}_proximal"
        )
        link = body.chain(side, link, pip, f, ("pip", NEG_Y), link=f + "_{s}_middle")
        body.chain(side, link, dip, f, ("dip", NEG_Y), link=f + "_{s}_distal")
    cmc = wrist + (0.0, A.THUMB_BASE_Y_H * h, -A.THUMB_BASE_HAND * d["hand"])
    t_mcp = cmc - (0.0, 0.0, A.THUMB_H[0] * h)
    link = body.chain(
        side, hand, cmc, "thumb", ("cmc_flexion", X), ("cmc_abduction", NEG_Y), link="thumb_{s}_metacarpal"
    )
    link = body.chain(side, link, t_mcp, "thumb", ("mcp", X), link="thumb_{s}_proximal")
    body.chain(side, link, t_mcp - (0.0, 0.0, A.THUMB_H[1] * h), "thumb", ("ip", X), link="thumb_{s}_distal")
    palm = wrist + (A.PALM_DEPTH_H * h, 0.0, -A.PALM_HAND * d["hand"])  # the right palm faces +x
    # Grasp frame: x toward the fingertips, z out of the palm (columns of the rotation).
    grip = np.array([[0, 0, 1], [0, 1, 0], [-1, 0, 0]] if s == "r" else [[0, 0, -1], [0, -1, 0], [-1, 0, 0]], float)
    body.tcp(f"hand_{s}", f"hand_{s}", side.p(palm), rotation=grip)
    body.tcp(f"knuckles_{s}", f"hand_{s}", side.p(met3))
    body.tcp(f"forearm_{s}", f"forearm_{s}", side.p(elbow - (0.0, 0.0, 0.5 * d["forearm"])))
    body.tcp(f"elbow_{s}", f"forearm_{s}", side.p(elbow))
    body.tcp(f"shoulder_{s}", f"upper_arm_{s}", side.p(gh))


def _leg(body: _Body, d: dict, frac: dict, side: _Side) -> None:
    """Hip (3 joints), knee, ankle (2) and toes of one side, with the foot, heel, toe and knee TCPs."""
    s, fl, x = side.tag, d["foot_length"], -d["x_hip"]
    hip = np.array([x, d["y_body"], d["hip_height"]])
    knee = hip - (0.0, 0.0, d["thigh"])
    ankle = knee - (0.0, 0.0, d["shank"])
    heel_y, toe_y, mtp_y = 0.5 * fl, -0.5 * fl, (0.5 - A.MTP_FOOT) * fl
    m = {k: frac[k] * body.mass for k in ("thigh", "shank", "foot")}
    cm = {k: A.segment(k, body.sex)[1] for k in m}
    link = body.chain(side, "pelvis", hip, "hip", ("flexion", NEG_X), ("abduction", Y), ("rotation", Z),
                      link="thigh_{s}", mass=m["thigh"], com=hip - (0.0, 0.0, cm["thigh"] * d["thigh"]))  # fmt: skip
    link = body.chain(side, link, knee, "knee", ("flexion", X), link="shank_{s}", mass=m["shank"],
                      com=knee - (0.0, 0.0, cm["shank"] * d["shank"]))  # fmt: skip
    foot_cm = (x, heel_y + cm["foot"] * (toe_y - heel_y), A.FOOT_CM_HEIGHT * d["ankle_height"])
    foot = body.chain(side, link, ankle, "ankle", ("dorsiflexion", NEG_X), ("inversion", NEG_Y), link="foot_{s}",
                      mass=m["foot"], com=foot_cm)  # fmt: skip
    toes = body.chain(side, foot, (x, mtp_y, A.MTP_HEIGHT_H * body.h), "toes", ("flexion", X), link="toes_{s}")
    half_w = 0.5 * d["foot_width"]
    body.tcp(f"foot_{s}", foot, side.p((x, 0.0, 0.0)), sole=_rect(half_w, 0.5 * fl))
    body.tcp(f"heel_{s}", foot, side.p((x, heel_y, 0.0)))
    body.tcp(f"toe_{s}", toes, side.p((x, 0.5 * (mtp_y + toe_y), 0.0)), sole=_rect(half_w, 0.5 * (mtp_y - toe_y)))
    body.tcp(f"knee_{s}", f"shank_{s}", side.p(knee))
