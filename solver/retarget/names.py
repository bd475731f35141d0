"""A bone map filled in from the target's bone names (and, for the spine, its rest geometry). Plain Python/NumPy.

A name is split into words (``mixamorig:LeftUpLeg`` -> left, up, leg; ``upper_arm.L`` -> upper, arm, l;
``Bip01 L Thigh`` -> l, thigh; ``J_Bip_L_UpperArm`` -> l, upper, arm): a namespace before ``:``, Rigify's
``DEF-``/``ORG-`` layers and marker words (``bip``, ``j``, ``c``) are dropped, ``left``/``l``/``right``/``r``
give the side, digits are kept apart. The remaining words, joined, must match one of a part's patterns exactly
(``upleg``, ``thigh``, ``upperleg``, sided ``hip`` for our thigh...). Several candidates: the one nearest the root
(``upperarm01`` before ``upperarm02``), plain names before ``DEF-`` before ``ORG-``. ``shoulder`` is the clavicle
(Mixamo, Rigify) unless the rig also has a clavicle, then the upper arm (SMPL) or, with both, the scapula (MPFB).

The pelvis is ``hips``/``pelvis``, else the thighs' nearest common ancestor; the head is ``head`` (Rigify's
metarig: ``spine.006``). The bones between them (spine, chest, neck) take the vertebra of ours at the same
fraction of the way from the hip joints to the head. Fingers: the first three bones of each finger in chain order.
"""

from __future__ import annotations

import re

import numpy as np

from .skeleton import Skeleton

SIDES = {"l": "l", "left": "l", "r": "r", "right": "r"}
MARKERS = {"j", "bip", "c", "jnt"}  # VRoid's J_Bip_C_, 3ds Max's Bip01, joint prefixes
LAYERS = {"": 0, "DEF": 1, "ORG": 2}  # Rigify's generated layers, by preference (MCH bones are never mapped)

# Our limb bones (suffix _l/_r) and the exact word patterns naming them, the strong ones first.
LIMB_PATTERNS = {
    "clavicle": r"clavicle|clav|collar(bone)?",
    "scapula": r"scapula|scap",
    "upper_arm": r"upperarm|uparm|arm|shldr|humerus",
    "forearm": r"forearm|lowerarm|loarm|elbow",
    "hand": r"hand|wrist",
    "thigh": r"thigh|upleg|upperleg|uleg|femur|hip",
    "shank": r"shin|calf|leg|lowerleg|loleg|knee|crus|shank|tibia",
    "foot": r"foot|ankle",
    "toes": r"toebase|toes?|ball",
}
SHOULDER = "shoulder"  # the weak word: clavicle, else upper arm, else scapula
FINGERS = {
    "thumb": r"(hand|f)?thumb",
    "index": r"(hand|f)?(index|pointer)(finger)?",
    "middle": r"(hand|f)?(middle|mid)(finger)?",
    "ring": r"(hand|f)?ring(finger)?",
    "little": r"(hand|f)?(pinky|little)(finger)?",
}
NUMBERED_FINGER = r"(hand)?fingers?"  # finger1..5 (MPFB: 1 the thumb) or finger0..4 (3ds Max: 0 the thumb)
PHALANGES = {"thumb": ("metacarpal", "proximal", "distal")}
PHALANX = ("proximal", "middle", "distal")


def parse(name: str) -> tuple[str, str, tuple[str, ...], int]:
    """(side "l"/"r"/"", the words joined, the digit groups, Rigify layer rank or -1 for an MCH bone)."""
    bare = name.rsplit(":", 1)[-1]
    layer = ""
    match = re.match(r"^(DEF|ORG|MCH)[-_.]", bare)
    if match:
        layer, bare = match.group(1), bare[match.end() :]
    if layer == "MCH":
        return "", "", (), -1
    parts = re.findall(r"[A-Z]+(?=[A-Z][a-z])|[A-Z]?[a-z]+|[A-Z]+|\d+", bare)
    side, words, digits, skip_digits = "", [], [], False
    for part in parts:
        low = part.lower()
        if part.isdigit():
            if not skip_digits:
                digits.append(part)
            skip_digits = False
            continue
        skip_digits = low == "bip"
        if low in SIDES and not side:
            side = SIDES[low]
        elif low not in MARKERS:
            words.append(low)
    return side, "".join(words), tuple(digits), LAYERS[layer]


def _pick(skel: Skeleton, candidates: list[int], used: set[int]) -> int | None:
    free = [b for b in candidates if b not in used]
    if not free:
        return None
    return min(free, key=lambda b: (parse(skel.names[b])[3], skel.depth(b), len(skel.names[b])))


def _limbs(skel: Skeleton, parsed: list[tuple], used: set[int]) -> dict[str, int]:
    found: dict[str, int] = {}
    for side in "lr":
        for part, pattern in LIMB_PATTERNS.items():
            cands = [b for b, (s, core, digits, layer) in enumerate(parsed)
                     if s == side and layer >= 0 and re.fullmatch(pattern, core)
                     and not (part == "toes" and len(digits) > 1)]  # fmt: skip
            _take(found, f"{part}_{side}", _pick(skel, cands, used), used)
        weak = [b for b, (s, core, _, layer) in enumerate(parsed) if s == side and layer >= 0 and core == SHOULDER]
        for part in ("clavicle", "upper_arm", "scapula"):
            if f"{part}_{side}" not in found:
                _take(found, f"{part}_{side}", _pick(skel, weak, used), used)
    return found


def _take(found: dict[str, int], part: str, b: int | None, used: set[int]) -> None:
    if b is not None:
        found[part] = b
        used.add(b)


