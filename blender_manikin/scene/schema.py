"""How a manikin is stored in a Blender scene: every custom property key and object name prefix, and the lookups
that find a manikin's parts (bpy only; no solver, so the UI can draw before anything heavy is imported).

On the armature object: ``manikin_preset`` (preset name, or "" for a body file), ``manikin_body_file`` (path or
""), ``manikin_x`` (the last solution: joint values, then contact-edge weights), ``manikin_result`` (JSON summary
of the last solve, for the sidebar and the overlay), ``manikin_bake`` (JSON: the last bake's range and the frames
that did not converge), ``manikin_frames`` (the last bake's per-frame sidebar entries: motion/frame_store.py),
``manikin_job_verdicts`` (the Job panel's verdicts and the bake they rate; its settings: ``Object.manikin_job``)
and, while live mode cannot solve, ``manikin_error``. On each TCP empty: ``manikin_tcp``
(its TCP's name). On each body object (the skinned human, the capsules, the solids): ``manikin_display``. On an
obstacle a scenario import made: ``manikin_imported`` (the scenario's file name; importing again replaces it). On
a carried box: ``manikin_carried`` (JSON: its size, TCPs and manikin; never an obstacle). On a reach envelope:
``manikin_envelope`` (the file it came from; importing it again replaces it). On an armature a motion was
retargeted onto: ``manikin_retargeted`` (JSON: the source, frames, leg-length ratio). Settings live in the
``Object.manikin`` / ``Object.manikin_target`` / ``Object.manikin_obstacle`` property groups (``pose/properties.py``)
and, on a retarget target, ``Object.manikin_retarget`` (``retarget/properties.py``: the source manikin, the options
and the bone map); a population study's settings and rows in ``Scene.manikin_study`` (``study/properties.py``).
"""

from __future__ import annotations

import json
import zlib

import bpy

PRESET_KEY = "manikin_preset"
FILE_KEY = "manikin_body_file"
X_KEY = "manikin_x"
RESULT_KEY = "manikin_result"
BAKE_KEY = "manikin_bake"
FRAMES_KEY = "manikin_frames"  # group of JSON texts: "head" and, per baked frame (its number), the sidebar's entry
JOB_KEY = "manikin_job_verdicts"  # JSON: the Job panel's last Assess Job (motion/job_panel.py) and the bake it rated
ERROR_KEY = "manikin_error"
TCP_KEY = "manikin_tcp"
IMPORTED_KEY = "manikin_imported"  # on an obstacle object a scenario import made: the scenario's file name
CARRIED_KEY = "manikin_carried"  # on a carried box (scene/carried_object.py)
ENVELOPE_KEY = "manikin_envelope"  # on a reach envelope object: the file it was imported from (envelope/objects.py)
RETARGET_KEY = "manikin_retargeted"  # on a retarget target (retarget/motion.py); not the settings group's name
OBSTACLES = "Obstacles"  # every mesh in a collection of this name is an obstacle
OBSTACLES_KEY = "manikin_obstacles"  # on a scene's obstacle collection (Obstacles.001, ... in other scenes; renamed)
CARRIED_RIG_KEY = "manikin_carried_rig"  # on a carried box: a pointer to its armature (renaming keeps it)

TCP_PREFIX = "tcp."  # tcp.<name>: the empty riding on a TCP
PREFIXES = {"TARGET": "target.", "LOOP": "loop.", "LOAD": "load."}  # the empties a user moves, by role
BODY_SUFFIX = ".body"  # <armature>.body: the mesh (and its object) riding on the bones
DISPLAY_SUFFIXES = {"CAPSULES": ".capsules", "SOLIDS": ".solids"}  # the other displays' objects (made when chosen)
DISPLAY_KEY = "manikin_display"  # on each body object: the display it belongs to (HUMAN, CAPSULES, SOLIDS)
SKIN_MATERIAL = "manikin.skin"  # the bodies' material, shared by every manikin
EYE_MATERIALS = ("manikin.eye", "manikin.iris")  # the eyeballs' sclera and iris
SHADED_KEY = "manikin_shaded"  # on a material of ours with its own node setup (skin, eyes): pictures keep it
PICTURE_PREFIX = "picture."  # picture.floor, picture.sun, ...: the key-pose picture's staging, removed afterwards
PICTURE_COLLECTION = "manikin.picture"  # the collection holding that staging
OUR_MATERIALS = ("manikin.", PICTURE_PREFIX)  # name prefixes of the materials we make (a user's stay untouched)


def member_name(role: str, tcp: str) -> str:
    """The name of a new empty of ``role`` (TARGET, LOOP or LOAD) for ``tcp``: ``target.hand_r``, ..."""
    return PREFIXES[role] + tcp


def body_name(arm_name: str) -> str:
    """The name of a manikin's body mesh and object."""
    return arm_name + BODY_SUFFIX


def is_manikin(obj: bpy.types.Object | None) -> bool:
    return obj is not None and obj.type == "ARMATURE" and (PRESET_KEY in obj or FILE_KEY in obj)


