"""Bone maps (our bone -> their bone): the TOML files shipped in ``presets/bone_maps/`` and the checks a map must
pass before a retarget. Plain Python.

A map file::

    rig = "mixamo"                      # optional: the shipped rig it belongs to
    [bones]                             # our bone = their bone
    pelvis = "mixamorig:Hips"
    thigh_l = "mixamorig:LeftUpLeg"

Our bones are the manikin armature's (``pelvis``, ``l5`` .. ``c2``, ``head``, ``clavicle_l``, ``scapula_l``,
``upper_arm_l``, ``forearm_l``, ``hand_l``, fingers ``index_l_proximal`` .., ``thigh_l``, ``shank_l``,
``foot_l``, ``toes_l`` and the right side's). :data:`REQUIRED` must be mapped; the rest is optional.
"""

from __future__ import annotations

import json
import tomllib
from pathlib import Path

from ..errors import ModelError
from ..presets import PRESETS_DIR

BONE_MAPS_DIR = PRESETS_DIR / "bone_maps"
# The shipped rigs: name (their map's file stem) -> (their table in presets/body_mesh/mpfb2_rigs.json, a label).
SHIPPED_RIGS = {
    "mpfb_default": ("default", "MPFB default"),
    "game_engine": ("game_engine", "Game engine (Unreal names)"),
    "mixamo": ("mixamo", "Mixamo"),
    "cmu_mb": ("cmu_mb", "CMU motion capture"),
    "rigify": ("rigify_human", "Rigify human metarig"),
}
REQUIRED = ("pelvis",) + tuple(f"{part}_{s}" for s in "lr" for part in
                               ("thigh", "shank", "foot", "upper_arm", "forearm", "hand"))  # fmt: skip
CHAINS = tuple((f"{a}_{s}", f"{b}_{s}") for s in "lr" for a, b in
               (("thigh", "shank"), ("shank", "foot"), ("upper_arm", "forearm"), ("forearm", "hand")))  # fmt: skip


def shipped_path(name: str) -> Path:
    return BONE_MAPS_DIR / f"{name}.toml"


def load_map(path: str | Path) -> tuple[str | None, dict[str, str]]:
    """(the rig it names or None, our bone -> their bone) of a bone-map TOML file; ModelError naming the key."""
    path = Path(path)
    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise ModelError(f"{path}: bone map not found") from None
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError) as exc:
        raise ModelError(f"{path}: not a bone map ({' '.join(str(exc).split())})") from None
    bones = data.get("bones")
    if not isinstance(bones, dict):
        raise ModelError(f"{path}: bones: expected a table of our bone = their bone")
    for ours, theirs in bones.items():
        if not isinstance(theirs, str) or not theirs:
            raise ModelError(f"{path}: bones.{ours}: expected a bone name, got {theirs!r}")
    rig = data.get("rig")
    if rig is not None and not isinstance(rig, str):
        raise ModelError(f"{path}: rig: expected a name, got {rig!r}")
    return rig, dict(bones)


def dumps_map(bone_map: dict[str, str], rig: str | None = None) -> str:
    """The TOML text of a map (our bones in the given order)."""
    lines = [f"rig = {json.dumps(rig)}"] if rig else []
    lines += ["", "[bones]"] + [f"{_key(k)} = {json.dumps(v, ensure_ascii=False)}" for k, v in bone_map.items()]
    return "\n".join(lines).lstrip() + "\n"


def _key(name: str) -> str:
    return name if name.replace("_", "").replace("-", "").isalnum() and name.isascii() else json.dumps(name)


def check_map(bone_map: dict[str, str], ours: tuple[str, ...], theirs: dict[str, str | None], target: str) -> None:
    """ModelError (one line) unless every key is one of ``ours``, every value a bone of ``theirs`` (bone ->
    parent) used once, every :data:`REQUIRED` bone mapped and each limb's lower bone below its upper one."""
    unknown = [k for k in bone_map if k not in ours]
    if unknown:
        raise ModelError(f"bone map: '{unknown[0]}' is not a bone of the manikin")
    missing_bones = [(k, v) for k, v in bone_map.items() if v not in theirs]
    if missing_bones:
        k, v = missing_bones[0]
        raise ModelError(f"bone map: {k} -> '{v}': '{target}' has no such bone")
    seen: dict[str, str] = {}
    for k, v in bone_map.items():
        if v in seen:
            raise ModelError(f"bone map: '{v}' is mapped from both {seen[v]} and {k}")
        seen[v] = k
    missing = [k for k in REQUIRED if k not in bone_map]
    if missing:
        raise ModelError(f"bone map of '{target}': no bone for {', '.join(missing)} (fill them in, then retarget)")
    for upper, lower in CHAINS:
        bone, above = theirs[bone_map[lower]], set()
        while bone is not None and bone not in above:
            above.add(bone)
            bone = theirs.get(bone)
        if bone_map[upper] not in above:
            raise ModelError(f"bone map: {lower} -> '{bone_map[lower]}' is not below {upper} -> '{bone_map[upper]}'")
