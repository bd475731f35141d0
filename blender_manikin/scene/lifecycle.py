"""A manikin as one thing (bpy): what belongs to it, deleting all of it, and duplicating all of it.

What belongs to an armature is found by pointers, never by names: its children marked as body objects
(``DISPLAY_KEY``) or TCP empties (``TCP_KEY``), the empties whose ``manikin_target.rig`` is it (with the loops and
loads parented to its TCP empties), and the carried box whose pointer is it. Other objects (a user's tool parented
to a TCP empty, obstacles, other manikins) never are.
"""

from __future__ import annotations

import bpy
import numpy as np
from mathutils import Matrix

from .carried_object import find_carried
from .compat import object_fcurves
from .schema import BODY_SUFFIX, CARRIED_RIG_KEY, DISPLAY_KEY, TCP_KEY


def belongings(arm: bpy.types.Object) -> list[bpy.types.Object]:
    """``arm`` and the objects that belong to it (see the module), the armature first."""
    found = [arm]
    for child in arm.children:
        if DISPLAY_KEY in child or TCP_KEY in child or child.name == arm.name + BODY_SUFFIX:
            found.append(child)
    found += [ob for ob in bpy.data.objects if ob.manikin_target.role != "NONE" and ob.manikin_target.rig == arm]
    box = find_carried(arm)
    if box is not None:
        found.append(box)
    return list(dict.fromkeys(found))  # once each, in order


def delete_manikin(arm: bpy.types.Object) -> int:
    """Remove ``arm`` and what belongs to it (their meshes, armature data and actions when nothing else uses them;
    its collection when it is left empty); a user's object parented to one of them stays where it is. Returns the
    number of objects removed."""
    gone = belongings(arm)
    doomed = set(gone)
    for ob in gone:
        for child in ob.children:
            if child not in doomed:  # keep it in place, unparented
                world = child.matrix_world.copy()
                child.parent = None
                child.matrix_world = world
    data = [ob.data for ob in gone if ob.data is not None]
    actions = [ob.animation_data.action for ob in gone if ob.animation_data and ob.animation_data.action]
    collections = list(arm.users_collection)
    for ob in gone:
        bpy.data.objects.remove(ob, do_unlink=True)
    for block in dict.fromkeys(data + actions):
        if block.users == 0:
            _remove_data(block)
    for collection in collections:
        if not collection.all_objects and not collection.children and collection.users <= 1:
            bpy.data.collections.remove(collection)
    return len(gone)


def _remove_data(block: bpy.types.ID) -> None:
    data = bpy.data
    stores = {bpy.types.Mesh: data.meshes, bpy.types.Armature: data.armatures, bpy.types.Action: data.actions}
    store = stores.get(type(block))
    if store is not None:
        store.remove(block)


def duplicate_manikin(arm: bpy.types.Object, offset: float = 1.0) -> bpy.types.Object:
    """A working copy of ``arm`` with copies of everything that belongs to it (own data, actions and drivers
    pointing at the copies), ``offset`` m along ``arm``'s x axis (keyed locations too), in a collection of its own
    beside ``arm``'s; the new armature."""
    originals = belongings(arm)
    copies = {ob: _copy(ob) for ob in originals}
    new_arm = copies[arm]
    collection = bpy.data.collections.new(new_arm.name)
    for parent in _parents_of(arm.users_collection[0]) if arm.users_collection else [bpy.context.scene.collection]:
        parent.children.link(collection)
    own = set(arm.users_collection)
    for ob, new in copies.items():
        targets = [collection] if own & set(ob.users_collection) or not ob.users_collection else ob.users_collection
        for c in targets:
            c.objects.link(new)
        _remap(new, copies)
        if ob is not arm and ob.name.startswith(arm.name + "."):  # its body: <armature>.body, ...
            new.name = new_arm.name + ob.name[len(arm.name) :]
    shift = np.array(arm.matrix_world.to_3x3().normalized().col[0]) * offset
    for ob, new in copies.items():
        if new.parent is None:  # the armature, the targets, the box: moved; their children go with them
            new.matrix_world = Matrix.Translation(tuple(shift)) @ ob.matrix_world
            _shift_keys(new, shift)
    return new_arm


def _parents_of(collection: bpy.types.Collection) -> list[bpy.types.Collection]:
    """The collections (or scenes' master collections) that hold ``collection``."""
    found = [c for c in bpy.data.collections if collection.name in c.children]
    found += [s.collection for s in bpy.data.scenes if collection.name in s.collection.children]
    return found or [bpy.context.scene.collection]


def _copy(ob: bpy.types.Object) -> bpy.types.Object:
    new = ob.copy()
    if ob.data is not None:
        new.data = ob.data.copy()
    if ob.animation_data is not None and ob.animation_data.action is not None:
        new.animation_data.action = ob.animation_data.action.copy()
    return new


def _remap(new: bpy.types.Object, copies: dict) -> None:
    """Point ``new``'s parent, rig, modifiers, drivers and box pointer at the copies instead of the originals."""
    if new.parent in copies:
        new.parent = copies[new.parent]  # keeps the bone parenting and the parent inverse
    if new.manikin_target.rig in copies:
        new.manikin_target.rig = copies[new.manikin_target.rig]
    if new.get(CARRIED_RIG_KEY) in copies:
        new[CARRIED_RIG_KEY] = copies[new[CARRIED_RIG_KEY]]
    for modifier in new.modifiers:
        if getattr(modifier, "object", None) in copies:
            modifier.object = copies[modifier.object]
    if new.animation_data is not None:
        for fc in new.animation_data.drivers:  # the twist helpers follow their own armature's bones
            for variable in fc.driver.variables:
                for target in variable.targets:
                    if target.id in copies:
                        target.id = copies[target.id]


def _shift_keys(ob: bpy.types.Object, shift: np.ndarray) -> None:
    """Move the keyed locations of ``ob`` (an unparented object: world = its location) by ``shift`` (m)."""
    for fc in object_fcurves(ob):
        if fc.data_path != "location":
            continue
        d = float(shift[fc.array_index])
        for point in fc.keyframe_points:
            point.co.y += d
            point.handle_left.y += d
            point.handle_right.y += d
        fc.update()