def owner_rig(obj: bpy.types.Object | None, bodies: bool = True) -> bpy.types.Object | None:
    """The manikin armature an object belongs to (itself, a target's manikin, a TCP empty's or, with ``bodies``, a
    body's parent), even one deleted from every scene (X keeps it in the file while its targets point at it)."""
    if obj is None:
        return None
    if is_manikin(obj):
        return obj
    settings = getattr(obj, "manikin_target", None)
    if settings is not None and settings.role != "NONE" and is_manikin(settings.rig):
        return settings.rig
    if (TCP_KEY in obj or (bodies and DISPLAY_KEY in obj)) and is_manikin(obj.parent):
        return obj.parent
    return None


def rig_of(obj: bpy.types.Object | None) -> bpy.types.Object | None:
    """:func:`owner_rig` when that manikin is in a scene, else None (a deleted rig is never solved)."""
    arm = owner_rig(obj, bodies=False)
    return arm if arm is not None and arm.users_scene else None


def orphan_hint(obj: bpy.types.Object | None) -> str:
    """One line for an object whose manikin was deleted from the scene, else ""."""
    arm = owner_rig(obj)
    if arm is None or arm.users_scene:
        return ""
    return f"{obj.name} belongs to the deleted manikin {arm.name}: remove what it left with Delete Manikin"


def members(arm: bpy.types.Object, linked: list[bpy.types.Object] | None = None) -> list[bpy.types.Object]:
    """Target, loop and load empties of ``arm`` that are in some scene, sorted by name. ``linked``: the objects
    :func:`linked_objects` found (a bake finds them once: its frames read only their roles)."""
    return [ob for ob in (linked_objects(arm) if linked is None else linked) if ob.manikin_target.role != "NONE"]


def linked_objects(arm: bpy.types.Object) -> list[bpy.types.Object]:
    """The objects in some scene whose Manikin settings point at ``arm`` (any role, NONE too), sorted by name."""
    found = [ob for ob in bpy.data.objects if ob.manikin_target.rig == arm and ob.users_scene]
    return sorted(found, key=lambda ob: ob.name)


def tcp_empty(arm: bpy.types.Object, tcp: str) -> bpy.types.Object | None:
    """The ``tcp.<name>`` empty of ``arm`` (found by its TCP property, so renamed copies still work)."""
    for child in arm.children:
        if child.get(TCP_KEY) == tcp:
            return child
    found = bpy.data.objects.get(TCP_PREFIX + tcp)
    return found if found is not None and found.parent == arm else None


def is_obstacle(ob: bpy.types.Object) -> bool:
    """A mesh object marked as an obstacle, or in the "Obstacles" collection; never a carried box (it moves with the
    hands: as an obstacle it would push them away from itself)."""
    if not may_be_obstacle(ob):
        return False
    return ob.manikin_obstacle.enabled or in_obstacles(ob)


def may_be_obstacle(ob: bpy.types.Object) -> bool:
    """What :func:`is_obstacle` needs besides the settings and the collections: a mesh object, no carried box."""
    return ob.type == "MESH" and CARRIED_KEY not in ob


def in_obstacles(ob: bpy.types.Object) -> bool:
    """In an obstacle collection ("Obstacles", or one marked as a scene's): an obstacle whatever its settings."""
    return any(c.name == OBSTACLES or OBSTACLES_KEY in c for c in ob.users_collection)


def _json(arm: bpy.types.Object, key: str) -> dict | None:
    text = arm.get(key)
    if not text:
        return None
    try:
        data = json.loads(text)
    except (TypeError, ValueError):
        return None
    return data if isinstance(data, dict) else None


def last_result(arm: bpy.types.Object) -> dict | None:
    """The summary of the manikin's last solve (converged, residuals, loads, ...), or None."""
    return _json(arm, RESULT_KEY)


def last_retarget(arm: bpy.types.Object) -> dict | None:
    """The summary the last retarget onto ``arm`` stored, or None."""
    return _json(arm, RETARGET_KEY)


def baked_frame(arm: bpy.types.Object, frame: int | str) -> dict | None:
    """The sidebar entry the last bake stored for ``frame`` ("head": the motion's), or None."""
    group = arm.get(FRAMES_KEY)
    text = group.get(str(frame)) if hasattr(group, "get") else None
    try:
        data = json.loads(text) if isinstance(text, str) else None
    except ValueError:
        return None
    return data if isinstance(data, dict) else None


def frame_result(arm: bpy.types.Object, frame: int) -> dict | None:
    """What the Result panel shows at ``frame`` after a bake: the frame's stored entry (the same keys as
    :func:`last_result`'s, plus its ergonomics), or None outside the baked range or once a solve (Solve Pose, live)
    has replaced the result the bake left (its checksum, stored in the bake's "head", differs)."""
    head = baked_frame(arm, "head")
    if head is None or zlib.crc32(str(arm.get(RESULT_KEY, "")).encode()) != head.get("result_crc"):
        return None
    return baked_frame(arm, frame)


def last_bake(arm: bpy.types.Object) -> dict | None:
    """The summary the last bake stored on ``arm``, or None."""
    return _json(arm, BAKE_KEY)