def _fingers(skel: Skeleton, parsed: list[tuple], used: set[int]) -> dict[str, int]:
    numbered = [b for b, p in enumerate(parsed) if re.fullmatch(NUMBERED_FINGER, p[1]) and p[2] and p[3] >= 0]
    named_thumb = any(re.fullmatch(FINGERS["thumb"], p[1]) for p in parsed)
    # finger0 is the thumb (3ds Max); finger1 is the thumb (MPFB) unless the rig names its thumb (CMU: index)
    first = 0 if named_thumb or any(parsed[b][2][0][0] == "0" for b in numbered) else 1
    order = list(FINGERS)
    found: dict[str, int] = {}
    for side in "lr":
        for finger, pattern in FINGERS.items():
            cands = [b for b, (s, core, _, layer) in enumerate(parsed)
                     if s == side and layer >= 0 and re.fullmatch(pattern, core)]  # fmt: skip
            cands += [b for b in numbered if parsed[b][0] == side and int(parsed[b][2][0][0]) - first ==
                      order.index(finger)]  # fmt: skip
            chain = sorted((b for b in cands if b not in used), key=lambda b: (parsed[b][3], skel.depth(b)))
            for phalanx, b in zip(PHALANGES.get(finger, PHALANX), chain[:3], strict=False):
                found[f"{finger}_{side}_{phalanx}"] = b
                used.add(b)
    return found


def _common_ancestor(skel: Skeleton, a: int, b: int) -> int | None:
    up = set(skel.ancestors(a))
    return next((c for c in skel.ancestors(b) if c in up), None)


def _heights(s: Skeleton, found: dict[str, int], top: int, bones: list[int]) -> tuple[np.ndarray, np.ndarray]:
    """Heights (m) of the mid-points of ``bones`` along the body (hip joints' midpoint towards the head bone's
    head), and of the anchors: the hip joints (0), the shoulder joints (if mapped) and the head."""
    base = s.heads[[found["thigh_l"], found["thigh_r"]]].mean(axis=0)
    up = s.heads[top] - base
    up = up / float(np.linalg.norm(up))
    anchors = [0.0, float((s.heads[top] - base) @ up)]
    if {"upper_arm_l", "upper_arm_r"} <= set(found):
        shoulders = s.heads[[found["upper_arm_l"], found["upper_arm_r"]]].mean(axis=0)
        anchors.insert(1, float((shoulders - base) @ up))
    mids = 0.5 * (s.heads[bones] + s.tails[bones])
    return (mids - base) @ up, np.array(anchors)


def _spine(ours: Skeleton, skel: Skeleton, pelvis: int, head: int, found: dict[str, int]) -> dict[str, int]:
    """Bones strictly between ``pelvis`` and ``head`` onto our vertebrae at the same place along the body: heights
    mapped piecewise linearly between the hip joints, the shoulder joints and the head joint."""
    chain = skel.ancestors(head)
    if pelvis not in chain or not {"thigh_l", "thigh_r"} <= set(found):
        return {}
    chain = chain[: chain.index(pelvis)][::-1]  # from the pelvis up
    vertebrae = [b for b in ours.ancestors(ours.index("head"))][::-1][1:]  # l5 .. c2
    if not chain:
        return {}
    mine = {k: ours.index(k) for k in ("thigh_l", "thigh_r", "upper_arm_l", "upper_arm_r") if k in ours.names}
    if "upper_arm_l" not in found or "upper_arm_r" not in found:
        mine = {k: v for k, v in mine.items() if k.startswith("thigh")}
    ours_h, ours_anchors = _heights(ours, mine, ours.index("head"), vertebrae)
    theirs_h, theirs_anchors = _heights(skel, found, head, chain)
    out: dict[str, int] = {}
    last = -1
    for b, h in zip(chain, np.interp(theirs_h, theirs_anchors, ours_anchors), strict=True):
        k = max(int(np.argmin(np.abs(ours_h - h))), last + 1)  # each vertebra once, in order
        if k >= len(vertebrae):
            break
        out[ours.names[vertebrae[k]]], last = b, k
    return out


def auto_map(ours: Skeleton, theirs: Skeleton) -> dict[str, str]:
    """Our bone -> their bone for every part the names (and the spine's geometry) identify; may be partial."""
    parsed = [parse(n) for n in theirs.names]
    used: set[int] = set()
    found = _limbs(theirs, parsed, used)
    found.update(_fingers(theirs, parsed, used))
    centre = [b for b, p in enumerate(parsed) if p[0] == "" and p[3] >= 0]
    pelvis = _pick(theirs, [b for b in centre if parsed[b][1] in ("hips", "hip", "pelvis")], used)
    if pelvis is None and {"thigh_l", "thigh_r"} <= set(found):
        pelvis = _common_ancestor(theirs, found["thigh_l"], found["thigh_r"])
    head = _pick(theirs, [b for b in centre if parsed[b][1] == "head"], used)
    if head is None:  # Rigify's metarig: spine (pelvis), spine.001 .. .004, .005 (neck), .006 (head)
        head = _pick(theirs, [b for b in centre if parsed[b][1] == "spine" and parsed[b][2] == ("006",)], used)
    for part, b in (("pelvis", pelvis), ("head", head)):
        if b is not None and b not in found.values():
            found[part] = b
    if "pelvis" in found and "head" in found:
        found.update(_spine(ours, theirs, found["pelvis"], found["head"], found))
    return {part: theirs.names[b] for part, b in found.items() if part in ours.names}
